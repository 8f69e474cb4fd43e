"""Motor programs: a gesture's constraint tree planned into LMPs for each arm (seed 004, 4).

Planning runs in two steps.

**1. The stroke in its own time.** The constraint tree is compiled bottom-up into a
*fragment*: for every ``(arm, feature)`` — features ``location`` (wrist position),
``shape`` (hand parameters), ``fingers`` (extended-finger direction) and ``palm`` — a
list of keys ``(start, end, value)`` on a local clock ``[0, D]``, the value reached at
``start`` and held until ``end``; ``D`` is the fragment's *natural duration*:

* ``static``: one key at 0, duration 0; placed in a longer interval it holds throughout.
* ``dynamic``: keys at the segments' breakpoints. A ``HandLocation`` segment is linear
  from start to end, or from start along ``direction`` for ``distance`` metres; curves
  come from :func:`motor.guiding_strokes.curve_breakpoints`, circles from
  :func:`motor.guiding_strokes.circle_from_start`; a segment without a start starts
  where the previous one ended (or, with nothing before it, at the arm's neutral
  gesture position, with a warning). Other slots key their start and end values.
  Segment durations: :func:`movement_time` — the biocontrol duration of the movement
  kind and manner (0.4 s straight, ×1.3 curved, ×1.7 circle), or the path length at
  the comfortable mean speed :data:`COMFORTABLE_SPEED`, whichever is longer; the
  breakpoints inside a segment are timed by the power law
  (:func:`motor.trajectory.time_breakpoints`).
* ``parallel``: children share the interval; each is stretched to the longest.
* ``sequence``: children follow one another with a *transition* between them — the time
  to move every feature from the previous child's last value to the next child's first
  (:func:`movement_time` for the wrist, :data:`SHAPE_CHANGE` for the hand shape, the
  turning angle at :data:`ANGULAR_SPEED` for orientations, at least
  :data:`MIN_TURN`). Static hand locations in a sequence thus become successive
  breakpoints passed through by one fluent guiding-stroke trajectory.
* ``repetition``: the child ``count`` times, with a return transition between passes
  (``fromstart``); ``continue`` shifts each pass by the previous pass's displacement;
  ``reverse`` runs every other pass backwards. ``alternating`` is not realized (warning).
* ``symmetrical``: the child's constraints on the dominant arm are mirrored onto the
  other arm unless the child constrains that arm's feature itself: positions across
  the symmetry's planes, directions and palm normals likewise, hand shapes unchanged.
  The sagittal plane (``S``) is the body's mid-sagittal plane ``x = 0``. The transversal
  (``T``) and frontal (``F``) planes pass through the spec's ``center`` when it gives
  one, read as millimetres (the seed dialect's unit) with the height measured from the
  floor (the avatar's ``root_height`` is subtracted); otherwise through the dominant
  hand's mean stroke position. Only the first three numbers of a center are used.

A location out of the arm's reach (the IK falls short by more than :data:`REACH_TOLERANCE`)
is replaced by the nearest point the arm reaches, with a warning; a stroke too fast for
the wrist (above :data:`motor.trajectory.MAX_WRIST_SPEED`) is slowed by the trajectory
planner, and the warning is carried into the program.

``mode="pointTo"`` with a point: the wrist goes on the line from the shoulder toward
the point at :data:`POINTING_REACH` of the arm's length, and the fingers point from the
wrist to the point.

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

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, replace

import numpy as np

from motor.arm_ik import solve_arm
from motor.avatar import Avatar
from motor.biocontrol import MANNERS, movement_duration
from motor.guiding_strokes import circle_from_start, curve_breakpoints
from motor.hand import handshape_params
from motor.hand_orientation import hand_rotations_from_vectors
from motor.lmp import (
    LMP,
    HandShapeLMP,
    RetractionLMP,
    TimePegs,
    WristPositionLMP,
    WristRotationLMP,
)
from motor.locations import resolve_location
from motor.quaternion import between_vectors, continuous, rotate
from motor.symmetry import mirror_directions, mirror_points
from motor.torso import outside_torso
from motor.trajectory import fitts_duration, plan_wrist_trajectory, time_breakpoints
from mura.errors import SourceLocation, SpecError
from mura.model import (
    Arm,
    BehaviorSpec,
    Constraint,
    Dynamic,
    Parallel,
    Repetition,
    Segment,
    SegmentKind,
    Sequence,
    Static,
    Symmetrical,
    Symmetry,
)
from mura.values import (
    Direction,
    FingerBend,
    GridLocation,
    HandShape,
    PalmOrientation,
    PointLocation,
)

#: The arms, as the scheduler names them, and the avatar's side prefixes.
ARMS: tuple[str, ...] = ("right", "left")
AVATAR_SIDE: dict[str, str] = {"right": "r", "left": "l"}

#: Comfortable mean wrist speed of a stroke, m/s: long strokes take length / this.
COMFORTABLE_SPEED = 0.5
#: Time for a change of hand shape between two keys, seconds.
SHAPE_CHANGE = 0.3
#: Turning speed of the hand between orientation keys, rad/s, and the shortest turn, s.
ANGULAR_SPEED = 3.0
MIN_TURN = 0.2
#: Fraction of the arm's length at which a pointing hand is held toward its target.
POINTING_REACH = 0.75
#: Shortest retraction, seconds (Fitts' law gives less for tiny distances).
MIN_RETRACTION = 0.3
#: Shortest stroke interval for a moving stroke; a shorter one is widened (warning).
MIN_STROKE = 0.02
#: Shortest preparation; a later ``start`` is moved back to leave this much (warning).
MIN_PREPARATION = 1e-3
#: Extended-finger direction of an arm whose orientation is not constrained: forward.
NEUTRAL_FINGERS = np.array([0.0, 0.0, 1.0])
#: Neutral gesture position (grid) of the right hand, for a path with no start.
NEUTRAL_LOCATION = GridLocation("LocChest", "LocCCenterRight", "LocNorm")
#: The relaxed hand: this fraction of the way from the flat hand to the rounded one.
REST_CURL = 0.3
#: How far (m) the IK may fall short of a planned location before it is moved in reach.
REACH_TOLERANCE = 1e-3
#: Closest two key times may be and still count as distinct, seconds.
_SAME_TIME = 1e-9
_SAME_PLACE = 1e-4
_MM = 0.001

_FEATURES = {"HandLocation": "location", "HandShape": "shape", "ExtFingerOrientation": "fingers", "PalmOrientation": "palm"}
_MANNER_SYNONYMS = {"rest": "lax", "halt": "sudden_stop"}


class PlanningError(ValueError):
    """A gesture that cannot be planned; the message names the behaviour and the constraint."""


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
    """

    arms: frozenset[str]
    stroke_duration: float
    dynamic: bool
    repeatable: bool
    preparation_distance: float


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


