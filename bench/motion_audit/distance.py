"""Signed distances to the collision shapes, and how deep a capsule sinks into one.

Shapes are the three of the avatar files' ``collision`` volumes, in their own rest frame
(metres; y up): a **capsule** (segment ``a``–``b`` grown by ``radius``), an **ellipsoid**
(``center``, semi-axes ``radii`` along x, y, z) and an upright **elliptic cylinder**
(``center`` x/z, ``half_width`` along x, ``half_depth`` along z, from ``bottom`` to
``top``). A signed distance is negative inside. Every function takes points ``(n, 3)``
and works on all of them at once.

The distance to an ellipse or ellipsoid is exact (to float precision), found the way
D. Eberly describes ("Distance from a point to an ellipse, an ellipsoid, or a
hyperellipsoid", 2013): in the first orthant, with the semi-axes sorted, the closest
point is ``x_i = r_i·y_i / (s + r_i)`` for the root ``s`` of
``G(s) = Σ (r_i z_i / (s + r_i))² − 1`` (``z_i = y_i/e_i``, ``r_i = (e_i/e_min)²``),
bracketed and found by bisection. Coordinates exactly on an axis are moved off it by
:data:`AXIS_NUDGE` of the semi-axis so that one formula covers every case (the closest
point then moves by about a tenth of a micrometre). The elliptic cylinder is the ellipse
extruded between two planes, whose signed distance is exact too.

A capsule's depth in a convex shape is ``radius − min over its axis of the shape's signed
distance``; along a segment that distance is convex, so a golden-section search finds
the minimum (:data:`GOLDEN_STEPS` steps: to about 5e-7 of the segment's length, well
under a micrometre on an arm).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Bisection steps for the ellipse/ellipsoid root (the bracket shrinks by 2^-52).
BISECTION_STEPS = 52
#: Golden-section steps for a capsule's deepest point (the interval shrinks to 5e-7).
GOLDEN_STEPS = 30
#: Coordinates closer to an axis than this fraction of the semi-axis are moved off it.
AXIS_NUDGE = 1e-6
_GOLDEN = (np.sqrt(5.0) - 1.0) / 2.0


@dataclass(frozen=True)
class Capsule:
    """Segment ``a``–``b`` (metres) grown by ``radius``."""

    a: np.ndarray
    b: np.ndarray
    radius: float


@dataclass(frozen=True)
class Ellipsoid:
    """Centre and semi-axes along x, y, z (metres)."""

    center: np.ndarray
    radii: np.ndarray


@dataclass(frozen=True)
class EllipticCylinder:
    """Vertical axis through ``center`` (its x and z used); ``half_width`` along x,
    ``half_depth`` along z, heights ``bottom`` to ``top`` (metres)."""

    center: np.ndarray
    half_width: float
    half_depth: float
    bottom: float
    top: float


Shape = Capsule | Ellipsoid | EllipticCylinder


def ellipsoid_surface_distance(points: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """Signed distance ``(n,)`` of ``points`` ``(n, k)`` (k = 2 or 3, centred) to the
    ellipse or ellipsoid with semi-axes ``radii`` ``(k,)``; negative inside."""
    radii = np.asarray(radii, dtype=float)
    order = np.argsort(-radii)
    e = radii[order]
    y = np.abs(np.asarray(points, dtype=float)[:, order])
    y = np.maximum(y, AXIS_NUDGE * e)
    z = y / e
    r = (e / e[-1]) ** 2
    inside = np.sum(z * z, axis=1) < 1.0
    low = z[:, -1] - 1.0
    high = np.where(inside, 0.0, np.linalg.norm(r * z, axis=1) - 1.0)
    weighted = [r[i] * z[:, i] for i in range(e.size)]
    for _ in range(BISECTION_STEPS):
        middle = 0.5 * (low + high)
        g = -1.0
        for i in range(e.size):
            g = g + (weighted[i] / (middle + r[i])) ** 2
        above = g > 0.0
        low = np.where(above, middle, low)
        high = np.where(above, high, middle)
    s = 0.5 * (low + high)
    closest = r * y / (s[:, None] + r)
    distance = np.linalg.norm(closest - y, axis=1)
    return np.where(inside, -distance, distance)


def signed_distance(shape: Shape, points: np.ndarray) -> np.ndarray:
    """Signed distance ``(n,)`` of ``points`` ``(n, 3)`` to ``shape`` (negative inside)."""
    points = np.asarray(points, dtype=float)
    if isinstance(shape, Capsule):
        axis = shape.b - shape.a
        length2 = float(axis @ axis)
        along = np.clip((points - shape.a) @ axis / length2, 0.0, 1.0) if length2 > 0 else np.zeros(points.shape[0])
        return np.linalg.norm(points - (shape.a + along[:, None] * axis), axis=1) - shape.radius
    if isinstance(shape, Ellipsoid):
        return ellipsoid_surface_distance(points - shape.center, shape.radii)
    if isinstance(shape, EllipticCylinder):
        across = np.stack((points[:, 0] - shape.center[0], points[:, 2] - shape.center[2]), axis=1)
        radial = ellipsoid_surface_distance(across, np.array([shape.half_width, shape.half_depth]))
        vertical = np.abs(points[:, 1] - 0.5 * (shape.bottom + shape.top)) - 0.5 * (shape.top - shape.bottom)
        outside = np.hypot(np.maximum(radial, 0.0), np.maximum(vertical, 0.0))
        return np.minimum(np.maximum(radial, vertical), 0.0) + outside
    raise TypeError(f"not a collision shape: {type(shape).__name__}")


def capsule_depth(start: np.ndarray, end: np.ndarray, radius: float | np.ndarray, shape: Shape) -> tuple[np.ndarray, np.ndarray]:
    """How deep moving capsules sink into ``shape``: axes from ``start`` to ``end``
    ``(n, 3)`` (in the shape's frame) with ``radius`` (one, or ``(n,)``). Returns the depth ``(n,)`` in metres
    (``radius − min signed distance`` of the axis; ≤ 0 when apart) and the deepest point
    ``(n, 3)`` of each axis."""
    start, end = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    axis = end - start

    def depth_at(fraction: np.ndarray) -> np.ndarray:
        return radius - signed_distance(shape, start + fraction[:, None] * axis)

    n = start.shape[0]
    low, high = np.zeros(n), np.ones(n)
    left, right = high - _GOLDEN * (high - low), low + _GOLDEN * (high - low)
    left_depth, right_depth = depth_at(left), depth_at(right)
    for _ in range(GOLDEN_STEPS):
        keep_left = left_depth >= right_depth  # the deepest point lies in [low, right]
        high = np.where(keep_left, right, high)
        low = np.where(keep_left, low, left)
        probe = np.where(keep_left, high - _GOLDEN * (high - low), low + _GOLDEN * (high - low))
        probe_depth = depth_at(probe)
        left, right, left_depth, right_depth = (
            np.where(keep_left, probe, right),
            np.where(keep_left, left, probe),
            np.where(keep_left, probe_depth, right_depth),
            np.where(keep_left, left_depth, probe_depth),
        )
    candidates = np.stack((np.zeros(n), 0.5 * (low + high), np.ones(n)), axis=1)
    depths = np.stack([depth_at(candidates[:, k]) for k in range(3)], axis=1)
    best = np.argmax(depths, axis=1)
    fraction = candidates[np.arange(n), best]
    return depths[np.arange(n), best], start + fraction[:, None] * axis
