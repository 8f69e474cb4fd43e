"""pyttsx3 as the portable backend: real audio from the platform's engine, estimated timings.

pyttsx3 reports no phoneme or mark times (and its drivers ignore emphasis), so the
timings are the fake's rule-based model stretched uniformly to the length of the audio
pyttsx3 produced: ``approximate=True``. On Linux pyttsx3 needs the system espeak library;
without a working driver the backend reports itself unavailable with the reason. Its
espeak driver and mura's espeak backend cannot share a process (both would own the one
global espeak-ng engine), so whichever loads espeak-ng first makes the other unavailable.
"""

from __future__ import annotations

import dataclasses
import sys
import tempfile
from pathlib import Path

import numpy as np

from tts import espeak
from tts.fake import FakeSynthesizer
from tts.speech import (
    BackendUnavailable,
    Phoneme,
    SpeechError,
    SpeechRequest,
    SpeechTiming,
    UnknownVoice,
    frozen_marks,
)
from tts.text import validate
from tts.wav import read_wav


def scale_timing(model: SpeechTiming, audio: np.ndarray, sample_rate: int, keep_audio: bool, backend: str) -> SpeechTiming:
    """``model``'s times stretched so its duration equals that of ``audio``; ``approximate=True``."""
    if len(audio) == 0:
        raise SpeechError(f"{backend} produced no audio")
    duration = len(audio) / sample_rate
    factor = duration / model.duration
    return SpeechTiming(
        phonemes=tuple(Phoneme(p.symbol, p.start * factor, p.end * factor) for p in model.phonemes),
        words=tuple(dataclasses.replace(w, start=w.start * factor, end=w.end * factor) for w in model.words),
        marks=frozen_marks({name: t * factor for name, t in model.marks.items()}),
        duration=duration,
        sample_rate=sample_rate,
        audio=np.asarray(audio, dtype=np.int16) if keep_audio else None,
        backend=backend,
        approximate=True,
    )


class Pyttsx3Synthesizer:
    """Speech through pyttsx3's ``save_to_file``; ``driver`` is a pyttsx3 driver name or ``None``."""

    name = "pyttsx3"

    def __init__(self, voice: str | None = None, driver: str | None = None) -> None:
        self.voice = voice
        self.driver = driver

    def _engine(self):
        if sys.platform.startswith("linux") and self.driver in (None, "espeak") and espeak.library_loaded():
            # pyttsx3's espeak driver would open the same libespeak-ng.so.1 and initialize it
            # again, which makes espeak-ng exit the process.
            raise BackendUnavailable(
                "pyttsx3's espeak driver cannot run in a process where mura's espeak backend "
                "has already loaded espeak-ng"
            )
        try:
            import pyttsx3

            return pyttsx3.init(self.driver)
        except Exception as error:  # pyttsx3 raises whatever its driver's import raises
            raise BackendUnavailable(f"pyttsx3 has no working driver on this machine: {error}") from error

    def unavailable_reason(self) -> str | None:
        """Why this backend cannot speak here, or ``None`` when it can."""
        try:
            self._engine()
        except BackendUnavailable as error:
            return str(error)
        return None

    def available(self) -> bool:
        """True when pyttsx3 initializes a driver."""
        return self.unavailable_reason() is None

    def synthesize(self, request: SpeechRequest) -> SpeechTiming:
        """Speak ``request`` to a temporary WAV and time it by the scaled fake model."""
        validate(request)
        model = FakeSynthesizer().synthesize(dataclasses.replace(request, with_audio=False))
        engine = self._engine()
        self._choose_voice(engine, request.voice or self.voice)
        engine.setProperty("rate", int(round(engine.getProperty("rate") * request.rate)))
        with tempfile.TemporaryDirectory(prefix="mura-tts-") as folder:
            path = Path(folder) / "speech.wav"
            engine.save_to_file(request.text, str(path))
            engine.runAndWait()
            if not path.exists():
                raise SpeechError("pyttsx3 wrote no audio file")
            audio, sample_rate = read_wav(path)
        return scale_timing(model, audio, sample_rate, request.with_audio, self.name)

    @staticmethod
    def _choose_voice(engine, voice: str | None) -> None:
        if voice is None:
            return
        voices = engine.getProperty("voices") or []
        match = next((v for v in voices if voice in (v.id, v.name)), None)
        if match is None:
            raise UnknownVoice(f"pyttsx3 has no voice {voice!r}")
        engine.setProperty("voice", match.id)
