"""espeak-ng through its C library (ctypes): measured phoneme, word and mark times.

The library comes from the ``espeakng-loader`` wheel; a system ``libespeak-ng.so.1`` is
accepted when the wheel is absent. espeak-ng keeps global state and is not thread-safe,
so the process has one engine, initialized on first use and guarded by a lock. Before
each call the library's random seed is reset (``espeak_ng_SetRandSeed``, espeak-ng 1.51
and later). espeak-ng still carries some waveform state (its pitch flutter phase) from
one call to the next, so repeated calls in one process may differ by a sample or two;
the same sequence of calls in a fresh process gives identical timings and audio.

Times are sample-exact: each event's ``sample`` field counts samples from the start of
the synthesis call. A phoneme ends where the next begins (the last at the end of the
audio); a silence before the first phoneme becomes a ``_`` phoneme and zero-length
events are dropped, so the phonemes tile ``[0, duration]``. A word starts at its first
phoneme and ends at the end of its last non-silent phoneme.

Marks: espeak reports a ``<mark>`` where it sits among the pauses — directly before
punctuation it gets the previous word's end, otherwise the next word's start (reported at
the word event, moved to the word's first phoneme). Tags after the last word get the last
word's end. espeak silently drops a mark that follows a sentence end ("end. [t]Next");
such a mark gets the next word's start.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import sys
import threading
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from tts.speech import (
    BackendUnavailable,
    Phoneme,
    SpeechError,
    SpeechRequest,
    SpeechTiming,
    UnknownVoice,
    Word,
    frozen_marks,
)
from tts.ssml import to_ssml
from tts.text import WordSpan, validate

DEFAULT_VOICE = "en"
NORMAL_WPM = 175  # espeak's default rate; SpeechRequest.rate scales it
MIN_WPM, MAX_WPM = 80, 450

_AUDIO_OUTPUT_SYNCHRONOUS = 2
_INITIALIZE_PHONEME_EVENTS = 0x0001
_INITIALIZE_DONT_EXIT = 0x8000
_POS_CHARACTER = 1
_CHARS_UTF8 = 1
_SSML = 0x10
_PARAMETER_RATE = 1
_EVENT_LIST_TERMINATED, _EVENT_WORD, _EVENT_MARK, _EVENT_PHONEME = 0, 1, 3, 7
_EE_OK, _EE_NOT_FOUND = 0, 2
_RANDOM_SEED = 1  # espeak-ng jitters pitch pulses with rand(); a fixed seed makes every call repeatable


class _EventId(ctypes.Union):
    _fields_ = [("number", ctypes.c_int), ("name", ctypes.c_char_p), ("string", ctypes.c_char * 8)]


class _Event(ctypes.Structure):
    """espeak_EVENT from speak_lib.h."""

    _fields_ = [
        ("type", ctypes.c_int),
        ("unique_identifier", ctypes.c_uint),
        ("text_position", ctypes.c_int),
        ("length", ctypes.c_int),
        ("audio_position", ctypes.c_int),
        ("sample", ctypes.c_int),
        ("user_data", ctypes.c_void_p),
        ("id", _EventId),
    ]


_CALLBACK = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.POINTER(ctypes.c_short), ctypes.c_int, ctypes.POINTER(_Event))


@dataclass
class _Capture:
    """What one synthesis call delivered: audio chunks and ``(type, text_position, sample, payload)`` events."""

    chunks: list[np.ndarray] = field(default_factory=list)
    events: list[tuple[int, int, int, str]] = field(default_factory=list)


class _Engine:
    """The initialized library, its sample rate, and the callback that fills the current capture."""

    def __init__(self, library_path: str, data_path: str | None) -> None:
        try:
            lib = ctypes.CDLL(library_path)
        except OSError as error:
            raise BackendUnavailable(f"espeak-ng library {library_path} cannot be loaded: {error}") from error
        lib.espeak_Initialize.argtypes = [ctypes.c_int, ctypes.c_int, ctypes.c_char_p, ctypes.c_int]
        lib.espeak_Initialize.restype = ctypes.c_int
        lib.espeak_SetSynthCallback.argtypes = [_CALLBACK]
        lib.espeak_SetVoiceByName.argtypes = [ctypes.c_char_p]
        lib.espeak_SetVoiceByName.restype = ctypes.c_int
        lib.espeak_SetParameter.argtypes = [ctypes.c_int, ctypes.c_int, ctypes.c_int]
        lib.espeak_SetParameter.restype = ctypes.c_int
        lib.espeak_Synth.argtypes = [
            ctypes.c_void_p, ctypes.c_size_t, ctypes.c_uint, ctypes.c_int, ctypes.c_uint, ctypes.c_uint,
            ctypes.c_void_p, ctypes.c_void_p,
        ]
        lib.espeak_Synth.restype = ctypes.c_int
        self._seed = getattr(lib, "espeak_ng_SetRandSeed", None)  # espeak-ng >= 1.51
        if self._seed is not None:
            self._seed.argtypes = [ctypes.c_long]
            self._seed.restype = None
        path = data_path.encode() if data_path else None
        rate = lib.espeak_Initialize(
            _AUDIO_OUTPUT_SYNCHRONOUS, 0, path, _INITIALIZE_PHONEME_EVENTS | _INITIALIZE_DONT_EXIT
        )
        if rate <= 0:
            raise BackendUnavailable(f"espeak-ng failed to initialize (data path {data_path})")
        self.lib = lib
        self.library_path = library_path
        self.sample_rate = int(rate)
        self.capture = _Capture()
        self._callback = _CALLBACK(self._collect)  # kept alive as long as the engine
        lib.espeak_SetSynthCallback(self._callback)

    def _collect(self, wav, count, events) -> int:
        if count > 0 and wav:
            self.capture.chunks.append(np.ctypeslib.as_array(wav, shape=(count,)).copy())
        k = 0
        while events[k].type != _EVENT_LIST_TERMINATED:
            event = events[k]
            payload = ""
            if event.type == _EVENT_PHONEME:
                payload = event.id.string.decode("utf-8", "replace")
            elif event.type == _EVENT_MARK and event.id.name:
                payload = event.id.name.decode("utf-8", "replace")
            self.capture.events.append((event.type, event.text_position, event.sample, payload))
            k += 1
        return 0

    def speak(self, ssml: str, voice: str, words_per_minute: int) -> _Capture:
        if self.lib.espeak_SetVoiceByName(voice.encode()) != _EE_OK:
            raise UnknownVoice(f"espeak-ng has no voice {voice!r}")
        self.lib.espeak_SetParameter(_PARAMETER_RATE, words_per_minute, 0)
        if self._seed is not None:
            self._seed(_RANDOM_SEED)
        self.capture = _Capture()
        data = ssml.encode()
        status = self.lib.espeak_Synth(data, len(data) + 1, 0, _POS_CHARACTER, 0, _CHARS_UTF8 | _SSML, None, None)
        if status != _EE_OK:
            raise SpeechError(f"espeak-ng synthesis failed with status {status}")
        return self.capture


_LOCK = threading.Lock()
_engine: _Engine | None = None


def library_loaded() -> bool:
    """True once this process has loaded and initialized espeak-ng for this backend."""
    return _engine is not None


def _pyttsx3_drives_espeak() -> bool:
    """True when pyttsx3's espeak driver has initialized espeak-ng in this process."""
    driver = sys.modules.get("pyttsx3.drivers.espeak")
    return bool(driver and getattr(getattr(driver, "EspeakDriver", None), "_moduleInitialized", False))


