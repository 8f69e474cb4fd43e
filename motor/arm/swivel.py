"""The swivel: the elbow's angle about the shoulder–wrist axis (radians), the arm's one
redundant degree of freedom once the wrist is placed (seed 004's IK).

* :class:`SwivelLMP` — an LMP on ``(side, "swivel")`` that sets it through keys;
* :func:`smooth_swivels` — the swivel as a smooth function of time: a track over a
  grid of instants minimizing the IK's swivel cost (:func:`motor.arm.ik.swivel_costs`)
  plus a cost of change, never a per-instant argmin (which jumps between candidates of
  nearly equal cost and makes the elbow pop).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numba
import numpy as np

from motor.arm.swivel_cost import parabola_offset
from motor.kernel_types import READ2, READ_INTS1, WRITE2, WRITE_INTS1
from motor.program.lmp import TimePegs, VectorKeyframeLMP
from motor.trajectory.biocontrol import TimeProfile, minimum_jerk


class SwivelLMP(VectorKeyframeLMP):
    """Interpolation of the arm's swivel angle (radians) on ``(side, "swivel")``."""

    def __init__(
        self,
        side: str,
        pegs: TimePegs,
        angles: np.ndarray | Sequence[float],
        key_times: np.ndarray | None = None,
        time_profile: TimeProfile | str | None = None,
    ) -> None:
        super().__init__((side, "swivel"), pegs, np.asarray(angles, dtype=float), key_times, time_profile or minimum_jerk())


#: Swivel track (see :func:`smooth_swivels`): cost of changing the swivel between two
#: grid points (per radian squared), the largest change per grid point in candidate
#: steps, and how many grid points ahead each choice looks.
SMOOTHNESS = 2.0
MAX_STEP = 3
HORIZON = 8
DISCOUNT = 0.7


@dataclass(frozen=True)
class SwivelState:
    """Where a swivel track stands at one grid point: the chosen candidate as an unwrapped
    step count from the first candidate (``cell``, so that the track can turn past ±π
    without a jump) and the swivel there, refined between candidates (radians, unwrapped)."""

    cell: int
    swivel: float


