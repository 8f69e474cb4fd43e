"""The reach check's steps around its IK probes, in compiled passes.

Every step of :func:`motor.signing.reach.within_reach` probes each open wrist position a
margin beyond and short of itself, away from the shoulder, and from the IK's answers
moves it: pulled in within reach, stepped around the shoulder's front, or stepped back
from across the body. As numpy passes a step is some thirty operations over its rows,
and after the first step of a round most steps have only a few rows, so the calls'
overhead is most of their cost. Here each half is one compiled loop with numpy's
operations in numpy's order (a length sums its squares first to last, ``np.maximum``
keeps a NaN), so positions move bit for bit as the numpy passes moved them
(``tests/perf_equivalence/test_reach_steps.py``). Positions are metres in the avatar
frame.
"""

from __future__ import annotations

import numba
import numpy as np

from motor import quaternion as quat
from motor.arm.ik import ArmReach
from motor.kernel_types import READ1, READ2, READ_INTS1, WRITE2, WRITE_INTS1, maximum

#: Where :func:`reach_step` reads its constants in the ``limits`` it is given.
MARGIN, TOLERANCE, PENETRATION, STEP, INNER = range(5)


def reach_probes(fixed: np.ndarray, open_: np.ndarray, shoulder: np.ndarray, margin: float) -> tuple[np.ndarray, np.ndarray]:
    """For the open rows ``open_ (n,)`` of positions ``fixed (m, 3)``: the unit directions
    away from the ``shoulder`` ``(n, 3)``, and the targets ``margin`` metres beyond them
    and then short of them ``(2 n, 3)``."""
    away, targets = np.empty((open_.size, 3)), np.empty((2 * open_.size, 3))
    _probe_rows(fixed, open_, np.ascontiguousarray(shoulder, dtype=float), margin, away, targets)
    return away, targets


def reach_step(
    fixed: np.ndarray, open_: np.ndarray, away: np.ndarray, probed: ArmReach, shoulder: np.ndarray,
    limits: np.ndarray, outward: np.ndarray, ahead: np.ndarray, across: bool,
) -> np.ndarray:  # fmt: skip
    """Move the open rows ``open_ (n,)`` of ``fixed (m, 3)`` in place by the IK's answers
    ``probed`` beyond (rows ``0 … n − 1``) and short of them (``n … 2 n − 1``), as
    :func:`motor.signing.reach.within_reach` steps; returns which of them were moved
    ``(n,)``. ``limits``: the margin, the reach and penetration tolerances, the cross
    step (m) and the distance from the shoulder (m) within which a shortfall means too
    near (indices :data:`MARGIN` …); ``outward``: the step back from across the body;
    ``ahead``: the unit forward that turns a step away from the shoulder around its front."""
    moved = np.empty(open_.size, dtype=np.int64)
    columns = (probed.wrist, probed.shortfall, probed.penetration, shoulder, limits, outward, ahead)
    _step_rows(fixed, open_, away, *(np.ascontiguousarray(column, dtype=float) for column in columns), across, moved)
    return moved.astype(bool)


@numba.njit([numba.void(READ2, READ_INTS1, READ1, numba.float64, WRITE2, WRITE2)], cache=True, error_model="numpy")
def _probe_rows(fixed, open_, shoulder, margin, away, targets):  # noqa: ANN001, ANN202
    """Into ``away`` and ``targets``: :func:`reach_probes` row by row."""
    n = open_.size
    for j in range(n):
        i = open_[j]
        ax, ay, az = fixed[i, 0] - shoulder[0], fixed[i, 1] - shoulder[1], fixed[i, 2] - shoulder[2]
        scale = maximum(quat.length3(ax, ay, az), 1e-9)
        away[j, 0], away[j, 1], away[j, 2] = ax / scale, ay / scale, az / scale
        for c in range(3):
            targets[j, c] = fixed[i, c] + margin * away[j, c]
            targets[n + j, c] = fixed[i, c] - margin * away[j, c]


@numba.njit(
    [numba.void(WRITE2, READ_INTS1, READ2, READ2, READ1, READ1, READ1, READ1, READ1, READ1, numba.boolean, WRITE_INTS1)],
    cache=True,
    error_model="numpy",
)
def _step_rows(fixed, open_, away, wrist, shortfall, penetration, shoulder, limits, outward, ahead, across, moved):  # noqa: ANN001, ANN202
    """Into ``fixed`` and ``moved`` (1 where a row moved): :func:`reach_step` row by row."""
    n = open_.size
    margin, tolerance, deep, step, inner = limits[MARGIN], limits[TOLERANCE], limits[PENETRATION], limits[STEP], limits[INNER]
    for j in range(n):
        i = open_[j]
        outer = quat.length3(fixed[i, 0] - shoulder[0], fixed[i, 1] - shoulder[1], fixed[i, 2] - shoulder[2]) > inner
        far, near = shortfall[j], shortfall[n + j]
        # the IK reports a shortfall both beyond the arm's reach and too near the shoulder
        short = far > tolerance or near > tolerance
        too_far, too_near = short and outer, short and not outer
        crossing = maximum(penetration[j], penetration[n + j]) > deep and across
        lacking = (1.0 if too_near else 0.0) * maximum(maximum(far, near), step)
        rx, ry, rz = away[j, 0] + ahead[0], away[j, 1] + ahead[1], away[j, 2] + ahead[2]
        scale = maximum(quat.length3(rx, ry, rz), 1e-9)
        around = (rx / scale, ry / scale, rz / scale)
        back = 1.0 if crossing else 0.0
        for c in range(3):
            here = wrist[j, c] - margin * away[j, c] if too_far else fixed[i, c]
            fixed[i, c] = (here + lacking * around[c]) + back * outward[c]
        moved[j] = 1 if too_far or too_near or crossing else 0


def load_kernels() -> None:
    """Run this module's compiled loops once (they load when it is imported):
    :func:`motor.compiled.warm_up`."""
    fixed, open_ = np.ones((1, 3)), np.zeros(1, dtype=np.int64)
    away, _ = reach_probes(fixed, open_, np.zeros(3), 0.03)
    probed = ArmReach(np.ones((2, 3)), np.zeros(2), np.zeros(2))
    reach_step(fixed, open_, away, probed, np.zeros(3), np.array([0.03, 1e-3, 1e-3, 0.02, 0.3]), np.ones(3), np.array([0.0, 0.0, 1.0]), True)
