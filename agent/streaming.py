"""Rendering straight to files, in memory that does not grow with the utterance's length.

:func:`render_to_files` runs the scheduler without collecting its output
(``SchedulerConfig.keep_output=False``) and writes what its events carry as they come:
each chunk's speech into the WAV (silence up to its onset first), each window of frames
into BVH lines and face weights in scratch files. When the utterance is over it writes
the timeline and ``NAME.face.json``, puts the BVH header (``Frames: N``) before the frame
lines, and streams the avatar page with the BVH and the face embedded piece by piece. The
files are byte for byte what :meth:`Performance.save` writes for the same utterance; like
it, they are written under temporary names and renamed only when all are complete, and
removed on failure.

Memory holds one chunk's audio, at most ``FRAMES_PER_BLOCK`` frames and the timeline
(words and phonemes: a few hundred bytes per second of speech).
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import os
import wave
from collections.abc import Callable
from pathlib import Path
from typing import TextIO

import numpy as np

from agent.export.bvh import StreamingBvh
from agent.export.face import FaceWriter
from agent.export.gltf import GlbAnimation, motion_model
from agent.export.html import write_html_stream
from agent.export.page_model import page_model, write_sidecar
from agent.export.staging import Staging
from agent.performance import SILENT_RATE, PerformanceError, SavedFiles, rest_motion
from agent.sources import UtteranceSource, read_utterance
from blackboard.clock import VirtualClock
from blackboard.events import Event, FramesReady, SpeechStarted
from blackboard.scheduler import Scheduler, SchedulerConfig
from motor.body.avatar import Avatar
from motor.control import MotorControl
from tts import SpeechSynthesizer

#: Samples of silence written at a time, so a long pause never becomes one big array.
SILENCE_BLOCK = 1 << 16


class StreamingWav:
    """An int16 mono WAV track written as the chunks' speech arrives.

    ``add(time, audio, rate)`` places a chunk's samples at ``round(time · rate)``; speech
    that overlaps the previous chunk's is summed with it and clipped to int16, as the
    scheduler mixes it. Only the latest chunk is held in memory (the next one may still
    overlap it); everything before it is on disk. ``finish(duration)`` pads with silence
    (or cuts) to ``round(duration · rate)`` samples and closes the file; the ``wave``
    module patches the header's sizes then. A track without speech is silent at
    :data:`SILENT_RATE`.
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = Path(path)
        self.sample_rate: int | None = None
        self._out: wave.Wave_write | None = None
        self._written = 0
        self._pending = np.zeros(0, dtype=np.int32)
        self._pending_start = 0

    def add(self, time: float, audio: np.ndarray, sample_rate: int) -> None:
        """Chunk speech ``audio`` (int16 mono at ``sample_rate`` Hz) starting at ``time`` s."""
        if self.sample_rate is None:
            self._open(sample_rate)
        elif sample_rate != self.sample_rate:
            raise ValueError(f"{self.path.name}: speech at {sample_rate} Hz after speech at {self.sample_rate} Hz")
        start = int(round(time * sample_rate))
        if start < self._pending_start:
            raise ValueError(f"{self.path.name}: speech at {time:.3f} s arrived after speech that starts later")
        if start >= self._pending_start + len(self._pending):
            self._flush()
            self._pending = audio.astype(np.int32)
            self._pending_start = start
            return
        offset = start - self._pending_start
        mixed = np.zeros(max(len(self._pending), offset + len(audio)), dtype=np.int32)
        mixed[: len(self._pending)] = self._pending
        mixed[offset : offset + len(audio)] += audio
        self._pending = mixed

    def finish(self, duration: float) -> None:
        """Pad (or cut) the track to ``duration`` seconds and close the file."""
        if self.sample_rate is None:
            self._open(SILENT_RATE)
        total = int(round(duration * self.sample_rate))
        keep = max(0, min(len(self._pending), total - self._pending_start))
        self._pending = self._pending[:keep]
        self._flush()
        self._silence(total - self._written)
        self.close()

    def close(self) -> None:
        """Close the file (also after a failure; the caller removes it then)."""
        if self._out is not None:
            self._out.close()
            self._out = None

    def _open(self, sample_rate: int) -> None:
        if sample_rate <= 0:
            raise ValueError(f"{self.path.name}: sample rate must be positive, got {sample_rate}")
        self.sample_rate = int(sample_rate)
        self._out = wave.open(str(self.path), "wb")
        self._out.setnchannels(1)
        self._out.setsampwidth(2)
        self._out.setframerate(self.sample_rate)

    def _flush(self) -> None:
        if len(self._pending) == 0:
            return
        self._silence(self._pending_start - self._written)
        self._out.writeframesraw(np.clip(self._pending, -32768, 32767).astype("<i2").tobytes())
        self._written = self._pending_start + len(self._pending)
        self._pending = np.zeros(0, dtype=np.int32)

    def _silence(self, samples: int) -> None:
        while samples > 0:
            block = min(samples, SILENCE_BLOCK)
            self._out.writeframesraw(bytes(2 * block))
            self._written += block
            samples -= block


