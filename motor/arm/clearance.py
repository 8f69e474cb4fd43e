"""How close an arm comes to the body and to the other arm, for candidate elbows at once.

The arm's segments are the avatar's ``upper_arm`` and ``forearm`` capsules, carried along
their bones (the part of each capsule's axis between its end points, projected onto the
bone: the swivel search moves them with the elbow without building rotations). The
obstacles are the body's volumes (torso, pelvis, neck, head and any others that move
with neither arm), each carried rigidly by the joint the avatar file names for it — when
the trunk turns toward a reach, the neck and head turn with the shoulders, a chest on the
thoracic spine turns with the part of it below its joint, and the torso and pelvis stay
with the hips — and optionally the other arm's three capsules at
the same instants.

:func:`clearance` gives, for ``(n, K)`` candidate elbow positions (as coordinate arrays),
a penalty that grows quadratically as a segment comes within :data:`CLEARANCE` of an
obstacle (so the feasible set is entered from its inside, smoothly), and more steeply
once it is more than :data:`TOLERATED_DEPTH` inside, and the depth of the deepest
penetration of the body. Only the frames whose arm, for some candidate, comes
near an obstacle's bounding box are measured against it: by the compiled loops of
:mod:`motor.arm.candidate_clearance` (the body; it also holds the penalty's constants)
and :mod:`motor.arm.other_arm_clearance` (the other arm).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from motor import quaternion as quat
from motor.arm.reach_turn import TURN_JOINTS
from motor.body.avatar import Avatar
from motor.body.conventions import HAND_JOINTS
from motor.arm.candidate_clearance import (
    CLEARANCE,
    CONTACT_PENALTY,
    PENETRATION_PENALTY,
    TOLERATED_DEPTH,
    charge_trunk,
    clearance_rows,
)
from motor.arm.other_arm_clearance import other_arm_rows
from motor.body.distance import Components, volume_table
from motor.body.volumes import TRUNK_NAMES, Capsule, Ellipsoid, EllipticCylinder, Volume

@dataclass(frozen=True, eq=False)
class ArmCapsules:
    """One arm's capsules as the swivel search moves them: the upper arm from ``upper_ends``
    fractions of the way shoulder → elbow, the forearm ``fore_ends`` of elbow → wrist,
    the hand's end points relative to the wrist at rest ``hand_ends (2, 3)``; radii in metres."""

    upper_ends: tuple[float, float]
    upper_radius: float
    fore_ends: tuple[float, float]
    fore_radius: float
    hand_ends: np.ndarray
    hand_radius: float


@dataclass(frozen=True, eq=False)
class Obstacle:
    """A body volume with its axis-aligned bounding box ``(2, 3)`` (rest frame), and how
    many of the joints that turn the trunk where a hand reaches across the body
    (:data:`motor.arm.reach_turn.TURN_JOINTS`) carry it: 0 where it stays with the hips
    (the torso, on the lowest lumbar joint), all of them where it moves with the last or
    a joint beyond (the neck and head), in between for a chest on the thoracic spine;
    ``trunk`` for the trunk's volumes (:data:`motor.body.volumes.TRUNK_NAMES`)."""

    volume: Volume
    box: np.ndarray
    carriers: int
    trunk: bool


@dataclass(frozen=True, eq=False)
class ArmSegments:
    """An arm's posed capsules at ``n`` instants: end points ``(n, 3)`` of the upper arm,
    forearm and hand, and their radii (the obstacles the other arm keeps clear of)."""

    upper: tuple[np.ndarray, np.ndarray]
    fore: tuple[np.ndarray, np.ndarray]
    hand: tuple[np.ndarray, np.ndarray]
    radii: tuple[float, float, float]

    def take(self, rows: np.ndarray) -> ArmSegments:
        pick = lambda ends: (ends[0][rows], ends[1][rows])
        return ArmSegments(pick(self.upper), pick(self.fore), pick(self.hand), self.radii)

    def table(self) -> tuple[np.ndarray, np.ndarray]:
        """The capsules as the compiled loops of :mod:`motor.arm.other_arm_clearance` read
        them: end points ``(3, n, 6)`` (upper arm, forearm, hand; a then b) and radii ``(3,)``."""
        ends = np.stack([np.concatenate(pair, axis=1) for pair in (self.upper, self.fore, self.hand)])
        return np.ascontiguousarray(ends, dtype=float), np.array(self.radii, dtype=float)


