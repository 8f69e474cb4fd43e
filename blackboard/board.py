"""The blackboard of one chunk: what speech and movement planning contributed, the chunk's
state, and the feedback its behaviours post while they run (seed 004, section 5).

Times on the board are on the session clock (the scheduler's clock); ``origin`` is the
clock time of the utterance start, subtracted for the timeline and for observers.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, replace

from blackboard.chunk import ChunkState, ChunkStateMachine, Transition
from blackboard.events import BehaviorFeedback, ChunkStateChanged, EventBus
from blackboard.planning import GestureDemands, MotorProgramLike
from blackboard.timeline import Timeline
from blackboard.chunk_timing import ChunkTiming, GestureTiming
from motor.program.lmp import TimePegs
from mura.model import BehaviorSpec, ChunkSpec
from tts import SpeechTiming


@dataclass(frozen=True)
class PlannedGesture:
    """A gesture as planned on the board: its demands, solved timing and motor program."""

    behavior: BehaviorSpec
    demands: GestureDemands
    timing: GestureTiming
    program: MotorProgramLike
    next_gesture_follows: bool


@dataclass(frozen=True)
class SpentProgram:
    """What is kept of a motor program once its chunk is Completed (:meth:`Blackboard.retire`):
    the pegs it realized (seconds, session clock) and its warnings, without its LMPs."""

    pegs: TimePegs
    warnings: tuple[str, ...] = ()
    lmps: tuple[object, ...] = ()


class Blackboard:
    """One chunk's blackboard: contributions, state machine and feedback (thread-safe)."""

    def __init__(
        self,
        utterance: str,
        spec: ChunkSpec,
        behaviors: tuple[BehaviorSpec, ...],
        origin: float,
        time: float,
        bus: EventBus,
        timeline: Timeline,
    ) -> None:
        self.utterance = utterance
        self.spec = spec
        self.behaviors = behaviors
        self.origin = origin
        self.bus = bus
        self.timeline = timeline
        self.machine = ChunkStateMachine(f"{utterance}: chunk {spec.index + 1}", time)
        self.speech: SpeechTiming | None = None
        self.demands: dict[str, GestureDemands] = {}
        self.timing: ChunkTiming | None = None
        self.gestures: tuple[PlannedGesture, ...] = ()
        self.speech_end: float = time  # session clock; the onset plus the last word's end
        self.error: Exception | None = None
        self.feedback: list[BehaviorFeedback] = []
        self.effective_ends: dict[str, float] = {}
        self.cutoff: float | None = None  # set by an interrupt: when the last retraction ends
        self.lurk_allowed: float = time  # when the previous chunk subsides: this one may take over
        # agenda entries of the scheduler, kept to cancel or move them (interrupts, cut retractions)
        self.feedback_entries: list[int] = []
        self.finish_entries: dict[str, int] = {}
        self.speech_end_entry: int | None = None
        self.completed_entry: int | None = None
        self._lock = threading.Lock()
        self._announce(None, self.machine.history[0])

    @property
    def index(self) -> int:
        return self.spec.index

    @property
    def state(self) -> ChunkState:
        return self.machine.state

    @property
    def speech_onset(self) -> float:
        return self.timing.speech_onset

    @property
    def has_speech(self) -> bool:
        return self.speech is not None and bool(self.speech.words)

    @property
    def exec_start(self) -> float:
        """When the first behaviour or the speech starts (session clock)."""
        starts = [g.program.pegs.start for g in self.gestures]
        if self.has_speech or not starts:
            starts.append(self.speech_onset)
        return min(starts)

    @property
    def strokes_done(self) -> float:
        """When the phrase and every stroke (with its hold) are over: the chunk may subside."""
        return max([self.speech_end] + [g.program.pegs.relax for g in self.gestures])

    @property
    def effective_end(self) -> float:
        """When the last behaviour ends, retractions cut short by a following gesture included."""
        if self.cutoff is not None:
            return self.cutoff
        return max([self.strokes_done] + list(self.effective_ends.values()))

    def move(self, state: ChunkState, time: float, reason: str = "") -> None:
        """Enter ``state`` at session time ``time``; tells the timeline and the observers."""
        previous = self.machine.state
        transition = self.machine.move(state, time, reason)
        self._announce(previous, transition)

    def retire(self) -> None:
        """Drop what only planning and performing the chunk needed, once it is Completed.

        The utterance's job keeps every board to its end (for the end time and, when the
        output is collected, the audio), so what a board holds adds up with the length of
        the speech: a gesture's motor program (LMPs, wrist trajectories) is about 40 kB,
        so with the phonemes an hour of the memory benchmark's speech (a gesture every 2 s)
        would hold about 80 MB. The motor control holds the LMPs itself for as long as it
        samples them, and the phonemes are in the timeline; what the scheduler reads of a
        completed board stays: the programs' pegs, the speech's words, marks and audio, the
        timing and the state.
        """
        self.gestures = tuple(replace(g, program=SpentProgram(g.program.pegs, tuple(g.program.warnings))) for g in self.gestures)
        if self.speech is not None:
            self.speech = replace(self.speech, phonemes=())

    def _announce(self, previous: ChunkState | None, transition: Transition) -> None:
        local = Transition(transition.state, transition.time - self.origin, transition.reason)
        self.timeline.record_state(self.index, local)
        self.bus.publish(ChunkStateChanged(self.utterance, self.index, previous, local.state, local.time, local.reason))

    def post(self, behavior: str, kind: str, point: str, time: float) -> None:
        """A behaviour reports progress at session time ``time`` (``started``, ``sync``, ``finished``)."""
        feedback = BehaviorFeedback(self.utterance, self.index, behavior, kind, point, time - self.origin)
        with self._lock:
            self.feedback.append(feedback)
        self.bus.publish(feedback)
