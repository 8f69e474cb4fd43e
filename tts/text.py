"""The text side of a speech request: words, word boundaries, pauses, validation.

Every backend sees the same words: maximal runs of letters and digits, joined by an
inner apostrophe or hyphen ("don't", "well-known"). Time tags and emphasis spans must sit
at word boundaries; an offset strictly inside a word is refused, never snapped.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from tts.speech import SpeechError, SpeechRequest, check_rate, is_mark_name

_WORD = re.compile(r"[^\W_]+(?:['\u2019\-][^\W_]+)*")
_FULL_STOP = frozenset(".!?;:\u2026")
_COMMA = frozenset(",\u2013\u2014()\"")

PAUSE_NONE = 0
PAUSE_COMMA = 1
PAUSE_FULL_STOP = 2


@dataclass(frozen=True)
class WordSpan:
    """A word of the text: ``[start, end)`` character offsets."""

    text: str
    start: int
    end: int


def split_words(text: str) -> tuple[WordSpan, ...]:
    """The words of ``text`` in order."""
    return tuple(WordSpan(m.group(), m.start(), m.end()) for m in _WORD.finditer(text))


def pause_kind(between: str) -> int:
    """How strong a pause the characters between two words call for."""
    if any(ch in _FULL_STOP for ch in between):
        return PAUSE_FULL_STOP
    if any(ch in _COMMA for ch in between):
        return PAUSE_COMMA
    return PAUSE_NONE


def validate(request: SpeechRequest) -> tuple[WordSpan, ...]:
    """Check a request and return its words; raises :class:`SpeechError` naming the problem."""
    if not isinstance(request.text, str) or not request.text.strip():
        raise SpeechError("speech text is empty")
    words = split_words(request.text)
    if not words:
        raise SpeechError(f"speech text {request.text!r} has no words (only punctuation or symbols)")
    check_rate(request.rate)
    _check_marks(request, words)
    _check_emphasis(request, words)
    return words


def _inside_word(offset: int, words: tuple[WordSpan, ...]) -> WordSpan | None:
    return next((w for w in words if w.start < offset < w.end), None)


def _check_offset(what: str, offset: int, request: SpeechRequest, words: tuple[WordSpan, ...]) -> None:
    if not isinstance(offset, int) or not 0 <= offset <= len(request.text):
        raise SpeechError(f"{what} offset {offset!r} is outside the text (0..{len(request.text)})")
    word = _inside_word(offset, words)
    if word is not None:
        raise SpeechError(
            f"{what} offset {offset} is inside the word {word.text!r} "
            f"(characters {word.start}..{word.end}); time tags must sit at word boundaries"
        )


def _check_marks(request: SpeechRequest, words: tuple[WordSpan, ...]) -> None:
    seen: set[str] = set()
    for mark in request.marks:
        if not isinstance(mark.name, str) or not is_mark_name(mark.name):
            raise SpeechError(f"mark name {mark.name!r} is not a valid XML name (NCName)")
        if mark.name in seen:
            raise SpeechError(f"mark name {mark.name!r} appears twice")
        seen.add(mark.name)
        _check_offset(f"mark {mark.name!r}", mark.offset, request, words)


def _check_emphasis(request: SpeechRequest, words: tuple[WordSpan, ...]) -> None:
    previous_end = -1
    for span in sorted(request.emphasis):
        if len(span) != 2:
            raise SpeechError(f"emphasis span {span!r} is not a (start, end) pair")
        start, end = span
        _check_offset(f"emphasis span {span!r} start", start, request, words)
        _check_offset(f"emphasis span {span!r} end", end, request, words)
        if start >= end:
            raise SpeechError(f"emphasis span {span!r} is empty or reversed")
        if start < previous_end:
            raise SpeechError(f"emphasis span {span!r} overlaps another emphasis span")
        previous_end = end


def emphasized(word: WordSpan, spans: tuple[tuple[int, int], ...]) -> bool:
    """True when ``word`` lies inside one of the emphasis spans."""
    return any(start <= word.start and word.end <= end for start, end in spans)


def mark_at_previous_word_end(request: SpeechRequest, offset: int, words: tuple[WordSpan, ...]) -> bool:
    """True when the mark at ``offset`` sits before a pause, i.e. belongs to the previous word's end.

    A tag directly before punctuation ("word [t], next") is heard at the end of the word;
    a tag after the punctuation or in a plain gap ("word, [t] next") at the next word's start.
    """
    following = next((w for w in words if w.start >= offset), None)
    if following is None:
        return True
    if all(w.end > offset for w in words):
        return False
    return pause_kind(request.text[offset:following.start]) != PAUSE_NONE
