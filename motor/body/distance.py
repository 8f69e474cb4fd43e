"""Signed distances between a capsule and the body's volumes, compiled.

The swivel search measures every candidate elbow of every frame against every volume
near it (:mod:`motor.arm.clearance`): hundreds of distances per frame. Each distance here
is a scalar kernel compiled by numba; the public functions broadcast their arguments
(any leading axes: frames, candidates) into the rows of one array and run a compiled loop
over them — without the temporary arrays of a chain of ``np.where`` — and give the numbers
of the numpy arithmetic they replaced bit for bit (the same operations in the same order;
no fast-math): ``tests/perf_equivalence/test_compiled_distance.py`` holds them to the
numpy definitions. :func:`volume_distance` serves compiled callers.

* :func:`closest_parameters`, :func:`segment_distance`, :func:`point_segment_distance`:
  segments (degenerate ones allowed);
* :func:`capsule_distance` / :func:`capsule_apart`: a capsule against a
  :class:`~motor.body.volumes.Capsule` (exact), an :class:`~motor.body.volumes.Ellipsoid`
  or an :class:`~motor.body.volumes.EllipticCylinder` (along the radial direction: exact
  for spheres and circular cylinders; for the body's mildly elliptic shapes the sign is
  exact and the depth within a few millimetres near the surface, within 10 % deep inside).

Points are in metres, in the volume's rest frame. The kernels are cached on disk
(``__pycache__``) after their first compilation.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from motor.body.volumes import Capsule, Ellipsoid, Volume
from motor.kernel_types import READ1, READ2, WRITE1

#: Squared lengths (m²) and denominators below which a segment counts as a point.
_TINY = 1e-12
#: Least radius (in the volume's unit-circle or unit-sphere coordinates) a point is
#: measured from, so that the axis or centre itself has a direction.
_LEAST_RHO = 1e-9
#: Points along a segment, as fractions ``k / _ALONG_STEPS``, at which the distance of
#: its parts above or below a cylinder is measured.
_ALONG_STEPS = 16

#: A vector field as its three coordinate arrays (any broadcastable shapes): the layout
#: of the swivel search, where contiguous ``(n, K)`` arrays per coordinate are fastest.
Components = tuple[np.ndarray, np.ndarray, np.ndarray]


#: Compiled once, cached on disk; division by zero gives inf or nan as in numpy. The
#: loops' signatures are stated (inputs read-only), which compiles or loads them when
#: this module is imported; the scalar kernels they call are compiled with them.
_compiled = numba.njit(cache=True, error_model="numpy")


def components(v: np.ndarray) -> Components:
    """The coordinate arrays of vectors ``(..., 3)``."""
    return v[..., 0], v[..., 1], v[..., 2]


@_compiled
def _clip01(value: float) -> float:
    return min(max(value, 0.0), 1.0)


@_compiled
def _closest(p0x, p0y, p0z, p1x, p1y, p1z, q0x, q0y, q0z, q1x, q1y, q1z):  # noqa: ANN001, ANN202
    """Parameters ``s, t`` of the closest points of two segments (Ericson's clamped solution)."""
    d1x, d1y, d1z = p1x - p0x, p1y - p0y, p1z - p0z
    d2x, d2y, d2z = q1x - q0x, q1y - q0y, q1z - q0z
    rx, ry, rz = p0x - q0x, p0y - q0y, p0z - q0z
    a = d1x * d1x + d1y * d1y + d1z * d1z
    e = d2x * d2x + d2y * d2y + d2z * d2z
    f = d2x * rx + d2y * ry + d2z * rz
    b = d1x * d2x + d1y * d2y + d1z * d2z
    c = d1x * rx + d1y * ry + d1z * rz
    a_safe, e_safe = max(a, _TINY), max(e, _TINY)
    denominator = a * e - b * b
    s = _clip01((b * f - c * e) / max(denominator, _TINY)) if denominator > _TINY * max(a * e, _TINY) else 0.0
    t = (b * s + f) / e_safe
    if t < 0.0:
        s = _clip01(-c / a_safe)
    elif t > 1.0:
        s = _clip01((b - c) / a_safe)
    if not a > _TINY:
        s = 0.0
    t = _clip01(t) if e > _TINY else 0.0
    return s, t


@_compiled
def segments_gap(p0x, p0y, p0z, p1x, p1y, p1z, q0x, q0y, q0z, q1x, q1y, q1z):  # noqa: ANN001, ANN202
    """:func:`segment_distance` of one pair of segments; for compiled callers."""
    s, t = _closest(p0x, p0y, p0z, p1x, p1y, p1z, q0x, q0y, q0z, q1x, q1y, q1z)
    gx = (p0x + s * (p1x - p0x)) - (q0x + t * (q1x - q0x))
    gy = (p0y + s * (p1y - p0y)) - (q0y + t * (q1y - q0y))
    gz = (p0z + s * (p1z - p0z)) - (q0z + t * (q1z - q0z))
    return math.sqrt(gx * gx + gy * gy + gz * gz)


@_compiled
def _point_segment(px, py, pz, ax, ay, az, bx, by, bz):  # noqa: ANN001, ANN202
    dx, dy, dz = bx - ax, by - ay, bz - az
    t = _clip01(((px - ax) * dx + (py - ay) * dy + (pz - az) * dz) / max(dx * dx + dy * dy + dz * dz, _TINY))
    gx, gy, gz = px - (ax + t * dx), py - (ay + t * dy), pz - (az + t * dz)
    return math.sqrt(gx * gx + gy * gy + gz * gz)


@_compiled
def _ellipsoid(ax, ay, az, bx, by, bz, cx, cy, cz, rx, ry, rz):  # noqa: ANN001, ANN202
    """The segment's point nearest the centre in the space where the ellipsoid is a unit
    sphere, measured along its ray."""
    p0x, p0y, p0z = (ax - cx) / rx, (ay - cy) / ry, (az - cz) / rz
    dx, dy, dz = (bx - ax) / rx, (by - ay) / ry, (bz - az) / rz
    t = _clip01(-(p0x * dx + p0y * dy + p0z * dz) / max(dx * dx + dy * dy + dz * dz, _TINY))
    sx, sy, sz = p0x + t * dx, p0y + t * dy, p0z + t * dz
    rho = math.sqrt(sx * sx + sy * sy + sz * sz)
    ux, uy, uz = sx * rx, sy * ry, sz * rz
    return math.sqrt(ux * ux + uy * uy + uz * uz) * (1.0 - 1.0 / max(rho, _LEAST_RHO))


@_compiled
def _radial(sx, sz, width, depth):  # noqa: ANN001, ANN202
    """Signed radial distance (m) of a point given in the cylinder's unit-circle coordinates."""
    rho = math.sqrt(sx * sx + sz * sz)
    return math.sqrt((sx * width) * (sx * width) + (sz * depth) * (sz * depth)) * (1.0 - 1.0 / max(rho, _LEAST_RHO))


@_compiled
def _beyond(along, x0, z0, dx, dz, y0, dy, width, depth, bottom, top):  # noqa: ANN001, ANN202
    """Distance (m) from the cylinder of the segment's point at ``along``, a point above or below it."""
    gap = _radial(x0 + along * dx, z0 + along * dz, width, depth)
    y = y0 + along * dy
    vertical = max(max(bottom - y, y - top), 0.0)
    return math.sqrt(vertical * vertical + gap * gap) if gap > 0.0 else vertical


@_compiled
def _cylinder(ax, ay, az, bx, by, bz, cx, cz, width, depth, bottom, top):  # noqa: ANN001, ANN202
    """The least of the radial distance (in the horizontal plane, as the ellipsoid's) of the
    segment's part within the height range, and the distances of its parts above or below
    it, measured at ``k / 16`` of its length, where its horizontal gap is least and where
    it leaves the height range, by their vertical and radial gaps. An upper arm lying across the top of the chest passes nearest the rim between
    its ends, with most of it above the top: measuring only the part within the height
    range put such an arm 2 cm into the chest 7 cm clear."""
    x0, z0 = (ax - cx) / width, (az - cz) / depth
    dx, dz = (bx - ax) / width, (bz - az) / depth
    y0, dy = ay, by - ay
    if abs(dy) <= _TINY:
        enter = 0.0 if bottom <= y0 <= top else 2.0
        leave = 1.0
    else:
        low, high = (bottom - y0) / dy, (top - y0) / dy
        enter = max(min(low, high), 0.0)
        leave = min(max(low, high), 1.0)
    inside = enter <= leave
    nearest = -(x0 * dx + z0 * dz) / max(dx * dx + dz * dz, _TINY)
    t = min(max(nearest, enter), max(leave, enter))
    radial = _radial(x0 + t * dx, z0 + t * dz, width, depth) if inside else math.inf
    # the parts above or below are never nearer where the part within the height range is
    # inside the cylinder, or holds the point nearest the axis
    closest = _clip01(nearest)
    if inside and ((enter <= 0.0 and leave >= 1.0) or radial <= 0.0 or enter <= closest <= leave):
        return radial
    least = radial
    for k in range(_ALONG_STEPS + 1):
        least = min(least, _beyond(k / _ALONG_STEPS, x0, z0, dx, dz, y0, dy, width, depth, bottom, top))
    for along in (nearest, enter, leave):
        least = min(least, _beyond(_clip01(along), x0, z0, dx, dz, y0, dy, width, depth, bottom, top))
    return least


@_compiled
def _row12(ends, i):  # noqa: ANN001, ANN202
    return (ends[0, i], ends[1, i], ends[2, i], ends[3, i], ends[4, i], ends[5, i],
            ends[6, i], ends[7, i], ends[8, i], ends[9, i], ends[10, i], ends[11, i])  # fmt: skip


@numba.njit([numba.void(READ2, WRITE1, WRITE1)], cache=True, error_model="numpy")
def _closest_loop(ends, s, t):  # noqa: ANN001, ANN202
    for i in range(s.size):
        s[i], t[i] = _closest(*_row12(ends, i))


@numba.njit([numba.void(READ2, WRITE1)], cache=True, error_model="numpy")
def _segments_loop(ends, out):  # noqa: ANN001, ANN202
    for i in range(out.size):
        out[i] = segments_gap(*_row12(ends, i))


@numba.njit([numba.void(READ2, WRITE1)], cache=True, error_model="numpy")
def _point_segment_loop(ends, out):  # noqa: ANN001, ANN202
    for i in range(out.size):
        out[i] = _point_segment(ends[0, i], ends[1, i], ends[2, i], ends[3, i], ends[4, i], ends[5, i], ends[6, i], ends[7, i], ends[8, i])


#: Kinds of volume in a :func:`volume_table`.
CAPSULE, ELLIPSOID, CYLINDER = 0, 1, 2


def volume_table(volumes: tuple[Volume, ...]) -> tuple[np.ndarray, np.ndarray]:
    """The volumes as the compiled code reads them: kinds ``(V,)`` (:data:`CAPSULE`,
    :data:`ELLIPSOID`, :data:`CYLINDER`) and parameters ``(V, 7)`` — a capsule's end
    points and radius; an ellipsoid's centre and semi-axes; a cylinder's centre x and z,
    half width, half depth, bottom and top."""
    kinds = np.empty(len(volumes), dtype=np.int64)
    parameters = np.zeros((len(volumes), 7))
    for index, volume in enumerate(volumes):
        if isinstance(volume, Capsule):
            kinds[index], parameters[index] = CAPSULE, (*volume.a, *volume.b, volume.radius)
        elif isinstance(volume, Ellipsoid):
            kinds[index], parameters[index, :6] = ELLIPSOID, (*volume.center, *volume.radii)
        else:
            kinds[index], parameters[index, :6] = CYLINDER, (volume.center[0], volume.center[2], volume.half_width, volume.half_depth, volume.bottom, volume.top)
    return kinds, parameters


@_compiled
def volume_distance(kind, p, ax, ay, az, bx, by, bz, radius):  # noqa: ANN001, ANN201
    """Signed distance (m) of the capsule ``a``–``b`` with ``radius`` from the volume of
    ``kind`` with parameters ``p`` (a row of :func:`volume_table`); for compiled callers."""
    if kind == CAPSULE:
        return segments_gap(ax, ay, az, bx, by, bz, p[0], p[1], p[2], p[3], p[4], p[5]) - p[6] - radius
    if kind == ELLIPSOID:
        return _ellipsoid(ax, ay, az, bx, by, bz, p[0], p[1], p[2], p[3], p[4], p[5]) - radius
    return _cylinder(ax, ay, az, bx, by, bz, p[0], p[1], p[2], p[3], p[4], p[5]) - radius


@numba.njit([numba.void(READ2, numba.int64, READ1, WRITE1)], cache=True, error_model="numpy")
def _volume_loop(ends, kind, p, out):  # noqa: ANN001, ANN202
    for i in range(out.size):
        out[i] = volume_distance(kind, p, ends[0, i], ends[1, i], ends[2, i], ends[3, i], ends[4, i], ends[5, i], ends[6, i])


def _packed(*fields: np.ndarray | float) -> tuple[np.ndarray, tuple[int, ...]]:
    """The fields broadcast together, one row each of a contiguous ``(fields, size)``
    array (what the compiled loops read), and their broadcast shape."""
    shape = np.broadcast_shapes(*(np.shape(field) for field in fields))
    packed = np.empty((len(fields), *shape))
    for index, field in enumerate(fields):
        packed[index] = field
    return packed.reshape(len(fields), -1), shape


def closest_parameters(p0: np.ndarray, p1: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Parameters ``s, t`` in [0, 1] of the closest points ``p0 + s (p1 - p0)`` and
    ``q0 + t (q1 - q0)`` of two segments (arrays ``(..., 3)`` broadcast; degenerate
    segments allowed)."""
    ends, shape = _packed(*components(p0), *components(p1), *components(q0), *components(q1))
    s, t = np.empty(ends.shape[1]), np.empty(ends.shape[1])
    _closest_loop(ends, s, t)
    return s.reshape(shape), t.reshape(shape)


def segment_distance(p0: np.ndarray, p1: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """Shortest distance (m) between segments ``p0``–``p1`` and ``q0``–``q1`` (arrays ``(..., 3)`` broadcast)."""
    return segments_apart(components(p0), components(p1), components(q0), components(q1))


def segments_apart(p0: Components, p1: Components, q0: Components, q1: Components) -> np.ndarray:
    """:func:`segment_distance` of segments given by coordinate arrays."""
    ends, shape = _packed(*p0, *p1, *q0, *q1)
    out = np.empty(ends.shape[1])
    _segments_loop(ends, out)
    return out.reshape(shape)


def point_segment_distance(point: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """Distance (m) from points to segments ``q0``–``q1`` (arrays ``(..., 3)`` broadcast)."""
    ends, shape = _packed(*components(point), *components(q0), *components(q1))
    out = np.empty(ends.shape[1])
    _point_segment_loop(ends, out)
    return out.reshape(shape)


def capsule_distance(volume: Volume, a: np.ndarray, b: np.ndarray, radius: float | np.ndarray) -> np.ndarray:
    """Signed distance (m, negative inside) between the capsule ``a``–``b`` with
    ``radius`` and ``volume``; ``a``, ``b`` ``(..., 3)`` in the volume's rest frame."""
    return capsule_apart(volume, components(a), components(b), radius)


def capsule_apart(volume: Volume, a: Components, b: Components, radius: float | np.ndarray) -> np.ndarray:
    """:func:`capsule_distance` of a capsule given by coordinate arrays."""
    ends, shape = _packed(*a, *b, radius)
    out = np.empty(ends.shape[1])
    kinds, parameters = volume_table((volume,))
    _volume_loop(ends, kinds[0], parameters[0], out)
    return out.reshape(shape)


def load_kernels() -> None:
    """Run this module's compiled loops once (they load when it is imported):
    :func:`motor.compiled.warm_up`."""
    points = np.zeros((1, 3))
    closest_parameters(points, points, points, points)
    segment_distance(points, points, points, points)
    point_segment_distance(points, points, points)
    capsule_distance(Capsule("capsule", "root", points[0], points[0] + 1.0, 0.1), points, points, 0.0)
