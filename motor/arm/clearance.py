"""How close an arm comes to the body and to the other arm, for candidate elbows at once.

The arm's segments are the avatar's ``upper_arm`` and ``forearm`` capsules, carried along
their bones (the part of each capsule's axis between its end points, projected onto the
bone: the swivel search moves them with the elbow without building rotations). The
obstacles are the body's volumes (torso, pelvis, neck, head and any others that move
with neither arm), carried rigidly by the clavicles' parent joint when the torso turns,
and optionally the other arm's three capsules at the same instants.

:func:`clearance` gives, for ``(n, K)`` candidate elbow positions, a penalty that grows
quadratically as a segment comes within :data:`CLEARANCE` of an obstacle (so the
feasible set is entered from its inside, smoothly) and the depth of the deepest
penetration of the body. Obstacles no candidate of a frame can reach are skipped by a
bound: every candidate arm lies within the circle's radius of the two segments from the
shoulder and the wrist to the circle's centre.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from motor import quaternion as quat
from motor.arm.chain import ElbowCircle
from motor.body.avatar import HAND_JOINTS, Avatar
from motor.body.collision import capsule_distance, point_segment_distance, segment_distance
from motor.body.volumes import Capsule, Ellipsoid, Volume

#: Clearance (m) a segment keeps from an obstacle before it is penalized.
CLEARANCE = 0.01
#: Penalty of a segment at the obstacle's surface; it grows with the square of the
#: distance inside the clearance, per :data:`CLEARANCE`.
CONTACT_PENALTY = 50.0


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
    """A body volume with the bounding sphere (centre, radius; rest frame) that decides
    whether a frame's arm can reach it."""

    volume: Volume
    center: np.ndarray
    bound: float


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

    def capsules(self) -> tuple[tuple[np.ndarray, np.ndarray, float], ...]:
        return tuple((a, b, r) for (a, b), r in zip((self.upper, self.fore, self.hand), self.radii))


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
    """The body's volumes with their bounding spheres."""
    limbs = frozenset(f"{side}_{joint}" for side in "lr" for joint in ("sternoclavicular", "shoulder", "elbow", "wrist", *HAND_JOINTS))
    obstacles = []
    for volume in avatar.collision.body(limbs):
        if isinstance(volume, Capsule):
            center, bound = 0.5 * (volume.a + volume.b), 0.5 * float(np.linalg.norm(volume.b - volume.a)) + volume.radius
        elif isinstance(volume, Ellipsoid):
            center, bound = np.asarray(volume.center), float(np.max(volume.radii))
        else:
            center = np.array([volume.center[0], 0.5 * (volume.bottom + volume.top), volume.center[2]])
            bound = float(np.hypot(max(volume.half_width, volume.half_depth), 0.5 * (volume.top - volume.bottom)))
        obstacles.append(Obstacle(volume, center, bound))
    return tuple(obstacles)


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
    inside = np.maximum(CLEARANCE - distance, 0.0) / CLEARANCE
    return CONTACT_PENALTY * inside * inside


def clearance(
    avatar: Avatar,
    side: str,
    circle: ElbowCircle,
    elbow: np.ndarray,
    body_frame: tuple[np.ndarray, np.ndarray] | None = None,
    other: ArmSegments | None = None,
    body: bool = True,
) -> tuple[np.ndarray, np.ndarray]:
    """Penalty and body penetration depth (m) ``(n, K)`` of the arm with its elbow at
    ``elbow (n, K, 3)`` on ``circle`` (wrist at ``circle.wrist``).

    ``body_frame`` (rotation ``(n, 4)``, translation ``(n, 3)``) carries the body's rest
    geometry to where it is when the torso is not upright (None: upright, at rest).
    ``other``: the other arm's capsules at the same instants, kept clear of too;
    ``body``: False to keep clear of the other arm only."""
    capsules = arm_capsules(avatar, side)
    shoulder, wrist = circle.shoulder, circle.wrist
    cost = np.zeros(elbow.shape[:2])
    depth = np.zeros(elbow.shape[:2])
    reach = max(capsules.upper_radius, capsules.fore_radius) + CLEARANCE
    if body_frame is None:
        rest_shoulder, rest_elbow, rest_wrist, rest_center = shoulder, elbow, wrist, circle.center
    else:
        rotation, translation = body_frame
        inverse = quat.conjugate(rotation)
        rest_shoulder, rest_wrist, rest_center = (quat.rotate(inverse, p - translation) for p in (shoulder, wrist, circle.center))
        rest_elbow = quat.rotate(inverse[:, None], elbow - translation[:, None])
    for obstacle in body_obstacles(avatar) if body else ():
        near = _within(obstacle.center, obstacle.bound + reach, rest_shoulder, rest_center, rest_wrist, circle.radius)
        if not np.any(near):
            continue
        rows = np.flatnonzero(near)
        s, e, w = rest_shoulder[rows][:, None], rest_elbow[rows], rest_wrist[rows][:, None]
        for a, b, radius in _segments(capsules, s, e, w):
            distance = capsule_distance(obstacle.volume, a, b, radius)
            cost[rows] += penalty(distance)
            depth[rows] = np.maximum(depth[rows], -distance)
    if other is not None:
        for a_other, b_other, r_other in other.capsules():
            near = _segment_within(a_other, b_other, r_other + reach, shoulder, circle.center, wrist, circle.radius)
            if not np.any(near):
                continue
            rows = np.flatnonzero(near)
            s, e, w = shoulder[rows][:, None], elbow[rows], wrist[rows][:, None]
            for a, b, radius in _segments(capsules, s, e, w):
                distance = segment_distance(a, b, a_other[rows][:, None], b_other[rows][:, None]) - radius - r_other
                cost[rows] += penalty(distance)
    return cost, np.maximum(depth, 0.0)


def _segments(capsules: ArmCapsules, s: np.ndarray, e: np.ndarray, w: np.ndarray):
    """The upper arm's and forearm's capsules (end points broadcast to ``e``'s shape, radius)."""
    (u0, u1), (f0, f1) = capsules.upper_ends, capsules.fore_ends
    yield s + u0 * (e - s), s + u1 * (e - s), capsules.upper_radius
    yield e + f0 * (w - e), e + f1 * (w - e), capsules.fore_radius


def _within(center: np.ndarray, distance: float, shoulder: np.ndarray, middle: np.ndarray, wrist: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """Frames ``(n,)`` whose arm, for some swivel, may come within ``distance`` of ``center``."""
    nearest = np.minimum(point_segment_distance(center, shoulder, middle), point_segment_distance(center, middle, wrist))
    return nearest - radius < distance


def _segment_within(
    a: np.ndarray, b: np.ndarray, distance: float, shoulder: np.ndarray, middle: np.ndarray, wrist: np.ndarray, radius: np.ndarray
) -> np.ndarray:
    """Frames whose arm, for some swivel, may come within ``distance`` of segments ``a``–``b``."""
    nearest = np.minimum(segment_distance(a, b, shoulder, middle), segment_distance(a, b, middle, wrist))
    return nearest - radius < distance
