"""Clocks the scheduler runs on: virtual for offline rendering and tests, wall for live runs.

Both read seconds since the clock was made. The scheduler only ever asks ``now()`` and
``sleep_until(t)``, so the same code renders offline (the virtual clock jumps) and plays
live (the wall clock sleeps).
"""

from __future__ import annotations

import threading
import time
from typing import Protocol, runtime_checkable


@runtime_checkable
class Clock(Protocol):
    """A source of time in seconds; ``live`` clocks pass time on their own."""

    live: bool

    def now(self) -> float:
        """Seconds since the clock started."""
        ...

    def sleep_until(self, t: float) -> None:
        """Return once ``now() >= t`` (at once when ``t`` has passed)."""
        ...


class VirtualClock:
    """Deterministic time that advances only when the scheduler sleeps: as fast as the machine allows."""

    live = False

    def __init__(self, start: float = 0.0) -> None:
        self._now = float(start)
        self._lock = threading.Lock()

    def now(self) -> float:
        with self._lock:
            return self._now

    def sleep_until(self, t: float) -> None:
        with self._lock:
            self._now = max(self._now, float(t))


class WallClock:
    """Real time from :func:`time.monotonic`.

    ``speedup`` runs the clock faster than real time (10 means one clock second passes in
    0.1 s of wall time), for short live tests; 1 is real time.
    """

    live = True

    def __init__(self, speedup: float = 1.0) -> None:
        if not speedup > 0:
            raise ValueError(f"WallClock speedup must be positive, got {speedup!r}")
        self.speedup = float(speedup)
        self._origin = time.monotonic()

    def now(self) -> float:
        return (time.monotonic() - self._origin) * self.speedup

    def sleep_until(self, t: float) -> None:
        while (remaining := t - self.now()) > 0:
            time.sleep(remaining / self.speedup)
