"""The body's collision volumes in a pose: placement, signed distances, clear wrist targets.

* :func:`joint_placement` / :func:`to_rest` carry points between the avatar frame and a
  volume's rest frame (a volume moves rigidly with its joint; :mod:`motor.body.volumes`);
* :func:`segment_distance` and :func:`capsule_distance` give signed distances between a
  capsule and any volume, vectorized over any leading axes (frames, candidates): exact
  for capsules, along the radial direction for ellipsoids and elliptic cylinders (exact
  for spheres and circular cylinders; for the body's mildly elliptic shapes the sign is
  exact and the depth within a few millimetres near the surface, within 10 % deep inside);
* :func:`outside_torso` keeps wrist targets out of the torso, smoothly (C¹): a path that
  crosses the torso's front, top or bottom bends around it without a speed step;
* :func:`separate_hands` keeps the two hands a palm thickness apart (hands touch, never
  overlap), smoothly too; hands whose paths cross pass one over the other.
"""

from __future__ import annotations

import numpy as np

from motor import quaternion as quat
from motor.body.avatar import Avatar
from motor.body.volumes import Capsule, Ellipsoid, EllipticCylinder, Volume

#: Clearance of the wrist from the torso surface, metres.
TORSO_MARGIN = 0.04
#: Width (m) of the band above the torso's front in which a wrist target is eased out,
#: and of the bands beyond its top, bottom and sides over which the push fades.
SOFT_BAND = 0.02
EDGE_BAND = 0.025
#: Width (m) of the band above the palm thickness in which two hands are eased apart: a
#: contact the planner places exactly at the palm thickness (:mod:`motor.program.fragment`)
#: is left at most ``HAND_BAND / e`` (0.7 mm) wider.
HAND_BAND = 0.002
#: Share of a hand's midline, from either end, within which the nearest point to the other
#: hand counts as at that end (hands meeting end to end, :func:`separate_hands`).
END_SHARE = 0.1
#: Sine of the angle between the hands' long axes from which they count as crossing.
CROSSING_SINE = 0.3
#: Side the left hand takes where the hands cross: up, a little to the left and forward.
_PREFERRED = np.array([0.1, 1.0, 0.01])
_TINY = 1e-12


def joint_placement(avatar: Avatar, positions: np.ndarray, orientations: np.ndarray, joint: str) -> tuple[np.ndarray, np.ndarray]:
    """Rotation ``(n, 4)`` and translation ``(n, 3)`` carrying a joint's rest geometry to
    its pose: ``posed = rotate(rotation, rest) + translation``. ``positions (n, J, 3)`` and
    ``orientations (n, J, 4)`` are forward kinematics' global joint poses."""
    index = avatar.joint_index(joint)
    rotation = orientations[:, index]
    return rotation, positions[:, index] - quat.rotate(rotation, avatar.rest_positions[index])


