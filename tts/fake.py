"""A deterministic rule-based speech timer: the default backend of tests.

Words are split into rough grapheme units (digraphs such as ``th``, ``sh``, ``ee``,
``oo`` count as one), vowel units are syllable nuclei. Durations, in milliseconds before
the rate scaling: plosive 60, other consonant 70, fricative or consonant digraph 80,
single vowel 90, vowel digraph 120; the first syllable of each word is stressed (vowel
x1.25), emphasized words are lengthened x1.5, the last syllable of the chunk x1.4
(final lengthening; x1.1 when ``final=False``). Pauses: word gap 30, comma 200, full stop
350; the chunk ends with its own punctuation's pause, or a full stop's (a comma's when
``final=False``). Every duration is rounded to whole samples at 22050 Hz, so the times
are exact sample counts and identical on every machine.

Marks: a tag right before punctuation ("word [t], next") takes the previous word's end;
otherwise the next word's start; a tag after the last word takes the last word's end.
"""

from __future__ import annotations

import unicodedata

import numpy as np

from tts.speech import Phoneme, SpeechRequest, SpeechTiming, Word, frozen_marks
from tts.text import (
    PAUSE_COMMA,
    PAUSE_FULL_STOP,
    PAUSE_NONE,
    WordSpan,
    emphasized,
    mark_at_previous_word_end,
    pause_kind,
    validate,
)

SAMPLE_RATE = 22050
#: Samples of buzz computed at a time.
BUZZ_BLOCK = 1 << 18

_CONSONANT_DIGRAPHS = ("tch", "th", "sh", "ch", "ph", "wh", "ng", "ck", "gh", "qu")
_VOWEL_DIGRAPHS = ("ee", "ea", "oo", "ou", "ow", "ai", "ay", "oa", "oi", "oy", "ie", "ei", "au", "aw", "ue", "ew", "ey")
_VOWELS = frozenset("aeiou")
_PLOSIVES = frozenset("pbtdkgc")
_FRICATIVES = frozenset("fvszhxj")

_MS_PLOSIVE, _MS_CONSONANT, _MS_FRICATIVE = 60, 70, 80
_MS_VOWEL, _MS_LONG_VOWEL = 90, 120
_STRESS, _EMPHASIS = 1.25, 1.5
_FINAL_LENGTHENING, _NONFINAL_LENGTHENING = 1.4, 1.1
_PAUSE_MS = {PAUSE_NONE: 30, PAUSE_COMMA: 200, PAUSE_FULL_STOP: 350}

_F0_FINAL = (130.0, 95.0)     # Hz at the start and end of a final chunk: the final fall
_F0_NONFINAL = (120.0, 132.0)  # a chunk that continues keeps its pitch up
_AMPLITUDE_VOWEL, _AMPLITUDE_CONSONANT = 9000, 3000


def _fold(word: str) -> str:
    """Lower-case ASCII skeleton of a word: accents stripped, apostrophes and hyphens dropped."""
    decomposed = unicodedata.normalize("NFD", word.lower())
    return "".join(ch for ch in decomposed if not unicodedata.combining(ch) and ch not in "'\u2019-")


def _drop_silent_e(letters: str) -> str:
    if len(letters) > 2 and letters.endswith("e") and letters[-2] not in _VOWELS and any(
        ch in _VOWELS for ch in letters[:-2]
    ):
        return letters[:-1]
    return letters


def grapheme_units(word: str) -> tuple[tuple[str, bool, int], ...]:
    """The word's sound units as ``(symbol, is_vowel, milliseconds)``, before stress and rate."""
    letters = _drop_silent_e(_fold(word))
    units: list[tuple[str, bool, int]] = []
    i = 0
    while i < len(letters):
        unit, i = _next_unit(letters, i)
        if units and unit[0] == units[-1][0] and not unit[1]:
            continue  # a doubled consonant letter is one sound
        units.extend(_expand(unit))
    return tuple(units)


def _next_unit(letters: str, i: int) -> tuple[tuple[str, bool, int], int]:
    for digraph in _CONSONANT_DIGRAPHS:
        if letters.startswith(digraph, i):
            return (digraph, False, _MS_FRICATIVE), i + len(digraph)
    for digraph in _VOWEL_DIGRAPHS:
        if letters.startswith(digraph, i):
            return (digraph, True, _MS_LONG_VOWEL), i + len(digraph)
    ch = letters[i]
    if ch in _VOWELS or (ch == "y" and i > 0 and (i + 1 == len(letters) or letters[i + 1] not in _VOWELS)):
        return (ch, True, _MS_VOWEL), i + 1
    if ch in _PLOSIVES:
        return (ch, False, _MS_PLOSIVE), i + 1
    if ch in _FRICATIVES:
        return (ch, False, _MS_FRICATIVE), i + 1
    if ch.isascii() and ch.isalpha():
        return (ch, False, _MS_CONSONANT), i + 1
    return (ch, True, _MS_VOWEL), i + 1  # a digit or a letter of another script: one syllable


def _expand(unit: tuple[str, bool, int]) -> tuple[tuple[str, bool, int], ...]:
    symbol = unit[0]
    if symbol.isdigit():
        return ((symbol, False, _MS_CONSONANT), (symbol, True, _MS_VOWEL))
    return (unit,)


def _samples(milliseconds: float, rate: float) -> int:
    return int(round(milliseconds * SAMPLE_RATE / (1000.0 * rate)))