@dataclass(frozen=True)
class PointTarget:
    """A ``pointTo`` value: a point in the avatar frame, metres."""

    point: tuple[float, float, float]


@dataclass(frozen=True, eq=False)
class _Key:
    """A feature value reached at ``start`` and held until ``end`` (local seconds).

    ``curved`` marks a location reached along a curve (for the breakpoint-speed gain).
    """

    start: float
    end: float
    value: object
    curved: bool = False


Track = tuple[str, str]


@dataclass(frozen=True, eq=False)
class _Fragment:
    """Keys per ``(arm, feature)`` over a local clock ``[0, duration]``."""

    duration: float
    tracks: Mapping[Track, tuple[_Key, ...]]
    warnings: tuple[str, ...] = ()

    def placed(self, offset: float, length: float) -> _Fragment:
        """The fragment stretched onto ``[offset, offset + length]``; a zero-duration
        fragment (static keys) holds over the whole interval."""
        scale = length / self.duration if self.duration > 0.0 else 0.0

        def move(key: _Key) -> _Key:
            if self.duration <= 0.0:
                return replace(key, start=offset, end=offset + length)
            return replace(key, start=offset + key.start * scale, end=offset + key.end * scale)

        tracks = {track: tuple(move(key) for key in keys) for track, keys in self.tracks.items()}
        return _Fragment(length, tracks, self.warnings)

    def last(self, track: Track) -> object | None:
        keys = self.tracks.get(track)
        return keys[-1].value if keys else None

    def first(self, track: Track) -> object | None:
        keys = self.tracks.get(track)
        return keys[0].value if keys else None

    def mapped(self, track: Track, change: Callable[[_Key], _Key]) -> _Fragment:
        tracks = dict(self.tracks)
        tracks[track] = tuple(change(key) for key in tracks[track])
        return _Fragment(self.duration, tracks, self.warnings)


