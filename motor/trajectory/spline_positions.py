"""Positions on a quintic Hermite spline, one compiled pass over the sample times.

:meth:`motor.trajectory.spline.WristTrajectory.position` is asked for every frame of
every wrist's realization; in numpy it cost a dozen small array operations per call
(locating the knots, clipping, gathering the coefficients, Horner's rule), most of the
time in the calls themselves. :func:`spline_positions` does the same operations in the
same order per sample, so the same numbers bit for bit
(``tests/perf_equivalence/test_keyframe_sampling.py`` pins it to the numpy code kept in
``tests/perf_equivalence/plain_keyframes.py``). :func:`knot_segment` is numpy's way of
finding the span a time falls in, for this module's and other compiled callers.
"""

from __future__ import annotations

import numba
import numpy as np

from motor.kernel_types import READ1, READ3, WRITE2, clip


@numba.njit(cache=True, error_model="numpy", inline="always")
def knot_segment(knots, t):  # noqa: ANN001, ANN201
    """The span of increasing ``knots`` that time ``t`` falls in:
    ``np.clip(np.searchsorted(knots, t, side="right") - 1, 0, knots.size - 2)``, a NaN
    sorting after every knot as in numpy."""
    low, high = 0, knots.shape[0]
    while low < high:
        middle = (low + high) // 2
        if t < knots[middle]:
            high = middle
        else:
            low = middle + 1
    return min(max(low - 1, 0), knots.shape[0] - 2)


@numba.njit([numba.void(READ1, READ3, READ1, WRITE2)], cache=True, error_model="numpy")
def _position_rows(knots, coefficients, times, out):  # noqa: ANN001, ANN202
    first, last = knots[0], knots[knots.shape[0] - 1]
    for i in range(times.shape[0]):
        t = clip(times[i], first, last)
        k = knot_segment(knots, t)
        u = (t - knots[k]) / (knots[k + 1] - knots[k])
        for d in range(out.shape[1]):
            c = coefficients[k]
            out[i, d] = c[0, d] + u * (c[1, d] + u * (c[2, d] + u * (c[3, d] + u * (c[4, d] + u * c[5, d]))))


def spline_positions(knots: np.ndarray, coefficients: np.ndarray, times: np.ndarray) -> np.ndarray:
    """Positions ``(n, d)`` at ``times`` ``(n,)`` (seconds) of the quintic pieces
    ``coefficients`` ``(k − 1, 6, d)`` between increasing ``knots`` ``(k,)`` (seconds),
    in the unit time of each piece; held before the first knot and after the last."""
    t = np.ascontiguousarray(times, dtype=float).reshape(-1)
    out = np.empty((t.size, coefficients.shape[2]))
    _position_rows(knots, coefficients, t, out)
    return out


def load_kernels() -> None:
    """Run this module's compiled loop once (it loads when the module is imported):
    :func:`motor.compiled.warm_up`."""
    spline_positions(np.array([0.0, 1.0]), np.zeros((1, 6, 3)), np.array([0.5]))
