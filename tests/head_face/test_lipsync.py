"""Lip-sync: phoneme tables, coarticulation, the mouth against the audio, the fallbacks."""

from __future__ import annotations

import numpy as np
import pytest
from face_helpers import EXAMPLES, phases, rendered, weight

from bench.head_face import mouth_against_audio
from motor.face.arkit import FACE_INDEX, FACE_NAMES
from motor.face.control import FaceControl
from motor.face.lipsync import ANTICIPATION, Articulation, speech_segments
from motor.face.phonemes import Segment, lookup, sampa_symbols
from tts import make_synthesizer
from tts.speech import Phoneme, SpeechTiming, Word

SPOKEN = [p for p in sorted(EXAMPLES.glob("*.xml")) if "<specification>" in p.read_text()]
JAW = FACE_INDEX["jawOpen"]


@pytest.mark.parametrize(
    ("alphabet", "symbol", "visemes", "kind"),
    [
        ("espeak", "p", ("PP",), "bilabial"), ("espeak", "m", ("PP",), "bilabial"), ("espeak", "v", ("FF",), "labiodental"),
        ("espeak", "T", ("TH",), "dental"), ("espeak", "tS", ("CH",), "rounded"), ("espeak", "z", ("SS",), "sibilant"),
        ("espeak", "'aI", ("aa", "ih"), "vowel"), ("espeak", ",eI", ("E", "ih"), "vowel"), ("espeak", "'u:", ("ou",), "vowel"),
        ("espeak", "3:", ("E",), "vowel"), ("espeak", "w", ("ou",), "rounded"), ("espeak", "I2", ("ih",), "vowel"),
        ("fake", "th", ("TH",), "dental"), ("fake", "ee", ("ih",), "vowel"), ("fake", "ou", ("aa", "ou"), "vowel"),
        ("fake", "sh", ("CH",), "rounded"), ("fake", "7", ("E",), "vowel"), ("fake", "é", ("E",), "vowel"),
        ("sampa", "V", ("aa",), "vowel"), ("sampa", "U", ("ou",), "vowel"), ("sampa", "h", ("E",), "glottal"),
        ("sampa", "dZ", ("CH",), "rounded"), ("sampa", "i:", ("ih",), "vowel"),
    ],
)  # fmt: skip
def test_phoneme_tables(alphabet, symbol, visemes, kind):
    assert lookup(symbol, alphabet) == (visemes, kind, True)


@pytest.mark.parametrize(("picture", "symbols", "skipped"), [("hVlU", ["h", "V", "l", "U"], []), ("'tSi:z", ["tS", "i:", "z"], []), ("pa!", ["p", "a"], [(3, "!")])])
def test_sampa_mouth_pictures_split_into_symbols(picture, symbols, skipped):
    assert sampa_symbols(picture) == (symbols, skipped)


def _mouth(parts: list[Segment], times: np.ndarray) -> np.ndarray:
    articulation = Articulation.of(parts, lead=0.0)
    out = np.zeros((times.size, len(FACE_NAMES)))
    out[:, articulation.columns] = articulation.sample(times)
    return out


def test_bilabials_close_the_mouth_between_open_vowels():
    parts = [Segment("aa", 0.0, 0.15, 0.5), Segment("PP", 0.15, 0.23, 1.0), Segment("aa", 0.23, 0.38, 0.5)]
    mouth = _mouth(parts, np.array([0.075, 0.19, 0.305]))
    assert mouth[0, JAW] > 0.4 and mouth[2, JAW] > 0.4
    lips_apart = mouth[1, JAW] - mouth[1, FACE_INDEX["mouthClose"]]  # ARKit: mouthClose shuts the lips over an open jaw
    assert lips_apart < 0.03 and mouth[1, JAW] < 0.2 and mouth[1, FACE_INDEX["mouthPressLeft"]] > 0.25


def test_tongue_consonants_keep_the_lips_of_their_vowels():
    """Rounding carries through a t between two u's; a p between them closes the lips."""
    around = lambda middle: [Segment("ou", 0.0, 0.12, 0.5), middle, Segment("ou", 0.18, 0.3, 0.5)]  # noqa: E731
    t = _mouth(around(Segment("DD", 0.12, 0.18, 0.25)), np.array([0.15]))[0]
    p = _mouth(around(Segment("PP", 0.12, 0.18, 1.0)), np.array([0.15]))[0]
    assert t[FACE_INDEX["mouthPucker"]] > 0.4 > p[FACE_INDEX["mouthPucker"]]


