"""Where a time tag falls in the audio: the anchors strokes are timed against.

A stroke is synchronized with what a listener hears, so an affiliate's onset is the
acoustic onset of its first word and its end the acoustic end of its last word — the
word times the speech backend measured (espeak-ng: from its phoneme events, a word
starting at its first non-silent phoneme; the fake: by rule; pyttsx3: word level only,
the fake's word times stretched to its audio). The SSML mark a backend reports for the
tag is kept beside them for the timeline, but not used: espeak places a mark before the
emphasis pause it inserts, up to about 80 ms before the word is heard.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from mura.model import TimeTag
from tts import SpeechTiming


@dataclass(frozen=True)
class TagAnchor:
    """A time tag in its chunk's speech, seconds from the chunk's speech onset.

    ``onset``: the acoustic onset of the first word after the tag (the end of the last
    word when none follows); ``end``: the acoustic end of the last word before the tag
    (the start of the first word when none precedes); ``mark``: the backend's mark time
    for the tag, None when it reported none.
    """

    mark: float | None
    onset: float
    end: float


def acoustic_anchors(speech: SpeechTiming, tags: Iterable[TimeTag]) -> dict[str, TagAnchor]:
    """The anchors of ``tags`` (offsets into the text ``speech`` was made from) by their ids."""
    words = [w for w in speech.words if w.end >= w.start]
    anchors = {}
    for tag in tags:
        after = next((w for w in words if w.char_start >= tag.offset), None)
        before = next((w for w in reversed(words) if w.char_end <= tag.offset), None)
        onset = after.start if after is not None else words[-1].end
        end = before.end if before is not None else words[0].start
        anchors[tag.id] = TagAnchor(speech.marks.get(tag.id), onset, end)
    return anchors
