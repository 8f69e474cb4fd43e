"""The speech protocol: what a chunk asks for and the timing a backend gives back.

Every time is in seconds from the chunk's speech onset (the first word's start is at or
near 0). Phoneme symbols starting with ``_`` are silences (pauses, word gaps).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Protocol, runtime_checkable

import numpy as np

# XML NCName restricted to what an SSML <mark name> needs (letters, digits, . - _ and
# non-ASCII letters; no colon, must not start with a digit, '.' or '-').
_NCNAME = re.compile(r"^[^\W\d.\-:][\w.\-]*$", re.UNICODE)


class SpeechError(ValueError):
    """A speech request that cannot be spoken, or a backend that cannot speak it."""


class UnknownVoice(SpeechError):
    """The backend has no voice of that name."""


class BackendUnavailable(SpeechError):
    """The backend's library or driver is missing on this machine."""


@dataclass(frozen=True)
class TextMark:
    """A time tag inside the chunk text, at a word boundary.

    ``name`` must be an XML NCName (it becomes an SSML ``<mark name=...>``); ``offset`` is
    the character offset into :attr:`SpeechRequest.text` where the tag sits.
    """

    name: str
    offset: int


@dataclass(frozen=True)
class SpeechRequest:
    """One chunk of speech to synthesize.

    ``emphasis`` holds ``[start, end)`` character spans to emphasize (the affiliates).
    ``final=False`` means another chunk follows: backends keep the pitch up and skip the
    final fall and final lengthening where they can. ``rate`` is relative (1.0 = normal).
    """

    text: str
    marks: tuple[TextMark, ...] = ()
    emphasis: tuple[tuple[int, int], ...] = ()
    final: bool = True
    voice: str | None = None
    rate: float = 1.0
    with_audio: bool = False


@dataclass(frozen=True)
class Phoneme:
    """One phoneme (or silence, symbol starting with ``_``), times in seconds."""

    symbol: str
    start: float
    end: float


@dataclass(frozen=True)
class Word:
    """One word of the request text, times in seconds, ``[char_start, char_end)`` into the text."""

    text: str
    start: float
    end: float
    char_start: int
    char_end: int


@dataclass(frozen=True)
class SpeechTiming:
    """What a backend measured (or estimated, when ``approximate``) for one request.

    ``duration`` includes the trailing silence the backend produces; ``audio`` holds int16
    mono samples at ``sample_rate`` when the request asked for them, else ``None``.
    """

    phonemes: tuple[Phoneme, ...]
    words: tuple[Word, ...]
    marks: Mapping[str, float]
    duration: float
    sample_rate: int
    audio: np.ndarray | None
    backend: str
    approximate: bool


@runtime_checkable
class SpeechSynthesizer(Protocol):
    """A speech backend: ``name`` is ``"fake"``, ``"espeak"`` or ``"pyttsx3"``."""

    name: str

    def available(self) -> bool:
        """True when this backend can speak on this machine."""
        ...

    def synthesize(self, request: SpeechRequest) -> SpeechTiming:
        """Speak ``request``; raises :class:`SpeechError` on bad input or a missing backend."""
        ...


def frozen_marks(marks: Mapping[str, float]) -> Mapping[str, float]:
    """A read-only copy of ``marks`` (name -> seconds)."""
    return MappingProxyType(dict(marks))


def is_mark_name(name: str) -> bool:
    """True when ``name`` is usable as an SSML mark name (an XML NCName)."""
    return bool(_NCNAME.match(name))


def check_rate(rate: float) -> None:
    """Refuse a relative speaking rate that is not a positive finite number."""
    if not isinstance(rate, (int, float)) or not math.isfinite(rate) or rate <= 0:
        raise SpeechError(f"speaking rate must be a positive finite number, got {rate!r}")
