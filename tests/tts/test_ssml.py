"""SSML for espeak: escaping, mark and emphasis placement, the position map."""

from __future__ import annotations

import pytest

from tts import SpeechRequest, TextMark
from tts.ssml import to_ssml
from tts.text import validate


def _ssml(request: SpeechRequest) -> tuple[str, tuple[int, ...]]:
    return to_ssml(request, validate(request))


@pytest.mark.parametrize(
    ("request_", "expected"),
    [
        (SpeechRequest("a < b & c"), "<speak>a &lt; b &amp; c</speak>"),
        (SpeechRequest("say \"hi\" 'x' >"), "<speak>say &quot;hi&quot; &apos;x&apos; &gt;</speak>"),
        (
            SpeechRequest("go to the red house.", marks=(TextMark("t1", 10), TextMark("t2", 20)), emphasis=((10, 13),)),
            '<speak>go to the <mark name="t1"/><emphasis>red</emphasis> house.<mark name="t2"/></speak>',
        ),
        (SpeechRequest("go home.", final=False), "<speak>go home,</speak>"),
        (SpeechRequest("go home", final=False), "<speak>go home,</speak>"),
        (SpeechRequest("go home,", final=False), "<speak>go home,</speak>"),
        (SpeechRequest("go home?!", final=True), "<speak>go home?!</speak>"),
        (
            SpeechRequest("stop, then go", marks=(TextMark("a", 4), TextMark("b", 13))),
            '<speak>stop<mark name="a"/>, then go<mark name="b"/></speak>',
        ),
    ],
)
def test_ssml_text(request_, expected):
    assert _ssml(request_)[0] == expected


def test_position_map_leads_back_to_the_text():
    request = SpeechRequest('x & "why"', marks=(TextMark("m", 4),), emphasis=((5, 8),))
    ssml, offsets = _ssml(request)
    assert len(offsets) == len(ssml)
    why = ssml.index("why")
    assert offsets[why : why + 3] == (5, 6, 7)
    amp = ssml.index("&amp;")
    assert set(offsets[amp : amp + 5]) == {2}
    assert list(offsets) == sorted(offsets)
