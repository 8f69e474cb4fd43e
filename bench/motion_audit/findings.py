"""Where a figure is worst: the value, the file, the time and what (joint, pair, stroke).

Every metric of the audit reports its worst case as a :class:`Worst`, so that a
developer can open the file at that time and look.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace

import numpy as np


@dataclass(frozen=True)
class Worst:
    """``value`` in the metric's unit; ``time`` in seconds on the render's clock; ``what``
    names the joint, pair or stroke; ``file`` the render (filled in by the file audit)."""

    value: float
    time: float
    what: str
    file: str = ""

    def in_file(self, file: str) -> Worst:
        return replace(self, file=file)

    def as_json(self) -> dict:
        return {"value": _finite(self.value), "time": round(self.time, 4), "what": self.what, "file": self.file}


@dataclass(frozen=True)
class EventCount:
    """Frames (frame-to-frame transitions) flagged, the events they form (runs of flagged
    transitions with at most :data:`EVENT_GAP` unflagged ones between) and the worst one."""

    frames: int
    events: int
    worst: Worst | None

    def as_json(self) -> dict:
        return {"frames": self.frames, "events": self.events, "worst": self.worst.as_json() if self.worst else None}


@dataclass(frozen=True)
class Failure:
    """A file that could not be audited (or an item that could not be rendered), and why."""

    file: str
    reason: str

    def as_json(self) -> dict:
        return {"file": self.file, "reason": self.reason}


#: Flagged transitions this close (in frames) belong to one event.
EVENT_GAP = 2


def count_events(flags: np.ndarray) -> int:
    """Runs of True in ``flags``, joining runs separated by at most :data:`EVENT_GAP` False."""
    where = np.flatnonzero(flags)
    if where.size == 0:
        return 0
    return int(1 + np.count_nonzero(np.diff(where) > EVENT_GAP + 1))


def worst_of(candidates: Iterable[Worst | None], badness: Callable[[float], float] = float) -> Worst | None:
    """The candidate with the largest ``badness(value)``; None if there is none."""
    present = [candidate for candidate in candidates if candidate is not None]
    return max(present, key=lambda worst: badness(worst.value)) if present else None


def _finite(value: float) -> float | None:
    return round(float(value), 6) if np.isfinite(value) else None
