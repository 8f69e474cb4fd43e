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

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, fields, replace

import numpy as np

from motor.arm.hand_orientation import hand_rotations_from_vectors
from motor.arm.wrist_path import followable, uncrowded_placement
from motor.arm.wrist_retraction import WristRetractionLMP
from motor.arm.wrist_position import WristPositionLMP, preparation_timing
from motor.arm.wrist_rotation import HandRetractionLMP, WristRotationLMP
from motor.body.avatar import Avatar
from motor.body.conventions import ARMS, AVATAR_SIDE
from motor.hand.lmp import HandShapeLMP
from motor.hand.shape import handshape_params
from motor.program.fragment import (
    SAME_TIME,
    Compiler,
    Fragment,
    PointTarget,
    first_location,
    timed_values,
    unit_vector,
    value_at,
)
from motor.program.lmp import LMP, ChannelState, RetractionLMP, TimePegs
from motor.quaternion import between_vectors, continuous, rotate
from motor.trajectory.speed_budget import CEILING, SpeedBudget, budget
from motor.trajectory.spline import HOLD_LENGTH, WristTrajectory, fitts_duration, plan_wrist_trajectory, stretch_factor
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
#: A location this far (m) out of reach or more is reported when it is moved into reach
#: (closer ones are rounding and are moved silently).
NOTICEABLE_SHORTFALL = 1e-3
#: The manner whose speed budget (:mod:`motor.trajectory.speed_budget`) MURML gestures keep.
GESTURE_MANNER = "targetted"
#: Rounds of lengthening a stroke until it is within its budget (the second rarely acts).
_STRETCH_ROUNDS = 3
_PEG_NAMES = tuple(f.name for f in fields(TimePegs))
#: Excess over a limit below this fraction is rounding.
_ROUNDING = 1e-6





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
class WristPath:
    """One arm's stroke path: breakpoints ``(n, 3)`` (metres), their times ``(n,)`` (s) and
    the trajectory through them (None for a single location)."""

    points: np.ndarray
    times: np.ndarray
    trajectory: WristTrajectory | None

    def stretched(self, origin: float, factor: float) -> WristPath:
        """The path timed ``factor`` times slower about ``origin`` (the trajectory planned
        anew on those times)."""
        times = origin + (self.times - origin) * factor
        return WristPath(self.points, times, None if self.trajectory is None else unlimited(self.points, times))

    def shifted(self, delay: float) -> WristPath:
        """The path ``delay`` seconds later."""
        return WristPath(self.points, self.times + delay, None if self.trajectory is None else self.trajectory.shifted(delay))


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














def unlimited(points: np.ndarray, times: np.ndarray) -> WristTrajectory:
    """The wrist trajectory through ``points`` at ``times`` as they are: the planner keeps
    it within its limits itself (:meth:`Planner.within_budget`)."""
    return plan_wrist_trajectory(points, times, max_speed=np.inf)