def _default_library() -> tuple[str, str | None]:
    """The wheel's library and data, else the system library with its own data."""
    try:
        import espeakng_loader
    except ImportError:
        espeakng_loader = None
    if espeakng_loader is not None:
        path = espeakng_loader.get_library_path()
        if Path(path).exists():
            try:
                data = espeakng_loader.get_data_path()
            except (RuntimeError, OSError) as error:  # the wheel raises RuntimeError when its data folder is gone
                raise BackendUnavailable(f"espeak-ng's data folder is missing ({error})") from None
            return path, data
    system = ctypes.util.find_library("espeak-ng")
    if system is None:
        raise BackendUnavailable("espeak-ng library not found: install espeakng-loader or libespeak-ng1")
    return system, None


def _get_engine(library_path: str | None, data_path: str | None) -> _Engine:
    """The process's engine, loaded on first use; call with ``_LOCK`` held."""
    global _engine
    if library_path is None:
        if _engine is not None:
            return _engine
        library_path, data_path = _default_library()
    if not Path(library_path).exists() and "/" in library_path:
        raise BackendUnavailable(f"espeak-ng library {library_path} does not exist")
    if data_path is not None and not Path(data_path).is_dir():
        raise BackendUnavailable(f"espeak-ng data folder {data_path} does not exist")
    if _engine is None and _pyttsx3_drives_espeak():
        raise BackendUnavailable("pyttsx3's espeak driver already owns espeak-ng in this process")
    if _engine is not None:
        if _engine.library_path != library_path:
            raise BackendUnavailable(f"espeak-ng is already loaded from {_engine.library_path} in this process")
        return _engine
    _engine = _Engine(library_path, data_path)
    return _engine


