"""Timing a call the way every speed benchmark does: the median over several runs."""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable


def median_seconds(call: Callable[[], object], repeats: int, clock: Callable[[], float] = time.perf_counter) -> float:
    """Median time of ``repeats`` calls of ``call``, seconds, read from ``clock``: wall time
    by default, or e.g. :func:`time.process_time` (this process's CPU time, steadier on a
    shared machine)."""
    durations = []
    for _ in range(repeats):
        started = clock()
        call()
        durations.append(clock() - started)
    return statistics.median(durations)