@functools.lru_cache(maxsize=32)
def arm_capsules(avatar: Avatar, side: str) -> ArmCapsules:
    """The arm's capsules (:class:`ArmCapsules`) from the avatar's collision volumes."""
    _, shoulder, elbow, wrist = (avatar.rest_positions[i] for i in avatar.arm_joints(side))
    along = lambda point, start, end: float((point - start) @ (end - start) / ((end - start) @ (end - start)))
    upper, fore, hand = (avatar.collision.arm(side, part) for part in ("upper_arm", "forearm", "hand"))
    return ArmCapsules(
        upper_ends=(along(upper.a, shoulder, elbow), along(upper.b, shoulder, elbow)),
        upper_radius=upper.radius,
        fore_ends=(along(fore.a, elbow, wrist), along(fore.b, elbow, wrist)),
        fore_radius=fore.radius,
        hand_ends=np.stack((hand.a - wrist, hand.b - wrist)),
        hand_radius=hand.radius,
    )


@functools.lru_cache(maxsize=32)
def body_obstacles(avatar: Avatar) -> tuple[Obstacle, ...]:
    """The body's volumes with their bounding boxes."""
    limbs = frozenset(f"{side}_{joint}" for side in "lr" for joint in ("sternoclavicular", "shoulder", "elbow", "wrist", *HAND_JOINTS))
    carriers = _turn_carriers(avatar)
    obstacles = []
    for volume in avatar.collision.body(limbs):
        if isinstance(volume, Capsule):
            box = np.stack((np.minimum(volume.a, volume.b) - volume.radius, np.maximum(volume.a, volume.b) + volume.radius))
        elif isinstance(volume, Ellipsoid):
            box = np.stack((volume.center - volume.radii, volume.center + volume.radii))
        else:
            box = np.array([
                [volume.center[0] - volume.half_width, volume.bottom, volume.center[2] - volume.half_depth],
                [volume.center[0] + volume.half_width, volume.top, volume.center[2] + volume.half_depth],
            ])  # fmt: skip
        obstacles.append(Obstacle(volume, box, carriers[avatar.joint_index(volume.joint)], volume.name in TRUNK_NAMES))
    return tuple(obstacles)


@functools.lru_cache(maxsize=32)
def _by_carriers(avatar: Avatar) -> tuple[tuple[Obstacle, ...], ...]:
    """The body's obstacles by how many turning joints carry them (0 … all)."""
    obstacles = body_obstacles(avatar)
    return tuple(tuple(o for o in obstacles if o.carriers == count) for count in range(len(TURN_JOINTS) + 1))


def _turn_carriers(avatar: Avatar) -> list[int]:
    """Per joint, how many of the trunk's turning joints are the joint itself or above it."""
    turning = {avatar.joint_index(name) for name in TURN_JOINTS}
    counts = []
    for index in range(len(avatar.joint_names)):
        count, joint = 0, index
        while joint >= 0:
            count += joint in turning
            joint = avatar.parents[joint]
        counts.append(count)
    return counts


def arm_segments(capsules: ArmCapsules, shoulder: np.ndarray, elbow: np.ndarray, wrist: np.ndarray, hands: np.ndarray) -> ArmSegments:
    """An arm's posed capsules from its joint positions ``(n, 3)`` and global hand rotations ``(n, 4)``."""
    along = lambda start, end, ends: tuple(start + f * (end - start) for f in ends)
    hand = tuple(wrist + quat.rotate(hands, offset) for offset in capsules.hand_ends)
    return ArmSegments(
        along(shoulder, elbow, capsules.upper_ends),
        along(elbow, wrist, capsules.fore_ends),
        hand,
        (capsules.upper_radius, capsules.fore_radius, capsules.hand_radius),
    )


def penalty(distance: np.ndarray) -> np.ndarray:
    """Cost of a signed distance (m): 0 beyond :data:`CLEARANCE`, quadratic inside it."""
    inside = np.maximum(CLEARANCE - distance, 0.0) * (1.0 / CLEARANCE)
    return CONTACT_PENALTY * inside * inside


def overlap_penalty(distance: np.ndarray) -> np.ndarray:
    """Cost of a segment's signed distance (m) from a body volume or the other arm's upper
    arm or forearm: :func:`penalty`, and :func:`penetration_penalty` of its depth."""
    return penalty(distance) + penetration_penalty(-distance)


def penetration_penalty(depth: np.ndarray) -> np.ndarray:
    """What a depth ``depth`` (m) into the body pays beyond :data:`TOLERATED_DEPTH`:
    :data:`PENETRATION_PENALTY` per :data:`CLEARANCE` of it, squared (0 at a distance).
    Part of :func:`overlap_penalty`, and what a candidate swivel beyond the measured
    window pays (:mod:`motor.arm.swivel_cost`)."""
    beyond = np.maximum(depth - TOLERATED_DEPTH, 0.0) * (1.0 / CLEARANCE)
    return PENETRATION_PENALTY * beyond * beyond