def to_rest(rotation: np.ndarray, translation: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Posed points ``(n, ..., 3)`` expressed in the rest frame of a placement ``(n, 4)``, ``(n, 3)``."""
    extra = (slice(None),) + (None,) * (points.ndim - 2)
    return quat.rotate(quat.conjugate(rotation)[extra], points - translation[extra])


def posed_capsule(capsule: Capsule, rotation: np.ndarray, translation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A capsule's end points ``(n, 3)`` in a placement."""
    return quat.rotate(rotation, capsule.a) + translation, quat.rotate(rotation, capsule.b) + translation


#: A vector field as its three coordinate arrays (any broadcastable shapes): the layout
#: of the swivel search, where contiguous ``(n, K)`` arrays per coordinate are fastest.
Components = tuple[np.ndarray, np.ndarray, np.ndarray]


def components(v: np.ndarray) -> Components:
    """The coordinate arrays of vectors ``(..., 3)``."""
    return v[..., 0], v[..., 1], v[..., 2]


def _dot(u: Components, v: Components) -> np.ndarray:
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def _minus(u: Components, v: Components) -> Components:
    return u[0] - v[0], u[1] - v[1], u[2] - v[2]


def _clip01(value: np.ndarray) -> np.ndarray:
    return np.minimum(np.maximum(value, 0.0), 1.0)


def closest_parameters(p0: np.ndarray, p1: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Parameters ``s, t`` in [0, 1] of the closest points ``p0 + s (p1 - p0)`` and
    ``q0 + t (q1 - q0)`` of two segments (arrays ``(..., 3)`` broadcast; degenerate
    segments allowed)."""
    return _closest(components(p0), components(p1), components(q0), components(q1))


def _closest(p0: Components, p1: Components, q0: Components, q1: Components) -> tuple[np.ndarray, np.ndarray]:
    d1, d2, r = _minus(p1, p0), _minus(q1, q0), _minus(p0, q0)
    a, e, f = _dot(d1, d1), _dot(d2, d2), _dot(d2, r)
    b, c = _dot(d1, d2), _dot(d1, r)
    a_safe, e_safe = np.maximum(a, _TINY), np.maximum(e, _TINY)
    denominator = a * e - b * b
    s = np.where(denominator > _TINY * np.maximum(a * e, _TINY), _clip01((b * f - c * e) / np.maximum(denominator, _TINY)), 0.0)
    t = (b * s + f) / e_safe
    s = np.where(t < 0.0, _clip01(-c / a_safe), np.where(t > 1.0, _clip01((b - c) / a_safe), s))
    s = np.where(a > _TINY, s, 0.0)
    t = np.where(e > _TINY, _clip01(t), 0.0)
    return s, t


def segment_distance(p0: np.ndarray, p1: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """Shortest distance between segments ``p0``–``p1`` and ``q0``–``q1`` (arrays ``(..., 3)`` broadcast)."""
    return segments_apart(components(p0), components(p1), components(q0), components(q1))


def segments_apart(p0: Components, p1: Components, q0: Components, q1: Components) -> np.ndarray:
    """:func:`segment_distance` of segments given by coordinate arrays."""
    s, t = _closest(p0, p1, q0, q1)
    gap = tuple((p0[i] + s * (p1[i] - p0[i])) - (q0[i] + t * (q1[i] - q0[i])) for i in range(3))
    return np.sqrt(_dot(gap, gap))


def point_segment_distance(point: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """Distance from points to segments ``q0``–``q1`` (arrays ``(..., 3)`` broadcast)."""
    p, a, b = components(point), components(q0), components(q1)
    d = _minus(b, a)
    t = _clip01(_dot(_minus(p, a), d) / np.maximum(_dot(d, d), _TINY))
    gap = tuple(p[i] - (a[i] + t * d[i]) for i in range(3))
    return np.sqrt(_dot(gap, gap))


def capsule_distance(volume: Volume, a: np.ndarray, b: np.ndarray, radius: float | np.ndarray) -> np.ndarray:
    """Signed distance (m, negative inside) between the capsule ``a``–``b`` with
    ``radius`` and ``volume``; ``a``, ``b`` ``(..., 3)`` in the volume's rest frame."""
    return capsule_apart(volume, components(a), components(b), radius)


def capsule_apart(volume: Volume, a: Components, b: Components, radius: float | np.ndarray) -> np.ndarray:
    """:func:`capsule_distance` of a capsule given by coordinate arrays."""
    if isinstance(volume, Capsule):
        return segments_apart(a, b, tuple(volume.a), tuple(volume.b)) - volume.radius - radius
    if isinstance(volume, Ellipsoid):
        return _ellipsoid_distance(volume, a, b) - radius
    return _cylinder_distance(volume, a, b) - radius


def _ellipsoid_distance(ellipsoid: Ellipsoid, a: Components, b: Components) -> np.ndarray:
    """Signed radial distance of a segment from an ellipsoid: the segment's point nearest
    the centre in the space where the ellipsoid is a unit sphere, measured along its ray."""
    (cx, cy, cz), (rx, ry, rz) = ellipsoid.center, ellipsoid.radii
    p0 = ((a[0] - cx) / rx, (a[1] - cy) / ry, (a[2] - cz) / rz)
    d = ((b[0] - a[0]) / rx, (b[1] - a[1]) / ry, (b[2] - a[2]) / rz)
    t = _clip01(-_dot(p0, d) / np.maximum(_dot(d, d), _TINY))
    scaled = (p0[0] + t * d[0], p0[1] + t * d[1], p0[2] + t * d[2])
    rho = np.sqrt(_dot(scaled, scaled))
    unscaled = (scaled[0] * rx, scaled[1] * ry, scaled[2] * rz)
    return np.sqrt(_dot(unscaled, unscaled)) * (1.0 - 1.0 / np.maximum(rho, 1e-9))


def _cylinder_distance(cylinder: EllipticCylinder, a: Components, b: Components) -> np.ndarray:
    """Signed distance of a segment from a vertical elliptic cylinder: within the height
    range, radial (as :func:`_ellipsoid_distance`, in the horizontal plane); a segment
    wholly above or below it is as far as its nearest end's vertical and radial gaps."""
    width, depth = cylinder.half_width, cylinder.half_depth
    x0, z0 = (a[0] - cylinder.center[0]) / width, (a[2] - cylinder.center[2]) / depth
    dx, dz = (b[0] - a[0]) / width, (b[2] - a[2]) / depth
    y0, dy = a[1], b[1] - a[1]
    flat = np.abs(dy) <= _TINY
    safe = np.where(flat, _TINY, dy)
    low, high = (cylinder.bottom - y0) / safe, (cylinder.top - y0) / safe
    level = (y0 >= cylinder.bottom) & (y0 <= cylinder.top)
    enter = np.maximum(np.where(flat, np.where(level, 0.0, 2.0), np.minimum(low, high)), 0.0)
    leave = np.minimum(np.where(flat, 1.0, np.maximum(low, high)), 1.0)
    inside = enter <= leave
    t = np.minimum(np.maximum(-(x0 * dx + z0 * dz) / np.maximum(dx * dx + dz * dz, _TINY), enter), np.maximum(leave, enter))
    # outside the height range: the end nearer to it
    middle = 0.5 * (cylinder.bottom + cylinder.top)
    t = np.where(inside, t, np.where(np.abs(y0 + dy - middle) < np.abs(y0 - middle), 1.0, 0.0))
    sx, sz = x0 + t * dx, z0 + t * dz
    rho = np.sqrt(sx * sx + sz * sz)
    radial = np.sqrt((sx * width) ** 2 + (sz * depth) ** 2) * (1.0 - 1.0 / np.maximum(rho, 1e-9))
    y = y0 + t * dy
    vertical = np.maximum(cylinder.bottom - y, y - cylinder.top)
    return np.where(inside, radial, np.where(radial > 0.0, np.sqrt(vertical * vertical + radial * radial), vertical))


def outside_torso(avatar: Avatar, points: np.ndarray) -> np.ndarray:
    """Wrist positions ``(n, 3)`` (avatar frame at rest, metres) kept out of the torso.

    The torso's elliptic cylinder grown by :data:`TORSO_MARGIN`: a point inside it, or
    behind it within its width, is moved forward to its front surface; a point in front
    of the surface by less than :data:`SOFT_BAND` is eased out with a C¹ curve (so a path
    meeting the surface bends instead of stopping dead), and beyond the torso's top,
    bottom and sides the push fades out over :data:`EDGE_BAND`. Points farther away are
    unchanged; no moved point is left inside."""
    torso = avatar.torso
    a, b = torso.half_width + TORSO_MARGIN, torso.half_depth + TORSO_MARGIN
    dx = np.abs(points[:, 0] - torso.center[0]) / a
    front = torso.center[2] + b * np.sqrt(_clip01(1.0 - dx * dx))
    gap = points[:, 2] - front
    eased = np.where(gap >= SOFT_BAND, gap, SOFT_BAND * np.exp(np.minimum(gap, SOFT_BAND) / SOFT_BAND - 1.0))
    fade = (
        _fade(torso.bottom - points[:, 1])
        * _fade(points[:, 1] - torso.top)
        * _fade((dx - 1.0) * a)
    )
    push = (eased - gap) * fade
    if not np.any(push > 0.0):
        return points
    out = np.array(points, dtype=float)
    out[:, 2] += push
    return out


def inside_torso(avatar: Avatar, points: np.ndarray) -> np.ndarray:
    """Which wrist positions ``(n, 3)`` lie inside the torso grown by :data:`TORSO_MARGIN`,
    or behind it within its width: those :func:`outside_torso` moves out (it never leaves
    one there)."""
    torso = avatar.torso
    a, b = torso.half_width + TORSO_MARGIN, torso.half_depth + TORSO_MARGIN
    dx = (points[:, 0] - torso.center[0]) / a
    front = torso.center[2] + b * np.sqrt(_clip01(1.0 - dx * dx))
    return (np.abs(dx) < 1.0) & (points[:, 2] < front) & (points[:, 1] > torso.bottom) & (points[:, 1] < torso.top)


def _fade(beyond: np.ndarray) -> np.ndarray:
    """1 where ``beyond`` ≤ 0 (inside an edge), falling smoothly to 0 at :data:`EDGE_BAND`."""
    u = np.minimum(np.maximum(beyond / EDGE_BAND, 0.0), 1.0)
    return 1.0 - u * u * (3.0 - 2.0 * u)


def hand_segments(avatar: Avatar, side: str, wrists: np.ndarray, hands: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """End points ``(n, 3)`` of a hand's capsule for wrist positions and global hand
    rotations ``(n, 4)``."""
    capsule = avatar.collision.arm(side, "hand")
    wrist_rest = avatar.rest_positions[avatar.joint_index(f"{side}_wrist")]
    return wrists + quat.rotate(hands, capsule.a - wrist_rest), wrists + quat.rotate(hands, capsule.b - wrist_rest)


def separate_hands(
    avatar: Avatar, left: np.ndarray, right: np.ndarray, left_hands: np.ndarray, right_hands: np.ndarray, allowance: float = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """Wrist positions ``(n, 3)`` of both arms moved apart where their hands would come
    closer than the palm thickness (the distance of the hands' midlines when palm meets
    palm): each wrist moves half the deficit along the line between the hands' nearest
    points. Where the hands cross or coincide that line is tilted toward
    :func:`_parting`, which it becomes where they meet. The distance kept eases in C¹
    from :data:`HAND_BAND` above the thickness, so hands meet without a speed step;
    hands farther apart are unchanged. With an ``allowance`` (m) the hands may come that
    much nearer than the palm thickness before they are moved (a second look at hands
    already eased apart as asked)."""
    palm = avatar.collision.palm_thickness
    thickness = palm - allowance
    near = np.flatnonzero(hands_may_meet(avatar, left, right))
    if near.size == 0:
        return left, right
    l0, l1 = hand_segments(avatar, "l", left[near], left_hands[near])
    r0, r1 = hand_segments(avatar, "r", right[near], right_hands[near])
    s, t = closest_parameters(l0, l1, r0, r1)
    between = (l0 + s[:, None] * (l1 - l0)) - (r0 + t[:, None] * (r1 - r0))
    gap = quat.norm(between) - thickness
    if not np.any(gap < HAND_BAND):
        return left, right
    eased = np.where(gap >= HAND_BAND, gap, HAND_BAND * np.exp(np.minimum(gap, HAND_BAND) / HAND_BAND - 1.0))
    # where the hands (nearly) pass through each other, the line between them means little:
    # tilt it toward the way they part — not where they meet end to end (fingertips or
    # wrists touching: both nearest points at an end), which part along that line, as
    # mirrored hands do symmetrically, unless the ends (nearly) coincide
    distance = quat.norm(between)
    meeting = np.maximum(1.0 - distance / (0.5 * palm), 0.0)
    through = np.minimum(np.maximum(np.minimum(s, 1.0 - s), np.minimum(t, 1.0 - t)) / END_SHARE, 1.0)
    coinciding = np.maximum(1.0 - distance / (END_SHARE * palm), 0.0)
    tilt = (meeting * np.maximum(through, coinciding))[:, None]
    direction = between + 0.25 * palm * tilt * _parting(l1 - l0, r1 - r0)
    direction = direction / np.maximum(quat.norm(direction), _TINY)[:, None]
    half = (0.5 * (eased - gap))[:, None] * direction
    left, right = np.array(left, dtype=float), np.array(right, dtype=float)
    left[near] += half
    right[near] -= half
    return left, right


def hands_may_meet(avatar: Avatar, left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """Which wrist positions ``(n, 3)`` are near enough for the hands to come within the
    palm thickness (and :data:`HAND_BAND`), whichever way the hands turn."""
    reach = max(float(np.linalg.norm(avatar.collision.arm(side, "hand").b - avatar.collision.arm(side, "hand").a)) for side in "lr")
    return quat.norm(left - right) < 2.0 * reach + avatar.collision.palm_thickness + HAND_BAND


def _parting(left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """The way the left hand leaves the right where they touch: across both hands
    (perpendicular to their long axes ``left``, ``right`` (n, 3)) where they cross —
    the side toward the avatar's top and left — and toward the avatar's left where they
    lie side by side (palm against palm), blended between."""
    across = quat.cross(left, right)
    sine = quat.norm(across) / np.maximum(quat.norm(left) * quat.norm(right), _TINY)
    across = across * np.where(across @ _PREFERRED >= 0.0, 1.0, -1.0)[:, None]
    across = across / np.maximum(quat.norm(across), _TINY)[:, None]
    weight = np.minimum(np.maximum(sine / CROSSING_SINE, 0.0), 1.0)[:, None]
    parting = weight * across + (1.0 - weight) * np.array([1.0, 0.0, 0.0])
    return parting / np.maximum(quat.norm(parting), _TINY)[:, None]
