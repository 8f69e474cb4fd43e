"""The numpy definitions of the signed distances, as they stood before they were compiled
(:mod:`motor.body.distance`, issue 19): the plain path the compiled kernels are held to,
bit for bit, by ``test_compiled_distance.py``. Not used by mura itself."""

from __future__ import annotations

import numpy as np

from motor.body.volumes import Capsule, Ellipsoid, EllipticCylinder, Volume

Components = tuple[np.ndarray, np.ndarray, np.ndarray]
_TINY = 1e-12


def components(v: np.ndarray) -> Components:
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
    """Signed distance of a segment from a vertical elliptic cylinder: the least of the
    radial distance (as :func:`_ellipsoid_distance`, in the horizontal plane) of its part
    within the height range, and the distances of its parts above or below it, measured at
    :data:`_ALONG`, where its horizontal gap is least and where it leaves the height range,
    by their vertical and radial gaps. An upper arm lying across the top of the chest
    passes nearest the rim between its ends, with most of it above the top: measuring only
    the part within the height range put such an arm 2 cm into the chest 7 cm clear."""
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
    nearest = -(x0 * dx + z0 * dz) / np.maximum(dx * dx + dz * dz, _TINY)
    t = np.minimum(np.maximum(nearest, enter), np.maximum(leave, enter))
    radial = np.where(inside, _radial(x0 + t * dx, z0 + t * dz, width, depth), np.inf)
    # the parts above or below are never nearer where the part within the height range is
    # inside the cylinder, or holds the point nearest its axis
    closest = np.minimum(np.maximum(nearest, 0.0), 1.0)
    within = inside & ((enter <= 0.0) & (leave >= 1.0) | (radial <= 0.0) | (closest >= enter) & (closest <= leave))
    if np.all(within):
        return radial
    shape = np.broadcast(radial, within, x0, z0, dx, dz, y0, dy).shape
    rows = np.flatnonzero(np.broadcast_to(~within, shape))
    pick = lambda v: np.broadcast_to(v, shape).reshape(-1)[rows][:, None]
    ends = np.minimum(np.maximum(np.concatenate([pick(nearest), pick(enter), pick(leave)], axis=1), 0.0), 1.0)
    samples = np.concatenate([np.broadcast_to(_ALONG, (rows.size, _ALONG.size)), ends], axis=1)
    outside = _beyond(cylinder, pick(x0), pick(z0), pick(dx), pick(dz), pick(y0), pick(dy), samples).min(axis=1)
    distance = np.array(np.broadcast_to(radial, shape), dtype=float)
    distance.reshape(-1)[rows] = np.minimum(distance.reshape(-1)[rows], outside)
    return distance


#: Fractions along a segment at which the distance of its parts above or below a cylinder is measured.
_ALONG = np.linspace(0.0, 1.0, 17)


def _radial(sx: np.ndarray, sz: np.ndarray, width: float, depth: float) -> np.ndarray:
    """Signed radial distance (m) of points given in the cylinder's unit-circle coordinates."""
    rho = np.sqrt(sx * sx + sz * sz)
    return np.sqrt((sx * width) ** 2 + (sz * depth) ** 2) * (1.0 - 1.0 / np.maximum(rho, 1e-9))


def _beyond(cylinder: EllipticCylinder, x0: np.ndarray, z0: np.ndarray, dx: np.ndarray, dz: np.ndarray, y0: np.ndarray, dy: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Distance (m) from the cylinder of the segment's point at ``t``, a point above or below it."""
    radial = _radial(x0 + t * dx, z0 + t * dz, cylinder.half_width, cylinder.half_depth)
    y = y0 + t * dy
    vertical = np.maximum(np.maximum(cylinder.bottom - y, y - cylinder.top), 0.0)
    return np.where(radial > 0.0, np.sqrt(vertical * vertical + radial * radial), vertical)