def _merge(fragments: Iterable[_Fragment], duration: float, warnings: Iterable[str] = ()) -> _Fragment:
    tracks: dict[Track, list[_Key]] = {}
    notes = list(warnings)
    for fragment in fragments:
        notes.extend(fragment.warnings)
        for track, keys in fragment.tracks.items():
            tracks.setdefault(track, []).extend(keys)
    ordered = {track: tuple(sorted(keys, key=lambda k: k.start)) for track, keys in tracks.items()}
    return _Fragment(duration, ordered, tuple(notes))


def movement_time(length: float, kind: str = "straight", manner: str | None = None) -> float:
    """Natural duration (s) of a wrist movement of ``length`` metres.

    The longer of the biocontrol duration of the movement kind in its manner (seed 000)
    and the time at :data:`COMFORTABLE_SPEED`; 0 for no movement.
    """
    if length < _SAME_PLACE:
        return 0.0
    name = _MANNER_SYNONYMS.get(manner or "targetted", manner or "targetted")
    base = movement_duration(kind, name if name in MANNERS else "targetted")
    return max(base, length / COMFORTABLE_SPEED)


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


class _Compiler:
    """Compiles one gesture's constraint tree into a fragment for one avatar."""

    def __init__(self, avatar: Avatar, behavior: str) -> None:
        self.avatar = avatar
        self.behavior = behavior

    def error(self, message: str, where: SourceLocation | None) -> PlanningError:
        place = f" ({where})" if where is not None else ""
        return PlanningError(f"behaviour {self.behavior!r}{place}: {message}")

    # -- tree -------------------------------------------------------------------------

    def compile(self, node: Constraint, origin: Mapping[str, np.ndarray]) -> _Fragment:
        if isinstance(node, Static):
            return self.static(node)
        if isinstance(node, Dynamic):
            return self.dynamic(node, origin)
        if isinstance(node, Parallel):
            return self.parallel(node, origin)
        if isinstance(node, Sequence):
            return self.sequence(node.children, origin)
        if isinstance(node, Repetition):
            return self.repetition(node, origin)
        if isinstance(node, Symmetrical):
            return self.symmetrical(node, origin)
        raise self.error(f"unknown constraint {type(node).__name__}", None)

    def parallel(self, node: Parallel, origin: Mapping[str, np.ndarray]) -> _Fragment:
        children = [self.compile(child, origin) for child in node.children]
        duration = max((child.duration for child in children), default=0.0)
        return _merge((child.placed(0.0, duration) for child in children), duration)

    def sequence(self, nodes: Iterable[Constraint], origin: Mapping[str, np.ndarray]) -> _Fragment:
        placed: list[_Fragment] = []
        here = dict(origin)
        previous: _Fragment | None = None
        clock = 0.0
        for node in nodes:
            child = self.compile(node, here)
            if previous is not None:
                clock += self.transition(previous, child)
            placed.append(child.placed(clock, child.duration))
            clock += child.duration
            here.update(_last_locations(child))
            previous = child
        return _merge(placed, clock)

    def repetition(self, node: Repetition, origin: Mapping[str, np.ndarray]) -> _Fragment:
        child = self.compile(node.child, origin)
        notes = [f"{self.behavior}: alternating repetition not realized; both hands move together"] if node.alternating else []
        return self.repeat(child, node.count, node.mode, notes)

    def repeat(self, child: _Fragment, count: int, mode: str = "fromstart", notes: list[str] | None = None) -> _Fragment:
        notes = list(notes or [])
        if count < 1:
            raise self.error(f"repetition count must be at least 1, got {count}", None)
        if child.duration <= 0.0:
            if count > 1:
                notes.append(f"{self.behavior}: a held posture cannot be repeated; holding it once")
            return _merge([child], 0.0, notes)
        passes = [child]
        for index in range(1, count):
            if mode == "continue":
                passes.append(_shifted(passes[-1], _displacements(child)))
            elif mode == "reverse" and index % 2 == 1:
                passes.append(_reversed(child))
            else:
                passes.append(child)
        placed, clock = [], 0.0
        for index, fragment in enumerate(passes):
            if index:
                clock += self.transition(passes[index - 1], fragment)
            placed.append(fragment.placed(clock, fragment.duration))
            clock += fragment.duration
        return _merge(placed, clock, notes)

    def symmetrical(self, node: Symmetrical, origin: Mapping[str, np.ndarray]) -> _Fragment:
        child = self.compile(node.child, origin)
        dominant, other = node.dominant.side, node.dominant.other.side
        center = self.mirror_center(node, child)
        tracks = dict(child.tracks)
        for (arm, feature), keys in child.tracks.items():
            if arm != dominant or (other, feature) in child.tracks:
                continue
            tracks[(other, feature)] = tuple(replace(key, value=_mirror(feature, key.value, node.symmetry, center)) for key in keys)
        return _Fragment(child.duration, tracks, child.warnings)

    def mirror_center(self, node: Symmetrical, child: _Fragment) -> np.ndarray:
        """Center of the mirror planes, metres (module docstring)."""
        if node.center is not None:
            if len(node.center) < 3:
                raise self.error(f"symmetry center needs three numbers, got {list(node.center)}", node.where)
            x, y, z = (value * _MM for value in node.center[:3])
            return np.array([x, y - self.avatar.root_height, z])
        keys = child.tracks.get((node.dominant.side, "location"), ())
        points = [np.asarray(key.value) for key in keys]
        mean = np.mean(points, axis=0) if points else np.zeros(3)
        return np.array([0.0, mean[1], mean[2]])

    def transition(self, previous: _Fragment, following: _Fragment) -> float:
        """Time to bring every feature from ``previous``'s last to ``following``'s first value."""
        longest = 0.0
        for track in set(previous.tracks) & set(following.tracks):
            a, b = previous.last(track), following.first(track)
            longest = max(longest, _change_time(track[1], a, b))
        return longest

    # -- leaves -----------------------------------------------------------------------

    def arm_of(self, leaf: Static | Dynamic) -> str:
        scope = leaf.scope
        if isinstance(scope, Arm):
            return scope.side
        if scope in ("right_arm", "left_arm"):
            return Arm(scope).side
        return "right"

    def static(self, leaf: Static) -> _Fragment:
        feature = _FEATURES.get(leaf.slot)
        if feature is None:
            return _Fragment(0.0, {}, (self.unrealized(leaf.slot),))
        arm = self.arm_of(leaf)
        value = self.value(feature, leaf.value, arm, leaf.mode, leaf.where)
        return _Fragment(0.0, {(arm, feature): (_Key(0.0, 0.0, value),)})

    def unrealized(self, slot: str) -> str:
        return f"{self.behavior}: slot {slot} is not realized by the arm motor programs"

    def value(self, feature: str, value: object, arm: str, mode: str | None, where: SourceLocation | None) -> object:
        """A slot value as the planner keys it (metres, unit vectors, hand parameters)."""
        try:
            if mode == "pointTo" and feature in ("location", "fingers"):
                target = self.point_of(value, arm, where)
                if feature == "fingers":
                    return PointTarget(tuple(float(v) for v in target))
                return self.pointing_position(target, arm, where)
            if feature == "location":
                return resolve_location(self.avatar, value, AVATAR_SIDE[arm])  # type: ignore[arg-type]
            if feature == "shape":
                if not isinstance(value, HandShape):
                    raise self.error(f"HandShape needs a hand shape, got {value!r}", where)
                return handshape_params(value)
            if feature == "fingers":
                if isinstance(value, PointLocation):
                    return PointTarget(value.position)
                if not isinstance(value, Direction):
                    raise self.error(f"ExtFingerOrientation needs a direction, got {value!r}", where)
                return _unit_vector(value.vector, self.error("ExtFingerOrientation has zero length", where))
            if not isinstance(value, PalmOrientation):
                raise self.error(f"PalmOrientation needs a palm orientation, got {value!r}", where)
            _unit_vector(value.direction, self.error("PalmOrientation has zero length", where))
            return value
        except SpecError as error:
            raise self.error(str(error), where) from None

    def point_of(self, value: object, arm: str, where: SourceLocation | None) -> np.ndarray:
        try:
            return resolve_location(self.avatar, value, AVATAR_SIDE[arm])  # type: ignore[arg-type]
        except (SpecError, TypeError, AttributeError):
            raise self.error(f"pointTo needs a location to point at, got {value!r}", where) from None

    def shoulder(self, arm: str) -> np.ndarray:
        return self.avatar.rest_positions[self.avatar.joint_index(f"{AVATAR_SIDE[arm]}_shoulder")]

    def pointing_position(self, target: np.ndarray, arm: str, where: SourceLocation | None) -> np.ndarray:
        shoulder = self.shoulder(arm)
        toward = _unit_vector(target - shoulder, self.error("pointTo target lies at the shoulder", where))
        return shoulder + POINTING_REACH * self.avatar.arm_length(AVATAR_SIDE[arm]) * toward

    def neutral_location(self, arm: str) -> np.ndarray:
        location = NEUTRAL_LOCATION if arm == "right" else replace(NEUTRAL_LOCATION, lateral="LocCCenterLeft")
        return resolve_location(self.avatar, location, AVATAR_SIDE[arm])

    def dynamic(self, leaf: Dynamic, origin: Mapping[str, np.ndarray]) -> _Fragment:
        feature = _FEATURES.get(leaf.slot)
        if feature is None:
            return _Fragment(0.0, {}, (self.unrealized(leaf.slot),))
        if not leaf.segments:
            raise self.error(f"dynamic {leaf.slot} has no segments", leaf.where)
        arm = self.arm_of(leaf)
        if feature == "location":
            return self.path(leaf, arm, origin.get(arm))
        keys: list[_Key] = []
        clock = 0.0
        previous: object | None = None
        for segment in leaf.segments:
            start = None if segment.start is None else self.value(feature, segment.start, arm, None, segment.where)
            end = None if segment.end is None else self.value(feature, segment.end, arm, None, segment.where)
            first = start if start is not None else previous
            if start is not None:
                keys.append(_Key(clock, clock, start))
            if end is not None:
                clock += max(_change_time(feature, first, end), MIN_TURN) if first is not None else MIN_TURN
                keys.append(_Key(clock, clock, end))
            previous = end if end is not None else start
        return _Fragment(clock, {(arm, feature): tuple(keys)})

    def path(self, leaf: Dynamic, arm: str, origin: np.ndarray | None) -> _Fragment:
        keys: list[_Key] = []
        notes: list[str] = []
        clock = 0.0
        here = origin
        for segment in leaf.segments:
            where = segment.where or leaf.where
            if segment.start is not None:
                here = self.value("location", segment.start, arm, None, where)
            elif here is None:
                here = self.neutral_location(arm)
                notes.append(f"{self.behavior}: path without a start; starting at the neutral position {np.round(here, 3).tolist()}")
            points, curved, kind, segment_notes = self.segment_points(segment, np.asarray(here, dtype=float), arm, where)
            notes.extend(segment_notes)
            if keys and np.linalg.norm(points[0] - np.asarray(keys[-1].value)) > _SAME_PLACE:
                clock += movement_time(float(np.linalg.norm(points[0] - np.asarray(keys[-1].value))))
            if not keys or np.linalg.norm(points[0] - np.asarray(keys[-1].value)) > _SAME_PLACE:
                keys.append(_Key(clock, clock, points[0]))
            length = float(np.sum(np.linalg.norm(np.diff(points, axis=0), axis=1)))
            if length < _SAME_PLACE:
                notes.append(f"{self.behavior}: a {segment.kind.value} segment of zero length is a hold")
                here = points[-1]
                continue
            duration = movement_time(length, kind, segment.manner)
            times = clock + time_breakpoints(points, 0.0, duration)
            keys.extend(_Key(float(t), float(t), p, curved) for t, p in zip(times[1:], points[1:]))
            clock += duration
            here = points[-1]
        return _Fragment(clock, {(arm, "location"): tuple(keys)}, tuple(notes))

    def segment_points(
        self, segment: Segment, start: np.ndarray, arm: str, where: SourceLocation | None
    ) -> tuple[np.ndarray, bool, str, list[str]]:
        """Breakpoints ``(n, 3)`` of one HandLocation segment from ``start``, whether they
        approximate a curve, the movement kind for its duration, and notes."""
        end = self.segment_end(segment, start, arm, where)
        try:
            if segment.kind is SegmentKind.CURVE:
                normal = None if segment.normal is None else segment.normal.vector
                strokes = curve_breakpoints(
                    start, end, normal, segment.shape or "LeftC",
                    0.5 if segment.extent is None else segment.extent,
                    segment.roundness or 0.0, segment.skewedness or 0.0,
                )  # fmt: skip
                notes = [f"{self.behavior}: {note}" for note in strokes.warnings]
                if segment.shape is None:
                    notes.append(f"{self.behavior}: curve without a shape; using LeftC")
                return strokes.points, True, "curved", notes
            if segment.kind is SegmentKind.CIRCLE:
                axis = (0.0, 0.0, 1.0) if segment.normal is None else segment.normal.vector
                radius = 0.5 * segment.distance if segment.distance else _CIRCLE_RADIUS.get(segment.size or "", 0.06)
                return circle_from_start(start, axis, radius), True, "circle", []
        except ValueError as error:
            raise self.error(f"{segment.kind.value} segment: {error}", where) from None
        return np.stack([start, end]), False, "straight", []

    def segment_end(self, segment: Segment, start: np.ndarray, arm: str, where: SourceLocation | None) -> np.ndarray:
        if segment.end is not None:
            return np.asarray(self.value("location", segment.end, arm, None, where), dtype=float)
        if segment.direction is not None and segment.distance is not None:
            direction = _unit_vector(segment.direction.vector, self.error("segment direction has zero length", where))
            return start + direction * float(segment.distance)
        if segment.kind is SegmentKind.CIRCLE:
            return start
        raise self.error("a HandLocation segment needs an end, or a direction and a distance", where)


