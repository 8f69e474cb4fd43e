"""The stroke-onset landmark detector, the acoustic onset on a WAV, and the timeline reader,
on synthetic wrist paths, synthetic audio and synthetic timelines."""

import json
import wave

import numpy as np
import pytest

from bench.motion_audit import audio, movement, stroke_onset
from bench.motion_audit.timeline import Behaviour, Word, timeline_for

from .synthetic import FPS, minimum_jerk

START = (0.1, 1.0, 0.3)


def piecewise(*pieces) -> np.ndarray:
    """A synthetic wrist path along x: ``("move", frames, metres)`` minimum-jerk moves,
    ``("hold", frames)`` holds and ``("glide", frames, metres)`` constant-speed glides."""
    x = [0.0]
    for kind, frames, *distance in pieces:
        if kind == "hold":
            x += [x[-1]] * frames
        elif kind == "move":
            x += list(x[-1] + distance[0] * minimum_jerk(frames + 1)[1:])
        else:
            x += list(x[-1] + distance[0] * np.arange(1, frames + 1) / frames)
    return np.outer(x, [1.0, 0.0, 0.0]) + START


def behaviour(stroke_start: float, stroke_end: float, onset: float | None = None) -> Behaviour:
    phases = {"start": 0.0, "ready": stroke_start, "stroke_start": stroke_start, "stroke": stroke_start + 0.2, "stroke_end": stroke_end, "relax": stroke_end, "end": stroke_end + 0.5}
    return Behaviour("synthetic", "gesture", ("r",), phases, onset, None, False, "")


CASES = [
    # (what, path, planned stroke start, stroke end, expected landmark, expected onset in s)
    ("static: arrival", piecewise(("hold", 10), ("move", 50, 0.3), ("hold", 60)), 1.0, 1.9, "arrival", 1.0),
    ("pre-stroke hold: departure", piecewise(("hold", 10), ("move", 30, 0.3), ("hold", 20), ("move", 40, 0.2), ("hold", 20)), 1.0, 1.6, "departure", 1.0),
    ("valley between preparation and stroke", piecewise(("hold", 10), ("move", 50, 0.3), ("move", 40, 0.2), ("hold", 20)), 1.0, 1.6, "valley", 1.0),
    ("stroke opening with the hand, wrist still: arrival", piecewise(("hold", 10), ("move", 50, 0.3), ("hold", 20), ("move", 40, 0.2), ("hold", 20)), 1.0, 2.0, "arrival", 1.0),
    ("flowing through: no landmark", piecewise(("hold", 10), ("glide", 100, 0.6), ("hold", 10)), 1.0, 1.6, None, None),
    ("landmark too far from the plan", piecewise(("hold", 10), ("move", 50, 0.3), ("hold", 60)), 1.35, 1.9, None, None),
]


@pytest.mark.parametrize("what, path, planned, end, landmark, onset", CASES, ids=[case[0] for case in CASES])
def test_landmarks_are_found_where_the_motion_shows_them(what, path, planned, end, landmark, onset):
    found = stroke_onset.stroke_onset(behaviour(planned, end), "r", path, movement.segment(path, FPS), FPS, 0.0, None)
    assert found.landmark == landmark
    if onset is None:
        assert found.onset is None
    else:
        assert found.onset == pytest.approx(onset, abs=0.5 / FPS)


@pytest.mark.parametrize("acoustic, lead", [(1.2, 0.2), (1.1, 0.1), (1.25, 0.25)])
def test_lead_is_acoustic_onset_minus_landmark(acoustic, lead):
    path = CASES[0][1]
    onset = audio.AcousticOnset("word", acoustic, acoustic, True)
    found = stroke_onset.stroke_onset(behaviour(1.0, 1.9, acoustic), "r", path, movement.segment(path, FPS), FPS, 0.0, onset)
    assert found.lead == pytest.approx(lead, abs=1e-9)


RATE = 22050


def write_wav(path, samples: np.ndarray) -> None:
    with wave.open(str(path), "wb") as out:
        out.setnchannels(1)
        out.setsampwidth(2)
        out.setframerate(RATE)
        out.writeframes((np.clip(samples, -1, 1) * 32767).astype("<i2").tobytes())


def tone(seconds: float, start: float, end: float, amplitude: float = 0.5) -> np.ndarray:
    t = np.arange(int(seconds * RATE)) / RATE
    return np.where((t >= start) & (t < end), amplitude * np.sin(2 * np.pi * 180 * t), 0.0)


@pytest.mark.parametrize("sound_at, event_at", [(1.23, 1.20), (1.21, 1.20), (1.20, 1.23)])
def test_acoustic_onset_is_refined_on_the_audio(tmp_path, sound_at, event_at):
    """Synthetic speech: silence, then a tone from ``sound_at``; the word event says ``event_at``."""
    write_wav(tmp_path / "synthetic.wav", tone(2.0, sound_at, 1.7))
    onset = audio.acoustic_onset(audio.read_wav(tmp_path / "synthetic.wav"), Word("word", event_at, 1.7))
    assert onset.refined and onset.onset == pytest.approx(sound_at, abs=0.002)


def test_a_word_without_a_gap_keeps_its_event_time(tmp_path):
    write_wav(tmp_path / "synthetic.wav", tone(2.0, 0.5, 1.7))
    onset = audio.acoustic_onset(audio.read_wav(tmp_path / "synthetic.wav"), Word("word", 1.2, 1.6))
    assert not onset.refined and onset.onset == 1.2


WORDS = (Word("wheel", 0.75, 0.98), Word("is", 0.98, 1.156), Word("perfectly", 1.23, 1.82), Word("round", 1.84, 2.29))


@pytest.mark.parametrize("mark, end, expected", [(1.149, 2.29, "perfectly"), (0.75, 2.29, "wheel"), (2.1, 2.29, None), (1.149, 1.2, None)])
def test_affiliate_word_is_the_first_word_after_the_mark(mark, end, expected):
    word = audio.affiliate_word(WORDS, mark, end)
    assert (word.text if word else None) == expected


def test_timeline_is_read_from_the_page_when_there_is_no_json(tmp_path):
    timeline = {"behaviors": [{"id": "HOUSE", "arms": ["right_arm", "left_arm"], "phases": {"start": 0.0, "ready": 0.4, "stroke_start": 0.4, "stroke": 0.7, "stroke_end": 1.0, "relax": 1.0, "end": 1.0}}], "words": []}
    island = json.dumps(timeline).replace("<", "\\u003c")
    (tmp_path / "HOUSE.html").write_text(f'<html><script type="application/json" id="mura-timeline">{island}</script></html>')
    read = timeline_for(tmp_path / "HOUSE.bvh")
    assert read.behaviours[0].id == "HOUSE" and read.behaviours[0].sides == ("r", "l")
    assert timeline_for(tmp_path / "absent.bvh") is None