class EspeakSynthesizer:
    """Speech from espeak-ng with measured timings; ``voice`` is an espeak voice name."""

    name = "espeak"

    def __init__(self, voice: str = DEFAULT_VOICE, library_path: str | None = None, data_path: str | None = None):
        self.voice = voice
        self.library_path = library_path
        self.data_path = data_path

    def unavailable_reason(self) -> str | None:
        """Why this backend cannot speak here, or ``None`` when it can."""
        try:
            with _LOCK:
                _get_engine(self.library_path, self.data_path)
        except BackendUnavailable as error:
            return str(error)
        return None

    def available(self) -> bool:
        """True when the espeak-ng library loads and initializes."""
        return self.unavailable_reason() is None

    def synthesize(self, request: SpeechRequest) -> SpeechTiming:
        """Speak ``request``; raises :class:`SpeechError` (or a subclass) naming what is wrong."""
        words = validate(request)
        words_per_minute = int(round(NORMAL_WPM * request.rate))
        if not MIN_WPM <= words_per_minute <= MAX_WPM:
            raise SpeechError(
                f"rate {request.rate} gives {words_per_minute} words/min; espeak-ng speaks {MIN_WPM}..{MAX_WPM}"
            )
        voice = request.voice or self.voice
        if not voice or "\0" in voice:
            raise UnknownVoice(f"espeak-ng has no voice {voice!r}")
        ssml, offsets = to_ssml(request, words)
        with _LOCK:
            engine = _get_engine(self.library_path, self.data_path)
            capture = engine.speak(ssml, voice, words_per_minute)
            sample_rate = engine.sample_rate
        return _timing(request, words, offsets, capture, sample_rate)


def _timing(
    request: SpeechRequest, words: tuple[WordSpan, ...], offsets: tuple[int, ...], capture: _Capture, sample_rate: int
) -> SpeechTiming:
    audio = np.concatenate(capture.chunks).astype(np.int16) if capture.chunks else np.zeros(0, np.int16)
    total = len(audio)
    phonemes = _phonemes(capture.events, total)
    word_events = _word_events(capture.events, offsets, words)
    segments = _event_segments(word_events, phonemes, total)
    spans = _word_samples(word_events, segments, len(words))
    timed_words = tuple(
        Word(w.text, start / sample_rate, end / sample_rate, w.start, w.end) for w, (start, end) in zip(words, spans)
    )
    onsets = {sample: segment[0] for (sample, _), segment in zip(word_events, segments)}
    marks = _mark_samples(request, words, capture.events, spans, onsets)
    return SpeechTiming(
        phonemes=tuple(Phoneme(s, a / sample_rate, b / sample_rate) for s, a, b in phonemes),
        words=timed_words,
        marks=frozen_marks({name: sample / sample_rate for name, sample in marks.items()}),
        duration=total / sample_rate,
        sample_rate=sample_rate,
        audio=audio if request.with_audio else None,
        backend="espeak",
        approximate=False,
    )


