"""One sign compiled into timed hand moves (seed 000, sections 4.1–4.6): the first half
of planning (:mod:`motor.signing.planning` drives it over a collection).

:class:`SignCompiler` walks a :class:`mura.signs.Sign`'s postures and movement tree into
each hand's first posture and moves on the sign's own clock (palm-centre paths, hand
rotation and shape keys), then lays them out as wrist paths and makes the
:class:`motor.signing.plan.SignPlan` of them (:meth:`SignCompiler.plan`).

**Where the hand is**: :mod:`motor.signing.hand_placement` (a location names where the
palm centre, or the part of the hand its contact bracket names, goes).

**Two hands.** Under ``lr`` symmetry the non-dominant hand's path is the dominant hand's
mirrored across the symmetry's planes (the sagittal plane ``x = 0`` at least), its
orientation mirrored across the sagittal plane, its shape the same; under ``par``
symmetry the path is translated, not mirrored. Alternating symmetry plays the
non-dominant hand's path displacements reversed (one hand goes down while the other goes
up). Leaves scoped to one arm move that hand only. A hand constellation puts the
non-dominant hand at the pair's location and the dominant hand so that its named site
meets the non-dominant hand's (touch, close …). A symmetric sign whose hands change into
a constellation (``hamreplace … hampinkyside hamplus hampinkyside``) brings both hands
together, each halfway, the pair meeting on the sagittal plane; the moves of a parallel
group are planned to the hands as its shape and orientation changes leave them. A dominant hand located on the other hand
or arm in a one-handed sign brings the other hand up as a passive base
(:data:`PASSIVE_POSTURE`).

**Movements** (:mod:`motor.signing.path_shapes`). Straight moves go ``SIZE_FRACTIONS`` of the arm's length (small, normal,
large); arcs bulge by ``ARC_EXTENT`` of the chord to the side their name gives;
wavy and zigzag paths come from :mod:`motor.trajectory.guiding_strokes`; circles and ellipses have
radii ``CIRCLE_FRACTIONS`` of the arm's length and start where the hand is (clock
positions choose where on the circle). Local movements: nodding and swinging turn the
wrist by :data:`LOCAL_ANGLE` (down–up, side to side), twisting turns the forearm, finger
play bends or opens alternate fingers by half a bend from their own shape (folded fingers
stay), stirring is a small horizontal circle. Durations are
:func:`motor.trajectory.biocontrol.movement_duration` of the movement kind in the sign's manner,
independent of size. Time profiles: targetted for the sign's movements, linear for
circles, hard contact for movements ending in touch, sudden stop for ``halt``/``rest``,
the fast/slow/tense tables for those manners. A static sign holds its posture for
:data:`STATIC_HOLD` seconds; a sign with movement first holds its first posture for
:data:`INITIAL_HOLD` seconds (its citation form; :func:`motor.signing.planning.without_initial_hold` for a sign
inside an utterance).

**Repetition.** ``fromstart``: back to the start (lax) and again; ``continue``: on from
where the pass ended; ``reverse``: back along the same path (targetted), then forward.
A displaced repetition shifts each further pass by the displacement's direction and size
(small by default) once more. A ``Symmetrical`` node inside the movement (a part of a
compound sign with its own symmetry operator) makes both hands take part, mirrored or in
parallel as it says, for that part; ``neutralspace`` is neutral space.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace

import numpy as np

from motor import quaternion as quat
from motor.body.conventions import AVATAR_SIDE
from motor.body.locations import resolve_location
from motor.hand.shape import played
from motor.signing.hand_geometry import HandGeometry
from motor.signing.hand_placement import NEUTRAL_FINGERS, PALM, HandPlacement, PlannedHand
from motor.signing.layout import Layout, placed
from motor.signing.lmp import Move
from motor.signing.path_shapes import SIZE_FRACTIONS, circle, curve, line, unit
from motor.signing.plan import SignPlan, SignPlanningError
from motor.signing.reach import arc_fractions
from motor.signing.sites import (
    hand_site,
    is_hand_site,
    leaf_location,
    on_other_hand,
    touches,
)
from motor.trajectory.biocontrol import movement_duration, shortest_duration
from motor.trajectory.symmetry import mirror_directions
from mura.constraints import (
    Arm,
    Constraint,
    Dynamic,
    Parallel,
    Repetition,
    Segment,
    SegmentKind,
    Static,
    Symmetrical,
    Symmetry,
    iter_leaves,
)
from mura.constraints import Sequence as SequenceNode
from mura.signs import HandPosture, Sign
from mura.values import (
    BodySite,
    Direction,
    GridLocation,
    HandShape,
    PalmOrientation,
)

#: Wrist turn of nodding and swinging, forearm turn of twisting, radians.
LOCAL_ANGLE = 0.45
#: How long a static sign holds its posture, seconds (tense: ×1.5 by its manner table).
STATIC_HOLD = 0.5
#: How long a sign with movement holds its first posture before moving, seconds: the
#: initial hold of the citation form (Liddell and Johnson's hold–movement model), which
#: lets the viewer see where the sign's movement begins (a departure from rest).
INITIAL_HOLD = 0.08
#: Half the gap between symmetric hands sent to one central site, metres.
SIDE_BY_SIDE = 0.05
#: The passive non-dominant hand that a one-handed sign touches: flat, palm up, in front.
PASSIVE_POSTURE = HandPosture(
    HandShape("flathand"),
    Direction((0.0, 0.0, 1.0)),
    PalmOrientation((0.0, 1.0, 0.0)),
    GridLocation("LocStomach", "LocCCenterLeft", "LocNorm"),
)
#: HamNoSys manners to (duration manner, profile manner) of the biocontrol tables.
MANNERS: dict[str, str] = {"targetted": "targetted", "fast": "fast", "slow": "slow", "tense": "tense", "halt": "sudden_stop", "rest": "sudden_stop"}
_SAME = 1e-6
#: The movement kind (:data:`motor.trajectory.biocontrol.MOVEMENT_KIND_DURATION`) of each segment kind.
_KINDS = {SegmentKind.LINEAR: "straight", SegmentKind.CURVE: "curved", SegmentKind.CIRCLE: "circle"}
_SAGITTAL = Symmetry(frozenset({"S"}), "SymMS")
_CHANNELS = ("wrist_position", "hand_rotation", "handshape")



@dataclass(eq=False, slots=True)
class _HandMove:
    """One move of one hand on the sign's clock: palm-centre path, rotation and shape keys (unchanged once made, as :class:`PlannedHand`)."""

    start: float
    end: float
    manner: str
    locations: np.ndarray
    rotations: np.ndarray
    shapes: np.ndarray


