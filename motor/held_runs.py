"""Runs of identical rows evaluated once: a held channel value (a hold, the rest) gives
the same frame after frame, so the frame's function of it is computed once per run and
repeated, which is exact. The last run of a call is remembered, so that a value held
across calls (window after window) is not evaluated again either."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np


def run_starts(values: np.ndarray) -> np.ndarray:
    """Indices where a run of identical rows of ``values (n, ...)`` begins."""
    if values.shape[0] == 0:
        return np.zeros(0, dtype=int)
    changed = np.any(values[1:] != values[:-1], axis=1)
    return np.concatenate([[0], np.flatnonzero(changed) + 1])


class HeldRuns:
    """A row-wise function evaluated once per run of identical rows, remembering the
    last run of the previous call."""

    def __init__(self) -> None:
        self.row: np.ndarray | None = None
        self.result: np.ndarray | None = None

    def apply(self, function: Callable[[np.ndarray], np.ndarray], values: np.ndarray) -> np.ndarray:
        """``function`` of every row of ``values (n, ...)``: of each run's row once, repeated."""
        starts = run_starts(values)
        if starts.size == 0:
            return function(values)
        unique = values[starts]
        reuse = self.row is not None and np.array_equal(unique[0], self.row)
        fresh = function(unique[1:] if reuse else unique) if unique.shape[0] > int(reuse) else None
        result = fresh if not reuse else (self.result[None] if fresh is None else np.concatenate([self.result[None], fresh]))
        self.row, self.result = unique[-1].copy(), result[-1].copy()
        return np.repeat(result, np.diff(np.append(starts, values.shape[0])), axis=0)