def clearance(
    avatar: Avatar,
    side: str,
    shoulder: np.ndarray,
    wrist: np.ndarray,
    elbow: Components,
    body_frame: tuple[np.ndarray, np.ndarray] | None = None,
    other: ArmSegments | None = None,
    body: bool = True,
    carried_frames: tuple[tuple[np.ndarray, np.ndarray], ...] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Penalty and body penetration depth (m) ``(n, K)`` of the arm from ``shoulder`` to
    ``wrist`` ``(n, 3)`` with its elbow at the coordinate arrays ``elbow`` ``(n, K)``.

    ``body_frame`` (rotation ``(n, 4)``, translation ``(n, 3)``) carries the body's rest
    geometry to where it is when the torso is not upright (None: upright, at rest);
    ``carried_frames``, if given, do so for the volumes that do not turn with the whole
    trunk (by :attr:`Obstacle.carriers`: :meth:`motor.arm.reach_turn.TrunkTurn.carried_frames`),
    which stand still or turn less while the arm is solved in the turned trunk's frame.
    ``other``: the other arm's capsules at the same instants, kept clear of too;
    ``body``: False to keep clear of the other arm only."""
    capsules = arm_capsules(avatar, side)
    shape = elbow[0].shape
    cost, depth = _body_costs(avatar, capsules, shoulder, wrist, elbow, body_frame, carried_frames) if body else (np.zeros(shape), np.zeros(shape))
    if other is not None:
        _other_arm_clearance(capsules, shoulder, wrist, elbow, other, cost)
    return cost, np.maximum(depth, 0.0)


def _other_arm_clearance(capsules: ArmCapsules, shoulder: np.ndarray, wrist: np.ndarray, elbow: Components, other: ArmSegments, cost: np.ndarray) -> None:
    """Add into ``cost`` (contiguous ``(n, K)``) what the candidate elbows pay for coming near
    the ``other`` arm's capsules: :func:`overlap_penalty` of the distance from its upper arm
    and forearm, :func:`penalty` from its hand (hands may touch the other arm where it is
    asked). Compiled (:func:`motor.arm.other_arm_clearance.other_arm_rows`)."""
    ex, ey, ez = (np.ascontiguousarray(np.broadcast_to(c, cost.shape), dtype=float) for c in elbow)
    other_arm_rows(np.ascontiguousarray(shoulder, dtype=float), np.ascontiguousarray(wrist, dtype=float), ex, ey, ez, segment_table(capsules), *other.table(), cost)


def _body_costs(
    avatar: Avatar,
    capsules: ArmCapsules,
    shoulder: np.ndarray,
    wrist: np.ndarray,
    elbow: Components,
    body_frame: tuple[np.ndarray, np.ndarray] | None,
    carried_frames: tuple[tuple[np.ndarray, np.ndarray], ...] | None,
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`clearance`'s penalty and depth from the body ``(n, K)``: the instants where
    the trunk does not turn (all of them without ``carried_frames``) against
    :func:`upright_obstacles`, the others against every volume where the joints above it
    carry it (:func:`body_groups`). The trunk's volumes (a torso and a chest: one body
    cut in two) are not penalized one by one but by each segment's least distance from
    any of them, so that a segment near the cut pays once. Each instant's figures are
    its own, whatever the others. Compiled (:func:`motor.arm.candidate_clearance.clearance_rows`,
    then :func:`motor.arm.candidate_clearance.charge_trunk`)."""
    shape = np.broadcast_shapes(*(c.shape for c in elbow))
    ex, ey, ez = (np.ascontiguousarray(np.broadcast_to(c, shape), dtype=float) for c in elbow)
    kinds, parameters, boxes, in_trunk, groups, sets = body_groups(upright_obstacles(avatar), _by_carriers(avatar))
    count = len(TURN_JOINTS) + 1
    rotations, translations = np.zeros((count, shape[0], 4)), np.zeros((count, shape[0], 3))
    framed = np.zeros(count, dtype=np.bool_)
    for slot, frame in enumerate((*(carried_frames or (None,) * (count - 1)), body_frame)):
        if frame is not None:
            rotations[slot], translations[slot] = frame
            framed[slot] = True
    turned = np.zeros(shape[0], dtype=np.bool_) if carried_frames is None else ~np.all(carried_frames[0][0] == quat.IDENTITY, axis=1)
    cost, depth = np.zeros(shape), np.zeros(shape)
    trunk = (np.full(shape, np.inf), np.full(shape, np.inf))
    clearance_rows(
        np.ascontiguousarray(shoulder, dtype=float), np.ascontiguousarray(wrist, dtype=float), ex, ey, ez,
        rotations, translations, framed, groups, sets, turned, segment_table(capsules), kinds, parameters, boxes, in_trunk,
        cost, depth, *trunk,
    )  # fmt: skip
    charge_trunk(cost, *trunk)
    return cost, depth


@functools.lru_cache(maxsize=32)
def body_groups(upright: tuple[Obstacle, ...], by_carriers: tuple[tuple[Obstacle, ...], ...]) -> tuple[np.ndarray, ...]:
    """The body's obstacles as :func:`motor.arm.candidate_clearance.clearance_rows` reads
    them: an :func:`obstacle_table` of the ``upright`` ones (:func:`upright_obstacles`)
    followed by those of ``by_carriers``, by how many turning joints carry them (0 … all:
    :func:`_by_carriers`); the groups ``(G, 3)`` — first obstacle, stop, and the frame
    that carries them (``j`` < all: the ``j``-th carried frame, all: the body's frame);
    and which groups serve an upright and a turned trunk ``(2, 2)`` (first group, stop)."""
    parts = [(upright, len(by_carriers) - 1)] + [(found, slot) for slot, found in enumerate(by_carriers) if found]
    obstacles, groups, first = [], [], 0
    for found, slot in parts:
        obstacles.extend(found)
        groups.append((first, first + len(found), slot))
        first += len(found)
    spans = np.array(groups, dtype=np.int64), np.array([[0, 1], [1, len(groups)]], dtype=np.int64)
    for array in spans:
        array.setflags(write=False)
    return (*obstacle_table(tuple(obstacles)), *spans)


@functools.lru_cache(maxsize=32)
def upright_obstacles(avatar: Avatar) -> tuple[Obstacle, ...]:
    """The body's obstacles where no part of the spine turns: the trunk's pieces, where they
    are elliptic cylinders of one cross-section stacked without a gap, as the one cylinder
    they make (the same body, one distance to measure instead of two, and no cut)."""
    obstacles = body_obstacles(avatar)
    trunk = sorted((o for o in obstacles if o.trunk), key=lambda o: getattr(o.volume, "bottom", 0.0))
    if len(trunk) < 2 or not _stacked([o.volume for o in trunk]):
        return obstacles
    lower, upper = trunk[0].volume, trunk[-1].volume
    whole = EllipticCylinder(lower.name, lower.joint, lower.center, lower.half_width, lower.half_depth, lower.bottom, upper.top)
    box = np.stack((np.min([o.box[0] for o in trunk], axis=0), np.max([o.box[1] for o in trunk], axis=0)))
    return (*(o for o in obstacles if not o.trunk), Obstacle(whole, box, trunk[0].carriers, True))


def _stacked(volumes: list[Volume]) -> bool:
    """Whether the volumes, lowest first, are elliptic cylinders of one cross-section, each
    starting where the one below ends."""
    if not all(isinstance(v, EllipticCylinder) for v in volumes):
        return False
    first = volumes[0]
    same = all(
        np.allclose(v.center[[0, 2]], first.center[[0, 2]]) and np.isclose(v.half_width, first.half_width) and np.isclose(v.half_depth, first.half_depth)
        for v in volumes
    )
    return same and all(np.isclose(low.top, high.bottom) for low, high in zip(volumes, volumes[1:]))


@functools.lru_cache(maxsize=32)
def segment_table(capsules: ArmCapsules) -> np.ndarray:
    """The arm's segments as the compiled clearance reads them ``(2, 4)``: the upper arm's
    and the forearm's end fractions, radius, and 1 where the fractions count from the
    shoulder toward the elbow (0: from the elbow toward the wrist)."""
    table = np.array([
        [*capsules.upper_ends, capsules.upper_radius, 1.0],
        [*capsules.fore_ends, capsules.fore_radius, 0.0],
    ])  # fmt: skip
    table.setflags(write=False)
    return table


@functools.lru_cache(maxsize=64)
def obstacle_table(obstacles: tuple[Obstacle, ...]) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The obstacles as the compiled clearance reads them: :func:`volume_table`'s kinds and
    parameters, the bounding boxes ``(V, 2, 3)`` and which are the trunk's."""
    kinds, parameters = volume_table(tuple(o.volume for o in obstacles))
    boxes = np.array([o.box for o in obstacles], dtype=float).reshape(-1, 2, 3)
    return kinds, parameters, boxes, np.array([o.trunk for o in obstacles], dtype=np.bool_)


def load_kernels() -> None:
    """Run this module's compiled loops once (they load when the module is imported):
    :func:`motor.compiled.warm_up`."""
    capsules = ArmCapsules((0.0, 1.0), 0.05, (0.0, 1.0), 0.04, np.zeros((2, 3)), 0.03)
    point, elbow = np.zeros((1, 3)), np.ones((1, 1))
    cells = [np.zeros((1, 1)) for _ in range(4)]
    groups, sets = np.array([[0, 0, 0]]), np.array([[0, 1], [0, 1]])
    flags = np.zeros(1, dtype=np.bool_)
    clearance_rows(point, point, elbow, elbow, elbow, np.zeros((1, 1, 4)), np.zeros((1, 1, 3)), flags, groups, sets, flags, segment_table(capsules), *obstacle_table(()), *cells)
    charge_trunk(*cells[:3])
