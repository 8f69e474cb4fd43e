"""The contract between the scheduler and the motor side (seed 004, section 5).

The scheduler times gestures against speech; the motor side turns a timed gesture into
a motor program of LMPs and samples frames from everything activated so far. This module
is the whole interface: :class:`GestureDemands` (the motor's own dataclass), what the
scheduler must know before it can time a gesture, and :class:`MotorControl`, the object
it calls. Times are seconds on the utterance clock of the session (the clock the
scheduler hands out), distances metres.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Protocol, runtime_checkable

from motor.motion import Motion
from motor.program.gesture import GestureDemands
from motor.program.lmp import TimePegs
from mura.model import BehaviorSpec
from tts.speech import SpeechTiming

#: The pegs in phase order, as they appear in the timeline.
PEG_NAMES: tuple[str, ...] = ("start", "ready", "stroke_start", "stroke", "stroke_end", "relax", "end")


@runtime_checkable
class MotorProgramLike(Protocol):
    """A planned gesture: its LMPs, the pegs it realizes, and planner warnings."""

    lmps: Sequence[object]
    warnings: Sequence[str]
    pegs: TimePegs


@runtime_checkable
class MotorControl(Protocol):
    """The motor side as the scheduler uses it.

    Call order for each chunk: ``demands`` and ``preparation_distances`` while timing
    (InPrep), ``plan`` once the pegs are fixed, ``activate`` when the chunk becomes
    Lurking, always before ``frames`` samples any time at or after the program's start.
    Frames are asked for in consecutive windows ``[start, end)`` that never overlap.
    """

    fps: float

    def demands(self, behavior: BehaviorSpec) -> GestureDemands:
        """Arms, stroke duration and preparation distance of ``behavior``'s gesture."""
        ...

    def preparation_distances(self, behavior: BehaviorSpec, at_time: float) -> Mapping[str, float]:
        """Per arm, metres from where the wrist will be at ``at_time`` (given the programs
        activated so far) to the start of ``behavior``'s stroke (and possibly ``"gaze"``: a
        distance whose preparation time lets eyes and head reach the behaviour's gaze target)."""
        ...

    def plan(
        self,
        behavior: BehaviorSpec,
        pegs: TimePegs,
        *,
        repetitions: int = 1,
        next_gesture_follows: bool = False,
    ) -> MotorProgramLike:
        """The motor program performing ``behavior`` on ``pegs``.

        ``pegs.start`` … ``pegs.relax`` are binding: preparation from ``start`` to
        ``ready``, the stroke from ``stroke_start`` to ``stroke_end`` performed
        ``repetitions`` times (slowed evenly to fill it), held until ``relax``.
        ``pegs.end`` is the scheduler's estimate of the end of the retraction; the program's
        own ``pegs`` give the real one. ``next_gesture_follows`` asks for a retraction into
        an interim rest position instead of the full rest.
        """
        ...

    def activate(self, program: MotorProgramLike) -> None:
        """Hand the program's LMPs to the channel timelines; they start themselves at their
        start times and connect to the arm's state there (cutting a retraction in progress)."""
        ...

    def frames(self, start: float, end: float) -> Motion:
        """Frames at times ``k / fps`` in ``[start, end)`` from everything activated so far."""
        ...

    def speak(self, speech: SpeechTiming, onset: float, accents: Sequence[tuple[float, float]] = ()) -> Sequence[str]:
        """Lip-sync a chunk's speech that starts at ``onset``, with the face and head
        marking the ``accents`` (utterance-clock spans of its emphasized affiliates);
        called when the chunk becomes Lurking, before frames at ``onset`` are sampled.
        Returns warnings for the timeline."""
        ...

    def busy_until(self, arm: str) -> float:
        """When the arm's last activated LMP (retraction included) ends; 0 when never used."""
        ...

    def interrupt(self, at_time: float) -> None:
        """Stop every gesture at ``at_time`` and retract from wherever the arms are then."""
        ...
