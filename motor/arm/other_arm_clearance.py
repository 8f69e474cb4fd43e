"""How close an arm's candidate elbows bring it to the other arm, compiled.

:func:`motor.arm.clearance.clearance` keeps an arm clear of the other arm's upper arm,
forearm and hand (:class:`motor.arm.clearance.ArmSegments`) as well as of the body. Per
frame, the box of each of the arm's two segments over all candidate elbows (its ends are
affine in the elbow with non-negative weights), grown by the segment's radius and
:data:`motor.arm.candidate_clearance.CLEARANCE`, is tested against the box of each of
the other arm's capsules; where they meet, every candidate's segment is measured against
that capsule (:func:`other_arm_rows`). The arithmetic of the numpy version it replaced
(``tests/perf_equivalence/plain_clearance.py``), the same operations in the same order,
numpy's NaN rules included: a frame whose boxes hold a NaN is not measured. Metres.
"""

from __future__ import annotations

import numba
import numpy as np

from motor.arm.candidate_clearance import CLEARANCE, CONTACT_PENALTY, overlap_cost, segment_ends
from motor.body.distance import segments_gap
from motor.kernel_types import READ1, READ2, READ3, READ_INTS1, READ_INTS2, WRITE2, maximum, minimum


@numba.njit(cache=True, error_model="numpy", inline="always")
def _column_extremes(elbows, c):  # noqa: ANN001, ANN202
    """``elbows[:, c].min()`` and ``.max()`` as numpy gives them (NaN if any is)."""
    low, high = elbows[0, c], elbows[0, c]
    for k in range(1, elbows.shape[0]):
        low, high = minimum(low, elbows[k, c]), maximum(high, elbows[k, c])
    return low, high


@numba.njit(cache=True, error_model="numpy", inline="always")
def _penalty(distance):  # noqa: ANN001, ANN202
    """:func:`motor.arm.clearance.penalty` of one distance, the same operations in the same order."""
    inside = max(CLEARANCE - distance, 0.0) * (1.0 / CLEARANCE)
    return CONTACT_PENALTY * inside * inside


@numba.njit(cache=True, error_model="numpy", inline="always")
def _add_frame(s, w, elbows, segments, other, other_radii, i, cost):  # noqa: ANN001, ANN202
    """Add into ``cost (K,)`` the penalties of frame ``i``'s candidate elbows ``elbows (K, 3)``
    of the arm from shoulder ``s`` to wrist ``w`` (3-tuples): :func:`other_arm_rows` of one frame."""
    (lx, hx), (ly, hy), (lz, hz) = _column_extremes(elbows, 0), _column_extremes(elbows, 1), _column_extremes(elbows, 2)
    low, high = (lx, ly, lz), (hx, hy, hz)
    for g in range(2):
        f0, f1, radius, from_shoulder = segments[g, 0], segments[g, 1], segments[g, 2], segments[g, 3] > 0.5
        start = s if from_shoulder else w
        w0, w1 = (f0, f1) if from_shoulder else (1.0 - f0, 1.0 - f1)
        grow = radius + CLEARANCE
        box_low = [minimum(start[c] + w0 * (low[c] - start[c]), start[c] + w1 * (low[c] - start[c])) - grow for c in range(3)]
        box_high = [maximum(start[c] + w0 * (high[c] - start[c]), start[c] + w1 * (high[c] - start[c])) + grow for c in range(3)]
        for p in range(3):
            r = other_radii[p]
            near = True
            for c in range(3):
                a, b = other[p, i, c], other[p, i, 3 + c]
                near = near and box_low[c] <= maximum(a, b) + r and box_high[c] >= minimum(a, b) - r
            if not near:
                continue
            oa = (other[p, i, 0], other[p, i, 1], other[p, i, 2])
            ob = (other[p, i, 3], other[p, i, 4], other[p, i, 5])
            for k in range(elbows.shape[0]):
                ax, ay, az, bx, by, bz = segment_ends(s, w, elbows[k, 0], elbows[k, 1], elbows[k, 2], f0, f1, from_shoulder)
                distance = segments_gap(ax, ay, az, bx, by, bz, *oa, *ob) - radius - r
                cost[k] += _penalty(distance) if p == 2 else overlap_cost(distance)