def _phonemes(events: list[tuple[int, int, int, str]], total: int) -> list[tuple[str, int, int]]:
    """``(symbol, start, end)`` in samples, tiling ``[0, total]``."""
    starts = [(sample, symbol) for kind, _, sample, symbol in events if kind == _EVENT_PHONEME]
    starts.sort(key=lambda item: item[0])
    if not starts or starts[0][0] > 0:
        starts.insert(0, (0, "_"))
    ends = [sample for sample, _ in starts[1:]] + [total]
    return [(symbol, start, end) for (start, symbol), end in zip(starts, ends) if end > start]


def _word_events(
    events: list[tuple[int, int, int, str]], offsets: tuple[int, ...], words: tuple[WordSpan, ...]
) -> list[tuple[int, int]]:
    """Every espeak word event as ``(sample, index of the request word or -1)``."""
    found = []
    for kind, position, sample, _ in events:
        if kind != _EVENT_WORD:
            continue
        offset = offsets[min(max(position - 1, 0), len(offsets) - 1)]
        index = next((k for k, w in enumerate(words) if w.start <= offset < w.end), -1)
        found.append((sample, index))
    return found


def _event_segments(word_events: list[tuple[int, int]], phonemes: list[tuple[str, int, int]], total: int) -> list[tuple[int, int]]:
    """``(start, end)`` of the voiced phonemes each word event owns.

    A word event owns the audio up to the next word event. Its start is its first
    non-silent phoneme (espeak emits the word event a few milliseconds before the first
    phoneme, while the previous word still sounds), its end that of its last one.
    """
    bounds = [sample for sample, _ in word_events] + [total]
    segments = []
    for k in range(len(word_events)):
        voiced = [(a, b) for s, a, b in phonemes if bounds[k] <= a < bounds[k + 1] and not s.startswith("_")]
        start = voiced[0][0] if voiced else bounds[k]
        segments.append((start, voiced[-1][1] if voiced else start))
    return segments


def _word_samples(word_events: list[tuple[int, int]], segments: list[tuple[int, int]], count: int) -> list[tuple[int, int]]:
    """``(start, end)`` in samples for each request word.

    espeak may split one of our words ("well-known") or speak symbols we do not count as
    words ("&"); a word is the union of the segments of its events. A word espeak gave no
    event gets zero length at the previous word's end.
    """
    spans: list[tuple[int, int]] = []
    for index in range(count):
        mine = [segments[k] for k, (_, owner) in enumerate(word_events) if owner == index]
        if not mine:
            previous = spans[-1][1] if spans else 0
            spans.append((previous, previous))
            continue
        spans.append((mine[0][0], max(end for _, end in mine)))
    return spans


def _mark_samples(
    request: SpeechRequest,
    words: tuple[WordSpan, ...],
    events: list[tuple[int, int, int, str]],
    spans: list[tuple[int, int]],
    onsets: dict[int, int],
) -> dict[str, int]:
    """Mark times in samples; a mark espeak reports at a word event moves to that word's first phoneme."""
    reported = {payload: onsets.get(sample, sample) for kind, _, sample, payload in events if kind == _EVENT_MARK}
    marks = {}
    for mark in request.marks:
        following = next((k for k, w in enumerate(words) if w.start >= mark.offset), None)
        if following is None:
            marks[mark.name] = spans[-1][1]
        elif mark.name in reported:
            marks[mark.name] = reported[mark.name]
        else:
            marks[mark.name] = spans[following][0]
    return marks