@dataclass(eq=False)
class _Change:
    """What one leaf does to one hand: new state fields and explicit keys along the way."""

    hand: PlannedHand
    path: np.ndarray | None = None
    rotations: np.ndarray | None = None
    shapes: np.ndarray | None = None
    #: Whether ``path`` is a straight line of evenly spaced points (:func:`line`, or its
    #: displacements mirrored or translated): no reversal, its stopping length at most its chord.
    straight: bool = False


@dataclass(eq=False)
class _Step:
    duration: float
    manner: str
    changes: dict[str, _Change]

class SignCompiler:
    """One sign walked into its hands' first postures and timed moves (module docstring),
    the hands placed and measured by its :class:`HandPlacement`."""

    def __init__(self, geometry: HandGeometry, sign: Sign) -> None:
        self.geometry = geometry
        self.avatar = geometry.avatar
        self.sign = sign
        self.dominant = sign.dominant.side
        self.other = sign.dominant.other.side
        self.arm_length = geometry.arm_length()
        self.warnings: list[str] = []
        self.placement = HandPlacement(geometry, {}, self.note)
        self.moves: dict[str, list[_HandMove]] = {}
        self.clock = 0.0
        symmetry = sign.symmetry
        self.symmetric = symmetry is not None
        self.alternating = bool(symmetry and symmetry.alternating)
        planes = frozenset() if symmetry is None or symmetry.kind == "par" else symmetry.planes | {"S"}
        self.path_mirror = Symmetry(planes, "path")
        self.sagittal = _SAGITTAL
        self.start: dict[str, PlannedHand] = {}
        self.static = False
        self._palm_requests: list[tuple[str, BodySite, np.ndarray, np.ndarray]] | None = None

    @property
    def hands(self) -> dict[str, PlannedHand]:
        """The sign's hands as compiled so far, kept by the placement (a site on the other
        hand is read from them)."""
        return self.placement.hands

    @hands.setter
    def hands(self, hands: dict[str, PlannedHand]) -> None:
        self.placement.hands = hands

    def note(self, message: str) -> None:
        self.warnings.append(f"{self.sign.gloss}: {message}")

    # -- the whole sign ----------------------------------------------------------------

    def compile_sign(self) -> SignCompiler:
        """Walk the sign's movement into hand moves (the first half of planning)."""
        self.initial_postures()
        self.start = dict(self.hands)
        self.static = self.sign.movement is None
        if self.static:
            self.hold(STATIC_HOLD, self.sign.manner if self.sign.manner in MANNERS else "targetted")
        else:
            self.clock = INITIAL_HOLD
            self.compile(self.sign.movement)
            if self.clock <= INITIAL_HOLD:
                self.hold(STATIC_HOLD, "targetted")
        return self

    def palm_offset_requests(self) -> list[tuple[str, BodySite, np.ndarray, np.ndarray]]:
        """The wrist-to-palm offsets :meth:`layout` takes, as ``(side, site, rotation,
        params)``: each first posture's, then per hand and move those of its first and last
        postures; made once, so that they can be computed for the whole collection at once."""
        if self._palm_requests is None:
            self._palm_requests = [self.placement.offset_request(arm, self.placement.rotation(arm, hand), hand.params, PALM) for arm, hand in self.start.items()]
            for arm in self.start:
                for move in self.moves.get(arm, []):
                    self._palm_requests.append(self.placement.offset_request(arm, move.rotations[0], move.shapes[0], PALM))
                    self._palm_requests.append(self.placement.offset_request(arm, move.rotations[-1], move.shapes[-1], PALM))
        return self._palm_requests

    def plan(self) -> SignPlan:
        """The sign's plan from its compiled hand moves (the second half of planning)."""
        return self.plan_from(placed(self.avatar, [self.layout()])[0])

    def layout(self) -> Layout:
        """Each hand's first posture and, per move, its palm path with the offsets from the
        wrist to the palm in the move's first and last postures (:meth:`palm_offset_requests`)."""
        offsets = iter(self.geometry.site_offsets(self.palm_offset_requests()))
        first = {arm: self.placement.pose(arm, hand, next(offsets)) for arm, hand in self.start.items()}
        return Layout(first, {arm: [(move.locations, next(offsets), next(offsets)) for move in self.moves.get(arm, [])] for arm in first})

    def plan_from(self, layout: Layout) -> SignPlan:
        """The plan of a layout whose wrists are kept out of the torso."""
        moves = self.channel_moves(layout)
        return SignPlan(self.sign.gloss, self.clock, layout.first, moves, self.static, dict(self.sign.nonmanual), tuple(self.warnings))

    def hold(self, duration: float, manner: str) -> None:
        scale = movement_duration("straight", MANNERS.get(manner, "targetted")) / movement_duration("straight")
        self.apply(_Step(duration * scale, "targetted", {arm: _Change(hand) for arm, hand in self.hands.items()}))

    # -- postures ------------------------------------------------------------------------

    def initial_postures(self) -> None:
        sign = self.sign
        dominant = sign.posture
        leaves = iter_leaves(sign.movement) if sign.movement is not None else ()
        # the other hand takes part, as a passive base if the dominant hand touches it (a
        # two-handed sign's leaves are not searched for that)
        if sign.two_handed or on_other_hand(dominant.location) or any(on_other_hand(leaf_location(leaf)) for leaf in leaves):
            self.hands[self.other] = self.other_hand()
        self.hands[self.dominant] = self.placement.hand_from(self.dominant, dominant, self.hands.get(self.other))
        if sign.constellation is not None and self.other in self.hands:
            self.place_constellation()
        elif self.symmetric and self.other in self.hands:
            self.side_by_side()

    def other_hand(self) -> PlannedHand:
        posture = self.other_posture()
        hand = self.placement.hand_from(self.other, posture, None)
        own = self.sign.nondominant
        if not self.symmetric or (own is not None and own.ext_finger is not None):
            return hand
        # the non-dominant hand mirrors the dominant hand's orientation
        dominant = self.sign.posture
        fingers = np.asarray(dominant.ext_finger.vector if dominant.ext_finger else NEUTRAL_FINGERS, dtype=float)
        palm = self.placement.palm_vector(self.dominant, fingers, dominant.palm)
        mirrored = hand.turned(mirror_directions(fingers, self.sagittal), mirror_directions(palm, self.sagittal))
        return mirrored.at(self.placement.locate(self.other, posture.location, mirrored, None) + self.placement.part_to_palm(self.other, mirrored, posture.location))

    def other_posture(self) -> HandPosture:
        """The non-dominant hand's posture: its own fields, else the mirrored dominant's
        (symmetric signs), else the passive base's."""
        own = self.sign.nondominant or HandPosture()
        if self.symmetric:
            base = self.sign.posture
            if on_other_hand(base.location):
                base = replace(base, location=None)
        elif self.sign.two_handed and self.sign.nondominant is not None:
            base = replace(PASSIVE_POSTURE, shape=self.sign.posture.shape or PASSIVE_POSTURE.shape)
        else:
            base = PASSIVE_POSTURE
        return HandPosture(
            own.shape or base.shape,
            own.ext_finger or base.ext_finger,
            own.palm or base.palm,
            own.location if own.location is not None else base.location,
        )

    def side_by_side(self) -> None:
        """Symmetric hands sent to the same central site go to either side of it."""
        mine, theirs = self.hands[self.dominant], self.hands[self.other]
        if quat.length(mine.location - theirs.location) > SIDE_BY_SIDE:
            return
        shift = np.array([SIDE_BY_SIDE, 0.0, 0.0])
        sign = 1.0 if self.dominant == "left" else -1.0
        self.hands[self.dominant] = mine.at(mine.location + sign * shift)
        self.hands[self.other] = theirs.at(theirs.location - sign * shift)

    def place_constellation(self) -> None:
        """Put the hands relative to each other (module docstring)."""
        constellation = self.sign.constellation
        assert constellation is not None
        other = self.hands[self.other]
        if constellation.location is not None:
            other = other.at(self.placement.locate(self.other, constellation.location, other, None))
        other_site = hand_site(constellation.nondominant, constellation.contact)
        own_site = hand_site(constellation.dominant, "touch")
        dominant = self.hands[self.dominant]
        self.placement.expect_offsets(
            ([(self.other, other, PALM)] if is_hand_site(other_site) else [])
            + [(self.dominant, dominant, PALM)]
            + ([(self.dominant, dominant, own_site)] if is_hand_site(own_site) else [])
        )  # fmt: skip
        if is_hand_site(other_site):
            pose = self.placement.arm_pose(self.other, other)
            meeting = resolve_location(self.avatar, other_site, AVATAR_SIDE[self.dominant], pose)
        else:
            meeting = other.location
        palm = self.placement.offset(self.dominant, dominant, PALM)
        own = self.placement.offset(self.dominant, dominant, own_site) if is_hand_site(own_site) else palm
        self.hands[self.other] = other
        self.hands[self.dominant] = dominant.at(meeting - own + palm)


    # -- the movement tree ---------------------------------------------------------------

    def compile(self, node: Constraint) -> None:
        if isinstance(node, SequenceNode):
            for child in node.children:
                self.compile(child)
        elif isinstance(node, Parallel):
            self.parallel(node)
        elif isinstance(node, Repetition):
            self.repetition(node)
        elif isinstance(node, Symmetrical):
            self.symmetrical(node)
        elif isinstance(node, Dynamic) and len(node.segments) > 1:
            for segment in node.segments:
                self.apply(self.leaf(replace(node, segments=(segment,))))
        else:
            self.apply(self.leaf(node))

    def parallel(self, node: Parallel) -> None:
        children = _flattened(node)
        leaves = [child for child in children if isinstance(child, (Static, Dynamic))]
        if len(leaves) != len(children):
            self.note("a parallel group with compound parts is performed one part after another")
            for child in children:
                self.compile(child)
            return
        base = dict(self.hands)
        # moves are planned to the hands as the group leaves them: a site on the other hand
        # is where that hand's new orientation puts it
        steps = [self.leaf(leaf) for leaf in leaves if leaf.slot != "HandLocation"]
        places = [leaf for leaf in leaves if leaf.slot == "HandLocation"]
        if places and steps:
            self.hands = {**base, **{arm: change.hand for arm, change in _merge_steps(steps, base).changes.items()}}
        try:
            steps += [self.leaf(leaf) for leaf in places]
        finally:
            self.hands = base
        self.apply(_merge_steps(steps, base))

    def symmetrical(self, node: Symmetrical) -> None:
        """A part of a compound sign with a symmetry of its own: both hands, mirrored (or
        in parallel) as it says, for that part only."""
        saved = (self.symmetric, self.alternating, self.path_mirror)
        planes = frozenset() if node.symmetry.name == "par" else node.symmetry.planes | {"S"}
        self.symmetric, self.alternating, self.path_mirror = True, node.symmetry.alternating, Symmetry(planes, "path")
        try:
            self.compile(node.child)
        finally:
            self.symmetric, self.alternating, self.path_mirror = saved

    def repetition(self, node: Repetition) -> None:
        if node.alternating and self.other in self.hands:
            self.alternating = True
        start_hands, start_clock = dict(self.hands), self.clock
        first = {arm: len(moves) for arm, moves in self.moves.items()}
        self.compile(node.child)
        passed = {arm: self.moves.get(arm, [])[first.get(arm, 0):] for arm in self.hands}
        end_hands, length = dict(self.hands), self.clock - start_clock
        if length <= 0.0:
            return
        shift = self.shift_of(node.displacement)
        for index in range(1, node.count):
            if node.mode == "continue":
                if shift is not None:
                    self.apply(_Step(movement_duration("straight", "targetted"), "lax", self.shifted(self.hands, shift)))
                self.compile(node.child)
            elif node.mode == "reverse" and index % 2 == 1:
                backward = {arm: [_reversed(m, start_clock, start_clock + length) for m in reversed(moves)] for arm, moves in passed.items()}
                self.replay(backward, length)
                self.hands = dict(start_hands)
            else:
                offset = None if shift is None else {arm: index * vector for arm, vector in shift.items()}
                if node.mode != "reverse":
                    back = self.shifted(start_hands, offset) if offset is not None else {arm: _Change(hand) for arm, hand in start_hands.items()}
                    self.apply(_Step(movement_duration("straight", "targetted"), "lax", back))
                self.replay(passed, length, offset)
                self.hands = dict(end_hands) if offset is None else {arm: change.hand for arm, change in self.shifted(end_hands, offset).items()}

    def shift_of(self, displacement: Segment | None) -> dict[str, np.ndarray] | None:
        """Each hand's shift between passes of a displaced repetition (the dominant hand's
        along the displacement, the other hand's mirrored under symmetry), None without one."""
        if displacement is None or displacement.direction is None:
            return None
        size = displacement.size if displacement.size in SIZE_FRACTIONS else "small"
        vector = unit(displacement.direction.vector) * SIZE_FRACTIONS[size] * self.arm_length
        shifts = {self.dominant: vector}
        if self.symmetric and self.other in self.hands:
            shifts[self.other] = mirror_directions(vector, self.path_mirror)
        return shifts

    def shifted(self, hands: Mapping[str, PlannedHand], offset: Mapping[str, np.ndarray]) -> dict[str, _Change]:
        """Changes that put ``hands`` where they are, moved by ``offset`` (hands without one stay)."""
        return {arm: _Change(hand.at(hand.location + offset.get(arm, 0.0))) for arm, hand in hands.items()}

    def replay(self, moves: Mapping[str, list[_HandMove]], length: float, offset: Mapping[str, np.ndarray] | None = None) -> None:
        """The recorded moves of one pass again, from the current clock (moved by ``offset``)."""
        starts = [m.start for ms in moves.values() for m in ms]
        origin = min(starts) if starts else self.clock
        for arm, ms in moves.items():
            shift = 0.0 if offset is None else offset.get(arm, 0.0)
            self.moves.setdefault(arm, []).extend(
                _HandMove(m.start - origin + self.clock, m.end - origin + self.clock, m.manner, m.locations + shift, m.rotations, m.shapes) for m in ms
            )
        self.clock += length

    def apply(self, step: _Step) -> None:
        """Append one step's moves (all hands it changes) and advance the clock."""
        end = self.clock + max(step.duration, _SAME)
        for arm, change in step.changes.items():
            before = self.hands[arm]
            after = change.hand
            path = change.path if change.path is not None else line(before.location, after.location)
            rotations = change.rotations if change.rotations is not None else np.array([self.placement.rotation(arm, before), self.placement.rotation(arm, after)])
            shapes = change.shapes if change.shapes is not None else np.array([before.params, after.params])
            self.moves.setdefault(arm, []).append(_HandMove(self.clock, end, step.manner, path, rotations, shapes))
            self.hands[arm] = after
        self.clock = end

    # -- leaves --------------------------------------------------------------------------

    def arms_of(self, leaf: Static | Dynamic) -> tuple[str, ...]:
        scope = leaf.scope
        if scope in (Arm.RIGHT, Arm.LEFT, "right_arm", "left_arm"):
            arm = Arm(scope).side if isinstance(scope, str) else scope.side
            if arm not in self.hands:
                self.hands[arm] = self.other_hand() if arm == self.other else self.placement.hand_from(arm, self.sign.posture, None)
            return (arm,)
        if self.symmetric and self.other in self.hands:
            return (self.dominant, self.other)
        return (self.dominant,)

    def leaf(self, leaf: Static | Dynamic) -> _Step:
        """What one leaf does to the hands it applies to, from their current state."""
        arms = self.arms_of(leaf)
        if isinstance(leaf, Static):
            segment = Segment(SegmentKind.LINEAR, end=leaf.value, manner="targetted")
        else:
            if not leaf.segments:
                raise SignPlanningError(f"sign {self.sign.gloss!r}: dynamic {leaf.slot} without segments")
            if len(leaf.segments) > 1:
                self.note(f"{leaf.slot}: of {len(leaf.segments)} segments in a parallel group only the first is realized")
            segment = leaf.segments[0]
        manner = MANNERS.get(segment.manner or "targetted")
        if manner is None:
            self.note(f"unknown manner {segment.manner!r}; targetted")
            manner = "targetted"
        lead = arms[0]
        hands = {arm: self.hands[arm] for arm in arms}
        if leaf.slot == "HandLocation":
            change, kind, profile = self.path(lead, hands[lead], segment, manner)
            changes = {lead: change}
            if len(arms) > 1:
                changes[arms[1]] = self.follower_path(arms[1], hands[arms[1]], change, hands[lead])
            elif self.meet_halfway(lead, segment):
                changes = self.met_halfway(lead, change)
        elif leaf.slot in ("HandShape", "ExtFingerOrientation", "PalmOrientation"):
            kind, profile = "straight", manner
            changes = {arm: self.posture_change(arm, hands[arm], leaf.slot, segment, arm != lead) for arm in arms}
        else:
            self.note(f"slot {leaf.slot} is not realized by the hands")
            return _Step(0.0, manner, {})
        duration = movement_duration(kind, manner)
        return _Step(max(duration, self.shortest(changes, profile, duration)), profile, changes)

    def meet_halfway(self, arm: str, segment: Segment) -> bool:
        """Whether the dominant hand's move onto the other hand meets it halfway: under
        symmetry both hands are active, so a constellation they change into (``hamreplace``
        … ``hampinkyside hamplus hampinkyside``) brings them together in front of the
        body's midline, not the dominant hand across to wherever the other one is."""
        return arm == self.dominant and self.symmetric and self.other in self.hands and on_other_hand(segment.end)

    def met_halfway(self, arm: str, change: _Change) -> dict[str, _Change]:
        """The dominant hand's ``change`` onto the other hand, both hands moved sideways
        (x, m) so that where they meet — halfway between the dominant palm's target and the
        other palm — lies on the sagittal plane: the dominant path bent toward it along its
        arc, the other hand on a straight line."""
        assert change.path is not None
        other = self.hands[self.other]
        shift = np.array([-0.5 * (change.hand.location[0] + other.location[0]), 0.0, 0.0])
        path = change.path + arc_fractions(change.path)[:, None] * shift
        moved = other.at(other.location + shift)
        return {
            arm: replace(change, hand=change.hand.at(path[-1]), path=path, straight=False),
            self.other: _Change(moved, path=line(other.location, moved.location), straight=True),
        }

    def shortest(self, changes: Mapping[str, _Change], manner: str, floor: float) -> float:
        """The least time (s) the hands' paths need within the speed budget of ``manner``
        (stopping at each reversal: :func:`motor.signing.lmp.stopping_length`), where it
        may exceed ``floor`` (s), the time the leaf takes anyway.

        When memoizing, a straight path whose chord needs no more than ``floor`` is not
        measured: it is one piece (no reversal), and the B-spline traced within it is no
        longer than its polyline, which is its chord, so its stopping length needs no
        more either (:func:`_chord_bound` adds a margin for the rounding). The leaf's
        duration, the greater of ``floor`` and this, is the same."""
        memoize = self.geometry.memoize
        paths = [
            change.path for change in changes.values()
            if change.path is not None and len(change.path) > 1
            and not (memoize and change.straight and shortest_duration(_chord_bound(change.path), manner) <= floor)
        ]  # fmt: skip
        return max((shortest_duration(self.geometry.stopping_length(path), manner) for path in paths), default=0.0)

    def path(self, arm: str, hand: PlannedHand, segment: Segment, manner: str) -> tuple[_Change, str, str]:
        """The palm-centre path of one HandLocation segment, its kind and time profile."""
        start = hand.location
        size = segment.size if segment.size in SIZE_FRACTIONS else "normal"
        contact = any(m.startswith("contact=") and m != "contact=close" for m in segment.modifiers)
        if segment.end is not None:
            end = self.placement.locate(arm, segment.end, hand, None, here=start) + self.placement.part_to_palm(arm, hand, segment.end)
            contact = contact or touches(segment.end)
        elif segment.direction is not None:
            end = start + unit(segment.direction.vector) * SIZE_FRACTIONS[size] * self.arm_length
        else:
            end = start
        kind = _KINDS[segment.kind]
        straight = False
        if segment.kind is SegmentKind.CIRCLE:
            points = circle(start, segment, self.arm_length)
        elif segment.kind is SegmentKind.CURVE and quat.length(end - start) > _SAME:
            points, note = curve(start, end, segment)
            if note:
                self.note(note)
        else:
            if segment.shape not in (None, "nomotion") and quat.length(end - start) <= _SAME:
                self.note(f"local movement {segment.shape!r} of the hand's location is held in place")
            points = line(start, end)
            straight = True
        if manner == "sudden_stop":
            profile = "sudden_stop"
        elif segment.kind is SegmentKind.CIRCLE:
            profile = "linear"
        elif contact:
            profile = "hard_contact"
        else:
            profile = manner
        return _Change(hand.at(points[-1]), path=points, straight=straight), kind, profile

    def follower_path(self, arm: str, hand: PlannedHand, lead: _Change, lead_hand: PlannedHand) -> _Change:
        """The non-dominant hand's path under symmetry: the dominant's displacements
        mirrored (lr) or translated (par), reversed when alternating."""
        assert lead.path is not None
        displacement = mirror_directions(lead.path - lead.path[0], self.path_mirror)
        if self.alternating:
            displacement = -displacement
        path = hand.location + displacement
        return _Change(hand.at(path[-1]), path=path, straight=lead.straight)

    def posture_change(self, arm: str, hand: PlannedHand, slot: str, segment: Segment, mirrored: bool) -> _Change:
        """A change of shape or orientation (``replace``) or a local movement in place."""
        local = segment.shape
        if local in ("nodding", "swinging", "twisting"):
            return self.local_turn(arm, hand, local)
        if local == "fingerplay":
            return self.fingerplay(hand)
        value = segment.end if segment.end is not None else segment.start
        if value is None:
            self.note(f"{slot} change without a target is held")
            return _Change(hand)
        if slot == "HandShape":
            if not isinstance(value, HandShape):
                raise SignPlanningError(f"sign {self.sign.gloss!r}: HandShape change to {value!r}")
            return _Change(hand.shaped(value, self.geometry.params(value)))
        if slot == "ExtFingerOrientation":
            if not isinstance(value, Direction):
                raise SignPlanningError(f"sign {self.sign.gloss!r}: extended-finger change to {value!r}")
            fingers = np.asarray(value.vector, dtype=float)
            if mirrored:
                fingers = mirror_directions(fingers, self.sagittal)
            return _Change(hand.turned(fingers, hand.palm))
        if not isinstance(value, PalmOrientation):
            raise SignPlanningError(f"sign {self.sign.gloss!r}: palm change to {value!r}")
        palm = self.placement.palm_vector(arm, hand.fingers if not mirrored else mirror_directions(hand.fingers, self.sagittal), value)
        if mirrored:
            palm = mirror_directions(palm, self.sagittal)
        return _Change(hand.turned(hand.fingers, palm))

    def local_turn(self, arm: str, hand: PlannedHand, kind: str) -> _Change:
        """Nodding (wrist flexion), swinging (side to side) or twisting (forearm), there
        and back, about the hand's own axes."""
        rotation = self.placement.rotation(arm, hand)
        frame = self.avatar.hand_frames[AVATAR_SIDE[arm]]
        local_axis = {"nodding": frame.bend_axis, "swinging": frame.splay_axis, "twisting": frame.finger_axis}[kind]
        axis = quat.rotate(rotation, local_axis)
        angles = np.array([0.0, LOCAL_ANGLE, 0.0, -LOCAL_ANGLE, 0.0]) if kind != "nodding" else np.array([0.0, LOCAL_ANGLE, 0.0])
        turns = quat.from_axis_angle(np.broadcast_to(axis, (angles.size, 3)), angles)
        return _Change(hand, rotations=quat.continuous(quat.multiply(turns, rotation)))

    def fingerplay(self, hand: PlannedHand) -> _Change:
        """Fingers moving in turn: index and ring, then middle and pinky, then back, each
        bending or opening by a half bend from its own shape (:func:`motor.hand.shape.played`;
        the folded fingers of a fist or pinch stay folded)."""
        first = played(hand.params, ("index", "ring"))
        second = played(hand.params, ("middle", "pinky"))
        return _Change(hand, shapes=np.stack([hand.params, first, second, first, hand.params]))

    # -- from hand moves to channel moves ------------------------------------------------

    def channel_moves(self, layout: Layout) -> dict[tuple[str, str], tuple[Move, ...]]:
        """Each hand's moves by channel, all of the sign's made at once (:meth:`Move.many`)."""
        channels: dict[tuple[str, str], list[tuple[float, float, str, np.ndarray]]] = {}
        for arm in layout.first:
            moves = self.moves.get(arm, [])
            channels[(arm, "wrist_position")] = [(m.start, m.end, m.manner, w) for m, w in zip(moves, layout.wrists[arm])]
            channels[(arm, "hand_rotation")] = [(m.start, m.end, m.manner, m.rotations) for m in moves]
            channels[(arm, "handshape")] = [(m.start, m.end, m.manner, m.shapes) for m in moves]
        made = iter(Move.many([move for moves in channels.values() for move in moves]))
        return {channel: tuple(next(made) for _ in moves) for channel, moves in channels.items()}