#: Circle radius by HamNoSys size, metres.
_CIRCLE_RADIUS = {"small": 0.03, "large": 0.1, "": 0.06}


def _unit_vector(vector: Iterable[float], error: Exception) -> np.ndarray:
    v = np.asarray(tuple(vector), dtype=float)
    norm = float(np.linalg.norm(v))
    if not np.isfinite(norm) or norm < 1e-9:
        raise error
    return v / norm


def _last_locations(fragment: _Fragment) -> dict[str, np.ndarray]:
    return {arm: np.asarray(keys[-1].value) for (arm, feature), keys in fragment.tracks.items() if feature == "location" and keys}


def _displacements(fragment: _Fragment) -> dict[str, np.ndarray]:
    return {
        arm: np.asarray(keys[-1].value) - np.asarray(keys[0].value)
        for (arm, feature), keys in fragment.tracks.items()
        if feature == "location" and keys
    }


def _shifted(fragment: _Fragment, by: Mapping[str, np.ndarray]) -> _Fragment:
    for arm, offset in by.items():
        fragment = fragment.mapped((arm, "location"), lambda key, o=offset: replace(key, value=np.asarray(key.value) + o))
    return fragment


def _reversed(fragment: _Fragment) -> _Fragment:
    d = fragment.duration
    tracks = {
        track: tuple(replace(key, start=d - key.end, end=d - key.start) for key in reversed(keys))
        for track, keys in fragment.tracks.items()
    }
    return _Fragment(d, tracks, fragment.warnings)


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.arccos(np.clip(a @ b / (np.linalg.norm(a) * np.linalg.norm(b)), -1.0, 1.0)))


