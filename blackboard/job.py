"""One utterance on its way through the scheduler, and what it yields once performed.

A :class:`Job` holds an utterance's chunks, their blackboards, the frames collected so far
and its timeline; :func:`performed` assembles the :class:`ScheduledUtterance` (audio of
every chunk mixed at its speech onset, the frames concatenated) when the last chunk is over.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field

import numpy as np

from blackboard.board import Blackboard
from blackboard.chunk import ChunkState
from blackboard.errors import ScheduleError
from blackboard.timeline import Timeline
from motor.motion import Motion
from mura.model import BehaviorSpec, ChunkSpec, Utterance


@dataclass(frozen=True)
class ScheduledUtterance:
    """A performed utterance: its timeline, the audio (int16 mono, pauses included, None when
    the speech backend gave none), the motion from the utterance start to the end of the last
    retraction, warnings, and, when a chunk failed, its index and the error. Without
    ``SchedulerConfig.keep_output`` the audio and motion are None (``sample_rate`` stays)."""

    timeline: Timeline
    audio: np.ndarray | None
    sample_rate: int | None
    motion: Motion | None
    warnings: tuple[str, ...]
    failed_chunk: int | None = None
    error: Exception | None = None


@dataclass
class Job:
    """An utterance being scheduled: its chunks, blackboards and collected output."""

    utterance: Utterance
    name: str
    chunks: tuple[ChunkSpec, ...]
    timeline: Timeline
    origin: float = 0.0
    boards: list[Blackboard] = field(default_factory=list)
    absolute: list[BehaviorSpec] = field(default_factory=list)
    absolute_delay: float = 0.0  # how late the absolute clock starts, seconds (see blackboard.chunk_timing)
    frames: list[Motion] = field(default_factory=list)
    audio_end: int = 0  # without keep_output: samples from the utterance start to the end of the last audio
    sample_rate: int | None = None
    failed: Blackboard | None = None
    interrupted: bool = False
    done: threading.Event = field(default_factory=threading.Event)
    result: ScheduledUtterance | None = None
    end: float = 0.0

    @property
    def finished(self) -> bool:
        planned_all = len(self.boards) == len(self.chunks) or self.failed is not None or self.interrupted
        return planned_all and all(b.machine.finished for b in self.boards)

    def performed_boards(self) -> list[Blackboard]:
        """The chunks that were planned and not failed."""
        return [b for b in self.boards if b.timing is not None and b.state is not ChunkState.FAILED]


def performed(job: Job, keep_output: bool) -> ScheduledUtterance:
    """The result of ``job`` once every chunk is over; sets its end and the timeline's duration."""
    boards = job.performed_boards()
    job.end = max([b.effective_end for b in boards] + [job.origin])
    audio, rate = mixed_audio(job, boards) if keep_output else (None, job.sample_rate)
    if audio is not None:
        job.end = max(job.end, job.origin + len(audio) / rate)
    elif job.audio_end:
        job.end = max(job.end, job.origin + job.audio_end / rate)
    job.timeline.duration = job.end - job.origin
    failed = job.failed
    return ScheduledUtterance(
        timeline=job.timeline,
        audio=audio,
        sample_rate=rate,
        motion=concatenated(job.frames, job.origin),
        warnings=tuple(job.timeline.warnings),
        failed_chunk=failed.index if failed is not None else None,
        error=failed.error if failed is not None else None,
    )


def mixed_audio(job: Job, boards: list[Blackboard]) -> tuple[np.ndarray | None, int | None]:
    """Every chunk's audio at its speech onset (int16, clipped), and the sample rate."""
    pieces = [(b.speech_onset - job.origin, b.speech) for b in boards if b.speech is not None and b.speech.audio is not None]
    if not pieces:
        return None, None
    rate = pieces[0][1].sample_rate
    if any(s.sample_rate != rate for _, s in pieces):
        raise ScheduleError(f"{job.name}: chunks came back at different sample rates")
    starts = [int(round(onset * rate)) for onset, _ in pieces]
    length = max(start + len(s.audio) for start, (_, s) in zip(starts, pieces))
    mix = np.zeros(length, dtype=np.int32)
    for start, (_, speech) in zip(starts, pieces):
        mix[start:start + len(speech.audio)] += speech.audio.astype(np.int32)
    return np.clip(mix, -32768, 32767).astype(np.int16), rate


def concatenated(frames: list[Motion], origin: float) -> Motion | None:
    """The frame windows as one motion, its start on the utterance clock."""
    if not frames:
        return None
    first = frames[0]
    faces = [m.face_weights for m in frames if m.face_weights is not None]
    return Motion(
        fps=first.fps,
        joint_names=first.joint_names,
        parents=first.parents,
        offsets=first.offsets,
        rotations=np.concatenate([m.rotations for m in frames]),
        root_translation=np.concatenate([m.root_translation for m in frames]),
        start_time=first.start_time - origin,
        face_names=first.face_names,
        face_weights=np.concatenate(faces) if first.face_names and len(faces) == len(frames) else None,
    )
