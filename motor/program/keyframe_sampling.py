"""Keyframe realizations sampled in one compiled pass over the sample times.

:class:`motor.program.lmp.VectorKeyframes` (hand shapes, swivels, retractions) and
:class:`motor.program.lmp.RotationKeyframes` (the hand's rotation) are asked for every
frame of every realization; in numpy each call cost some thirty small array operations —
locating the keys, the time profile's lookup, the incoming blend, and for rotations two
rotation vectors turned into quaternions and two products — most of the time in the calls
themselves. The loops here do the same operations in the same order per sample, so the
same numbers bit for bit (``tests/perf_equivalence/test_keyframe_sampling.py`` pins them to
the numpy code kept in ``tests/perf_equivalence/plain_keyframes.py``): numpy's clipping
(:mod:`motor.kernel_types`), its ``searchsorted`` (:func:`motor.trajectory.spline_positions.knot_segment`)
and ``interp`` on the profile's table, and the C library's ``sin`` and ``cos``, which round
as numpy's do here (as :func:`motor.quaternion.about_axis` relies on).
"""

from __future__ import annotations

import numba
import numpy as np

from motor import quaternion as quat
from motor.kernel_types import READ1, READ2, WRITE2, clip
from motor.trajectory.biocontrol import TimeProfile
from motor.trajectory.spline_positions import knot_segment


@numba.njit(cache=True, error_model="numpy", inline="always")
def _path_fraction(grid, fractions, u):  # noqa: ANN001, ANN202
    """``np.interp(np.clip(u, 0, 1), grid, fractions)`` on a time profile's table, whose
    ``grid`` runs from 0 to 1 (:meth:`motor.trajectory.biocontrol.TimeProfile.fraction`)."""
    x = clip(u, 0.0, 1.0)
    if x != x:
        return x
    last = grid.shape[0] - 1
    j = min(int(x * last), last)
    while j > 0 and grid[j] > x:
        j -= 1
    while j < last and grid[j + 1] <= x:
        j += 1
    if j == last or grid[j] == x:
        return fractions[j]
    # numpy's retry from the right end applies only to a NaN, which finite tables never give
    slope = (fractions[j + 1] - fractions[j]) / (grid[j + 1] - grid[j])
    return slope * (x - grid[j]) + fractions[j]


@numba.njit(cache=True, error_model="numpy", inline="always")
def _located(knots, grid, fractions, t):  # noqa: ANN001, ANN202
    """The key segment of time ``t``, the path fraction through it, and the incoming
    blend's weight ``τ (1 − τ/T)²`` (:func:`motor.program.lmp.incoming_blend`)."""
    k = knot_segment(knots, t)
    s = _path_fraction(grid, fractions, clip((t - knots[k]) / (knots[k + 1] - knots[k]), 0.0, 1.0))
    window = knots[1] - knots[0]
    tau = clip(t - knots[0], 0.0, window)
    rest = 1.0 - tau / window
    return k, s, tau * (rest * rest)


@numba.njit([numba.void(READ1, READ2, READ1, READ1, READ1, READ1, WRITE2)], cache=True, error_model="numpy")
def _vector_rows(knots, values, incoming, grid, fractions, times, out):  # noqa: ANN001, ANN202
    for i in range(times.shape[0]):
        k, s, weight = _located(knots, grid, fractions, times[i])
        for d in range(out.shape[1]):
            out[i, d] = values[k, d] + s * (values[k + 1, d] - values[k, d]) + weight * incoming[d]


@numba.njit([numba.void(READ1, READ2, READ2, READ1, READ1, READ1, READ1, WRITE2)], cache=True, error_model="numpy")
def _rotation_rows(knots, keys, steps, incoming, grid, fractions, times, out):  # noqa: ANN001, ANN202
    for i in range(times.shape[0]):
        k, s, weight = _located(knots, grid, fractions, times[i])
        sx, sy, sz, sw = quat.of_rotation_vector(s * steps[k, 0], s * steps[k, 1], s * steps[k, 2])
        px, py, pz, pw = quat.multiplied(keys[k, 0], keys[k, 1], keys[k, 2], keys[k, 3], sx, sy, sz, sw)
        bx, by, bz, bw = quat.of_rotation_vector(weight * incoming[0], weight * incoming[1], weight * incoming[2])
        out[i, 0], out[i, 1], out[i, 2], out[i, 3] = quat.multiplied(bx, by, bz, bw, px, py, pz, pw)


def vector_keyframes(knots: np.ndarray, values: np.ndarray, incoming: np.ndarray, profile: TimeProfile, times: np.ndarray) -> np.ndarray:
    """Values ``(n, D)`` at ``times`` ``(n,)`` (seconds) of a vector channel moving through
    ``values`` ``(m + 1, D)`` at increasing ``knots`` ``(m + 1,)`` (activation first) along
    ``profile``, plus the blend of the ``incoming`` velocity ``(D,)`` over the first
    transition (:meth:`motor.program.lmp.VectorKeyframes.sample`)."""
    t = np.ascontiguousarray(times, dtype=float).reshape(-1)
    out = np.empty((t.size, values.shape[1]))
    _vector_rows(knots, values, incoming, profile.grid, profile.fractions, t, out)
    return out


def rotation_keyframes(knots: np.ndarray, keys: np.ndarray, steps: np.ndarray, incoming: np.ndarray, profile: TimeProfile, times: np.ndarray) -> np.ndarray:
    """Quaternions ``(n, 4)`` at ``times`` ``(n,)`` (seconds) of a rotation turning from
    each of ``keys`` ``(m + 1, 4)`` by its segment's local rotation vector ``steps``
    ``(m, 3)`` along ``profile`` between ``knots`` ``(m + 1,)``, with the ``incoming``
    angular velocity ``(3,)`` blended in on the left
    (:meth:`motor.program.lmp.RotationKeyframes.sample`)."""
    t = np.ascontiguousarray(times, dtype=float).reshape(-1)
    out = np.empty((t.size, 4))
    _rotation_rows(knots, keys, steps, incoming, profile.grid, profile.fractions, t, out)
    return out


def load_kernels() -> None:
    """Run this module's compiled loops once (they load when it is imported):
    :func:`motor.compiled.warm_up`."""
    knots, table = np.array([0.0, 1.0]), TimeProfile("straight", np.array([0.0, 1.0]), np.ones(2))
    vector_keyframes(knots, np.zeros((2, 1)), np.zeros(1), table, np.array([0.5]))
    rotation_keyframes(knots, np.array([[0.0, 0.0, 0.0, 1.0]] * 2), np.zeros((1, 3)), np.zeros(3), table, np.array([0.5]))
