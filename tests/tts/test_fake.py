"""The fake speech timer: golden timings, its rules, its audio, and bad input."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from tts import FakeSynthesizer, SpeechError, SpeechRequest, TextMark
from tts.fake import SAMPLE_RATE, grapheme_units

# (request, words as (text, start, end) seconds, duration, marks, phoneme symbols)
GOLDEN = [
    (
        SpeechRequest("Hello world."),
        [("Hello", 0.0, 0.352517), ("world", 0.38254, 0.890068)],
        1.240091,
        {},
        "h e l o _ w o r l d _",
    ),
    (
        SpeechRequest("The thinking machine sings.", emphasis=((4, 12),)),
        [("The", 0.0, 0.192517), ("thinking", 0.22254, 0.96127), ("machine", 0.991293, 1.413832), ("sings", 1.443855, 1.905397)],
        2.25542,
        {},
        "th e _ th i n k i ng _ m a ch i n _ s i ng s _",
    ),
    (
        SpeechRequest(
            "Yes, I see. Go now",
            marks=(TextMark("t1", 0), TextMark("t2", 3), TextMark("t3", 5), TextMark("t4", 18)),
            final=False,
        ),
        [("Yes", 0.0, 0.26254), ("I", 0.46254, 0.575057), ("see", 0.605079, 0.835102), ("Go", 1.185125, 1.357642), ("now", 1.387664, 1.622676)],
        1.822676,
        {"t1": 0.0, "t2": 0.26254, "t3": 0.46254, "t4": 1.622676},
        "y e s _ i _ s ee _ g o _ n ow _",
    ),
    (
        SpeechRequest("Don't re-use 42 cafés!"),
        [("Don't", 0.0, 0.30254), ("re-use", 0.332562, 0.685079), ("42", 0.715102, 1.057642), ("cafés", 1.087664, 1.578186)],
        1.928209,
        {},
        "d o n t _ r e u s _ 4 4 2 2 _ c a f e s _",
    ),
]


@pytest.fixture
def fake() -> FakeSynthesizer:
    return FakeSynthesizer()


@pytest.mark.parametrize(("request_", "words", "duration", "marks", "symbols"), GOLDEN, ids=lambda v: getattr(v, "text", None))
def test_golden_timings(fake, request_, words, duration, marks, symbols):
    timing = fake.synthesize(request_)
    assert [(w.text, round(w.start, 6), round(w.end, 6)) for w in timing.words] == words
    assert round(timing.duration, 6) == duration
    assert {k: round(v, 6) for k, v in timing.marks.items()} == marks
    assert " ".join(p.symbol for p in timing.phonemes) == symbols
    assert timing.backend == "fake" and not timing.approximate and timing.audio is None


@pytest.mark.parametrize("request_", [g[0] for g in GOLDEN])
def test_phonemes_tile_the_duration(fake, request_):
    timing = fake.synthesize(request_)
    starts = np.array([p.start for p in timing.phonemes])
    ends = np.array([p.end for p in timing.phonemes])
    assert starts[0] == 0.0 and ends[-1] == timing.duration
    assert np.array_equal(starts[1:], ends[:-1]) and np.all(ends > starts)
    for word in timing.words:
        assert word.start in starts and word.end in ends


def test_words_carry_their_text_offsets(fake):
    text = "  Big, bold   words "
    timing = fake.synthesize(SpeechRequest(text))
    assert [text[w.char_start : w.char_end] for w in timing.words] == ["Big", "bold", "words"]


@pytest.mark.parametrize(
    ("word", "units"),
    [("the", "th e"), ("make", "m a k"), ("ball", "b a l"), ("queen", "qu ee n"), ("rhythm", "r h y th m"), ("yes", "y e s")],
)
def test_grapheme_units(word, units):
    assert " ".join(symbol for symbol, _, _ in grapheme_units(word)) == units


def _word_length(timing, text):
    word = next(w for w in timing.words if w.text == text)
    return word.end - word.start


def test_emphasis_lengthens_the_affiliate_by_half(fake):
    plain = fake.synthesize(SpeechRequest("a red ball here"))
    stressed = fake.synthesize(SpeechRequest("a red ball here", emphasis=((2, 5),)))
    assert _word_length(stressed, "red") == pytest.approx(1.5 * _word_length(plain, "red"), abs=2 / SAMPLE_RATE)
    assert _word_length(stressed, "here") == pytest.approx(_word_length(plain, "here"), abs=1e-12)


def test_non_final_chunk_shortens_final_lengthening(fake):
    final = fake.synthesize(SpeechRequest("we go there"))
    more = fake.synthesize(SpeechRequest("we go there", final=False))
    assert _word_length(more, "there") < _word_length(final, "there")
    assert more.words[0] == final.words[0]
    assert more.duration < final.duration


@pytest.mark.parametrize("rate", [0.5, 2.0])
def test_rate_scales_every_time(fake, rate):
    normal = fake.synthesize(SpeechRequest("one more time, please."))
    scaled = fake.synthesize(SpeechRequest("one more time, please.", rate=rate))
    assert scaled.duration == pytest.approx(normal.duration / rate, abs=len(normal.phonemes) / SAMPLE_RATE)


@pytest.mark.parametrize(
    ("text", "pause"),
    [("one two", 0.030), ("one, two", 0.200), ("one. two", 0.350), ("one; two", 0.350), ("one - two", 0.030)],
)
def test_pauses_follow_punctuation(fake, text, pause):
    first, second = fake.synthesize(SpeechRequest(text)).words
    assert second.start - first.end == pytest.approx(pause, abs=1 / SAMPLE_RATE)


def test_audio_is_exact_length_int16_and_silent_in_pauses(fake):
    timing = fake.synthesize(SpeechRequest("Hi, there.", with_audio=True))
    audio = timing.audio
    assert audio.dtype == np.int16 and audio.ndim == 1 and timing.sample_rate == 22050
    assert len(audio) == round(timing.duration * SAMPLE_RATE)
    for phoneme in timing.phonemes:
        part = audio[round(phoneme.start * SAMPLE_RATE) : round(phoneme.end * SAMPLE_RATE)]
        if phoneme.symbol == "_":
            assert not part.any()
        else:
            assert np.abs(part).max() > 1000


def test_two_runs_are_identical(fake):
    request = SpeechRequest("Exactly the same, every time.", marks=(TextMark("m", 8),), with_audio=True)
    first, second = fake.synthesize(request), FakeSynthesizer().synthesize(request)
    assert dataclasses.replace(first, audio=None) == dataclasses.replace(second, audio=None)
    assert np.array_equal(first.audio, second.audio)


def test_marks_are_read_only(fake):
    timing = fake.synthesize(SpeechRequest("a b", marks=(TextMark("x", 1),)))
    with pytest.raises(TypeError):
        timing.marks["x"] = 0.0  # type: ignore[index]


BAD = [
    (SpeechRequest(""), "empty"),
    (SpeechRequest("   \n"), "empty"),
    (SpeechRequest("?! ... ,"), "no words"),
    (SpeechRequest("hello there", marks=(TextMark("1st", 0),)), "not a valid XML name"),
    (SpeechRequest("hello there", marks=(TextMark("a b", 0),)), "not a valid XML name"),
    (SpeechRequest("hello there", marks=(TextMark("x:y", 0),)), "not a valid XML name"),
    (SpeechRequest("hello there", marks=(TextMark("t", 0), TextMark("t", 5))), "appears twice"),
    (SpeechRequest("hello there", marks=(TextMark("t", 3),)), "inside the word 'hello'"),
    (SpeechRequest("hello there", marks=(TextMark("t", 12),)), "outside the text"),
    (SpeechRequest("hello there", marks=(TextMark("t", -1),)), "outside the text"),
    (SpeechRequest("hello there", emphasis=((0, 3),)), "inside the word 'hello'"),
    (SpeechRequest("hello there", emphasis=((6, 0),)), "empty or reversed"),
    (SpeechRequest("hello there now", emphasis=((0, 11), (6, 15))), "overlaps"),
    (SpeechRequest("hello", rate=0.0), "rate"),
    (SpeechRequest("hello", rate=math.nan), "rate"),
]


@pytest.mark.parametrize(("request_", "message"), BAD, ids=[m for _, m in BAD])
def test_bad_requests_are_refused_clearly(fake, request_, message):
    with pytest.raises(SpeechError, match=message.replace("'", ".")):
        fake.synthesize(request_)


def test_speech_error_is_a_value_error():
    assert issubclass(SpeechError, ValueError)