def _change_time(feature: str, a: object, b: object) -> float:
    """Natural time to change a feature's value from ``a`` to ``b``, seconds."""
    if a is None or b is None:
        return 0.0
    if feature == "location":
        return movement_time(float(np.linalg.norm(np.asarray(b) - np.asarray(a))))
    if feature == "shape":
        return SHAPE_CHANGE if float(np.max(np.abs(np.asarray(a) - np.asarray(b)))) > 1e-3 else 0.0
    if isinstance(a, PointTarget) or isinstance(b, PointTarget):
        return 0.0 if a == b else MIN_TURN
    va = np.asarray(a.direction if isinstance(a, PalmOrientation) else a, dtype=float)
    vb = np.asarray(b.direction if isinstance(b, PalmOrientation) else b, dtype=float)
    angle = _angle(va, vb)
    return 0.0 if angle < 1e-3 else max(MIN_TURN, angle / ANGULAR_SPEED)


def _mirror(feature: str, value: object, symmetry: Symmetry, center: np.ndarray) -> object:
    if feature == "location":
        return mirror_points(np.asarray(value, dtype=float), symmetry, center)
    if feature == "shape":
        return value
    if isinstance(value, PointTarget):
        return PointTarget(tuple(float(v) for v in mirror_points(np.asarray(value.point), symmetry, center)))
    if isinstance(value, PalmOrientation):
        mirrored = mirror_directions(np.asarray(value.direction, dtype=float), symmetry)
        return PalmOrientation(tuple(float(v) for v in mirrored), value.name, value.relative)
    return mirror_directions(np.asarray(value, dtype=float), symmetry)