class FakeSynthesizer:
    """Deterministic speech timing from the text alone; synthetic buzz audio on request."""

    name = "fake"

    def available(self) -> bool:
        """The fake can always speak."""
        return True

    def synthesize(self, request: SpeechRequest) -> SpeechTiming:
        """Time ``request`` by rule; raises :class:`SpeechError` on bad input."""
        words = validate(request)
        segments = _segments(request, words)
        bounds = np.concatenate(([0], np.cumsum([n for _, n, _ in segments], dtype=np.int64)))
        seconds = bounds / SAMPLE_RATE
        phonemes = tuple(
            Phoneme(symbol, float(seconds[k]), float(seconds[k + 1])) for k, (symbol, _, _) in enumerate(segments)
        )
        timed_words = _timed_words(request, words, segments, seconds)
        marks = _mark_times(request, words, timed_words)
        total = int(bounds[-1])
        audio = _buzz(segments, request.final) if request.with_audio else None
        return SpeechTiming(
            phonemes=phonemes,
            words=timed_words,
            marks=frozen_marks(marks),
            duration=total / SAMPLE_RATE,
            sample_rate=SAMPLE_RATE,
            audio=audio,
            backend=self.name,
            approximate=False,
        )


def _segments(request: SpeechRequest, words: tuple[WordSpan, ...]) -> list[tuple[str, int, int]]:
    """Every phoneme and pause as ``(symbol, samples, word index or -1 for a pause)``."""
    segments: list[tuple[str, int, int]] = []
    last = len(words) - 1
    for index, word in enumerate(words):
        if index > 0:
            kind = pause_kind(request.text[words[index - 1].end : word.start])
            segments.append(("_", _samples(_PAUSE_MS[kind], request.rate), -1))
        segments.extend((s, _samples(ms, request.rate), index) for s, ms in _word_durations(request, word, index == last))
    tail = pause_kind(request.text[words[-1].end :])
    if tail == PAUSE_NONE:
        tail = PAUSE_FULL_STOP if request.final else PAUSE_COMMA
    segments.append(("_", _samples(_PAUSE_MS[tail], request.rate), -1))
    return segments


def _word_durations(request: SpeechRequest, word: WordSpan, is_last: bool) -> list[tuple[str, float]]:
    units = grapheme_units(word.text)
    vowels = [k for k, (_, is_vowel, _) in enumerate(units) if is_vowel]
    factor = _EMPHASIS if emphasized(word, request.emphasis) else 1.0
    lengthening = _FINAL_LENGTHENING if request.final else _NONFINAL_LENGTHENING
    last_syllable = vowels[-1] if vowels else len(units)
    durations = []
    for k, (symbol, _, ms) in enumerate(units):
        scale = factor
        if vowels and k == vowels[0]:
            scale *= _STRESS
        if is_last and k >= last_syllable:
            scale *= lengthening
        durations.append((symbol, ms * scale))
    return durations


def _timed_words(
    request: SpeechRequest, words: tuple[WordSpan, ...], segments: list[tuple[str, int, int]], seconds: np.ndarray
) -> tuple[Word, ...]:
    owner = np.array([w for _, _, w in segments])
    timed = []
    for index, word in enumerate(words):
        rows = np.flatnonzero(owner == index)
        timed.append(Word(word.text, float(seconds[rows[0]]), float(seconds[rows[-1] + 1]), word.start, word.end))
    return tuple(timed)


def _mark_times(request: SpeechRequest, words: tuple[WordSpan, ...], timed: tuple[Word, ...]) -> dict[str, float]:
    marks = {}
    for mark in request.marks:
        previous = [w for w in timed if w.char_end <= mark.offset]
        following = [w for w in timed if w.char_start >= mark.offset]
        if previous and mark_at_previous_word_end(request, mark.offset, words):
            marks[mark.name] = previous[-1].end
        else:
            marks[mark.name] = following[0].start
    return marks


def _buzz(segments: list[tuple[str, int, int]], final: bool) -> np.ndarray:
    """A triangle-wave buzz under the phonemes, silence in pauses, int16, exact length.

    Integer phase accumulation keeps it bit-identical across machines (no libm calls).
    Computed in blocks of :data:`BUZZ_BLOCK` samples, so that the temporaries stay small
    however long the chunk (the result is the same as in one piece).
    """
    lengths = np.array([n for _, n, _ in segments], dtype=np.int64)
    bounds = np.concatenate(([0], np.cumsum(lengths)))
    total = int(bounds[-1])
    amplitude_per_segment = np.array(
        [0 if owner < 0 else (_AMPLITUDE_VOWEL if _is_vowel_symbol(s) else _AMPLITUDE_CONSONANT) for s, _, owner in segments],
        dtype=np.int64,
    )
    f0_start, f0_end = _F0_FINAL if final else _F0_NONFINAL
    out = np.empty(total, dtype=np.int16)
    carry = 0
    for start in range(0, total, BUZZ_BLOCK):
        index = np.arange(start, min(start + BUZZ_BLOCK, total), dtype=np.int64)
        amplitude = amplitude_per_segment[np.searchsorted(bounds, index, side="right") - 1]
        f0 = f0_start + (f0_end - f0_start) * (index.astype(np.float64) / max(total, 1))
        increment = np.round(f0 * (2.0**32 / SAMPLE_RATE)).astype(np.int64)
        phase = (carry + np.cumsum(increment)) % (1 << 32)
        carry = int(phase[-1])
        triangle = np.abs(phase - (1 << 31)) - (1 << 30)  # -2^30 .. 2^30
        out[start : start + len(index)] = (triangle * amplitude) >> 30
    return out


def _is_vowel_symbol(symbol: str) -> bool:
    return symbol in _VOWEL_DIGRAPHS or symbol in _VOWELS or symbol == "y" or not symbol.isascii()
