"""SSML for espeak-ng: the request text escaped, with ``<mark>`` and ``<emphasis>`` inserted.

Alongside the markup goes a position map: for every character of the SSML string, the
offset in the request text it stands for, so the character positions espeak reports in
its events lead back to the request's words. Markup characters map to the offset where
the markup sits; an escaped character's entity maps to that character.

Tags after the last word are written at the very end (after the closing punctuation), so
espeak never reads a stranded full stop aloud as "dot". ``final=False`` turns the closing
full-stop punctuation into a comma (or appends one): espeak then speaks the chunk with
its comma intonation, level or rising, without the final fall, and a short pause.
"""

from __future__ import annotations

from collections import defaultdict

from tts.speech import SpeechRequest
from tts.text import WordSpan

_ESCAPES = {"&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&apos;"}
_CLOSING_FALLS = frozenset(".!?;:\u2026")


def to_ssml(request: SpeechRequest, words: tuple[WordSpan, ...]) -> tuple[str, tuple[int, ...]]:
    """The SSML document for ``request`` and the request-text offset of each of its characters."""
    text = request.text
    markup = _markup_by_offset(request, words)
    tail_start = words[-1].end
    parts: list[str] = []
    offsets: list[int] = []

    def emit(piece: str, offset: int) -> None:
        parts.append(piece)
        offsets.extend([offset] * len(piece))

    emit("<speak>", 0)
    for i, ch in enumerate(text):
        for piece in markup.get(i, ()):
            emit(piece, i)
        if not request.final and i >= tail_start and ch in _CLOSING_FALLS:
            ch = ","
        emit(_ESCAPES.get(ch, ch), i)
    if not request.final and not any(ch in _CLOSING_FALLS or ch == "," for ch in text[tail_start:]):
        emit(",", len(text))
    for piece in markup.get(len(text), ()):
        emit(piece, len(text))
    emit("</speak>", len(text))
    return "".join(parts), tuple(offsets)


def _markup_by_offset(request: SpeechRequest, words: tuple[WordSpan, ...]) -> dict[int, list[str]]:
    """Markup to write before the character at each offset: closings, then marks, then openings."""
    closings: dict[int, list[str]] = defaultdict(list)
    marks: dict[int, list[str]] = defaultdict(list)
    openings: dict[int, list[str]] = defaultdict(list)
    last_end = words[-1].end
    end = len(request.text)
    for start, stop in request.emphasis:
        openings[start].append("<emphasis>")
        closings[stop].append("</emphasis>")
    for mark in request.marks:
        where = end if mark.offset >= last_end else mark.offset
        marks[where].append(f'<mark name="{mark.name}"/>')
    offsets = set(closings) | set(marks) | set(openings)
    return {k: closings[k] + marks[k] + openings[k] for k in offsets}
