"""The scheduler's agenda: actions due at times on the session clock, in time order.

Entries are kept in a heap; cancelling marks an entry, which is then skipped when due
(so that moving an entry is cancelling it and adding another). Entries due at the same
time run in the order they were added.
"""

from __future__ import annotations

import heapq
import itertools
import math
from collections.abc import Callable


class Agenda:
    """Actions due at times (s); :meth:`at` returns the key :meth:`cancel` takes."""

    def __init__(self) -> None:
        self._heap: list[tuple[float, int, Callable[[], None]]] = []
        self._cancelled: set[int] = set()
        self._counter = itertools.count()

    def __bool__(self) -> bool:
        self._drop_cancelled()
        return bool(self._heap)

    def at(self, time: float, action: Callable[[], None]) -> int:
        """Run ``action`` when time ``time`` is reached; returns the entry's key."""
        key = next(self._counter)
        heapq.heappush(self._heap, (time, key, action))
        return key

    def cancel(self, key: int) -> None:
        """The entry ``key`` will not run."""
        self._cancelled.add(key)

    def next_time(self) -> float:
        """When the earliest entry not cancelled is due (``inf`` when there is none)."""
        self._drop_cancelled()
        return self._heap[0][0] if self._heap else math.inf

    def _drop_cancelled(self) -> None:
        """Forget cancelled entries at the front, so that nobody waits for them."""
        while self._heap and self._heap[0][1] in self._cancelled:
            self._cancelled.discard(heapq.heappop(self._heap)[1])

    def pop_due(self, time: float) -> Callable[[], None] | None:
        """The earliest entry not cancelled that is due by ``time``, removed; None when there is none."""
        while self._heap and self._heap[0][0] <= time:
            _, key, action = heapq.heappop(self._heap)
            if key in self._cancelled:
                self._cancelled.discard(key)
                continue
            return action
        return None
