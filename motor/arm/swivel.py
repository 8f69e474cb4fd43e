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

import numpy as np

from motor.arm.ik import parabola_offset
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
MAX_STEP = 2
HORIZON = 3


@dataclass(frozen=True)
class SwivelState:
    """Where a swivel track stands at one grid point: the chosen candidate as an unwrapped
    step count from the first candidate (``cell``, so that the track can turn past ±π
    without a jump) and the swivel there, refined between candidates (radians, unwrapped)."""

    cell: int
    swivel: float


def smooth_swivels(
    costs: np.ndarray, candidates: np.ndarray, previous: SwivelState | None, horizon: int = HORIZON, now: np.ndarray | None = None
) -> list[SwivelState]:
    """A swivel track over ``m`` grid points, continuous by construction.

    ``costs (m + horizon, K)`` are the costs of the evenly spaced ``candidates (K,)`` (a
    whole circle) at consecutive grid points; ``previous`` is the track's state at the
    grid point before the first (None: the track starts here, at its cheapest candidate).
    ``now (m, K)``, if given, are costs that count at their own grid point only, not in
    the look ahead of earlier ones (what depends on another track's future).

    Each grid point's swivel moves at most :data:`MAX_STEP` candidates from the previous
    one, to the candidate minimizing the cost of the change (:data:`SMOOTHNESS`) plus the
    cost to go over the next ``horizon`` grid points — a fixed-lag dynamic programme
    whose value tables are computed for all grid points at once; only the walk along the
    chosen candidates is sequential, one table look-up per grid point. The swivel is then
    refined between candidates by a parabola through the chosen one's neighbours. The
    result depends on the costs up to ``horizon`` grid points ahead and on ``previous``
    only, so a track computed piece by piece equals one computed at once.
    """
    count = len(candidates)
    step = float(candidates[1] - candidates[0])
    shifts = np.arange(-MAX_STEP, MAX_STEP + 1)
    change = SMOOTHNESS * (shifts * step) ** 2
    value = costs
    for _ in range(horizon):
        value = costs[: value.shape[0] - 1] + _banded_minimum(value[1:], shifts, change)
    if now is not None:
        value = value + now
    rows = value.shape[0]
    options = np.stack([np.roll(value, -int(d), axis=1) + c for d, c in zip(shifts, change)], axis=1)
    moves = (np.argmin(options, axis=1) - MAX_STEP).ravel()
    cells = np.empty(rows, dtype=np.int64)
    cell = int(np.argmin(value[0])) if previous is None else previous.cell
    begin = 1 if previous is None else 0
    if previous is None:
        cells[0] = cell
    for row in range(begin, rows):
        cell += int(moves[row * count + cell % count])
        cells[row] = cell
    before = np.concatenate([[cells[0] if previous is None else previous.cell], cells[:-1]])
    near = cells[:, None] + np.array([-1, 0, 1])
    quadratic = SMOOTHNESS * ((near - before[:, None]) * step) ** 2
    if previous is None:
        quadratic[0] = 0.0
    around = value[np.arange(rows)[:, None], near % count] + quadratic
    offsets = parabola_offset(around[:, 0], around[:, 1], around[:, 2])
    swivels = candidates[0] + (cells + offsets) * step
    return [SwivelState(int(c), float(s)) for c, s in zip(cells, swivels)]


def _banded_minimum(value: np.ndarray, shifts: np.ndarray, change: np.ndarray) -> np.ndarray:
    """``min_d change[d] + value[:, (i + shifts[d]) mod K]`` for every candidate ``i``."""
    best = np.roll(value, -int(shifts[0]), axis=1) + change[0]
    for d, c in zip(shifts[1:], change[1:]):
        best = np.minimum(best, np.roll(value, -int(d), axis=1) + c)
    return best
