"""A fake motor control with trivial math, and fake speech backends, for the blackboard tests.

The fake motor moves each arm along one number, its "distance from rest": preparation goes
to the gesture's preparation distance, the stroke holds there, the retraction returns to 0
(or to an interim rest at 30 % when another gesture follows). Each arm's shoulder rotates
about x by that number, so frames show where the arm is. A new program cuts the arm's
keyframes at its start: the retraction in progress is skipped (co-articulation).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from blackboard import GestureDemands, TimePegs
from motor.motion import Motion
from motor.trajectory.spline import fitts_duration
from mura.constraints import ARM_SLOTS, Dynamic, Repetition, Symmetrical, iter_leaves
from mura.model import BehaviorSpec
from mura.murml import load_utterance
from tts import FakeSynthesizer, SpeechError, SpeechRequest, SpeechTiming

REPO = Path(__file__).resolve().parents[2]
UTTERANCES = sorted((REPO / "specs" / "utterances").glob("*.xml"))
CORPUS = REPO.parent / "shared" / "corpora" / "murml"
JOINTS = ("humanoid_root", "r_shoulder", "l_shoulder")
ARM_JOINT = {"right": 1, "left": 2}
STROKE_PER_SEGMENT = 0.4
DEFAULT_DISTANCE = 0.3
HEAD_DISTANCE = 0.01


@dataclass(frozen=True)
class FakeProgram:
    behavior: str
    arms: frozenset[str]
    target: float
    rest: float
    pegs: TimePegs
    repetitions: int
    next_gesture_follows: bool
    lmps: tuple = ()
    warnings: tuple[str, ...] = ()


def _count_dynamic(node) -> float:
    if isinstance(node, Dynamic):
        return 1.0
    if isinstance(node, Repetition):
        return node.count * _count_dynamic(node.child)
    if isinstance(node, Symmetrical):
        return _count_dynamic(node.child)
    if hasattr(node, "children"):
        return sum(_count_dynamic(c) for c in node.children)
    return 0.0


class FakeMotor:
    """Implements blackboard.MotorControl with one number per arm."""

    fps = 60.0

    def __init__(self, distances: dict[str, float] | None = None, repeatable: bool = True) -> None:
        self.distances = distances or {}
        self.repeatable = repeatable
        self.keys: dict[str, list[tuple[float, float]]] = {"right": [(0.0, 0.0)], "left": [(0.0, 0.0)]}
        self.owner: dict[str, str | None] = {"right": None, "left": None}
        self.plans: list[FakeProgram] = []
        self.activated: list[FakeProgram] = []
        self.cuts: list[tuple[str, str, float]] = []  # (arm, behaviour whose retraction was cut, time)
        self.interrupts: list[float] = []
        self.spoken: list[tuple[float, tuple[tuple[float, float], ...]]] = []  # (speech onset, accents)
        self.sampled_until = 0.0

    def demands(self, behavior: BehaviorSpec) -> GestureDemands:
        if behavior.spatial is not None:  # pointing or an indicating verb: one right-arm stroke here
            distance = self.distances.get(behavior.id, DEFAULT_DISTANCE)
            where = {"right": (distance, 0.0, 0.0)}
            return GestureDemands(frozenset({"right"}), STROKE_PER_SEGMENT, True, False, distance,
                                  first_wrists=where, last_wrists=where, stroke_distance=0.1)
        gesture = behavior.gesture
        node = gesture.constraints if gesture is not None else behavior.sign.to_constraint()
        scope = (gesture.scope if gesture is not None else None) or ""
        if isinstance(node, Symmetrical):
            arms = frozenset({"right", "left"})
        elif "head" in scope or not any(leaf.slot in ARM_SLOTS for leaf in iter_leaves(node)):
            arms = frozenset()
        elif "left" in scope:
            arms = frozenset({"left"})
        else:
            arms = frozenset({"right"})
        dynamic = any(isinstance(leaf, Dynamic) for leaf in iter_leaves(node))
        distance = self.distances.get(behavior.id, DEFAULT_DISTANCE if arms else HEAD_DISTANCE)
        where = {arm: (distance, 0.0, 0.0) for arm in arms}  # the stroke holds at its distance from rest
        return GestureDemands(arms, STROKE_PER_SEGMENT * _count_dynamic(node), dynamic, dynamic and self.repeatable, distance,
                              first_wrists=where, last_wrists=where, stroke_distance=0.1 * _count_dynamic(node))

    def position(self, arm: str, t: float | np.ndarray) -> np.ndarray:
        times, values = zip(*self.keys[arm])
        return np.interp(t, times, values)

    def preparation_distances(self, behavior: BehaviorSpec, at_time: float) -> dict[str, float]:
        d = self.demands(behavior)
        return {a: abs(d.preparation_distance - float(self.position(a, at_time))) for a in d.arms}

    def plan(self, behavior, pegs, *, repetitions=1, next_gesture_follows=False) -> FakeProgram:
        d = self.demands(behavior)
        rest = 0.3 * d.preparation_distance if next_gesture_follows else 0.0
        end = pegs.relax + float(fitts_duration(abs(d.preparation_distance - rest)))
        program = FakeProgram(behavior.id, d.arms, d.preparation_distance, rest, replace(pegs, end=end), repetitions, next_gesture_follows)
        self.plans.append(program)
        return program

    def activate(self, program: FakeProgram) -> None:
        p = program.pegs
        assert p.start >= self.sampled_until - 1e-9, f"{program.behavior} activated after frames at {p.start} were sampled"
        self.activated.append(program)
        for arm in program.arms:
            keys = self.keys[arm]
            if keys[-1][0] > p.start + 1e-9 and self.owner[arm] is not None:
                self.cuts.append((arm, self.owner[arm], p.start))
            here = float(self.position(arm, p.start))
            kept = [k for k in keys if k[0] < p.start]
            self.keys[arm] = kept + [(p.start, here), (p.ready, program.target), (p.relax, program.target), (p.end, program.rest)]
            self.owner[arm] = program.behavior

    def frames(self, start: float, end: float) -> Motion:
        first, stop = math.ceil(start * self.fps - 1e-6), math.ceil(end * self.fps - 1e-6)
        times = np.arange(first, stop) / self.fps
        rotations = np.zeros((len(times), len(JOINTS), 4))
        rotations[..., 3] = 1.0
        for arm, joint in ARM_JOINT.items():
            angle = self.position(arm, times)
            rotations[:, joint, 0] = np.sin(angle / 2)
            rotations[:, joint, 3] = np.cos(angle / 2)
        self.sampled_until = max(self.sampled_until, end)
        return Motion(self.fps, JOINTS, (-1, 0, 0), np.zeros((3, 3)), rotations, np.zeros((len(times), 3)), first / self.fps)

    def busy_until(self, arm: str) -> float:
        return self.keys[arm][-1][0]

    def speak(self, speech, onset: float, accents=()) -> tuple[str, ...]:
        self.spoken.append((onset, tuple(accents)))
        return ()

    def interrupt(self, at_time: float) -> None:
        self.interrupts.append(at_time)
        for arm in self.keys:
            here = float(self.position(arm, at_time))
            kept = [k for k in self.keys[arm] if k[0] < at_time]
            self.keys[arm] = kept + [(at_time, here), (at_time + float(fitts_duration(abs(here))), 0.0)]


class FailingSpeech(FakeSynthesizer):
    """The fake speech timer, failing on the request for chunk ``fail_at`` (counting from 0)."""

    def __init__(self, fail_at: int) -> None:
        super().__init__()
        self.fail_at = fail_at
        self.calls = 0

    def synthesize(self, request: SpeechRequest) -> SpeechTiming:
        call, self.calls = self.calls, self.calls + 1
        if call == self.fail_at:
            raise SpeechError("the speech backend crashed")
        return super().synthesize(request)


class RecordingSpeech(FakeSynthesizer):
    """The fake speech timer, keeping every request."""

    def __init__(self) -> None:
        super().__init__()
        self.requests: list[SpeechRequest] = []

    def synthesize(self, request: SpeechRequest) -> SpeechTiming:
        self.requests.append(request)
        return super().synthesize(request)


def utterance(name: str):
    return load_utterance(REPO / "specs" / "utterances" / name)