def _flattened(node: Parallel) -> list[Constraint]:
    """The children of nested parallel groups, as one group."""
    children: list[Constraint] = []
    for child in node.children:
        children.extend(_flattened(child) if isinstance(child, Parallel) else [child])
    return children


def _merge_steps(steps: list[_Step], base: Mapping[str, PlannedHand]) -> _Step:
    """Parallel leaves: one step as long as the longest, each hand's fields from the leaf
    that changes them."""
    steps = [s for s in steps if s.changes]
    if not steps:
        return _Step(0.0, "targetted", {})
    longest = max(steps, key=lambda s: s.duration)
    merged: dict[str, _Change] = {}
    for step in steps:
        for arm, change in step.changes.items():
            before = base[arm]
            current = merged.get(arm, _Change(before))
            hand = current.hand
            if not _close(change.hand.location, before.location):
                hand = hand.at(change.hand.location)
            if not (_close(change.hand.fingers, before.fingers) and _close(change.hand.palm, before.palm)):
                hand = hand.turned(change.hand.fingers, change.hand.palm)
            if not _close(change.hand.params, before.params):
                hand = hand.shaped(change.hand.shape, change.hand.params)
            merged[arm] = _Change(
                hand,
                change.path if change.path is not None else current.path,
                change.rotations if change.rotations is not None else current.rotations,
                change.shapes if change.shapes is not None else current.shapes,
            )
    return _Step(longest.duration, longest.manner, merged)


