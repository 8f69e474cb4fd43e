"""The scheduler offline (virtual clock) on the example utterances, with fake speech and the fake motor."""

from __future__ import annotations

import json

import numpy as np
import pytest
from blackboard_fakes import CORPUS, UTTERANCES, FakeMotor, RecordingSpeech, utterance

from blackboard import ChunkState, FramesReady, Scheduler, SpeechStarted, VirtualClock
from mura.murml import load_utterance

ORDER = ["InPrep", "Pending", "Lurking", "InExec", "Subsiding", "Completed"]


def render(path, motor=None, speech=None):
    motor = motor or FakeMotor()
    speech = speech or RecordingSpeech()
    result = Scheduler(speech, motor, VirtualClock()).run(load_utterance(path), name=path.stem)
    return result, motor, speech


@pytest.fixture(params=UTTERANCES, ids=lambda p: p.stem)
def rendered(request):
    return render(request.param)


def test_every_stroke_starts_one_syllable_before_its_affiliate(rendered):
    result, _, _ = rendered
    data = result.timeline.to_json()
    assert result.failed_chunk is None, result.error
    for b in data["behaviors"]:
        if b["affiliate"].get("absolute"):
            assert b["phases"]["stroke_start"] == pytest.approx(b["affiliate"]["onset"], abs=1e-3)
        else:
            assert b["affiliate"]["onset"] - b["phases"]["stroke_start"] == pytest.approx(0.2, abs=1e-3)
        assert b["phases"]["relax"] >= b["affiliate"]["end"] - 1e-6, b["id"]


def test_every_chunk_passes_through_the_states_in_order(rendered):
    result, _, _ = rendered
    for chunk in result.timeline.to_json()["chunks"]:
        states = [s["state"] for s in chunk["states"]]
        times = [s["time"] for s in chunk["states"]]
        assert times == sorted(times)
        if "Subsiding" not in states:
            assert states == ORDER[:4] + ["Completed"]
            assert "no retraction active" in chunk["states"][-1]["reason"]
        else:
            assert states == ORDER


def test_speech_onsets_keep_the_pause_or_a_documented_stretch(rendered):
    result, _, _ = rendered
    data = result.timeline.to_json()
    stretched = {s["chunk"]: s["amount"] for s in data["stretches"]}
    for previous, chunk in zip(data["chunks"], data["chunks"][1:]):
        gap = chunk["speech_onset"] - previous["speech_end"]
        assert gap == pytest.approx(0.25 + stretched.get(chunk["index"], 0.0), abs=1e-6)
    first = data["chunks"][0]
    assert first["speech_onset"] == pytest.approx(stretched.get(0, 0.0), abs=1e-6)


def test_rendering_twice_gives_the_same_timeline(rendered):
    result, _, _ = rendered
    path = UTTERANCES[[p.stem for p in UTTERANCES].index(result.timeline.name)]
    again, _, _ = render(path)
    assert json.dumps(again.timeline.to_json()) == json.dumps(result.timeline.to_json())
    assert np.array_equal(again.audio, result.audio)
    assert np.array_equal(again.motion.rotations, result.motion.rotations)


def test_audio_and_motion_cover_the_utterance(rendered):
    result, motor, _ = rendered
    data = result.timeline.to_json()
    assert result.audio.dtype == np.int16 and result.sample_rate == 22050
    assert len(result.audio) / result.sample_rate <= data["duration"] + 1e-6
    # the frames run to the last retraction, or to the last word when the speech outlasts the behaviours
    last_end = max([b["phases"]["end"] for b in data["behaviors"]] + [c["speech_end"] for c in data["chunks"]])
    assert result.motion.start_time == 0.0
    assert result.motion.frame_count == pytest.approx(last_end * 60, abs=2)
    assert np.allclose(np.diff(result.motion.times), 1 / 60)
    # the fake arm is at its stroke position during every stroke
    for b in data["behaviors"]:
        plan = next(p for p in motor.plans if p.behavior == b["id"])
        for arm in plan.arms:
            joint = 1 if arm == "right" else 2
            frames = (result.motion.times >= b["phases"]["ready"] + 1e-6) & (result.motion.times < b["phases"]["relax"])
            angle = 2 * np.arcsin(result.motion.rotations[frames, joint, 0])
            assert np.allclose(angle, plan.target, atol=1e-9)


def test_fig2_pitch_stays_up_and_the_first_retraction_leads_to_an_interim_rest():
    result, motor, speech = render(UTTERANCES[[p.stem for p in UTTERANCES].index("fig2_take_this_bar")])
    assert [r.final for r in speech.requests] == [False, True]
    assert [r.emphasis for r in speech.requests] == [((13, 21),), ((12, 21),)]
    first, second = motor.plans
    assert first.next_gesture_follows and not second.next_gesture_follows