@numba.njit(
    [numba.void(READ2, READ2, READ2, READ2, READ2, READ2, READ3, READ1, WRITE2)],
    cache=True,
    error_model="numpy",
)
def other_arm_rows(shoulder, wrist, ex, ey, ez, segments, other, other_radii, cost):  # noqa: ANN001, ANN202
    """Add into ``cost (n, K)`` the penalty of each candidate elbow ``ex, ey, ez (n, K)`` of
    the arm from ``shoulder`` to ``wrist (n, 3)`` (segments: a
    :func:`motor.arm.clearance.segment_table`) coming near the other arm's capsules
    ``other (3, n, 6)`` (upper arm, forearm, hand: end points a then b) of radii
    ``other_radii (3,)``: :func:`motor.arm.clearance.overlap_penalty` of the distance from
    its upper arm and forearm, the plain :func:`motor.arm.clearance.penalty` from its hand
    (hands may touch the other arm where it is asked). By segment, then capsule, as the
    numpy version added them."""
    n, k_count = ex.shape
    elbows = np.empty((k_count, 3))
    for i in range(n):
        for k in range(k_count):
            elbows[k, 0], elbows[k, 1], elbows[k, 2] = ex[i, k], ey[i, k], ez[i, k]
        s = (shoulder[i, 0], shoulder[i, 1], shoulder[i, 2])
        w = (wrist[i, 0], wrist[i, 1], wrist[i, 2])
        _add_frame(s, w, elbows, segments, other, other_radii, i, cost[i])


@numba.njit(
    [numba.void(READ2, READ2, READ2, READ1, READ1, READ3, READ1, numba.boolean[::1])],
    cache=True,
    error_model="numpy",
)
def near_frames(shoulder, wrist, center, radius, margins, other, other_radii, near):  # noqa: ANN001, ANN202
    """Into ``near (n,)``: whether the arm from ``shoulder`` to ``wrist (n, 3)`` with its
    elbow anywhere on the circle of ``center (n, 3)`` and ``radius (n,)`` may come near
    the other arm's capsules ``other (3, n, 6)``: the box of the shoulder, the wrist and
    the circle's centre grown by its radius plus ``margins`` (the other arm's largest
    radius, this arm's largest, the clearance; added in that order) meets one of theirs."""
    for i in range(near.size):
        reach = radius[i] + margins[0] + margins[1] + margins[2]
        low = [minimum(minimum(shoulder[i, c], wrist[i, c]), center[i, c] - reach) for c in range(3)]
        high = [maximum(maximum(shoulder[i, c], wrist[i, c]), center[i, c] + reach) for c in range(3)]
        found = False
        for p in range(3):
            meets = True
            for c in range(3):
                a, b = other[p, i, c], other[p, i, 3 + c]
                meets = meets and low[c] <= maximum(a, b) + other_radii[p] and high[c] >= minimum(a, b) - other_radii[p]
            found = found or meets
        near[i] = found


@numba.njit(
    [numba.void(READ_INTS1, READ2, READ2, READ2, READ2, READ2, READ1, READ2, READ2, READ_INTS2, READ2, READ3, READ1, WRITE2)],
    cache=True,
    error_model="numpy",
)
def other_arm_window(rows, shoulder, wrist, center, down, out, radius, cos, sin, cells, segments, other, other_radii, costs):  # noqa: ANN001, ANN202, E501
    """Into ``costs (n, K)``, for the frames ``rows (R,)`` only: the other arm's penalty
    (:func:`other_arm_rows`) of the candidates at the swivels with cosines and sines
    ``cos``, ``sin (R, W)`` on the elbow circles (``center``, in-plane axes ``down`` and
    ``out`` ``(n, 3)``, ``radius (n,)``), each written to its candidate's cell
    ``cells (R, W)`` (indices into ``K``): the elbows as
    :func:`motor.arm.swivel_cost.candidate_elbows` places them, the same operations."""
    w_count = cos.shape[1]
    elbows = np.empty((w_count, 3))
    penalty = np.empty(w_count)
    for r in range(rows.size):
        i = rows[r]
        for k in range(w_count):
            for c in range(3):
                elbows[k, c] = center[i, c] + radius[i] * (down[i, c] * cos[r, k] + out[i, c] * sin[r, k])
        penalty[:] = 0.0
        s = (shoulder[i, 0], shoulder[i, 1], shoulder[i, 2])
        w = (wrist[i, 0], wrist[i, 1], wrist[i, 2])
        _add_frame(s, w, elbows, segments, other, other_radii, i, penalty)
        for k in range(w_count):
            costs[i, cells[r, k]] = penalty[k]


def load_kernels() -> None:
    """Run this module's compiled loops once (they load when the module is imported):
    :func:`motor.compiled.warm_up`."""
    row, cell, segments, other, radii = np.zeros((1, 3)), np.ones((1, 1)), np.zeros((2, 4)), np.zeros((3, 1, 6)), np.zeros(3)
    other_arm_rows(row, row, cell, cell, cell, segments, other, radii, np.zeros((1, 1)))
    near_frames(row, row, row, np.zeros(1), np.zeros(3), other, radii, np.zeros(1, dtype=np.bool_))
    other_arm_window(np.zeros(1, dtype=np.int64), row, row, row, row, row, np.zeros(1), cell, cell, np.zeros((1, 1), dtype=np.int64), segments, other, radii, np.zeros((1, 1)))
