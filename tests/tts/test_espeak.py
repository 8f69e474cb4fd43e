"""espeak-ng through ctypes: measured events against the words, marks and audio they describe."""

from __future__ import annotations

import dataclasses
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from tts import (
    BackendUnavailable,
    EspeakSynthesizer,
    SpeechError,
    SpeechRequest,
    TextMark,
    UnknownVoice,
)
from tts.espeak import _Engine


@pytest.fixture(scope="module")
def espeak() -> EspeakSynthesizer:
    synthesizer = EspeakSynthesizer()
    reason = synthesizer.unavailable_reason()
    if reason is not None:
        pytest.skip(f"espeak-ng library unavailable: {reason}")
    return synthesizer


MARKED = SpeechRequest(
    "I saw [it], over there. Then it left",
    marks=(
        TextMark("start", 0),
        TextMark("before_it", 6),
        TextMark("before_comma", 10),
        TextMark("after_comma", 11),
        TextMark("after_stop", 24),
        TextMark("end", 36),
    ),
)


def _boundaries(timing) -> set[float]:
    return {p.start for p in timing.phonemes} | {timing.phonemes[-1].end}


def test_phonemes_tile_the_audio(espeak):
    timing = espeak.synthesize(dataclasses.replace(MARKED, with_audio=True))
    starts = np.array([p.start for p in timing.phonemes])
    ends = np.array([p.end for p in timing.phonemes])
    assert starts[0] == 0.0 and ends[-1] == timing.duration
    assert np.array_equal(starts[1:], ends[:-1]) and np.all(ends > starts)
    assert timing.audio.dtype == np.int16 and len(timing.audio) == round(timing.duration * timing.sample_rate)
    assert timing.backend == "espeak" and not timing.approximate


def test_words_are_ordered_and_on_phoneme_boundaries(espeak):
    timing = espeak.synthesize(MARKED)
    assert [w.text for w in timing.words] == ["I", "saw", "it", "over", "there", "Then", "it", "left"]
    boundaries = _boundaries(timing)
    for before, after in zip(timing.words, timing.words[1:]):
        assert before.start < before.end <= after.start
    for word in timing.words:
        assert word.start in boundaries and word.end in boundaries


def test_marks_lie_on_word_boundaries_and_agree_with_phonemes(espeak):
    timing = espeak.synthesize(MARKED)
    words = {w.text + str(w.char_start): w for w in timing.words}
    marks = timing.marks
    assert set(marks) == {m.name for m in MARKED.marks}
    assert marks["start"] == timing.words[0].start
    assert marks["before_it"] == words["it7"].start
    assert marks["before_comma"] == words["it7"].end  # heard before the comma's pause
    assert marks["after_comma"] == words["over12"].start
    assert marks["after_stop"] == words["Then24"].start  # espeak drops it; next word's start
    assert marks["end"] == timing.words[-1].end
    ordered = [marks[m.name] for m in sorted(MARKED.marks, key=lambda m: m.offset)]
    assert ordered == sorted(ordered)
    assert set(marks.values()) <= _boundaries(timing)


def test_emphasis_lengthens_the_affiliate(espeak):
    plain = espeak.synthesize(SpeechRequest("take the red ball"))
    stressed = espeak.synthesize(SpeechRequest("take the red ball", emphasis=((9, 12),)))
    def red(timing):
        return next(w.end - w.start for w in timing.words if w.text == "red")

    assert red(stressed) > 1.05 * red(plain)


_RUN_TWICE = """
import hashlib, sys
from tts import EspeakSynthesizer, SpeechRequest, TextMark
timing = EspeakSynthesizer().synthesize(SpeechRequest(
    "I saw it, over there.", marks=(TextMark("m", 6),), emphasis=((6, 8),), with_audio=True))
print([(p.symbol, p.start) for p in timing.phonemes], [(w.text, w.start, w.end) for w in timing.words],
      dict(timing.marks), timing.duration, hashlib.sha256(timing.audio.tobytes()).hexdigest())
"""


def test_two_runs_are_identical(espeak):
    """Two fresh processes give the same timings and audio, bit for bit."""
    root = Path(__file__).resolve().parents[2]
    outputs = [
        subprocess.run([sys.executable, "-c", _RUN_TWICE], cwd=root, capture_output=True, text=True, check=True).stdout
        for _ in range(2)
    ]
    assert outputs[0] == outputs[1] and outputs[0].strip()


def test_repeated_calls_agree_within_a_millisecond(espeak):
    request = dataclasses.replace(MARKED, emphasis=((7, 9),))
    first, second = espeak.synthesize(request), espeak.synthesize(request)
    assert [p.symbol for p in first.phonemes] == [p.symbol for p in second.phonemes]
    starts = np.array([[p.start for p in t.phonemes] for t in (first, second)])
    assert np.abs(starts[0] - starts[1]).max() < 1e-3
    assert first.marks.keys() == second.marks.keys()


def test_ssml_special_characters_are_spoken_as_text(espeak):
    text = 'if a < b & "c" > d'
    timing = espeak.synthesize(SpeechRequest(text, marks=(TextMark("m", 7),)))
    assert [w.text for w in timing.words] == ["if", "a", "b", "c", "d"]
    assert timing.marks["m"] in _boundaries(timing)


def test_faster_rate_is_shorter(espeak):
    normal = espeak.synthesize(SpeechRequest("one two three"))
    fast = espeak.synthesize(SpeechRequest("one two three", rate=1.6))
    assert fast.duration < 0.85 * normal.duration


def test_non_final_chunk_synthesizes_without_final_fall(espeak):
    timing = espeak.synthesize(SpeechRequest("and then.", final=False, marks=(TextMark("e", 9),)))
    assert timing.marks["e"] == timing.words[-1].end


def test_voice_is_chosen(espeak):
    british = espeak.synthesize(SpeechRequest("hello tomato", voice="en"))
    american = espeak.synthesize(SpeechRequest("hello tomato", voice="en-us"))
    assert [p.symbol for p in british.phonemes] != [p.symbol for p in american.phonemes]


def test_unknown_voice_names_the_voice(espeak):
    with pytest.raises(UnknownVoice, match="no-such-voice"):
        espeak.synthesize(SpeechRequest("hello", voice="no-such-voice"))
    assert espeak.synthesize(SpeechRequest("hello")).words[0].text == "hello"


@pytest.mark.parametrize("rate", [0.2, 4.0])
def test_rate_outside_espeak_range_is_refused(espeak, rate):
    with pytest.raises(SpeechError, match="words/min"):
        espeak.synthesize(SpeechRequest("hello", rate=rate))


@pytest.mark.parametrize("text", ["", "...", "  "])
def test_bad_text_never_reaches_the_library(espeak, text):
    with pytest.raises(SpeechError):
        espeak.synthesize(SpeechRequest(text))


def test_missing_library_reports_unavailable(tmp_path):
    missing = EspeakSynthesizer(library_path=str(tmp_path / "libespeak-ng.so.1"))
    assert not missing.available()
    assert "does not exist" in missing.unavailable_reason()
    with pytest.raises(BackendUnavailable):
        missing.synthesize(SpeechRequest("hello"))


def test_file_that_is_not_a_library_reports_unavailable(tmp_path):
    bogus = tmp_path / "libespeak-ng.so.1"
    bogus.write_text("not a shared object")
    assert not EspeakSynthesizer(library_path=str(bogus)).available()
    with pytest.raises(BackendUnavailable, match="cannot be loaded"):
        _Engine(str(bogus), None)  # the loader itself, before any process-wide state
