"""The body's collision volumes in a pose: placement, signed distances, clear wrist targets.

* :func:`joint_placement` / :func:`to_rest` carry points between the avatar frame and a
  volume's rest frame (a volume moves rigidly with its joint; :mod:`motor.body.volumes`);
* :func:`segment_distance` and :func:`capsule_distance` give signed distances between a
  capsule and any volume, vectorized over any leading axes (frames, candidates): exact
  for capsules, along the radial direction for ellipsoids and elliptic cylinders (exact
  for spheres and circular cylinders; within a few millimetres for the body's mildly
  elliptic shapes);
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
#: Width (m) of the band above the palm thickness in which two hands are eased apart.
HAND_BAND = 0.004
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


def _dot(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return u[..., 0] * v[..., 0] + u[..., 1] * v[..., 1] + u[..., 2] * v[..., 2]


def closest_parameters(p0: np.ndarray, p1: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Parameters ``s, t`` in [0, 1] of the closest points ``p0 + s (p1 - p0)`` and
    ``q0 + t (q1 - q0)`` of two segments (arrays broadcast; degenerate segments allowed)."""
    d1, d2, r = p1 - p0, q1 - q0, p0 - q0
    a, e, f = _dot(d1, d1), _dot(d2, d2), _dot(d2, r)
    b, c = _dot(d1, d2), _dot(d1, r)
    a_safe, e_safe = np.maximum(a, _TINY), np.maximum(e, _TINY)
    denominator = a * e - b * b
    s = np.where(denominator > _TINY * np.maximum(a * e, _TINY), np.clip((b * f - c * e) / np.maximum(denominator, _TINY), 0.0, 1.0), 0.0)
    t = (b * s + f) / e_safe
    s = np.where(t < 0.0, np.clip(-c / a_safe, 0.0, 1.0), np.where(t > 1.0, np.clip((b - c) / a_safe, 0.0, 1.0), s))
    t = np.clip(t, 0.0, 1.0)
    s = np.where(a > _TINY, s, 0.0)
    t = np.where(e > _TINY, t, 0.0)
    return s, t