def test_the_mouth_opens_before_the_sound():
    """Anticipation: the jaw is half open some tens of milliseconds before the vowel sounds."""
    parts, _ = speech_segments([("_", 0.0, 0.5), ("a", 0.5, 0.7), ("_", 0.7, 1.2)], "fake")
    articulation = Articulation.of(parts)
    times = np.linspace(0.0, 1.2, 1201)
    jaw = articulation.sample(times)[:, list(articulation.columns).index(JAW)]
    half_open = times[np.argmax(jaw > 0.5 * jaw.max())]
    assert 0.02 <= 0.5 - half_open <= ANTICIPATION + 0.03
    assert jaw[times < 0.3].max() < 0.02 and jaw[times > 0.95].max() < 0.02


def test_sampling_in_windows_gives_the_same_mouth():
    parts, _ = speech_segments([(s, 0.1 * i, 0.1 * i + 0.1) for i, s in enumerate("_thisisabigbar_")], "fake")
    articulation = Articulation.of(parts)
    times = np.arange(120) / 60.0
    whole = articulation.sample(times)
    pieces = np.concatenate([articulation.sample(times[a:b]) for a, b in ((0, 7), (7, 61), (61, 120))])
    assert np.array_equal(whole, pieces)


@pytest.fixture(scope="module")
def espeak():
    synthesizer = make_synthesizer("espeak")
    if not synthesizer.available():
        pytest.skip("espeak-ng is not available on this machine")
    return synthesizer


@pytest.mark.parametrize("path", SPOKEN, ids=lambda p: p.stem)
def test_the_mouth_opens_with_the_espeak_audio(espeak, path):
    """r ≥ 0.5 between jawOpen and the WAV's energy envelope, and the mouth closed (≤ 0.1)
    inside every pause of at least 0.2 s (its last 0.1 s left to the next word's lead-in)."""
    figures = mouth_against_audio(rendered(path.stem, "max", "espeak"))
    assert figures["r"] >= 0.5, figures
    assert figures["pauses"] >= 1 and figures["pause_jaw_max"] <= 0.1, figures


def test_the_fake_backend_is_lip_synced_exactly():
    """Over the fake's phonemes, shown ANTICIPATION ahead of their sound, the lips are open
    on vowels and sealed on bilabials (jawOpen − mouthClose, the lips' opening in ARKit)."""
    performance = rendered("fig2_take_this_bar")
    motion = performance.motion
    lips = weight(motion, "jawOpen") - weight(motion, "mouthClose")
    mean = {}
    for group in ("aeiou", "pbm"):
        spans = [(p["start"] - ANTICIPATION, p["end"] - ANTICIPATION) for p in performance.timeline["phonemes"] if p["symbol"] in group]
        frames = [i for i, t in enumerate(motion.times) if any(a + 0.015 <= t < b - 0.015 for a, b in spans)]
        mean[group] = float(lips[frames].mean())
    assert mean["aeiou"] > 0.25 and mean["pbm"] < 0.05, mean


def _words_only(text: str) -> SpeechTiming:
    words = [Word(w, 0.4 * i, 0.4 * i + 0.3, 0, len(w)) for i, w in enumerate(text.split())]
    return SpeechTiming((), tuple(words), {}, 0.4 * len(words), 22050, None, "pyttsx3", True)


def test_a_backend_without_phonemes_opens_the_mouth_per_word_and_says_so_once():
    face = FaceControl()
    first, _ = face.speak(_words_only("hello there friend"), 1.0)
    second, _ = face.speak(_words_only("again"), 3.0)
    assert len(first) == 1 and "word by word" in first[0] and second == ()
    times = np.arange(1.0, 2.3, 1 / 60)
    jaw = face.weights(times)[:, JAW]
    assert jaw.max() > 0.2


def test_unknown_phonemes_are_reported_once_and_shown_neutral():
    timing = SpeechTiming((Phoneme("Q!", 0.0, 0.1), Phoneme("a", 0.1, 0.2)), (Word("x", 0.0, 0.2, 0, 1),), {}, 0.2, 22050, None, "espeak", False)
    face = FaceControl()
    notes, _ = face.speak(timing, 0.0)
    again, _ = face.speak(timing, 1.0)
    assert len(notes) == 1 and "'Q!'" in notes[0] and again == ()


def test_accents_raise_the_brows_and_nod():
    performance = rendered("fig2_take_this_bar")
    motion = performance.motion
    brows = weight(motion, "browInnerUp")
    for behavior in ("gesture_1", "gesture_2"):
        affiliate = next(b for b in performance.timeline["behaviors"] if b["id"] == behavior)["affiliate"]
        inside = (motion.times >= affiliate["onset"]) & (motion.times <= affiliate["end"])
        assert brows[inside].max() > 0.4, behavior
    assert brows[motion.times < 0.2].max() == 0.0
    assert phases(performance, "gesture_1")["stroke"] > 0
