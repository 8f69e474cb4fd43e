"""The timeline of a whole utterance: chunk states, gesture phases, speech, pauses, warnings.

Every time is on the utterance clock (0 = the utterance's start), seconds. The scheduler
fills a :class:`Timeline` as it plans and runs; :meth:`Timeline.to_json` is the shape the
viewer reads and that ``agent.plots.plot_timeline`` draws as the seed's Fig. 6.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field

from blackboard.chunk import ChunkState, Transition
from blackboard.chunk_timing import PauseStretch

JSON_VERSION = 1


@dataclass
class ChunkEntry:
    """One chunk as it went: text, speech window, states with times, the error if it failed."""

    index: int
    text: str
    speech_onset: float | None = None
    speech_end: float | None = None
    states: list[Transition] = field(default_factory=list)
    error: str | None = None


@dataclass
class BehaviorEntry:
    """One behaviour's phases (the pegs its motor program realized), affiliate times (the
    acoustic onset and end of its words, with the mark times beside them) and the
    relaxations taken for it (``step``, ``amount``, ``unit``, ``constraint``, ``conflict``);
    ``performed`` is False for a BML behaviour that is timed but that no motor module performs."""

    id: str
    chunk: int
    kind: str
    arms: tuple[str, ...]
    phases: dict[str, float]
    affiliate: dict[str, float] | None
    mode: str = ""
    repetitions: int = 1
    slowdown: float = 1.0
    retraction_skipped: bool = False
    next_gesture_follows: bool = False
    relaxations: list[dict] = field(default_factory=list)
    performed: bool = True


@dataclass(frozen=True)
class PlanningSlack:
    """How early chunk ``chunk``'s plan was ready: ``needed − ready`` seconds (positive = in time)."""

    chunk: int
    ready: float
    needed: float

    @property
    def slack(self) -> float:
        return self.needed - self.ready


class Timeline:
    """What happened to one utterance, filled in by the scheduler (thread-safe)."""

    def __init__(self, name: str, fps: float) -> None:
        self.name = name
        self.fps = fps
        self.duration = 0.0
        self.origin = 0.0  # clock time of the utterance start (non-zero for queued live utterances)
        self.absolute_delay = 0.0  # how late absolute timings run, seconds (see blackboard.timing)
        self.chunks: list[ChunkEntry] = []
        self.behaviors: list[BehaviorEntry] = []
        self.words: list[dict] = []
        self.phonemes: list[dict] = []
        self.time_tags: dict[str, float] = {}  # the speech backend's mark times
        self.tag_anchors: dict[str, dict] = {}  # per tag: mark, acoustic_onset, acoustic_end
        self.stretches: list[PauseStretch] = []
        self.slack: list[PlanningSlack] = []
        self.warnings: list[str] = []
        self._lock = threading.Lock()
        self._chunk_index: dict[int, ChunkEntry] = {}
        self._behavior_index: dict[str, BehaviorEntry] = {}

    def chunk(self, index: int) -> ChunkEntry:
        with self._lock:
            return self._chunk_index[index]

    def add_chunk(self, entry: ChunkEntry) -> None:
        with self._lock:
            self.chunks.append(entry)
            self._chunk_index[entry.index] = entry

    def record_state(self, index: int, transition: Transition) -> None:
        self.chunk(index).states.append(transition)

    def behavior(self, behavior_id: str) -> BehaviorEntry:
        with self._lock:
            return self._behavior_index[behavior_id]

    def add_behavior(self, entry: BehaviorEntry) -> None:
        with self._lock:
            self.behaviors.append(entry)
            self._behavior_index[entry.id] = entry

    def warn(self, message: str) -> None:
        with self._lock:
            self.warnings.append(message)

    def states_of(self, index: int) -> list[ChunkState]:
        return [t.state for t in self.chunk(index).states]

    def to_json(self) -> dict:
        """The viewer's JSON shape (version 1) plus ``origin``, ``absolute_delay``, ``stretches``, ``slack``,
        ``warnings`` and ``tag_anchors``; ``time_tags`` are the backend's mark times, ``tag_anchors``
        each tag's mark beside the acoustic onset of the word after it and end of the word before it."""
        with self._lock:
            return {
                "version": JSON_VERSION,
                "name": self.name,
                "duration": self.duration,
                "fps": self.fps,
                "chunks": [_chunk_json(c) for c in self.chunks],
                "behaviors": [_behavior_json(b) for b in self.behaviors],
                "words": list(self.words),
                "phonemes": list(self.phonemes),
                "time_tags": dict(self.time_tags),
                "tag_anchors": {name: dict(anchor) for name, anchor in self.tag_anchors.items()},
                "origin": self.origin,
                "absolute_delay": self.absolute_delay,
                "stretches": [
                    {"chunk": s.chunk, "amount": s.amount, "reason": s.reason, "behavior": s.behavior}
                    for s in self.stretches
                ],
                "slack": [{"chunk": s.chunk, "ready": s.ready, "needed": s.needed, "slack": s.slack} for s in self.slack],
                "warnings": list(self.warnings),
            }


def _chunk_json(c: ChunkEntry) -> dict:
    out = {
        "index": c.index,
        "text": c.text,
        "speech_onset": c.speech_onset,
        "speech_end": c.speech_end,
        "states": [{"state": t.state.value, "time": t.time, **({"reason": t.reason} if t.reason else {})} for t in c.states],
    }
    if c.error is not None:
        out["error"] = c.error
    return out


def _behavior_json(b: BehaviorEntry) -> dict:
    return {
        "id": b.id,
        "chunk": b.chunk,
        "kind": b.kind,
        "arms": list(b.arms),
        "phases": dict(b.phases),
        "affiliate": dict(b.affiliate) if b.affiliate is not None else None,
        "mode": b.mode,
        "repetitions": b.repetitions,
        "slowdown": b.slowdown,
        "retraction_skipped": b.retraction_skipped,
        "next_gesture_follows": b.next_gesture_follows,
        "relaxations": [dict(r) for r in b.relaxations],
        "performed": b.performed,
    }
