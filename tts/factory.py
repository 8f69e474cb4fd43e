"""Choosing a speech backend by name."""

from __future__ import annotations

import warnings

from tts.espeak import EspeakSynthesizer
from tts.fake import FakeSynthesizer
from tts.pyttsx3_backend import Pyttsx3Synthesizer
from tts.speech import BackendUnavailable, SpeechError, SpeechSynthesizer

BACKENDS = {"fake": FakeSynthesizer, "espeak": EspeakSynthesizer, "pyttsx3": Pyttsx3Synthesizer}


def make_synthesizer(name: str | None = None, **options) -> SpeechSynthesizer:
    """The backend ``name`` ("fake", "espeak", "pyttsx3") built with ``options``.

    ``None`` or ``"default"`` means espeak when its library works here, else the fake with
    a warning. A named backend that cannot speak here raises :class:`BackendUnavailable`.
    """
    if name in (None, "default"):
        espeak = EspeakSynthesizer(**options)
        reason = espeak.unavailable_reason()
        if reason is None:
            return espeak
        warnings.warn(f"espeak-ng unavailable ({reason}); using the fake speech timer", RuntimeWarning, stacklevel=2)
        return FakeSynthesizer()
    if name not in BACKENDS:
        raise SpeechError(f"unknown speech backend {name!r}; choose from {', '.join(BACKENDS)}")
    try:
        synthesizer = BACKENDS[name](**options)
    except TypeError as error:
        raise SpeechError(f"speech backend {name!r} does not take the options {sorted(options)}: {error}") from error
    reason = getattr(synthesizer, "unavailable_reason", lambda: None)()
    if reason is not None:
        raise BackendUnavailable(reason)
    return synthesizer
