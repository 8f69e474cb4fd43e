"""A chunk's processing states (seed 004, Fig. 6) and the transitions between them.

InPrep (speech and movement planning) → Pending (planned) → Lurking (control passed to
the chunk, its LMPs activate themselves) → InExec (speech or gesture running) →
Subsiding (phrase and strokes done, retractions still active) → Completed. Subsiding is
skipped when no retraction is active at the end of the strokes. FAILED ends a chunk whose
planning failed, or one dropped before it ran (an interrupt, or an earlier failure).
"""

from __future__ import annotations

import threading
from collections.abc import Mapping
from dataclasses import dataclass
from enum import Enum

from blackboard.errors import IllegalTransition


class ChunkState(Enum):
    """The processing state of one chunk; values are the seed's names."""

    IN_PREP = "InPrep"
    PENDING = "Pending"
    LURKING = "Lurking"
    IN_EXEC = "InExec"
    SUBSIDING = "Subsiding"
    COMPLETED = "Completed"
    FAILED = "Failed"


#: Legal transitions: state → the states it may move to.
TRANSITIONS: Mapping[ChunkState, frozenset[ChunkState]] = {
    ChunkState.IN_PREP: frozenset({ChunkState.PENDING, ChunkState.FAILED}),
    ChunkState.PENDING: frozenset({ChunkState.LURKING, ChunkState.FAILED}),
    ChunkState.LURKING: frozenset({ChunkState.IN_EXEC, ChunkState.FAILED}),
    ChunkState.IN_EXEC: frozenset({ChunkState.SUBSIDING, ChunkState.COMPLETED}),
    ChunkState.SUBSIDING: frozenset({ChunkState.COMPLETED}),
    ChunkState.COMPLETED: frozenset(),
    ChunkState.FAILED: frozenset(),
}


@dataclass(frozen=True)
class Transition:
    """One state change at ``time`` (seconds on the clock in use); ``reason`` says why when not obvious."""

    state: ChunkState
    time: float
    reason: str = ""


class ChunkStateMachine:
    """The states one chunk went through, with the time of each; thread-safe."""

    def __init__(self, label: str, time: float) -> None:
        self.label = label
        self._history: list[Transition] = [Transition(ChunkState.IN_PREP, time)]
        self._lock = threading.Lock()

    @property
    def state(self) -> ChunkState:
        with self._lock:
            return self._history[-1].state

    @property
    def history(self) -> tuple[Transition, ...]:
        with self._lock:
            return tuple(self._history)

    @property
    def finished(self) -> bool:
        return not TRANSITIONS[self.state]

    def move(self, state: ChunkState, time: float, reason: str = "") -> Transition:
        """Enter ``state`` at ``time``; :class:`IllegalTransition` when the machine has no such edge."""
        with self._lock:
            current = self._history[-1]
            if state not in TRANSITIONS[current.state]:
                allowed = ", ".join(s.value for s in TRANSITIONS[current.state]) or "none (final state)"
                raise IllegalTransition(
                    f"{self.label}: cannot go from {current.state.value} to {state.value} (allowed: {allowed})"
                )
            if time < current.time:
                time = current.time  # a live clock read on another thread may lag by microseconds
            transition = Transition(state, time, reason)
            self._history.append(transition)
            return transition
