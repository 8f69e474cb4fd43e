"""A gesture's constraint tree compiled into a fragment: the stroke in its own time (seed 004, 4).

The constraint tree is compiled bottom-up into a
*fragment*: for every ``(arm, feature)`` — features ``location`` (wrist position),
``shape`` (hand parameters), ``fingers`` (extended-finger direction) and ``palm`` — a
list of keys ``(start, end, value)`` on a local clock ``[0, D]``, the value reached at
``start`` and held until ``end``; ``D`` is the fragment's *natural duration*:

* ``static``: one key at 0, duration 0; placed in a longer interval it holds throughout.
* ``dynamic``: keys at the segments' breakpoints. A ``HandLocation`` segment is linear
  from start to end, or from start along ``direction`` for ``distance`` metres; curves
  come from :func:`motor.trajectory.guiding_strokes.curve_breakpoints`, circles from
  :func:`motor.trajectory.guiding_strokes.circle_from_start`; a segment without a start starts
  where the previous one ended (or, with nothing before it, at the arm's neutral
  gesture position, with a warning). Other slots key their start and end values.
  Segment durations: :func:`movement_time` — the biocontrol duration of the movement
  kind and manner (0.4 s straight, ×1.3 curved, ×1.7 circle), or the path length at
  the comfortable mean speed :data:`COMFORTABLE_SPEED`, whichever is longer; the
  breakpoints inside a segment are timed by the power law
  (:func:`motor.trajectory.spline.time_breakpoints`).
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
  Hands brought together touch and do not overlap: a mirrored location closer to its
  image than the avatar's palm thickness (``palm_thickness`` of its collision entry,
  :mod:`motor.body.volumes`) is moved apart, both hands equally, to that distance; the
  motor control keeps every pair of hands at least that far apart as the arms turn them
  (:func:`motor.body.collision.separate_hands`).

A location out of the arm's reach (the IK falls short of it; :mod:`motor.arm.wrist_path`)
is replaced by the nearest point the arm reaches, with a warning; a stroke too fast for
the speed budget is lengthened by the gesture planner (:mod:`motor.program.gesture`), with
a warning.

``mode="pointTo"`` with a point: the wrist goes on the line from the shoulder toward
the point at :data:`POINTING_REACH` of the arm's length, and the fingers point from the
wrist to the point.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, replace

import numpy as np

from motor.arm.wrist_path import uncrowded_placement
from motor.body.avatar import Avatar
from motor.body.conventions import AVATAR_SIDE
from motor.body.locations import resolve_location
from motor.face.planning import FACE_SLOTS
from motor.hand.shape import handshape_params
from motor.neck.planning import NECK_SLOTS
from motor.trajectory.biocontrol import MANNERS, movement_duration
from motor.trajectory.guiding_strokes import circle_from_start, curve_breakpoints
from motor.trajectory.spline import time_breakpoints
from motor.trajectory.symmetry import kept_apart, mirror_directions, mirror_points, reflection_signs
from mura.constraints import (
    Arm,
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
from mura.errors import SourceLocation, SpecError
from mura.values import (
    Direction,
    GridLocation,
    HandShape,
    PalmOrientation,
    PointLocation,
)

#: Comfortable mean wrist speed of a stroke, m/s: long strokes take length / this.
COMFORTABLE_SPEED = 0.5


#: Time for a change of hand shape between two keys, seconds.
SHAPE_CHANGE = 0.3


#: Turning speed of the hand between orientation keys, rad/s, and the shortest turn, s.
ANGULAR_SPEED = 3.0


MIN_TURN = 0.2


#: Fraction of the arm's length at which a pointing hand is held toward its target.
POINTING_REACH = 0.75


#: Neutral gesture position (grid) of the right hand, for a path with no start.
NEUTRAL_LOCATION = GridLocation("LocChest", "LocCCenterRight", "LocNorm")


#: Closest two key times may be and still count as distinct, seconds.
SAME_TIME = 1e-9
#: Clearance (m) between the forearms of mirrored arms that cross over each other
#: (:meth:`Compiler.stacked`).
CROSSING_CLEARANCE = 0.015
#: Smallest fraction of the way from elbow to wrist at which crossing forearms are taken
#: to cross (:meth:`Compiler.crossing_gap`): the lowering grows as the fraction shrinks,
#: to twice the thickness at most (at 0.4, max's lowered hand of ``12_denule_regal``
#: went down past the chest, where placing it out of the body brought the forearms 5.6 cm
#: into each other again).
CROSSING_NEAREST = 0.5
#: Most rounds of lowering the image's keys again where placing them (into reach, out of
#: the body) raised them back toward the dominant hand (:meth:`Compiler.stacked`).
STACKING_ROUNDS = 4


_SAME_PLACE = 1e-4


_MM = 0.001


_FEATURES = {"HandLocation": "location", "HandShape": "shape", "ExtFingerOrientation": "fingers", "PalmOrientation": "palm"}


_MANNER_SYNONYMS = {"rest": "lax", "halt": "sudden_stop"}


class PlanningError(ValueError):
    """A gesture that cannot be planned; the message names the behaviour and the constraint."""


@dataclass(frozen=True)
class PointTarget:
    """A ``pointTo`` value: a point in the avatar frame, metres."""

    point: tuple[float, float, float]


@dataclass(frozen=True, eq=False)
class Key:
    """A feature value reached at ``start`` and held until ``end`` (local seconds)."""

    start: float
    end: float
    value: object


Track = tuple[str, str]


@dataclass(frozen=True, eq=False)
class Fragment:
    """Keys per ``(arm, feature)`` over a local clock ``[0, duration]``."""

    duration: float
    tracks: Mapping[Track, tuple[Key, ...]]
    warnings: tuple[str, ...] = ()

    def placed(self, offset: float, length: float) -> Fragment:
        """The fragment stretched onto ``[offset, offset + length]``; a zero-duration
        fragment (static keys) holds over the whole interval."""
        scale = length / self.duration if self.duration > 0.0 else 0.0

        def move(key: Key) -> Key:
            if self.duration <= 0.0:
                return replace(key, start=offset, end=offset + length)
            return replace(key, start=offset + key.start * scale, end=offset + key.end * scale)

        tracks = {track: tuple(move(key) for key in keys) for track, keys in self.tracks.items()}
        return Fragment(length, tracks, self.warnings)

    def last(self, track: Track) -> object | None:
        keys = self.tracks.get(track)
        return keys[-1].value if keys else None

    def first(self, track: Track) -> object | None:
        keys = self.tracks.get(track)
        return keys[0].value if keys else None

    def mapped(self, track: Track, change: Callable[[Key], Key]) -> Fragment:
        tracks = dict(self.tracks)
        tracks[track] = tuple(change(key) for key in tracks[track])
        return Fragment(self.duration, tracks, self.warnings)


def merge_fragments(fragments: Iterable[Fragment], duration: float, warnings: Iterable[str] = ()) -> Fragment:
    tracks: dict[Track, list[Key]] = {}
    notes = list(warnings)
    for fragment in fragments:
        notes.extend(fragment.warnings)
        for track, keys in fragment.tracks.items():
            tracks.setdefault(track, []).extend(keys)
    ordered = {track: tuple(sorted(keys, key=lambda k: k.start)) for track, keys in tracks.items()}
    return Fragment(duration, ordered, tuple(notes))


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


class Compiler:
    """Compiles one gesture's constraint tree into a fragment for one avatar."""

    def __init__(self, avatar: Avatar, behavior: str) -> None:
        self.avatar = avatar
        self.behavior = behavior

    def error(self, message: str, where: SourceLocation | None) -> PlanningError:
        place = f" ({where})" if where is not None else ""
        return PlanningError(f"behaviour {self.behavior!r}{place}: {message}")

    # -- tree -------------------------------------------------------------------------

    def compile(self, node: Constraint, origin: Mapping[str, np.ndarray]) -> Fragment:
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

    def parallel(self, node: Parallel, origin: Mapping[str, np.ndarray]) -> Fragment:
        children = [self.compile(child, origin) for child in node.children]
        duration = max((child.duration for child in children), default=0.0)
        return merge_fragments((child.placed(0.0, duration) for child in children), duration)

    def sequence(self, nodes: Iterable[Constraint], origin: Mapping[str, np.ndarray]) -> Fragment:
        placed: list[Fragment] = []
        here = dict(origin)
        previous: Fragment | None = None
        clock = 0.0
        for node in nodes:
            child = self.compile(node, here)
            if previous is not None:
                clock += self.transition(previous, child)
            placed.append(child.placed(clock, child.duration))
            clock += child.duration
            here.update(_last_locations(child))
            previous = child
        return merge_fragments(placed, clock)

    def repetition(self, node: Repetition, origin: Mapping[str, np.ndarray]) -> Fragment:
        child = self.compile(node.child, origin)
        notes = [f"{self.behavior}: alternating repetition not realized; both hands move together"] if node.alternating else []
        return self.repeat(child, node.count, node.mode, notes)

    def repeat(self, child: Fragment, count: int, mode: str = "fromstart", notes: list[str] | None = None) -> Fragment:
        notes = list(notes or [])
        if count < 1:
            raise self.error(f"repetition count must be at least 1, got {count}", None)
        if child.duration <= 0.0:
            if count > 1:
                notes.append(f"{self.behavior}: a held posture cannot be repeated; holding it once")
            return merge_fragments([child], 0.0, notes)
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
        return merge_fragments(placed, clock, notes)

    def symmetrical(self, node: Symmetrical, origin: Mapping[str, np.ndarray]) -> Fragment:
        child = self.compile(node.child, origin)
        dominant, other = node.dominant.side, node.dominant.other.side
        center = self.mirror_center(node, child)
        tracks = dict(child.tracks)
        for (arm, feature), keys in child.tracks.items():
            if arm != dominant or (other, feature) in child.tracks:
                continue
            asked = keys
            if feature == "location":
                keys = self.kept_apart(keys, node.symmetry, center, dominant)
                tracks[(arm, feature)] = keys
            mirrored = tuple(replace(key, value=_mirror(feature, key.value, node.symmetry, center)) for key in keys)
            if feature == "location":
                touching = [not np.array_equal(np.asarray(a.value), np.asarray(b.value)) for a, b in zip(asked, keys)]
                mirrored = self.stacked(keys, mirrored, touching, node.symmetry, center, dominant)
            tracks[(other, feature)] = mirrored
        return Fragment(child.duration, tracks, child.warnings)

    def stacked(
        self, keys: tuple[Key, ...], mirrored: tuple[Key, ...], touching: list[bool], symmetry: Symmetry, center: np.ndarray, dominant: str
    ) -> tuple[Key, ...]:
        """The mirror image's location keys, below the dominant hand's where the arms cross:
        when the mirror is left–right (``S``) and a dominant key lies beyond the mirror plane
        (the right hand left of it, or the left hand right of it), the arms cross over each
        other in the gesture, and mirrored forearms would pass through each other; the
        image's keys then keep the forearms' thickness and :data:`CROSSING_CLEARANCE` below
        the dominant hand's mirror image — all but those where the hands touch
        (``touching``: kept a palm thickness apart at the plane), so that the forearms pass
        one over the other and the hands still meet where asked. The dominant hand stays
        where it was asked (it may be at the edge of its reach, high above the head). Both
        are measured where the planner places them (:func:`motor.arm.wrist_path.uncrowded_placement`:
        into reach, out of the body): a hand asked beyond its reach is pulled in toward its
        shoulder, and pulling both in closed most of a gap made where they were asked."""
        if reflection_signs(symmetry)[0] > 0.0:
            return mirrored
        beyond = -1.0 if dominant == "left" else 1.0
        if not any(beyond * (float(np.asarray(key.value)[0]) - center[0]) > 0.0 for key in keys):
            return mirrored
        kept = np.array(touching)
        reached = uncrowded_placement(self.avatar, AVATAR_SIDE[dominant], np.array([np.asarray(key.value, dtype=float) for key in keys]), kept).points
        image = mirror_points(reached, symmetry, center)
        gap = self.crossing_gap(reached, center, dominant)
        lower = gap.copy()
        for _ in range(STACKING_ROUNDS):
            below = image - lower[:, None] * np.array([0.0, 1.0, 0.0])
            placed = uncrowded_placement(self.avatar, AVATAR_SIDE["left" if dominant == "right" else "right"], below, kept).points
            short = gap - (image[:, 1] - placed[:, 1])
            if not np.any(short > _SAME_PLACE):
                break
            lower += np.maximum(short, 0.0)
        return tuple(key if touch else replace(key, value=point) for key, touch, point in zip(mirrored, touching, below))

    def crossing_gap(self, wrists: np.ndarray, center: np.ndarray, dominant: str) -> np.ndarray:
        """How far (m, ``(n,)``) the image's wrists go below the dominant hand's mirror image
        for the forearms to cross the forearms' thickness and :data:`CROSSING_CLEARANCE`
        apart. The forearms cross at the mirror plane, a fraction t of the way from the
        elbows (about under the shoulders, level with each other) to the wrists ``(n, 3)``,
        where they are only t of the wrists' height apart: the wrists are lowered by the
        thickness over t — twice it for hands reaching as far past the plane as the
        shoulder is before it (``12_denule_regal``'s shelf, whose forearms crossed 6.9 cm
        into each other at the thickness alone) — t taken no smaller than
        :data:`CROSSING_NEAREST`. Keys on the dominant hand's own side count as t = 1."""
        thickness = sum(self.avatar.collision.arm(side, "forearm").radius for side in "lr") + CROSSING_CLEARANCE
        shoulder = self.avatar.rest_positions[self.avatar.joint_index(f"{AVATAR_SIDE[dominant]}_shoulder"), 0] - center[0]
        span = np.abs(wrists[:, 0] - center[0] - shoulder)
        fraction = np.clip(abs(shoulder) / np.maximum(span, 1e-9), CROSSING_NEAREST, 1.0)
        return thickness / fraction

    def kept_apart(self, keys: tuple[Key, ...], symmetry: Symmetry, center: np.ndarray, dominant: str) -> tuple[Key, ...]:
        """Dominant-hand location keys at least a palm thickness from their mirror images
        (``avatar.collision.palm_thickness``): hands brought together touch, they do not
        overlap. A key on the mirror planes is moved to the dominant hand's side (the avatar's right is −x)."""
        signs = reflection_signs(symmetry)
        away = np.where(signs < 0.0, 1.0, 0.0)
        away[0] *= -1.0 if dominant == "right" else 1.0
        if not np.any(away):
            return keys
        points = np.array([np.asarray(key.value, dtype=float) for key in keys])
        apart = kept_apart(points, symmetry, center, self.avatar.collision.palm_thickness, away / np.linalg.norm(away))
        return tuple(replace(key, value=point) for key, point in zip(keys, apart))

    def mirror_center(self, node: Symmetrical, child: Fragment) -> np.ndarray:
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

    def transition(self, previous: Fragment, following: Fragment) -> float:
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

    def static(self, leaf: Static) -> Fragment:
        feature = _FEATURES.get(leaf.slot)
        if feature is None:
            return Fragment(0.0, {}, self.unrealized(leaf.slot))
        arm = self.arm_of(leaf)
        value = self.value(feature, leaf.value, arm, leaf.mode, leaf.where)
        return Fragment(0.0, {(arm, feature): (Key(0.0, 0.0, value),)})

    def unrealized(self, slot: str) -> tuple[str, ...]:
        """The warning for a slot no motor module realizes; none for the neck's and the face's."""
        if slot in NECK_SLOTS | FACE_SLOTS:
            return ()
        return (f"{self.behavior}: slot {slot} is not realized by the arm motor programs",)

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
                return unit_vector(value.vector, self.error("ExtFingerOrientation has zero length", where))
            if not isinstance(value, PalmOrientation):
                raise self.error(f"PalmOrientation needs a palm orientation, got {value!r}", where)
            unit_vector(value.direction, self.error("PalmOrientation has zero length", where))
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
        toward = unit_vector(target - shoulder, self.error("pointTo target lies at the shoulder", where))
        return shoulder + POINTING_REACH * self.avatar.arm_length(AVATAR_SIDE[arm]) * toward

    def neutral_location(self, arm: str) -> np.ndarray:
        location = NEUTRAL_LOCATION if arm == "right" else replace(NEUTRAL_LOCATION, lateral="LocCCenterLeft")
        return resolve_location(self.avatar, location, AVATAR_SIDE[arm])

    def dynamic(self, leaf: Dynamic, origin: Mapping[str, np.ndarray]) -> Fragment:
        if leaf.keyframes is not None and not leaf.segments:  # joint keyframes: neither the arm nor the neck planner reads them
            return Fragment(0.0, {}, (f"{self.behavior}: keyframed {leaf.slot} ({len(leaf.keyframes.frames)} frames of named joints) is not realized by the motor programs",))
        feature = _FEATURES.get(leaf.slot)
        if feature is None:
            return Fragment(0.0, {}, self.unrealized(leaf.slot))
        if not leaf.segments:
            raise self.error(f"dynamic {leaf.slot} has no segments", leaf.where)
        arm = self.arm_of(leaf)
        if feature == "location":
            return self.path(leaf, arm, origin.get(arm))
        keys: list[Key] = []
        clock = 0.0
        previous: object | None = None
        for segment in leaf.segments:
            start = None if segment.start is None else self.value(feature, segment.start, arm, None, segment.where)
            end = None if segment.end is None else self.value(feature, segment.end, arm, None, segment.where)
            first = start if start is not None else previous
            if start is not None:
                keys.append(Key(clock, clock, start))
            if end is not None:
                clock += max(_change_time(feature, first, end), MIN_TURN) if first is not None else MIN_TURN
                keys.append(Key(clock, clock, end))
            previous = end if end is not None else start
        return Fragment(clock, {(arm, feature): tuple(keys)})

    def path(self, leaf: Dynamic, arm: str, origin: np.ndarray | None) -> Fragment:
        keys: list[Key] = []
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
            points, kind, segment_notes = self.segment_points(segment, np.asarray(here, dtype=float), arm, where)
            notes.extend(segment_notes)
            if keys and np.linalg.norm(points[0] - np.asarray(keys[-1].value)) > _SAME_PLACE:
                clock += movement_time(float(np.linalg.norm(points[0] - np.asarray(keys[-1].value))))
            if not keys or np.linalg.norm(points[0] - np.asarray(keys[-1].value)) > _SAME_PLACE:
                keys.append(Key(clock, clock, points[0]))
            length = float(np.sum(np.linalg.norm(np.diff(points, axis=0), axis=1)))
            if length < _SAME_PLACE:
                notes.append(f"{self.behavior}: a {segment.kind.value} segment of zero length is a hold")
                here = points[-1]
                continue
            duration = movement_time(length, kind, segment.manner)
            times = clock + time_breakpoints(points, 0.0, duration)
            keys.extend(Key(float(t), float(t), p) for t, p in zip(times[1:], points[1:]))
            clock += duration
            here = points[-1]
        return Fragment(clock, {(arm, "location"): tuple(keys)}, tuple(notes))

    def segment_points(
        self, segment: Segment, start: np.ndarray, arm: str, where: SourceLocation | None
    ) -> tuple[np.ndarray, str, list[str]]:
        """Breakpoints ``(n, 3)`` of one HandLocation segment from ``start``, the movement
        kind for its duration, and notes."""
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
                return strokes.points, "curved", notes
            if segment.kind is SegmentKind.CIRCLE:
                axis = (0.0, 0.0, 1.0) if segment.normal is None else segment.normal.vector
                radius = 0.5 * segment.distance if segment.distance else _CIRCLE_RADIUS.get(segment.size or "", 0.06)
                return circle_from_start(start, axis, radius), "circle", []
        except ValueError as error:
            raise self.error(f"{segment.kind.value} segment: {error}", where) from None
        return np.stack([start, end]), "straight", []

    def segment_end(self, segment: Segment, start: np.ndarray, arm: str, where: SourceLocation | None) -> np.ndarray:
        if segment.end is not None:
            return np.asarray(self.value("location", segment.end, arm, None, where), dtype=float)
        if segment.direction is not None and segment.distance is not None:
            direction = unit_vector(segment.direction.vector, self.error("segment direction has zero length", where))
            return start + direction * float(segment.distance)
        if segment.kind is SegmentKind.CIRCLE:
            return start
        raise self.error("a HandLocation segment needs an end, or a direction and a distance", where)