# -- from a fragment to LMPs ------------------------------------------------------------


def _value_at(keys: tuple[_Key, ...], time: float) -> object:
    """The value in effect at ``time``: the latest key reached by then, else the first."""
    current = keys[0].value
    for key in keys:
        if key.start <= time + _SAME_TIME:
            current = key.value
    return current


def _timed_values(keys: Iterable[_Key]) -> tuple[list[float], list[object]]:
    """Key times and values with holds expanded and equal times merged (the later wins)."""
    times: list[float] = []
    values: list[object] = []
    for key in keys:
        for time in (key.start, key.end) if key.end - key.start > _SAME_TIME else (key.start,):
            if times and time - times[-1] <= _SAME_TIME:
                values[-1] = key.value
                continue
            times.append(time)
            values.append(key.value)
    return times, values


@dataclass(frozen=True, eq=False)
class Planner:
    """Plans gestures into motor programs for one avatar."""

    avatar: Avatar

    def fragment(self, behavior: BehaviorSpec) -> _Fragment:
        if behavior.gesture is None:
            return _Fragment(0.0, {}, (f"{behavior.id}: {behavior.kind} behaviour has no gesture to plan",))
        return _Compiler(self.avatar, behavior.id).compile(behavior.gesture.constraints, {})

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
        return GestureDemands(arms, fragment.duration, dynamic, dynamic, distance)

    def plan(
        self, behavior: BehaviorSpec, pegs: TimePegs, repetitions: int = 1, next_gesture_follows: bool = False
    ) -> MotorProgram:
        """The motor program of ``behavior`` on ``pegs`` (see the module docstring)."""
        compiler = _Compiler(self.avatar, behavior.id)
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
        self, compiler: _Compiler, stroke: _Fragment, arm: str, pegs: TimePegs, notes: list[str]
    ) -> tuple[list[LMP], np.ndarray | None]:
        """The stroke LMPs of one arm, and its wrist position at the end of the stroke."""
        held = replace(pegs, end=pegs.relax)
        lmps: list[LMP] = []
        locations = stroke.tracks.get((arm, "location"), ())
        last_wrist = None
        if locations:
            times, values = _timed_values(locations)
            curved_flags = tuple(_curved_into(locations, t) for t in times[1:])
            points = self.within_reach(compiler.behavior, arm, np.array([np.asarray(v, dtype=float) for v in values]), notes)
            if len(points) > 1:
                notes.extend(f"{compiler.behavior}: {note}" for note in plan_wrist_trajectory(points, np.array(times), curved=curved_flags).warnings)
            lmps.append(WristPositionLMP(arm, held, points, np.array(times), curved_flags))
            last_wrist = points[-1]
        shapes = stroke.tracks.get((arm, "shape"), ())
        if shapes:
            times, values = self.prepared(_timed_values(shapes), pegs.ready)
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
        if times[0] - ready > _SAME_TIME:
            return [ready, *times], [values[0], *values]
        return times, values

    def rotation_keys(self, compiler: _Compiler, stroke: _Fragment, arm: str, ready: float) -> tuple[np.ndarray, np.ndarray] | None:
        """Hand rotation keys composed from the fingers and palm tracks, or None when the
        arm's orientation and location are both unconstrained."""
        fingers = stroke.tracks.get((arm, "fingers"), ())
        palms = stroke.tracks.get((arm, "palm"), ())
        locations = stroke.tracks.get((arm, "location"), ())
        if not (fingers or palms or locations):
            return None
        times = sorted({t for keys in (fingers, palms) for t in _timed_values(keys)[0]} or {locations[0].start})
        merged: list[float] = []
        for t in times:
            if not merged or t - merged[-1] > _SAME_TIME:
                merged.append(t)
        inward = np.array([1.0 if arm == "right" else -1.0, 0.0, 0.0])
        finger_vectors, palm_vectors = [], []
        for t in merged:
            wrist = np.asarray(_value_at(locations, t), dtype=float) if locations else compiler.shoulder(arm)
            finger = _value_at(fingers, t) if fingers else NEUTRAL_FINGERS
            if isinstance(finger, PointTarget):
                finger = _unit_vector(
                    np.asarray(finger.point) - wrist, compiler.error("pointTo target lies at the wrist", None)
                )
            palm = _value_at(palms, t) if palms else PalmOrientation(tuple(inward))
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


def first_location(fragment: _Fragment, arm: str) -> np.ndarray | None:
    """Where the stroke of ``arm`` starts, or None when its location is unconstrained."""
    value = fragment.first((arm, "location"))
    return None if value is None else np.asarray(value, dtype=float)


def _curved_into(keys: tuple[_Key, ...], time: float) -> bool:
    """Whether the breakpoint at ``time`` is reached along a curve."""
    return any(key.curved and abs(key.start - time) <= _SAME_TIME for key in keys)