def retraction_duration(distance: float) -> float:
    """Seconds to retract the wrist over ``distance`` metres: Fitts' law, at least
    :data:`MIN_RETRACTION`, and long enough to stay within the lax manner's speed budget."""
    return max(MIN_RETRACTION, float(fitts_duration(distance)), budget("lax").shortest_duration(distance))


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
        self,
        behavior: BehaviorSpec,
        pegs: TimePegs,
        repetitions: int = 1,
        next_gesture_follows: bool = False,
        start_states: Mapping[str, ChannelState] | None = None,
    ) -> MotorProgram:
        """The motor program of ``behavior`` on ``pegs`` (see the module docstring).

        ``start_states`` are the arms' wrist states (position and velocity) at
        ``pegs.start`` (default: still in the rest posture), from which the pre-stroke hold
        is reckoned.
        """
        compiler = Compiler(self.avatar, behavior.id)
        fragment = self.fragment(behavior)
        if repetitions != 1:
            fragment = compiler.repeat(fragment, repetitions)
        notes = list(fragment.warnings)
        pegs = self.usable_pegs(behavior.id, pegs, fragment.duration > 0.0, notes)
        tentative = fragment.placed(pegs.stroke_start, pegs.stroke_end - pegs.stroke_start)
        arms = sorted({arm for arm, _ in tentative.tracks}, key=ARMS.index)
        paths = {arm: self.stroke_path(behavior.id, tentative, arm, notes) for arm in arms}
        pegs, paths = self.within_budget(behavior.id, paths, pegs, start_states or {}, notes)
        stroke = fragment.placed(pegs.stroke_start, pegs.stroke_end - pegs.stroke_start)
        lmps: list[LMP] = []
        retraction = 0.0
        posture = "interim_rest" if next_gesture_follows else "rest"
        for arm in arms:
            lmps.extend(self.arm_lmps(compiler, stroke, arm, pegs, paths[arm]))
            last_wrist = None if paths[arm] is None else paths[arm].points[-1]
            distance = 0.0 if last_wrist is None else float(np.linalg.norm(last_wrist - self.rest_wrist(arm, posture)))
            retraction = max(retraction, retraction_duration(distance))
        end = pegs.relax + retraction if arms else pegs.relax
        retract = TimePegs.movement(pegs.relax, end)
        lmps.extend([self.retraction(lmp.channel, retract, posture) for lmp in lmps])
        final = replace(pegs, end=end)
        return MotorProgram(behavior.id, tuple(lmps), tuple(notes), final, frozenset(arms))

    def stroke_path(self, behavior: str, stroke: Fragment, arm: str, notes: list[str]) -> WristPath | None:
        """The wrist path of ``arm``'s stroke as placed in ``stroke``: its locations moved out
        of the torso and into reach, the curve between them kept where the arm can follow it
        (:mod:`motor.arm.wrist_path`; warnings), and its trajectory; None when the arm's
        location is unconstrained."""
        locations = stroke.tracks.get((arm, "location"), ())
        if not locations:
            return None
        times, values = timed_values(locations)
        points = np.array([np.asarray(v, dtype=float) for v in values])
        points = self.within_reach(behavior, arm, points, notes, self.touching(stroke, arm, times, points))
        if len(times) < 2:
            return WristPath(points, np.array(times), None)
        points, times, replaced = followable(self.avatar, AVATAR_SIDE[arm], points, np.array(times))
        if replaced:
            notes.append(
                f"{behavior}: the {arm} hand's path left the reach or entered the torso between its "
                f"locations in {replaced} movement(s); kept where the arm can follow it"
            )
        return WristPath(points, times, unlimited(points, times))

    def within_budget(
        self,
        behavior: str,
        paths: Mapping[str, WristPath | None],
        pegs: TimePegs,
        start_states: Mapping[str, ChannelState],
        notes: list[str],
    ) -> tuple[TimePegs, dict[str, WristPath | None]]:
        """The pegs kept, or the stroke lengthened as little as the speed ceiling needs; the
        preparation's arrival (``ready``) before the pre-stroke hold; and the paths retimed
        to match.

        The scheduler has already relaxed the timing to :data:`GESTURE_MANNER`'s budget
        (``GestureDemands.manner``; preparations from where the arm will be, which it knows
        better than the motor control before the chunk's earlier gestures are activated),
        so its pegs are kept as long as the stroke stays below the absolute ceiling
        (:data:`motor.trajectory.speed_budget.CEILING`); a stroke that would exceed it is
        lengthened. A stroke that keeps the pegs but exceeds the manner's budget (the timing
        could not be relaxed enough, or the budget's minimum-jerk estimate falls short of
        what the path's stops and curves need) is reported. Either is one warning per
        behaviour, with the amounts. A preparation is kept below the ceiling when it is
        activated (:class:`motor.arm.wrist_position.WristPositionLMP`). Both arms share the
        pre-stroke hold (the shorter of theirs); a stroke whose wrists do not move has none:
        the hand's arrival is its onset."""
        limits = budget(GESTURE_MANNER)
        changes: list[str] = []
        moving = {arm: path for arm, path in paths.items() if path is not None}
        origin = pegs.stroke_start
        factor = max((self.stroke_stretch(path, CEILING) for path in moving.values()), default=1.0)
        if factor > 1.0:
            length = pegs.stroke_end - pegs.stroke_start
            stroke_end = pegs.stroke_start + factor * length
            changes.append(f"the stroke needs {factor * length:.3f} s instead of {length:.3f} s; it ends {stroke_end - pegs.stroke_end:.3f} s later")
            relax = max(pegs.relax, stroke_end)
            pegs = replace(
                pegs, stroke=pegs.stroke_start + factor * (pegs.stroke - pegs.stroke_start), stroke_end=stroke_end,
                relax=relax, end=max(pegs.end, relax + pegs.end - pegs.relax),
            )  # fmt: skip
            moving = {arm: path.stretched(origin, factor) for arm, path in moving.items()}
        over = [path.trajectory for path in moving.values() if path.trajectory is not None]
        if over and max(stretch_factor(t, limits.peak_speed, limits.peak_acceleration) for t in over) > 1.0 + _ROUNDING:
            speed, acceleration = max(t.peak_speed() for t in over), max(t.peak_acceleration() for t in over)
            changes.append(f"the stroke peaks at {speed:.2f} m/s and {acceleration:.1f} m/s² in its {pegs.stroke_end - pegs.stroke_start:.3f} s")
        window = pegs.stroke_start - pegs.start
        states = {arm: start_states.get(arm) or ChannelState.at_rest(self.rest_wrist(arm), pegs.start) for arm in moving}
        if changes:
            notes.append(
                f"{behavior}: over the {GESTURE_MANNER} speed budget ({limits.peak_speed} m/s, {limits.peak_acceleration} m/s²) "
                f"in the time given, kept below {CEILING.peak_speed} m/s and {CEILING.peak_acceleration} m/s²: " + "; ".join(changes)
            )
        holds = [preparation_timing(float(np.linalg.norm(path.points[0] - states[arm].value)), window)[1] for arm, path in moving.items()]
        if any(float(np.ptp(path.points, axis=0).max()) > HOLD_LENGTH for path in moving.values()) and holds and min(holds) > 0.0:
            pegs = replace(pegs, ready=pegs.stroke_start - min(holds))
        return pegs, {arm: moving.get(arm) for arm in paths}

    @staticmethod
    def stroke_stretch(path: WristPath, limits: SpeedBudget) -> float:
        """How much longer (≥ 1) a stroke must last to stay within ``limits``."""
        if path.trajectory is None:
            return 1.0
        factor = 1.0
        trajectory = path.trajectory
        for _ in range(_STRETCH_ROUNDS):
            step = stretch_factor(trajectory, limits.peak_speed, limits.peak_acceleration)
            if step <= 1.0 + 1e-6:
                break
            factor *= step * (1.0 + 1e-6)
            trajectory = path.stretched(path.times[0], factor).trajectory
        return factor

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

    def touching(self, stroke: Fragment, arm: str, times: Sequence[float], points: np.ndarray) -> np.ndarray:
        """Which of ``arm``'s locations at ``times`` the other hand touches at the same
        instant (its wrist within a palm thickness and a millimetre)."""
        other = stroke.tracks.get((next(a for a in ARMS if a != arm), "location"), ())
        if not other:
            return np.zeros(len(points), dtype=bool)
        other_times, other_values = timed_values(other)
        near = np.zeros(len(points), dtype=bool)
        for time, value in zip(other_times, other_values):
            same = np.abs(np.asarray(times) - time) < SAME_TIME
            near |= same & (np.linalg.norm(points - np.asarray(value, dtype=float), axis=1) <= self.avatar.collision.palm_thickness + 1e-3)
        return near

    def within_reach(self, behavior: str, arm: str, points: np.ndarray, notes: list[str], kept: np.ndarray | None = None) -> np.ndarray:
        """``points`` with those inside the torso pushed out in front of it, those the arm
        cannot reach moved to the nearest it can, and those the arm reaches only through the
        body moved forward, but for ``kept`` (:func:`motor.arm.wrist_path.uncrowded_placement`;
        warnings)."""
        placement = uncrowded_placement(self.avatar, AVATAR_SIDE[arm], points, kept)
        if placement.inside:
            notes.append(
                f"{behavior}: {placement.inside} location(s) of the {arm} hand inside the torso by up to "
                f"{placement.depth:.3f} m; moved in front of it"
            )
        if placement.crowded:
            notes.append(
                f"{behavior}: {placement.crowded} location(s) of the {arm} hand the arm reaches only through the body "
                f"(up to {placement.crowding:.3f} m deep); moved forward"
            )
        if placement.short and placement.shortfall >= NOTICEABLE_SHORTFALL:
            notes.append(
                f"{behavior}: {placement.short} location(s) of the {arm} hand out of reach by up to "
                f"{placement.shortfall:.3f} m; moved to the nearest reachable point"
            )
        return placement.points

    def arm_lmps(self, compiler: Compiler, stroke: Fragment, arm: str, pegs: TimePegs, path: WristPath | None) -> list[LMP]:
        """The stroke LMPs of one arm; ``path`` its wrist path (or None)."""
        held = replace(pegs, end=pegs.relax)
        lmps: list[LMP] = []
        if path is not None:
            lmps.append(WristPositionLMP(arm, held, path.points, path.times, stroke=path.trajectory, avatar=self.avatar))
        shapes = stroke.tracks.get((arm, "shape"), ())
        if shapes:
            times, values = self.prepared(timed_values(shapes), pegs.ready)
            lmps.append(HandShapeLMP(arm, held, np.array(values), np.array(times)))
        rotations = self.rotation_keys(compiler, stroke, arm, pegs.ready)
        if rotations is not None:
            times, values = rotations
            lmps.append(WristRotationLMP(arm, held, values, times))
        return lmps

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
    """The LMP taking ``channel`` back to the avatar's ``posture`` (``rest`` or
    ``interim_rest``); the wrist's way bows around the body where the straight way would
    crowd the arm (:class:`motor.arm.wrist_retraction.WristRetractionLMP`), and the hand
    turns the way of least cost (:class:`motor.arm.wrist_rotation.HandRetractionLMP`)."""
    arm, name = channel
    rest = avatar.postures[posture][AVATAR_SIDE[arm]]
    if name == "wrist_position":
        return WristRetractionLMP(channel, pegs, np.asarray(rest.wrist, dtype=float), avatar=avatar)
    if name == "hand_rotation":
        return HandRetractionLMP(channel, pegs, np.asarray(rest.hand_rotation, dtype=float), avatar=avatar)
    return RetractionLMP(channel, pegs, rest_handshape())