#: Circle radius by HamNoSys size, metres.
_CIRCLE_RADIUS = {"small": 0.03, "large": 0.1, "": 0.06}


def unit_vector(vector: Iterable[float], error: Exception) -> np.ndarray:
    v = np.asarray(tuple(vector), dtype=float)
    norm = float(np.linalg.norm(v))
    if not np.isfinite(norm) or norm < 1e-9:
        raise error
    return v / norm


def _last_locations(fragment: Fragment) -> dict[str, np.ndarray]:
    return {arm: np.asarray(keys[-1].value) for (arm, feature), keys in fragment.tracks.items() if feature == "location" and keys}


def _displacements(fragment: Fragment) -> dict[str, np.ndarray]:
    return {
        arm: np.asarray(keys[-1].value) - np.asarray(keys[0].value)
        for (arm, feature), keys in fragment.tracks.items()
        if feature == "location" and keys
    }


def _shifted(fragment: Fragment, by: Mapping[str, np.ndarray]) -> Fragment:
    for arm, offset in by.items():
        fragment = fragment.mapped((arm, "location"), lambda key, o=offset: replace(key, value=np.asarray(key.value) + o))
    return fragment


def _reversed(fragment: Fragment) -> Fragment:
    d = fragment.duration
    tracks = {
        track: tuple(replace(key, start=d - key.end, end=d - key.start) for key in reversed(keys))
        for track, keys in fragment.tracks.items()
    }
    return Fragment(d, tracks, fragment.warnings)


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


def value_at(keys: tuple[Key, ...], time: float) -> object:
    """The value in effect at ``time``: the latest key reached by then, else the first."""
    current = keys[0].value
    for key in keys:
        if key.start <= time + SAME_TIME:
            current = key.value
    return current


def timed_values(keys: Iterable[Key]) -> tuple[list[float], list[object]]:
    """Key times and values with holds expanded and equal times merged (the later wins)."""
    times: list[float] = []
    values: list[object] = []
    for key in keys:
        for time in (key.start, key.end) if key.end - key.start > SAME_TIME else (key.start,):
            if times and time - times[-1] <= SAME_TIME:
                values[-1] = key.value
                continue
            times.append(time)
            values.append(key.value)
    return times, values


def first_location(fragment: Fragment, arm: str) -> np.ndarray | None:
    """Where the stroke of ``arm`` starts, or None when its location is unconstrained."""
    value = fragment.first((arm, "location"))
    return None if value is None else np.asarray(value, dtype=float)

