"""Motor programs: a gesture planned into LMPs for each arm on the utterance clock (seed 004, 4).

Planning runs in two steps. The first, the stroke in its own time, compiles the
constraint tree into a fragment (:mod:`motor.program.fragment`). The second is here.

**2. LMPs on the utterance clock.** The fragment (repeated ``repetitions`` times) is
scaled onto ``[stroke_start, stroke_end]``. Per arm: a :class:`WristPositionLMP` through
the location breakpoints (its preparation arrives at the first at ``ready``), a
:class:`WristRotationLMP` through hand rotations composed from fingers and palm (an arm
whose location is constrained but not its orientation gets :data:`NEUTRAL_FINGERS`
with the palm toward the body's midline), a :class:`HandShapeLMP`. Each starts at
``start`` and holds its last value until ``relax``, where a :class:`RetractionLMP` per
channel takes the arm back to rest (or the interim rest when another gesture follows)
in :func:`retraction_duration`. The swivel is left to the arm IK's natural swivel.

Non-arm slots (gaze, head, face …) are not realized by the motor programs; a warning
names them.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace

import numpy as np

from motor.arm.hand_orientation import hand_rotations_from_vectors
from motor.arm.ik import solve_arm
from motor.arm.wrist_position import WristPositionLMP
from motor.arm.wrist_rotation import WristRotationLMP
from motor.body.avatar import ARMS, AVATAR_SIDE, Avatar
from motor.body.collision import outside_torso
from motor.hand.lmp import HandShapeLMP
from motor.hand.shape import handshape_params
from motor.program.fragment import (
    SAME_TIME,
    Compiler,
    Fragment,
    PointTarget,
    curved_into,
    first_location,
    timed_values,
    unit_vector,
    value_at,
)
from motor.program.lmp import LMP, RetractionLMP, TimePegs
from motor.quaternion import between_vectors, continuous, rotate
from motor.trajectory.spline import fitts_duration, plan_wrist_trajectory
from mura.model import BehaviorSpec
from mura.values import FingerBend, HandShape, PalmOrientation

#: Shortest retraction, seconds (Fitts' law gives less for tiny distances).
MIN_RETRACTION = 0.3
#: Shortest stroke interval for a moving stroke; a shorter one is widened (warning).
MIN_STROKE = 0.02
#: Shortest preparation; a later ``start`` is moved back to leave this much (warning).
MIN_PREPARATION = 1e-3
#: Extended-finger direction of an arm whose orientation is not constrained: forward.
NEUTRAL_FINGERS = np.array([0.0, 0.0, 1.0])
#: The relaxed hand: this fraction of the way from the flat hand to the rounded one.
REST_CURL = 0.3
#: How far (m) the IK may fall short of a planned location before it is moved in reach.
REACH_TOLERANCE = 1e-3





@dataclass(frozen=True)
class GestureDemands:
    """What the scheduler must know about a gesture before timing it.

    Attributes:
        arms: ``{"right"}``, ``{"left"}``, both, or empty (no arm moves).
        stroke_duration: natural stroke duration, seconds; 0 for a held posture.
        dynamic: the stroke moves.
        repeatable: the stroke can be performed again to fill a longer affiliate.
        preparation_distance: metres from the rest position to the stroke's start (the
            farthest of the arms used).
        first_wrists, last_wrists: per arm, where the wrist is when the stroke starts and
            ends (avatar frame, metres); arms whose location is unconstrained are absent.
            The scheduler times a preparation from one stroke's end to the next with them.
        stroke_distance: metres the wrist travels in one performance of the stroke (the
            farthest-travelling arm); with ``manner`` it bounds how fast the stroke may be.
        manner: the movement manner whose speed budget
            (``motor.trajectory.speed_budget.budget``) bounds the preparation and stroke.
        repetition_return: natural seconds from the stroke's end back to its start, what
            each repetition beyond the first adds besides the stroke itself.
    """

    arms: frozenset[str]
    stroke_duration: float
    dynamic: bool
    repeatable: bool
    preparation_distance: float
    first_wrists: Mapping[str, tuple[float, float, float]] = field(default_factory=dict)
    last_wrists: Mapping[str, tuple[float, float, float]] = field(default_factory=dict)
    stroke_distance: float = 0.0
    manner: str | None = None
    repetition_return: float = 0.0


@dataclass(frozen=True, eq=False)
class MotorProgram:
    """A planned gesture: its LMPs on every channel it uses, and what planning changed.

    ``pegs`` are the scheduler's pegs with ``end`` replaced by the end of the retraction
    (and ``start``/``stroke_end`` moved when a rule had to widen them, see warnings).
    """

    behavior: str
    lmps: tuple[LMP, ...]
    warnings: tuple[str, ...]
    pegs: TimePegs
    arms: frozenset[str]














def retraction_duration(distance: float) -> float:
    """Seconds to retract the wrist over ``distance`` metres: Fitts' law, at least
    :data:`MIN_RETRACTION`."""
    return max(MIN_RETRACTION, float(fitts_duration(distance)))


def rest_handshape() -> np.ndarray:
    """Hand parameters of the relaxed hand at rest (see :data:`REST_CURL`)."""
    flat = handshape_params(HandShape("flathand"))
    fingers = ("index", "middle", "ring", "pinky")
    rounded = handshape_params(HandShape("flathand", finger_bends=(FingerBend(fingers, "round"),)))
    return (1.0 - REST_CURL) * flat + REST_CURL * rounded






















# -- from a fragment to LMPs ------------------------------------------------------------






@dataclass(frozen=True, eq=False)
class Planner:
    """Plans gestures into motor programs for one avatar."""

    avatar: Avatar

    def fragment(self, behavior: BehaviorSpec) -> Fragment:
        if behavior.gesture is None:
            return Fragment(0.0, {}, (f"{behavior.id}: {behavior.kind} behaviour has no gesture to plan",))
        return Compiler(self.avatar, behavior.id).compile(behavior.gesture.constraints, {})

    def rest_wrist(self, arm: str, posture: str = "rest") -> np.ndarray:
        return np.asarray(self.avatar.postures[posture][AVATAR_SIDE[arm]].wrist, dtype=float)

    def demands(self, behavior: BehaviorSpec) -> GestureDemands:
        """Arms, natural stroke duration and preparation distance of a behaviour's gesture."""
        fragment = self.fragment(behavior)
        arms = frozenset(arm for arm, _ in fragment.tracks)
        distance = max(
            (float(np.linalg.norm(np.asarray(first_location(fragment, arm)) - self.rest_wrist(arm))) for arm in arms
             if first_location(fragment, arm) is not None),
            default=0.0,
        )  # fmt: skip
        dynamic = fragment.duration > 0.0
        paths = {arm: np.asarray([key.value for key in keys], dtype=float)
                 for (arm, feature), keys in fragment.tracks.items() if feature == "location" and keys}
        return GestureDemands(
            arms, fragment.duration, dynamic, dynamic, distance,
            first_wrists={arm: tuple(path[0]) for arm, path in paths.items()},
            last_wrists={arm: tuple(path[-1]) for arm, path in paths.items()},
            stroke_distance=max((float(np.sum(np.linalg.norm(np.diff(path, axis=0), axis=1))) for path in paths.values()), default=0.0),
            repetition_return=Compiler(self.avatar, behavior.id).transition(fragment, fragment) if dynamic else 0.0,
        )

    def plan(
        self, behavior: BehaviorSpec, pegs: TimePegs, repetitions: int = 1, next_gesture_follows: bool = False
    ) -> MotorProgram:
        """The motor program of ``behavior`` on ``pegs`` (see the module docstring)."""
        compiler = Compiler(self.avatar, behavior.id)
        fragment = self.fragment(behavior)
        if repetitions != 1:
            fragment = compiler.repeat(fragment, repetitions)
        notes = list(fragment.warnings)
        pegs = self.usable_pegs(behavior.id, pegs, fragment.duration > 0.0, notes)
        stroke = fragment.placed(pegs.stroke_start, pegs.stroke_end - pegs.stroke_start)
        arms = sorted({arm for arm, _ in stroke.tracks}, key=ARMS.index)
        lmps: list[LMP] = []
        retraction = 0.0
        posture = "interim_rest" if next_gesture_follows else "rest"
        for arm in arms:
            arm_lmps, last_wrist = self.arm_lmps(compiler, stroke, arm, pegs, notes)
            lmps.extend(arm_lmps)
            distance = 0.0 if last_wrist is None else float(np.linalg.norm(last_wrist - self.rest_wrist(arm, posture)))
            retraction = max(retraction, retraction_duration(distance))
        end = pegs.relax + retraction if arms else pegs.relax
        retract = TimePegs.movement(pegs.relax, end)
        lmps.extend([self.retraction(lmp.channel, retract, posture) for lmp in lmps])
        final = replace(pegs, end=end)
        return MotorProgram(behavior.id, tuple(lmps), tuple(notes), final, frozenset(arms))

    def usable_pegs(self, behavior: str, pegs: TimePegs, dynamic: bool, notes: list[str]) -> TimePegs:
        """The scheduler's pegs, widened by the documented rules where they cannot work."""
        if pegs.ready - pegs.start < MIN_PREPARATION:
            notes.append(f"{behavior}: no time for the preparation (start {pegs.start:.3f} s, ready {pegs.ready:.3f} s); starting {MIN_PREPARATION} s earlier")
            pegs = replace(pegs, start=pegs.ready - MIN_PREPARATION)
        if dynamic and pegs.stroke_end - pegs.stroke_start < MIN_STROKE:
            stroke_end = pegs.stroke_start + MIN_STROKE
            notes.append(f"{behavior}: stroke interval of {pegs.stroke_end - pegs.stroke_start:.3f} s too short for a movement; widened to {MIN_STROKE} s")
            pegs = replace(
                pegs, stroke=min(max(pegs.stroke, pegs.stroke_start), stroke_end), stroke_end=stroke_end,
                relax=max(pegs.relax, stroke_end), end=max(pegs.end, stroke_end),
            )  # fmt: skip
        return pegs

    def within_reach(self, behavior: str, arm: str, points: np.ndarray, notes: list[str]) -> np.ndarray:
        """``points`` with those inside the torso pushed out in front of it and those the arm
        cannot reach moved to the nearest it can (warnings)."""
        clear = outside_torso(self.avatar, points)
        moved = np.any(clear != points, axis=1)
        if np.any(moved):
            notes.append(
                f"{behavior}: {int(np.sum(moved))} location(s) of the {arm} hand inside the torso by up to "
                f"{float(np.max(np.abs(clear - points))):.3f} m; moved in front of it"
            )
            points = clear
        solution = solve_arm(self.avatar, AVATAR_SIDE[arm], points)
        short = solution.shortfall > REACH_TOLERANCE
        if not np.any(short):
            return points
        notes.append(
            f"{behavior}: {int(np.sum(short))} location(s) of the {arm} hand out of reach by up to "
            f"{float(np.max(solution.shortfall)):.3f} m; moved to the nearest reachable point"
        )
        return np.where(short[:, None], solution.wrist, points)

    def arm_lmps(
        self, compiler: Compiler, stroke: Fragment, arm: str, pegs: TimePegs, notes: list[str]
    ) -> tuple[list[LMP], np.ndarray | None]:
        """The stroke LMPs of one arm, and its wrist position at the end of the stroke."""
        held = replace(pegs, end=pegs.relax)
        lmps: list[LMP] = []
        locations = stroke.tracks.get((arm, "location"), ())
        last_wrist = None
        if locations:
            times, values = timed_values(locations)
            curved_flags = tuple(curved_into(locations, t) for t in times[1:])
            points = self.within_reach(compiler.behavior, arm, np.array([np.asarray(v, dtype=float) for v in values]), notes)
            if len(points) > 1:
                notes.extend(f"{compiler.behavior}: {note}" for note in plan_wrist_trajectory(points, np.array(times), curved=curved_flags).warnings)
            lmps.append(WristPositionLMP(arm, held, points, np.array(times), curved_flags))
            last_wrist = points[-1]
        shapes = stroke.tracks.get((arm, "shape"), ())
        if shapes:
            times, values = self.prepared(timed_values(shapes), pegs.ready)
            lmps.append(HandShapeLMP(arm, held, np.array(values), np.array(times)))
        rotations = self.rotation_keys(compiler, stroke, arm, pegs.ready)
        if rotations is not None:
            times, values = rotations
            lmps.append(WristRotationLMP(arm, held, values, times))
        return lmps, last_wrist

    @staticmethod
    def prepared(timed: tuple[list[float], list[object]], ready: float) -> tuple[list[float], list[object]]:
        """Keys with the first value reached at ``ready`` (the end of the preparation)."""
        times, values = timed
        if times[0] - ready > SAME_TIME:
            return [ready, *times], [values[0], *values]
        return times, values

    def rotation_keys(self, compiler: Compiler, stroke: Fragment, arm: str, ready: float) -> tuple[np.ndarray, np.ndarray] | None:
        """Hand rotation keys composed from the fingers and palm tracks, or None when the
        arm's orientation and location are both unconstrained."""
        fingers = stroke.tracks.get((arm, "fingers"), ())
        palms = stroke.tracks.get((arm, "palm"), ())
        locations = stroke.tracks.get((arm, "location"), ())
        if not (fingers or palms or locations):
            return None
        times = sorted({t for keys in (fingers, palms) for t in timed_values(keys)[0]} or {locations[0].start})
        merged: list[float] = []
        for t in times:
            if not merged or t - merged[-1] > SAME_TIME:
                merged.append(t)
        inward = np.array([1.0 if arm == "right" else -1.0, 0.0, 0.0])
        finger_vectors, palm_vectors = [], []
        for t in merged:
            wrist = np.asarray(value_at(locations, t), dtype=float) if locations else compiler.shoulder(arm)
            finger = value_at(fingers, t) if fingers else NEUTRAL_FINGERS
            if isinstance(finger, PointTarget):
                finger = unit_vector(
                    np.asarray(finger.point) - wrist, compiler.error("pointTo target lies at the wrist", None)
                )
            palm = value_at(palms, t) if palms else PalmOrientation(tuple(inward))
            direction = np.asarray(palm.direction, dtype=float)
            if palm.relative:
                direction = rotate(between_vectors(np.array([0.0, 0.0, 1.0]), np.asarray(finger)), direction)
            finger_vectors.append(np.asarray(finger, dtype=float))
            palm_vectors.append(direction)
        quaternions = hand_rotations_from_vectors(self.avatar, AVATAR_SIDE[arm], np.array(finger_vectors), np.array(palm_vectors))
        quaternions = continuous(quaternions)
        key_times, key_values = self.prepared((merged, list(quaternions)), ready)
        return np.array(key_times), np.array(key_values)

    def retraction(self, channel: tuple[str, str], pegs: TimePegs, posture: str) -> RetractionLMP:
        return retraction_lmp(self.avatar, channel, pegs, posture)


def retraction_lmp(avatar: Avatar, channel: tuple[str, str], pegs: TimePegs, posture: str) -> RetractionLMP:
    """The LMP taking ``channel`` back to the avatar's ``posture`` (``rest`` or ``interim_rest``)."""
    arm, name = channel
    rest = avatar.postures[posture][AVATAR_SIDE[arm]]
    target = {"wrist_position": rest.wrist, "hand_rotation": rest.hand_rotation}.get(name)
    return RetractionLMP(channel, pegs, rest_handshape() if target is None else np.asarray(target, dtype=float))






