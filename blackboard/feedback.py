"""BML 1.0 feedback: what a realizer tells the agent that sent it a block.

BML defines four kinds, and mura sends them as these events:

* :class:`PredictionFeedback` — the planned times of every sync point of a chunk's
  behaviours, as soon as the chunk is planned and before any of it runs (BML's
  ``<predictionFeedback>``; a block of several speeches gets one per speech);
* :class:`BlockProgress` — the block starts (sent when its first chunk takes control,
  with the time of the block clock's zero) and ends
  (``status`` ``DONE``, ``INTERRUPTED`` or ``FAILED``: BML 1.0 has only ``start`` and
  ``end``; the status is mura's, as AsapRealizer adds one);
* :class:`SyncPointProgress` — a behaviour passes one of its sync points (a speech its
  ``<sync>`` markers as well);
* :class:`WarningFeedback` — what the block leaves out, drops or cannot do as asked.

Times are on the block clock (seconds from the block start); ``global_time`` is the
session clock of the realizer. :class:`FeedbackTranslator` listens to the scheduler's
events (:mod:`blackboard.events`) and publishes these for the blocks registered with it.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Union

from blackboard.chunk import ChunkState
from blackboard.events import BehaviorFeedback, ChunkPlanned, ChunkStateChanged, Event, UtteranceEnded
from mura.model import BML_SYNC_PEGS

_STATUS = {"done": "DONE", "interrupted": "INTERRUPTED", "failed": "FAILED"}


@dataclass(frozen=True)
class BlockProgress:
    """Block ``block`` starts or ends (``point``); ``status`` says how it ended."""

    block: str
    point: str
    time: float
    global_time: float
    status: str = ""
    character: str | None = None

    @property
    def id(self) -> str:
        return f"{self.block}:{self.point}"


@dataclass(frozen=True)
class SyncPointProgress:
    """Behaviour ``behavior`` of block ``block`` passes its sync point ``sync`` (BML name)."""

    block: str
    behavior: str
    sync: str
    time: float
    global_time: float
    character: str | None = None

    @property
    def id(self) -> str:
        return f"{self.block}:{self.behavior}:{self.sync}"


@dataclass(frozen=True)
class PredictionFeedback:
    """The planned time of each sync point (BML names) of each behaviour of chunk ``chunk``."""

    block: str
    chunk: int
    behaviors: Mapping[str, Mapping[str, float]]
    kinds: Mapping[str, str]
    global_start: float
    global_end: float
    character: str | None = None


@dataclass(frozen=True)
class WarningFeedback:
    """Something block ``block`` asked for that mura leaves out or changes; ``where`` is
    ``FILE:LINE:COL`` when the block's text says where."""

    block: str
    kind: str
    message: str
    where: str | None = None


BmlFeedback = Union[BlockProgress, SyncPointProgress, PredictionFeedback, WarningFeedback]


@dataclass
class _Block:
    sync_points: Mapping[str, tuple[str, ...]]
    kinds: Mapping[str, str]
    character: str | None
    origin: float = 0.0
    started: bool = False
    warned: int = 0
    initial: set[str] = field(default_factory=set)


class FeedbackTranslator:
    """Turns the scheduler's events of registered blocks into BML feedback for ``publish``.

    Register a block (:meth:`register`) before the scheduler starts it; its utterance's name
    must be the block id. Thread-safe: the scheduler calls it from its own thread.
    """

    def __init__(self, publish: Callable[[BmlFeedback], None]) -> None:
        self._publish = publish
        self._blocks: dict[str, _Block] = {}
        self._lock = threading.Lock()

    def register(self, block: str, sync_points: Mapping[str, tuple[str, ...]], kinds: Mapping[str, str],
                 character: str | None = None, warnings: tuple[str, ...] = ()) -> None:
        """Follow block ``block``; ``warnings`` are the reader's, already reported (not repeated)."""
        with self._lock:
            self._blocks[block] = _Block(dict(sync_points), dict(kinds), character, initial=set(warnings))

    def registered(self, block: str) -> bool:
        with self._lock:
            return block in self._blocks

    def __call__(self, event: Event) -> None:
        with self._lock:
            block = self._blocks.get(getattr(event, "utterance", None))
        if block is None:
            return
        name = event.utterance
        if isinstance(event, ChunkPlanned):
            block.origin = event.origin
            self._warnings(name, block, event.warnings)
            self._publish(self._prediction(name, block, event))
        elif isinstance(event, ChunkStateChanged) and event.chunk == 0 and event.state is ChunkState.LURKING:
            block.started = True  # the block clock's zero: every sync time counts from it
            self._publish(BlockProgress(name, "start", 0.0, block.origin, "", block.character))
        elif isinstance(event, BehaviorFeedback):
            sync = self._sync_name(block, event.behavior, event.point)
            if sync is not None:
                self._publish(SyncPointProgress(name, event.behavior, sync, event.time, block.origin + event.time, block.character))
        elif isinstance(event, UtteranceEnded):
            block.origin = event.origin
            self._warnings(name, block, event.warnings)
            if event.error is not None:
                self._publish(WarningFeedback(name, "EXECUTION_FAILED", event.error))
            self._publish(BlockProgress(name, "end", event.time, event.origin + event.time, _STATUS[event.status], block.character))
            with self._lock:
                self._blocks.pop(name, None)

    def _warnings(self, name: str, block: _Block, warnings: tuple[str, ...]) -> None:
        for warning in warnings[block.warned:]:
            if warning not in block.initial:
                self._publish(WarningFeedback(name, "SCHEDULING", warning))
        block.warned = max(block.warned, len(warnings))

    def _prediction(self, name: str, block: _Block, event: ChunkPlanned) -> PredictionFeedback:
        predicted: dict[str, dict[str, float]] = {}
        for behavior, phases in event.phases.items():
            points = block.sync_points.get(behavior, ())
            predicted[behavior] = {sync: phases[BML_SYNC_PEGS[sync]] for sync in points if BML_SYNC_PEGS.get(sync) in phases}
        for tag, time in event.time_tags.items():
            behavior, _, sync = tag.partition(":")
            if behavior in block.sync_points:
                predicted.setdefault(behavior, {})[sync] = time
        times = [t for syncs in predicted.values() for t in syncs.values()]
        start, end = (min(times), max(times)) if times else (0.0, 0.0)
        kinds = {b: block.kinds.get(b, "") for b in predicted}
        return PredictionFeedback(name, event.chunk, predicted, kinds, event.origin + start, event.origin + end, block.character)

    @staticmethod
    def _sync_name(block: _Block, behavior: str, point: str) -> str | None:
        """The BML name of peg ``point`` of ``behavior`` (a speech reports BML names already)."""
        points = block.sync_points.get(behavior, ())
        if point in points:
            return point
        return next((sync for sync in points if BML_SYNC_PEGS.get(sync) == point), None)
