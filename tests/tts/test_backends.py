"""The backend factory and the pyttsx3 backend's timing estimate."""

from __future__ import annotations

import numpy as np
import pytest

import tts.factory as factory
from tts import (
    BackendUnavailable,
    EspeakSynthesizer,
    FakeSynthesizer,
    Pyttsx3Synthesizer,
    SpeechError,
    SpeechRequest,
    SpeechSynthesizer,
    TextMark,
    make_synthesizer,
    read_wav,
    write_wav,
)
from tts.pyttsx3_backend import scale_timing


@pytest.mark.parametrize("name", ["fake", "espeak", "pyttsx3"])
def test_every_backend_follows_the_protocol(name):
    synthesizer = factory.BACKENDS[name]()
    assert isinstance(synthesizer, SpeechSynthesizer) and synthesizer.name == name


def test_fake_by_name():
    assert isinstance(make_synthesizer("fake"), FakeSynthesizer)


def test_default_falls_back_to_fake_with_a_warning(monkeypatch):
    monkeypatch.setattr(EspeakSynthesizer, "unavailable_reason", lambda self: "library gone")
    with pytest.warns(RuntimeWarning, match="library gone"):
        assert isinstance(make_synthesizer(), FakeSynthesizer)


def test_default_is_espeak_when_it_works(monkeypatch):
    monkeypatch.setattr(EspeakSynthesizer, "unavailable_reason", lambda self: None)
    assert isinstance(make_synthesizer("default"), EspeakSynthesizer)


def test_named_backend_that_cannot_speak_says_why(monkeypatch):
    monkeypatch.setattr(Pyttsx3Synthesizer, "unavailable_reason", lambda self: "no driver")
    with pytest.raises(BackendUnavailable, match="no driver"):
        make_synthesizer("pyttsx3")


@pytest.mark.parametrize(("name", "options", "message"), [("festival", {}, "unknown speech backend"), ("fake", {"voice": "x"}, "does not take")])
def test_bad_factory_arguments(name, options, message):
    with pytest.raises(SpeechError, match=message):
        make_synthesizer(name, **options)


def test_pyttsx3_availability_is_a_clear_answer():
    synthesizer = Pyttsx3Synthesizer()
    reason = synthesizer.unavailable_reason()
    assert reason is None or "pyttsx3" in reason


def test_scaled_timing_stretches_the_fake_model_to_the_real_audio(tmp_path):
    request = SpeechRequest("Point at [t1]that one, please.", marks=(TextMark("t1", 9),), emphasis=((9, 13),))
    model = FakeSynthesizer().synthesize(request)
    write_wav(tmp_path / "real.wav", np.full(33075, 500, np.int16), 16000)  # 2.067 s of "speech"
    audio, rate = read_wav(tmp_path / "real.wav")
    timing = scale_timing(model, audio, rate, keep_audio=True, backend="pyttsx3")
    factor = timing.duration / model.duration
    assert timing.duration == pytest.approx(33075 / 16000)
    assert timing.approximate and timing.backend == "pyttsx3" and timing.sample_rate == 16000
    assert len(timing.audio) == 33075
    assert [w.text for w in timing.words] == [w.text for w in model.words]
    for real, estimate in zip(timing.words, model.words):
        assert (real.start, real.end) == pytest.approx((estimate.start * factor, estimate.end * factor))
        assert (real.char_start, real.char_end) == (estimate.char_start, estimate.char_end)
    assert timing.marks["t1"] == pytest.approx(model.marks["t1"] * factor)
    assert timing.phonemes[-1].end == pytest.approx(timing.duration)


def test_scaled_timing_refuses_empty_audio():
    model = FakeSynthesizer().synthesize(SpeechRequest("hi"))
    with pytest.raises(SpeechError, match="no audio"):
        scale_timing(model, np.zeros(0, np.int16), 22050, keep_audio=False, backend="pyttsx3")