def test_an_early_next_affiliate_skips_the_retraction():
    result, motor, _ = render(UTTERANCES[[p.stem for p in UTTERANCES].index("fig2_take_this_bar")])
    data = result.timeline.to_json()
    g1, g2 = data["behaviors"]
    assert motor.cuts == [("right", "gesture_1", pytest.approx(g2["phases"]["start"]))]
    assert g1["retraction_skipped"] and g1["phases"]["end"] == pytest.approx(g2["phases"]["start"])
    # gesture 2 prepares during the pause, before its chunk's speech starts (anticipation)
    assert g2["phases"]["start"] < data["chunks"][1]["speech_onset"]
    # chunk 1 became Lurking as chunk 0 stopped executing
    c0, c1 = data["chunks"]
    lurking = next(s["time"] for s in c1["states"] if s["state"] == "Lurking")
    assert lurking == pytest.approx(c0["states"][-1]["time"])


def test_a_long_preparation_stretches_the_pause():
    path = UTTERANCES[[p.stem for p in UTTERANCES].index("fig2_take_this_bar")]
    plain, _, _ = render(path)
    far, _, _ = render(path, motor=FakeMotor(distances={"gesture_2": 3.0}))
    stretch = next(s for s in far.timeline.to_json()["stretches"] if s["chunk"] == 1)
    assert stretch["behavior"] == "gesture_2" and "gesture_2: preparation takes" in stretch["reason"]
    plain_c1, far_c1 = plain.timeline.to_json()["chunks"][1], far.timeline.to_json()["chunks"][1]
    assert far_c1["speech_onset"] - plain_c1["speech_onset"] > 0.3
    g2 = far.timeline.to_json()["behaviors"][1]
    assert g2["affiliate"]["onset"] - g2["phases"]["stroke_start"] == pytest.approx(0.2, abs=1e-6)


def test_observers_hear_states_feedback_speech_and_frames():
    events = []
    scheduler = Scheduler(RecordingSpeech(), FakeMotor(), VirtualClock())
    scheduler.subscribe(events.append)
    result = scheduler.run(utterance("fig2_take_this_bar.xml"), name="fig2")
    kinds = {type(e).__name__ for e in events}
    assert kinds == {"ChunkStateChanged", "BehaviorFeedback", "SpeechStarted", "SpeechEnded", "FramesReady", "ChunkPlanned", "UtteranceEnded"}
    points = [(e.behavior, e.point) for e in events if type(e).__name__ == "BehaviorFeedback"]
    assert ("gesture_1", "stroke_start") in points and ("gesture_2", "end") in points
    frames = [e for e in events if isinstance(e, FramesReady)]
    assert sum(e.motion.frame_count for e in frames) == result.motion.frame_count
    assert all(a.end == pytest.approx(b.start) for a, b in zip(frames, frames[1:]))
    starts = [e.time for e in events if isinstance(e, SpeechStarted)]
    assert starts == [c["speech_onset"] for c in result.timeline.to_json()["chunks"]]


@pytest.mark.parametrize("path", sorted(CORPUS.glob("*.us")), ids=lambda p: p.stem)
def test_gesture_only_utterances_render_without_speech(path):
    result, _, speech = render(path)
    data = result.timeline.to_json()
    assert speech.requests == [] and result.audio is None and data["words"] == []
    assert [s["state"] for s in data["chunks"][0]["states"]][-1] == "Completed"
    for b, spec in zip(data["behaviors"], load_utterance(path).behaviors):
        assert b["phases"]["stroke_start"] == pytest.approx(spec.timing.onset, abs=1e-6)
        assert b["phases"]["relax"] == pytest.approx(spec.timing.end, abs=1e-6)
    assert result.motion.frame_count > 0


def test_json_has_the_viewer_shape():
    result, _, _ = render(UTTERANCES[[p.stem for p in UTTERANCES].index("fig2_take_this_bar")])
    data = json.loads(json.dumps(result.timeline.to_json()))
    assert {"version", "name", "duration", "fps", "chunks", "behaviors", "words", "phonemes", "time_tags"} <= set(data)
    assert data["version"] == 1 and data["fps"] == 60 and set(data["time_tags"]) == {"t1", "t2", "t3", "t4"}
    assert set(data["chunks"][0]) >= {"index", "text", "speech_onset", "speech_end", "states"}
    assert set(data["behaviors"][0]["phases"]) == {"start", "ready", "stroke_start", "stroke", "stroke_end", "relax", "end"}
    assert set(data["words"][0]) == {"text", "start", "end", "chunk"} and set(data["phonemes"][0]) == {"symbol", "start", "end", "chunk"}
    assert ChunkState.IN_EXEC.value in [s["state"] for s in data["chunks"][0]["states"]]