class _Recorder:
    """The observer that hands one utterance's speech and frames to the file writers."""

    def __init__(self, name: str, wav: StreamingWav, bvh: StreamingBvh, face: FaceWriter, glb: GlbAnimation | None = None) -> None:
        self.name = name
        self.wav = wav
        self.bvh = bvh
        self.face = face
        self.glb = glb
        self.first_frame_time: float | None = None  # session clock

    def __call__(self, event: Event) -> None:
        if getattr(event, "utterance", None) != self.name:
            return
        if isinstance(event, FramesReady):
            if self.first_frame_time is None:
                self.first_frame_time = event.motion.start_time
            self.bvh.add(event.motion)
            self.face.add(event.motion)
            if self.glb is not None:
                self.glb.add(event.motion)
        elif isinstance(event, SpeechStarted) and event.audio is not None:
            self.wav.add(event.time, event.audio, event.sample_rate)


def render_to_files(
    utterance: UtteranceSource,
    directory: str | os.PathLike[str],
    tts: SpeechSynthesizer,
    avatar: Avatar,
    fps: float,
    config: SchedulerConfig,
    name: str | None = None,
    glb: bool = False,
) -> SavedFiles:
    """Perform ``utterance`` offline (speech from ``tts``, motion for ``avatar`` at ``fps``
    frames/s, scheduled with ``config``) and write NAME.wav, NAME.bvh,
    NAME.timeline.json, NAME.face.json and NAME.html into ``directory`` (created if missing) as the
    performance runs, in bounded memory; the files equal :meth:`Performance.save`'s.

    With ``glb`` it also writes NAME.glb: the avatar with the animation
    (:mod:`agent.export.gltf`). Raises :class:`SpecError` for a bad spec and
    :class:`PerformanceError` (``partial`` is None) when a chunk fails; on any failure no
    file is left under the final names.
    """
    model, default_name = read_utterance(utterance, config.limits)
    name = name or default_name
    folder = Path(directory)
    folder.mkdir(parents=True, exist_ok=True)
    paths = SavedFiles(folder / f"{name}.wav", folder / f"{name}.bvh", folder / f"{name}.timeline.json", folder / f"{name}.html",
                       face=folder / f"{name}.face.json")  # fmt: skip
    if glb:
        paths = dataclasses.replace(paths, glb=folder / f"{name}.glb")
    staging = Staging(folder)
    wav = bvh = face = animation = None
    try:
        wav = StreamingWav(staging.temporary(paths.wav))
        bvh = StreamingBvh(staging.scratch(paths.bvh, ".frames.part"))
        face = FaceWriter(staging.scratch(paths.face, ".weights.part"))
        if glb:
            animation = GlbAnimation(staging.scratch(paths.glb, ".frames.part"), motion_model(avatar), avatar.root_height)
        recorder = _Recorder(name, wav, bvh, face, animation)
        config = dataclasses.replace(config, keep_output=False)
        scheduler = Scheduler(tts, MotorControl(avatar, fps), VirtualClock(), config)
        scheduler.subscribe(recorder)
        try:
            result = scheduler.run(model, name)
        finally:
            scheduler.close()
        if result.error is not None:
            raise PerformanceError(f"chunk {result.failed_chunk + 1} failed: {result.error}", None)
        timeline = result.timeline.to_json()
        wav.finish(float(timeline["duration"]))
        motion_start = 0.0
        if recorder.first_frame_time is None:
            bvh.add(rest_motion(avatar, fps))
            face.add(rest_motion(avatar, fps))
            if animation is not None:
                animation.add(rest_motion(avatar, fps))
        else:
            motion_start = recorder.first_frame_time - result.timeline.origin
        timeline = dict(timeline, motion_start_time=motion_start)
        _write_text(staging.temporary(paths.bvh), bvh.write)
        _write_text(staging.temporary(paths.timeline), lambda stream: json.dump(timeline, stream, indent=1), "utf-8")
        _write_text(staging.temporary(paths.face), lambda stream: stream.writelines(face.json_blocks()))
        model = page_model(avatar)
        _write_text(
            staging.temporary(paths.html),
            lambda stream: write_html_stream(stream, name=name, bvh_blocks=bvh.text_blocks(), timeline=timeline,
                                             wav_filename=paths.wav.name, model=model, face_blocks=face.page_blocks()),  # fmt: skip
            "utf-8",
        )
        if model is not None:
            write_sidecar(model, folder)
        if animation is not None:
            with open(staging.temporary(paths.glb), "wb") as stream:
                animation.write(stream)
    except BaseException:
        for writer in (wav, bvh, face, animation):
            if writer is not None:
                with contextlib.suppress(Exception):  # the failure being raised is the one to report
                    writer.close()
        staging.discard()
        raise
    staging.publish()
    return dataclasses.replace(paths, duration=float(timeline["duration"]), warnings=tuple(result.warnings))


def _write_text(path: Path, write: Callable[[TextIO], None], encoding: str = "ascii") -> None:
    with open(path, "w", encoding=encoding, newline="\n") as stream:
        write(stream)