def segment_distance(p0: np.ndarray, p1: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """Shortest distance between segments ``p0``–``p1`` and ``q0``–``q1`` (arrays broadcast)."""
    s, t = closest_parameters(p0, p1, q0, q1)
    gap = (p0 + s[..., None] * (p1 - p0)) - (q0 + t[..., None] * (q1 - q0))
    return np.sqrt(_dot(gap, gap))


def point_segment_distance(point: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """Distance from points to segments ``q0``–``q1`` (arrays broadcast)."""
    d = q1 - q0
    t = np.clip(_dot(point - q0, d) / np.maximum(_dot(d, d), _TINY), 0.0, 1.0)
    gap = point - (q0 + t[..., None] * d)
    return np.sqrt(_dot(gap, gap))


def capsule_distance(volume: Volume, a: np.ndarray, b: np.ndarray, radius: float | np.ndarray) -> np.ndarray:
    """Signed distance (m, negative inside) between the capsule ``a``–``b`` with
    ``radius`` and ``volume``; ``a``, ``b`` ``(..., 3)`` in the volume's rest frame."""
    if isinstance(volume, Capsule):
        return segment_distance(a, b, volume.a, volume.b) - volume.radius - radius
    if isinstance(volume, Ellipsoid):
        return _ellipsoid_distance(volume, a, b) - radius
    return _cylinder_distance(volume, a, b) - radius


def _ellipsoid_distance(ellipsoid: Ellipsoid, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Signed radial distance of a segment from an ellipsoid: the segment's point nearest
    the centre in the space where the ellipsoid is a unit sphere, measured along its ray."""
    p0 = (a - ellipsoid.center) / ellipsoid.radii
    d = (b - a) / ellipsoid.radii
    t = np.clip(-_dot(p0, d) / np.maximum(_dot(d, d), _TINY), 0.0, 1.0)
    scaled = p0 + t[..., None] * d
    rho = np.sqrt(_dot(scaled, scaled))
    unscaled = scaled * ellipsoid.radii
    return np.sqrt(_dot(unscaled, unscaled)) * (1.0 - 1.0 / np.maximum(rho, 1e-9))


def _cylinder_distance(cylinder: EllipticCylinder, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Signed distance of a segment from a vertical elliptic cylinder: within the height
    range, radial (as :func:`_ellipsoid_distance`, in the horizontal plane); a segment
    wholly above or below it is as far as its nearest end's vertical and radial gaps."""
    x0, z0 = (a[..., 0] - cylinder.center[0]) / cylinder.half_width, (a[..., 2] - cylinder.center[2]) / cylinder.half_depth
    dx, dz = (b[..., 0] - a[..., 0]) / cylinder.half_width, (b[..., 2] - a[..., 2]) / cylinder.half_depth
    y0, dy = a[..., 1], b[..., 1] - a[..., 1]
    safe = np.where(np.abs(dy) > _TINY, dy, _TINY)
    low, high = (cylinder.bottom - y0) / safe, (cylinder.top - y0) / safe
    enter = np.where(np.abs(dy) > _TINY, np.minimum(low, high), np.where((y0 >= cylinder.bottom) & (y0 <= cylinder.top), 0.0, 2.0))
    leave = np.where(np.abs(dy) > _TINY, np.maximum(low, high), 1.0)
    enter, leave = np.maximum(enter, 0.0), np.minimum(leave, 1.0)
    inside = enter <= leave
    t = np.clip(-(x0 * dx + z0 * dz) / np.maximum(dx * dx + dz * dz, _TINY), enter, np.maximum(leave, enter))
    # outside the height range: the end nearer to it
    end = np.where(np.abs(y0 + dy - 0.5 * (cylinder.bottom + cylinder.top)) < np.abs(y0 - 0.5 * (cylinder.bottom + cylinder.top)), 1.0, 0.0)
    t = np.where(inside, t, end)
    sx, sz = x0 + t * dx, z0 + t * dz
    rho = np.sqrt(sx * sx + sz * sz)
    radial = np.hypot(sx * cylinder.half_width, sz * cylinder.half_depth) * (1.0 - 1.0 / np.maximum(rho, 1e-9))
    y = y0 + t * dy
    vertical = np.maximum(cylinder.bottom - y, y - cylinder.top)
    return np.where(inside, radial, np.where(radial > 0.0, np.hypot(vertical, radial), vertical))


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
    front = torso.center[2] + b * np.sqrt(np.clip(1.0 - dx * dx, 0.0, 1.0))
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
    front = torso.center[2] + b * np.sqrt(np.clip(1.0 - dx * dx, 0.0, 1.0))
    return (np.abs(dx) < 1.0) & (points[:, 2] < front) & (points[:, 1] > torso.bottom) & (points[:, 1] < torso.top)


def _fade(beyond: np.ndarray) -> np.ndarray:
    """1 where ``beyond`` ≤ 0 (inside an edge), falling smoothly to 0 at :data:`EDGE_BAND`."""
    u = np.clip(beyond / EDGE_BAND, 0.0, 1.0)
    return 1.0 - u * u * (3.0 - 2.0 * u)


def hand_segments(avatar: Avatar, side: str, wrists: np.ndarray, hands: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """End points ``(n, 3)`` of a hand's capsule for wrist positions and global hand
    rotations ``(n, 4)``."""
    capsule = avatar.collision.arm(side, "hand")
    wrist_rest = avatar.rest_positions[avatar.joint_index(f"{side}_wrist")]
    return wrists + quat.rotate(hands, capsule.a - wrist_rest), wrists + quat.rotate(hands, capsule.b - wrist_rest)


def separate_hands(
    avatar: Avatar, left: np.ndarray, right: np.ndarray, left_hands: np.ndarray, right_hands: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Wrist positions ``(n, 3)`` of both arms moved apart where their hands would come
    closer than the palm thickness (the distance of the hands' midlines when palm meets
    palm): each wrist moves half the deficit along the line between the hands' nearest
    points. Where the hands cross or coincide that line is tilted toward
    :func:`_parting`, which it becomes where they meet. The distance kept eases in C¹
    from :data:`HAND_BAND` above the thickness, so hands meet without a speed step;
    hands farther apart are unchanged."""
    thickness = avatar.collision.palm_thickness
    l0, l1 = hand_segments(avatar, "l", left, left_hands)
    r0, r1 = hand_segments(avatar, "r", right, right_hands)
    s, t = closest_parameters(l0, l1, r0, r1)
    between = (l0 + s[:, None] * (l1 - l0)) - (r0 + t[:, None] * (r1 - r0))
    gap = quat.norm(between) - thickness
    if not np.any(gap < HAND_BAND):
        return left, right
    eased = np.where(gap >= HAND_BAND, gap, HAND_BAND * np.exp(np.minimum(gap, HAND_BAND) / HAND_BAND - 1.0))
    direction = between + 0.25 * thickness * _parting(l1 - l0, r1 - r0)
    direction = direction / np.maximum(quat.norm(direction), _TINY)[:, None]
    half = (0.5 * (eased - gap))[:, None] * direction
    return left + half, right - half


def _parting(left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """The way the left hand leaves the right where they touch: across both hands
    (perpendicular to their long axes ``left``, ``right`` (n, 3)) where they cross —
    the side toward the avatar's top and left — and toward the avatar's left where they
    lie side by side (palm against palm), blended between."""
    across = quat.cross(left, right)
    sine = quat.norm(across) / np.maximum(quat.norm(left) * quat.norm(right), _TINY)
    across = across * np.where(across @ _PREFERRED >= 0.0, 1.0, -1.0)[:, None]
    across = across / np.maximum(quat.norm(across), _TINY)[:, None]
    weight = np.clip(sine / CROSSING_SINE, 0.0, 1.0)[:, None]
    parting = weight * across + (1.0 - weight) * np.array([1.0, 0.0, 0.0])
    return parting / np.maximum(quat.norm(parting), _TINY)[:, None]
