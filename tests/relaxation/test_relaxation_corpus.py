"""Every example utterance and every published MURML file renders with fake speech and
espeak-ng, relaxing where it must; with espeak-ng, strokes lead the acoustic onset of
their affiliate's first word by 0.2 s; word-level backends (pyttsx3) anchor the same way."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
from relaxation_cases import EXAMPLES, PUBLISHED, check_timeline, perform, relaxed, word_onset

from mura.model import Affiliate
from tts import EspeakSynthesizer, FakeSynthesizer, SpeechRequest, SpeechTiming
from tts.pyttsx3_backend import scale_timing

FRAME = 1 / 60


def _speech(backend: str):
    if backend == "fake":
        return FakeSynthesizer()
    tts = EspeakSynthesizer()
    if not tts.available():
        pytest.skip(f"espeak-ng: {tts.unavailable_reason()}")
    return tts


_performed: dict = {}


def performed(path, backend):
    """Each file is performed once per backend for all the tests of this module."""
    key = (path, backend)
    if key not in _performed:
        _performed[key] = perform(path, _speech(backend))
    return _performed[key]


@pytest.mark.parametrize("backend", ["fake", "espeak"])
@pytest.mark.parametrize("path", EXAMPLES + PUBLISHED, ids=lambda p: p.stem)
def test_every_example_and_published_file_renders_keeping_its_constraints(path, backend):
    check_timeline(performed(path, backend))


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_with_espeak_strokes_lead_the_acoustic_onset_of_their_words_by_a_fifth_of_a_second(path):
    done = performed(path, "espeak")
    specs = {b.id: b for b in done.utterance.behaviors}
    affiliated = [b for b in done.timeline["behaviors"] if isinstance(specs[b["id"]].timing, Affiliate)]
    assert affiliated
    for b in affiliated:
        onset = word_onset(done, specs[b["id"]].timing.onset)
        lead = onset - b["phases"]["stroke_start"]
        assert abs(lead - (0.2 - relaxed(b, "later_stroke_onset"))) <= FRAME, (b["id"], lead)


def test_espeak_marks_come_before_the_words_they_tag():
    """Why the anchors are acoustic: espeak reports a mark before its emphasis pause."""
    early = []
    for path in EXAMPLES:
        anchors = performed(path, "espeak").timeline["tag_anchors"]
        early.extend(a["acoustic_onset"] - a["mark"] for a in anchors.values() if a["mark"] is not None)
    assert max(early) > 0.02 and min(early) >= -1e-9


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_performing_again_gives_the_same_timeline(path):
    assert json.dumps(perform(path).timeline) == json.dumps(performed(path, "fake").timeline)


class WordLevelSpeech:
    """Word-level timing as the pyttsx3 backend makes it: the fake's word times stretched to
    the length of the audio. The audio here is synthetic silence 30 % longer than the
    fake's (pyttsx3 needs a system speech engine the tests cannot count on)."""

    name = "pyttsx3"

    def available(self) -> bool:
        return True

    def synthesize(self, request: SpeechRequest) -> SpeechTiming:
        model = FakeSynthesizer().synthesize(dataclasses.replace(request, with_audio=False))
        audio = np.zeros(int(round(model.duration * 1.3 * model.sample_rate)), dtype=np.int16)  # synthetic
        return scale_timing(model, audio, model.sample_rate, request.with_audio, self.name)


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_word_level_backends_anchor_on_their_word_times(path):
    done = perform(path, WordLevelSpeech())
    check_timeline(done)
    specs = {b.id: b for b in done.utterance.behaviors}
    for b in done.timeline["behaviors"]:
        if isinstance(specs[b["id"]].timing, Affiliate):
            onset = word_onset(done, specs[b["id"]].timing.onset)
            assert onset - b["phases"]["stroke_start"] == pytest.approx(0.2 - relaxed(b, "later_stroke_onset"), abs=1e-6)
