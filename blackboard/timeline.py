"""The timeline of a whole utterance: chunk states, gesture phases, speech, pauses, warnings.

Every time is on the utterance clock (0 = the utterance's start), seconds. The scheduler
fills a :class:`Timeline` as it plans and runs; :meth:`Timeline.to_json` is the shape the
viewer reads, :func:`plot_timeline` draws the seed's Fig. 6 from it.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field
from pathlib import Path

from blackboard.chunk import ChunkState, Transition
from blackboard.timing import PauseStretch

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
    """One behaviour's phases (the pegs its motor program realized) and affiliate times."""

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
        self.chunks: list[ChunkEntry] = []
        self.behaviors: list[BehaviorEntry] = []
        self.words: list[dict] = []
        self.phonemes: list[dict] = []
        self.time_tags: dict[str, float] = {}
        self.stretches: list[PauseStretch] = []
        self.slack: list[PlanningSlack] = []
        self.warnings: list[str] = []
        self._lock = threading.Lock()

    def chunk(self, index: int) -> ChunkEntry:
        with self._lock:
            return next(c for c in self.chunks if c.index == index)

    def add_chunk(self, entry: ChunkEntry) -> None:
        with self._lock:
            self.chunks.append(entry)

    def record_state(self, index: int, transition: Transition) -> None:
        self.chunk(index).states.append(transition)

    def behavior(self, behavior_id: str) -> BehaviorEntry:
        with self._lock:
            return next(b for b in self.behaviors if b.id == behavior_id)

    def add_behavior(self, entry: BehaviorEntry) -> None:
        with self._lock:
            self.behaviors.append(entry)

    def warn(self, message: str) -> None:
        with self._lock:
            self.warnings.append(message)

    def states_of(self, index: int) -> list[ChunkState]:
        return [t.state for t in self.chunk(index).states]

    def to_json(self) -> dict:
        """The viewer's JSON shape (version 1) plus ``origin``, ``stretches``, ``slack`` and ``warnings``."""
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
                "origin": self.origin,
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
    }


_STATE_COLOURS = {
    "InPrep": "#9ecae1", "Pending": "#c6dbef", "Lurking": "#fdd0a2", "InExec": "#74c476",
    "Subsiding": "#fdae6b", "Completed": "#d9d9d9", "Failed": "#fb6a4a",
}
_PHASE_COLOURS = {"preparation": "#6baed6", "stroke": "#de2d26", "hold": "#fc9272", "retraction": "#bdbdbd"}


def plot_timeline(timeline: Timeline, path: str | Path) -> Path:
    """Draw the seed's Fig. 6 for ``timeline`` into a PNG at ``path``: per chunk a lane with its
    states, its speech words and its gestures' phases (preparation, stroke, hold, retraction)
    with the affiliate, on one time axis; stretched pauses are shaded."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = timeline.to_json()
    chunks = data["chunks"]
    end = max([data["duration"], 1.0] + [s["time"] for c in chunks for s in c["states"]])
    lanes = max(1, len(chunks))
    fig, ax = plt.subplots(figsize=(max(8.0, end * 2.5), 1.0 + 1.6 * lanes))
    for lane, chunk in enumerate(chunks):
        base = (lanes - 1 - lane) * 3.0
        _draw_states(ax, chunk, base + 2.0, end)
        for word in (w for w in data["words"] if w["chunk"] == chunk["index"]):
            ax.broken_barh([(word["start"], word["end"] - word["start"])], (base + 1.0, 0.8), color="#fff7bc", edgecolor="#999")
            ax.text((word["start"] + word["end"]) / 2, base + 1.4, word["text"], ha="center", va="center", fontsize=7)
        behaviors = [b for b in data["behaviors"] if b["chunk"] == chunk["index"]]
        for k, behavior in enumerate(behaviors):
            _draw_phases(ax, behavior, base + 0.1 + k * 0.8 / max(1, len(behaviors)), 0.7 / max(1, len(behaviors)))
        ax.text(-0.05, base + 1.5, f"chunk {chunk['index']}", ha="right", va="center", fontsize=8)
    for stretch in data["stretches"]:
        onset = next(c["speech_onset"] for c in chunks if c["index"] == stretch["chunk"])
        ax.axvspan(onset - stretch["amount"], onset, color="#fee0d2", alpha=0.5, zorder=0)
    ax.set_xlim(-0.1, end + 0.1)
    ax.set_ylim(-0.2, lanes * 3.0)
    ax.set_yticks([])
    ax.set_xlabel("time (s)")
    ax.set_title(f"{data['name']}: incremental chunk processing")
    fig.tight_layout()
    out = Path(path)
    fig.savefig(out, dpi=100)
    plt.close(fig)
    return out


def _draw_states(ax, chunk: dict, y: float, end: float) -> None:
    states = chunk["states"]
    for current, following in zip(states, states[1:] + [None]):
        stop = following["time"] if following else (current["time"] if current["state"] in ("Completed", "Failed") else end)
        width = max(stop - current["time"], 0.01)
        ax.broken_barh([(current["time"], width)], (y, 0.8), color=_STATE_COLOURS[current["state"]], edgecolor="#666")
        ax.text(current["time"] + width / 2, y + 0.4, current["state"], ha="center", va="center", fontsize=6)


def _draw_phases(ax, behavior: dict, y: float, height: float) -> None:
    p = behavior["phases"]
    spans = {
        "preparation": (p["start"], p["stroke_start"]),
        "stroke": (p["stroke_start"], p["stroke_end"]),
        "hold": (p["stroke_end"], p["relax"]),
        "retraction": (p["relax"], p["end"]),
    }
    for phase, (a, b) in spans.items():
        if b > a:
            ax.broken_barh([(a, b - a)], (y, height), color=_PHASE_COLOURS[phase])
    if behavior["affiliate"]:
        ax.plot([behavior["affiliate"]["onset"], behavior["affiliate"]["end"]], [y + height / 2] * 2, color="k", lw=1)
    ax.text(p["start"], y + height / 2, behavior["id"], ha="right", va="center", fontsize=6)
