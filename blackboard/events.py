"""What observers of the blackboard hear: plain event dataclasses and a bus to subscribe to.

Times are seconds on the utterance clock (0 = the utterance's start). Observers are
plain callables; in a live run they are called from the scheduler's thread or from the
planning worker, so they must be quick and thread-safe.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Union

import numpy as np

from blackboard.chunk import ChunkState
from motor.motion import Motion


@dataclass(frozen=True)
class ChunkStateChanged:
    """Chunk ``chunk`` of utterance ``utterance`` entered ``state`` (from ``previous``)."""

    utterance: str
    chunk: int
    previous: ChunkState | None
    state: ChunkState
    time: float
    reason: str = ""


@dataclass(frozen=True)
class BehaviorFeedback:
    """A behaviour reports progress: ``kind`` is ``started``, ``sync`` (``point`` names the peg) or ``finished``."""

    utterance: str
    chunk: int
    behavior: str
    kind: str
    point: str
    time: float


@dataclass(frozen=True, eq=False)
class SpeechStarted:
    """Chunk ``chunk`` starts speaking ``text`` at ``time``; ``audio`` (int16 mono at
    ``sample_rate`` Hz) is its speech when the backend produced audio, for live playback."""

    utterance: str
    chunk: int
    text: str
    time: float
    audio: np.ndarray | None = None
    sample_rate: int | None = None


@dataclass(frozen=True)
class SpeechEnded:
    utterance: str
    chunk: int
    time: float


@dataclass(frozen=True)
class FramesReady:
    """Frames with times in ``[start, end)`` are ready; ``motion.start_time`` is the first one's time."""

    utterance: str
    start: float
    end: float
    motion: Motion


@dataclass(frozen=True)
class ChunkPlanned:
    """Chunk ``chunk`` is planned (it enters Pending): the times its behaviours' pegs
    (``phases``, by behaviour id) and its time tags will have, before any of it runs.

    Times are on the utterance clock; ``origin`` is the session-clock time of the utterance
    start; ``warnings`` are the utterance's warnings so far.
    """

    utterance: str
    chunk: int
    origin: float
    speech_onset: float | None
    speech_end: float | None
    phases: Mapping[str, Mapping[str, float]]
    time_tags: Mapping[str, float]
    warnings: tuple[str, ...] = ()


@dataclass(frozen=True)
class UtteranceEnded:
    """The utterance is over at ``time`` (utterance clock): ``status`` is ``done``,
    ``interrupted`` or ``failed`` (``error`` says why); ``warnings`` are all of its warnings."""

    utterance: str
    time: float
    origin: float
    status: str
    warnings: tuple[str, ...] = ()
    error: str | None = None


Event = Union[ChunkStateChanged, BehaviorFeedback, SpeechStarted, SpeechEnded, FramesReady, ChunkPlanned, UtteranceEnded]
Observer = Callable[[Event], None]


class EventBus:
    """Delivers every event to every subscriber, in subscription order."""

    def __init__(self) -> None:
        self._observers: list[Observer] = []
        self._lock = threading.Lock()

    def subscribe(self, observer: Observer) -> Callable[[], None]:
        """Add ``observer``; returns a function that removes it again."""
        with self._lock:
            self._observers.append(observer)
        return lambda: self._unsubscribe(observer)

    def _unsubscribe(self, observer: Observer) -> None:
        with self._lock:
            if observer in self._observers:
                self._observers.remove(observer)

    def publish(self, event: Event) -> None:
        with self._lock:
            observers = tuple(self._observers)
        for observer in observers:
            observer(event)