def _close(a: np.ndarray, b: np.ndarray) -> bool:
    """:func:`numpy.allclose` with its default tolerances, for finite values, without its
    overhead (it is asked tens of thousands of times per collection, mostly of 3-vectors
    and of one hand's very parameters): element by element in Python floats, the same
    IEEE arithmetic as numpy's, about six times faster for a 3-vector."""
    if a is b:
        return True
    return all(abs(x - y) <= 1e-8 + 1e-5 * abs(y) for x, y in zip(a.tolist(), b.tolist()))


def _chord_bound(path: np.ndarray) -> float:
    """An upper bound (m) of the stopping length of a straight path ``(m, 3)``: its chord
    with a relative margin of 1e-6 and an absolute one of 1e-9 m, far above the rounding
    of the lengths summed along its points and its traced B-spline (~1e-15 m)."""
    return math.dist(path[0].tolist(), path[-1].tolist()) * (1.0 + 1e-6) + 1e-9


def _reversed(move: _HandMove, pass_start: float, pass_end: float) -> _HandMove:
    """A move of a pass played backwards within the pass (the return stroke of a reversed
    repetition), targetted."""
    return _HandMove(
        pass_start + pass_end - move.end, pass_start + pass_end - move.start, "targetted",
        move.locations[::-1], move.rotations[::-1], move.shapes[::-1],
    )