def smooth_swivels(
    costs: np.ndarray,
    candidates: np.ndarray,
    previous: SwivelState | None,
    horizon: int = HORIZON,
    now: np.ndarray | None = None,
    turns: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """A swivel track over ``m`` grid points, continuous by construction: the candidates
    chosen (unwrapped step counts from the first, ``(m,)`` integers) and the swivels there
    (radians, unwrapped, ``(m,)``).

    ``costs (m + horizon, K)`` are the costs of the evenly spaced ``candidates (K,)`` (a
    whole circle) at consecutive grid points; ``previous`` is the track's state at the
    grid point before the first (None: the track starts here, at its cheapest candidate).
    ``now (m, K)``, if given, are costs that count at their own grid point only, not in
    the look ahead of earlier ones (what depends on another track's future). ``turns
    (m + horizon,)`` (radians, 0 if None) are how far the swivel's zero turned since the
    grid point before: the change of swivel that keeps the elbow in place, which costs
    nothing.

    Each grid point's swivel moves at most :data:`MAX_STEP` candidates (beyond the turn of
    the zero) from the previous one, to the candidate minimizing the cost of the change
    (:data:`SMOOTHNESS`) plus the cost to go over the next ``horizon`` grid points — a
    fixed-lag dynamic programme whose value tables are computed for all grid points at
    once; only the walk along the chosen candidates is sequential, one table look-up per
    grid point. The swivel is then refined between candidates by a parabola through the
    chosen one's neighbours. The result depends on the costs and turns up to ``horizon``
    grid points ahead and on ``previous`` only, so a track computed piece by piece equals
    one computed at once.
    """
    count = len(candidates)
    step = float(candidates[1] - candidates[0])
    turn = np.zeros(costs.shape[0]) if turns is None else np.asarray(turns, dtype=float) / step
    base = np.rint(turn).astype(np.int64)
    shifts = np.arange(-MAX_STEP, MAX_STEP + 1)
    # the cost of moving from candidate i to i + base + d at each grid point
    change = SMOOTHNESS * ((base[:, None] + shifts - turn[:, None]) * step) ** 2
    value = _cost_to_go(np.ascontiguousarray(costs, dtype=float), base, change, horizon)
    if now is not None:
        value = value + now
    first = int(np.argmin(value[0])) if previous is None else previous.cell
    chosen = _walk(value, base[: value.shape[0]], np.ascontiguousarray(change[: value.shape[0]]), first, previous is None)
    near = chosen[:, None] + np.array([-1, 0, 1])
    around = np.take_along_axis(value, near % count, axis=1)
    offsets = parabola_offset(around[:, 0], around[:, 1], around[:, 2])
    return chosen, candidates[0] + (chosen + offsets) * step


@numba.njit([WRITE_INTS1(READ2, READ_INTS1, READ2, numba.int64, numba.boolean)], cache=True, error_model="numpy")
def _walk(value, base, change, cell, fresh):  # noqa: ANN001, ANN202
    """The cells of the track along the value tables ``value (m, K)``: from ``cell`` at
    the grid point before the first (``fresh``: at the first itself), each grid point's
    cell is the one before moved by the zero's turn ``base`` and by the move ``d`` (at
    most :data:`MAX_STEP` candidates) whose ``change[:, d]`` plus value there is least —
    the first least, or the first NaN, as ``np.argmin`` over the banded options picks
    it. Only the options of the cell walked from are summed (the same sums)."""
    rows, count = value.shape
    cells = np.empty(rows, dtype=np.int64)
    for row in range(rows):
        if fresh and row == 0:
            cells[0] = cell
            continue
        start = cell % count - MAX_STEP + base[row]
        best, least = 0, value[row, start % count] + change[row, 0]
        if least == least:
            for d in range(1, 2 * MAX_STEP + 1):
                option = value[row, (start + d) % count] + change[row, d]
                if option != option:
                    best = d
                    break
                if option < least:
                    best, least = d, option
        cell += base[row] + best - MAX_STEP
        cells[row] = cell
    return cells


@numba.njit(
    [WRITE2(READ2, READ_INTS1,
                           READ2, numba.int64)],
    cache=True,
    error_model="numpy",
)  # fmt: skip
def _cost_to_go(costs, base, change, horizon):  # noqa: ANN001, ANN202
    """The value tables of the fixed-lag programme, ``horizon`` times over: each grid point's
    cost plus :data:`DISCOUNT` times the least, over moves ``d`` of at most
    :data:`MAX_STEP` candidates (beyond the zero's turn ``base``), of the move's ``change``
    plus the next grid point's value — ``(m, K)`` for ``costs (m + horizon, K)``.
    Compiled; the arithmetic of the numpy version, element by element
    (``tests/perf_equivalence/test_compiled_swivel.py``)."""
    count = costs.shape[1]
    value = costs.copy()
    around = np.empty(count + 2 * MAX_STEP)
    for _ in range(horizon):
        rows = value.shape[0] - 1
        table = np.empty((rows, count))
        for r in range(rows):
            # the next row's values turned by the zero's turn and wrapped round the circle:
            # around[i + d] is the value of moving d - MAX_STEP steps from candidate i
            turn = base[r + 1]
            for j in range(count + 2 * MAX_STEP):
                around[j] = value[r + 1, (j - MAX_STEP + turn) % count]
            for i in range(count):
                best = around[i] + change[r + 1, 0]
                for d in range(1, 2 * MAX_STEP + 1):
                    best = min(best, around[i + d] + change[r + 1, d])
                table[r, i] = costs[r, i] + DISCOUNT * best
        value = table
    return value


def load_kernels() -> None:
    """Run this module's compiled loop once (it loads when the module is imported):
    :func:`motor.compiled.warm_up`."""
    _cost_to_go(np.zeros((2, 4)), np.zeros(2, dtype=np.int64), np.zeros((2, 2 * MAX_STEP + 1)), 1)
    _walk(np.zeros((2, 4)), np.zeros(2, dtype=np.int64), np.zeros((2, 2 * MAX_STEP + 1)), 0, True)
