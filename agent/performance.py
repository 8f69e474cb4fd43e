"""A rendered utterance and the files it is saved as.

``Performance.save(directory)`` writes ``NAME.wav`` (the whole utterance's speech,
pauses included, as long as the timeline), ``NAME.bvh`` (the full skeleton),
``NAME.timeline.json`` (the scheduler's timeline), ``NAME.face.json`` (the face's ARKit
morph weights per frame, :mod:`agent.export.face`) and ``NAME.html`` (the avatar page).
(``agent.streaming.render_to_files`` writes the same files without holding the whole
performance in memory.) Every file is first written under a temporary name; only when all are complete are
they renamed into place, so a failure never leaves files that look finished.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from agent.export.bvh import bvh_text, write_bvh
from agent.export.face import face_json, page_face_json
from agent.export.html import write_html
from agent.export.page_model import page_model
from agent.export.staging import Staging
from motor.body.avatar import Avatar
from motor.motion import Motion
from tts.wav import write_wav

#: Sample rate of the silent track written for an utterance without speech, Hz.
SILENT_RATE = 22050


@dataclass(frozen=True)
class SavedFiles:
    """Paths of the files a performance was saved as, with its duration (s) and warnings."""

    wav: Path
    bvh: Path
    timeline: Path
    html: Path
    duration: float = 0.0
    warnings: tuple[str, ...] = ()
    glb: Path | None = None
    face: Path | None = None


@dataclass(frozen=True, eq=False)
class Performance:
    """Speech and motion of one utterance, scheduled together.

    Attributes:
        name: base name of the saved files.
        timeline: the scheduler's timeline as a JSON-ready dict (seconds on the utterance clock).
        motion: the whole skeleton's animation from the utterance start to the last retraction.
        audio: int16 mono speech with the pauses between chunks, or None without speech.
        sample_rate: of ``audio``, Hz.
        warnings: what the planners resolved by rule (a slowed stroke, a stretched pause …).
        avatar: the avatar performed on, whose own model the page draws (None: the figure).
    """

    name: str
    timeline: dict
    motion: Motion
    audio: np.ndarray | None
    sample_rate: int
    warnings: tuple[str, ...] = ()
    avatar: Avatar | None = None

    @property
    def duration(self) -> float:
        """Length of the performance, seconds: the timeline's duration."""
        return float(self.timeline["duration"])

    def soundtrack(self) -> tuple[np.ndarray, int]:
        """The audio padded with silence (or cut) to exactly the timeline's duration."""
        rate = self.sample_rate if self.audio is not None else SILENT_RATE
        samples = int(round(self.duration * rate))
        track = np.zeros(samples, dtype=np.int16)
        if self.audio is not None:
            length = min(samples, len(self.audio))
            track[:length] = self.audio[:length]
        return track, rate

    def save(self, directory: str | os.PathLike[str]) -> SavedFiles:
        """Write the files into ``directory`` (created if missing), all or nothing."""
        folder = Path(directory)
        folder.mkdir(parents=True, exist_ok=True)
        final = SavedFiles(
            folder / f"{self.name}.wav",
            folder / f"{self.name}.bvh",
            folder / f"{self.name}.timeline.json",
            folder / f"{self.name}.html",
            self.duration,
            self.warnings,
            face=folder / f"{self.name}.face.json",
        )
        track, rate = self.soundtrack()
        timeline = dict(self.timeline, motion_start_time=self.motion.start_time)
        writers: list[tuple[Path, Callable[[Path], None]]] = [
            (final.wav, lambda path: write_wav(path, track, rate)),
            (final.bvh, lambda path: write_bvh(self.motion, path)),
            (final.timeline, lambda path: path.write_text(json.dumps(timeline, indent=1), encoding="utf-8")),
            (final.face, lambda path: path.write_text(face_json(self.motion), encoding="ascii")),
            (
                final.html,
                lambda path: write_html(path, name=self.name, bvh_text=bvh_text(self.motion), timeline=timeline, wav_filename=final.wav.name,
                                        model=page_model(self.avatar) if self.avatar is not None else None,
                                        face_json=page_face_json(self.motion)),  # fmt: skip
            ),
        ]
        _write_all(folder, writers)
        return final


def _write_all(folder: Path, writers: list[tuple[Path, Callable[[Path], None]]]) -> None:
    staging = Staging(folder)
    try:
        for target, write in writers:
            write(staging.temporary(target))
    except BaseException:
        staging.discard()
        raise
    staging.publish()


class PerformanceError(RuntimeError):
    """An utterance that could not be performed to the end (a chunk failed)."""

    def __init__(self, message: str, partial: Performance | None) -> None:
        super().__init__(message)
        self.partial = partial


def rest_motion(avatar: Avatar, fps: float) -> Motion:
    """One frame of ``avatar`` at rest: what a page shows before any frame arrives."""
    rotations = np.zeros((1, avatar.joint_count, 4))
    rotations[..., 3] = 1.0
    return Motion(fps, avatar.joint_names, tuple(int(p) for p in avatar.parents), np.asarray(avatar.offsets), rotations, np.zeros((1, 3)))
