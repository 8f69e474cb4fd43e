"""Mirror symmetry of the non-dominant hand (MURML ``SymMS``, ``SymMT``, ``SymMF`` …).

A symmetrical gesture gives the dominant arm's movement; the other arm performs its
mirror image. The mirror planes of a :class:`mura.model.Symmetry` are sagittal (``S``:
x ↦ −x, left–right), transversal (``T``: y about the centre's height) and frontal
(``F``: z about the centre's depth); several planes compose. Points reflect about the
centre (metres, avatar frame; default the origin), directions only flip components, and
rotations are conjugated by the reflection ``M``: ``R ↦ M R M``.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from motor.trajectory.spline import WristTrajectory
from mura.constraints import Symmetry

_AXIS_OF_PLANE = {"S": 0, "T": 1, "F": 2}


@lru_cache(maxsize=64)
def reflection_signs(symmetry: Symmetry) -> np.ndarray:
    """Diagonal ``(3,)`` of the reflection matrix M of ``symmetry`` (entries ±1), read-only
    and made once per symmetry: a sign planner mirrors thousands of directions."""
    signs = np.ones(3)
    for plane in symmetry.planes:
        if plane not in _AXIS_OF_PLANE:
            raise ValueError(f"symmetry {symmetry.name!r}: unknown mirror plane {plane!r} (expected S, T or F)")
        signs[_AXIS_OF_PLANE[plane]] = -1.0
    signs.flags.writeable = False
    return signs


def _check_last_axis(values: np.ndarray, size: int, what: str) -> np.ndarray:
    array = np.asarray(values, dtype=float)
    if array.shape[-1:] != (size,):
        raise ValueError(f"{what}: expected last axis of size {size}, got shape {array.shape}")
    return array


def mirror_points(
    points: np.ndarray, symmetry: Symmetry, center: np.ndarray | tuple[float, float, float] | None = None
) -> np.ndarray:
    """Positions ``(..., 3)`` reflected across the symmetry's planes through ``center``."""
    p = _check_last_axis(points, 3, "mirror_points")
    c = np.zeros(3) if center is None else _check_last_axis(center, 3, "mirror center")
    return c + (p - c) * reflection_signs(symmetry)


def mirror_directions(directions: np.ndarray, symmetry: Symmetry) -> np.ndarray:
    """Direction vectors or velocities ``(..., 3)`` reflected across the symmetry's planes."""
    return _check_last_axis(directions, 3, "mirror_directions") * reflection_signs(symmetry)


def mirror_quaternions(quaternions: np.ndarray, symmetry: Symmetry) -> np.ndarray:
    """Rotations ``(..., 4)`` (scalar-last) conjugated by the reflection: ``M R M``.

    A rotation's axis is a pseudovector: under M it becomes ``det(M) · M a`` while the
    angle stays, so the vector part maps to ``det(M) · M v`` and the scalar part is kept.
    """
    q = _check_last_axis(quaternions, 4, "mirror_quaternions")
    signs = reflection_signs(symmetry)
    factors = np.append(np.prod(signs) * signs, 1.0)
    return q * factors


def kept_apart(
    points: np.ndarray, symmetry: Symmetry, center: np.ndarray | tuple[float, float, float], gap: float, away: np.ndarray
) -> np.ndarray:
    """Positions ``(n, 3)`` of the dominant hand moved so that each is at least ``gap``
    (metres) from its own mirror image: a point closer to the mirror planes is pushed out
    along the line to its image (along ``away``, a unit vector, when it lies on the planes).
    Points already far enough are unchanged. The image of the result is the other hand."""
    p = _check_last_axis(points, 3, "kept_apart")
    images = mirror_points(p, symmetry, center)
    between = p - images
    distance = np.linalg.norm(between, axis=-1, keepdims=True)
    close = distance[..., 0] < gap
    if not np.any(close):
        return p
    direction = np.where(distance > 1e-9, between / np.maximum(distance, 1e-12), away)
    middle = 0.5 * (p + images)
    return np.where(close[..., None], middle + 0.5 * gap * direction, p)


def mirror_trajectory(
    trajectory: WristTrajectory, symmetry: Symmetry, center: np.ndarray | tuple[float, float, float] | None = None
) -> WristTrajectory:
    """The mirror image of a wrist trajectory: knots reflected, velocities and
    accelerations flipped.

    A Hermite spline commutes with the reflection, so the result is exactly the reflected
    curve at every time.
    """
    return WristTrajectory(
        trajectory.times,
        mirror_points(trajectory.positions, symmetry, center),
        mirror_directions(trajectory.velocities, symmetry),
        mirror_directions(trajectory.accelerations, symmetry),
        trajectory.warnings,
    )
