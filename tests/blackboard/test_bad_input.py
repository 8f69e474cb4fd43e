"""Bad input: each refused with an error naming what is wrong, or failing one chunk cleanly."""

from __future__ import annotations

from dataclasses import replace

import pytest
from blackboard_fakes import FailingSpeech, FakeMotor, RecordingSpeech, utterance

from blackboard import (
    BehaviorError,
    ChunkState,
    OverlappingGestures,
    ScheduleError,
    Scheduler,
    TimingConflict,
    VirtualClock,
)
from motor.trajectory.speed_budget import budget
from motor.trajectory.spline import fitts_duration
from mura.model import Affiliate, Utterance
from mura.murml import parse_utterance
from tts import SpeechError

FOUR_CHUNKS = """<definition><utterance><specification>
  First <time id="a1"/> this <time id="a2" chunkborder="true"/>
  then <time id="b1"/> that <time id="b2" chunkborder="true"/>
  and <time id="c1"/> one more <time id="c2" chunkborder="true"/>
  and <time id="d1"/> the last. <time id="d2"/>
</specification>
%s
</utterance></definition>"""

BEAT = """<behaviorspec id="%s"><gesture><affiliate onset="%s" end="%s"/><constraints><parallel>
  <static slot="HandShape" value="BSflat"/>
  <dynamic slot="HandLocation"><segment type="linear">
    <value type="start" name="LocChest LocCenterRight LocNorm"/><value type="direction" name="DirD"/>
    <value type="distance" name="DistShort"/></segment></dynamic>
</parallel></constraints></gesture></behaviorspec>"""


def schedule(utt, speech=None, motor=None):
    return Scheduler(speech or RecordingSpeech(), motor or FakeMotor(), VirtualClock()).run(utt, name="bad")


def with_affiliate(onset: str, end: str) -> Utterance:
    utt = utterance("fig2_take_this_bar.xml")
    first = utt.behaviors[0]
    return replace(utt, behaviors=(replace(first, timing=Affiliate(onset, end)),) + utt.behaviors[1:])


@pytest.mark.parametrize("onset, end, message", [
    ("t1", "nowhere", r"behaviour 'gesture_1': affiliate end names unknown time tag 'nowhere'"),
    ("ghost", "t2", r"behaviour 'gesture_1': affiliate onset names unknown time tag 'ghost'"),
    ("t1", "t4", r"behaviour 'gesture_1': affiliate end tag 't4' lies in chunk 2, not in the behaviour's chunk 1"),
    ("t2", "t1", r"behaviour 'gesture_1': affiliate from 't2' to 't1' spans no words"),
])
def test_affiliates_that_do_not_fit_their_chunk_are_refused(onset, end, message):
    with pytest.raises(BehaviorError, match=message):
        schedule(with_affiliate(onset, end))


@pytest.mark.parametrize("utt, message", [
    (Utterance((), ()), "neither text nor behaviours"),
    (replace(utterance("present_and_negate.xml"), chunks=(), behaviors=(utterance("present_and_negate.xml").behaviors[-1],)),
     "no text and no gesture"),
])
def test_nothing_to_say_or_do_is_refused(utt, message):
    with pytest.raises(ScheduleError, match=message):
        schedule(utt)


def test_overlapping_strokes_on_one_arm_are_refused_naming_both():
    utt = parse_utterance(FOUR_CHUNKS % (BEAT % ("one", "a1", "a2") + BEAT % ("two", "a1", "a2")))
    with pytest.raises(OverlappingGestures, match=r"gestures 'one' and 'two' both need the right arm"):
        schedule(utt)


TOUCHING = """<definition><utterance><specification>
  Take <time id="t1"/> this <time id="t2"/> and that <time id="t3"/></specification>%s</utterance></definition>"""


def test_touching_affiliates_on_one_arm_go_stroke_to_stroke_when_the_second_starts_where_the_first_ends():
    utt = parse_utterance(TOUCHING % (BEAT % ("one", "t1", "t2") + BEAT % ("two", "t2", "t3")))
    result = schedule(utt)  # the fake motor's strokes end and start at the same place: no preparation needed
    assert result.failed_chunk is None, result.error
    one, two = result.timeline.to_json()["behaviors"]
    assert [r["step"] for r in two["relaxations"]][:1] == ["co_articulation"]
    assert two["phases"]["start"] >= one["phases"]["relax"] - 1e-9


def test_touching_affiliates_on_one_arm_that_no_relaxation_separates_fail_naming_the_constraints():
    utt = parse_utterance(TOUCHING % (BEAT % ("one", "t1", "t2") + BEAT % ("two", "t2", "t3")))
    result = schedule(utt, motor=FakeMotor(distances={"one": 0.3, "two": 0.8}))
    assert result.failed_chunk == 0 and isinstance(result.error, TimingConflict)
    names = result.error.constraints
    assert "one: stroke spans its affiliate up to t2" in names and "two prepares after the stroke of one on the right arm" in names
    assert any(n.startswith("two: preparation takes") for n in names)
    assert "no relaxation satisfies them" in str(result.error)


def test_same_arm_gestures_apart_in_one_chunk_follow_without_retraction():
    text = """<definition><utterance><specification>
      Take <time id="t1"/> this <time id="t2"/> and after a long while also <time id="t3"/> that <time id="t4"/>
      </specification>%s</utterance></definition>"""
    motor = FakeMotor()
    result = schedule(parse_utterance(text % (BEAT % ("one", "t1", "t2") + BEAT % ("two", "t3", "t4"))), motor=motor)
    one, two = result.timeline.to_json()["behaviors"]
    assert two["phases"]["start"] >= one["phases"]["relax"] - 1e-9
    assert one["next_gesture_follows"] and one["retraction_skipped"]
    assert motor.cuts == [("right", "one", pytest.approx(two["phases"]["start"]))]


def test_a_speech_failure_in_chunk_3_fails_that_chunk_and_keeps_the_others():
    utt = parse_utterance(FOUR_CHUNKS % "".join(BEAT % (f"g{k}", f"{c}1", f"{c}2") for k, c in enumerate("abcd")))
    result = schedule(utt, speech=FailingSpeech(fail_at=3))
    data = result.timeline.to_json()
    assert result.failed_chunk == 3
    assert isinstance(result.error, SpeechError) and "chunk 4" in str(result.error) and "crashed" in str(result.error)
    assert [c["states"][-1]["state"] for c in data["chunks"]] == ["Completed"] * 3 + ["Failed"]
    assert [s["state"] for s in data["chunks"][3]["states"]] == ["InPrep", "Failed"]
    assert data["chunks"][3]["error"].startswith("SpeechError")
    assert [b["id"] for b in data["behaviors"]] == ["g0", "g1", "g2"]
    assert result.audio is not None and result.motion.frame_count > 0
    assert data["duration"] >= data["chunks"][2]["speech_end"]


def test_a_speech_failure_in_the_first_chunk_yields_an_empty_result():
    result = schedule(utterance("fig2_take_this_bar.xml"), speech=FailingSpeech(fail_at=0))
    assert result.failed_chunk == 0 and result.audio is None and result.motion is None
    assert result.timeline.states_of(0) == [ChunkState.IN_PREP, ChunkState.FAILED]


WAVE = """<behaviorspec id="wave"><gesture><timing onset="0.2" end="0.9"/><constraints><parallel>
  <static slot="HandShape" value="BSflat"/>
  <dynamic slot="HandLocation"><segment type="linear">
    <value type="start" name="LocChest LocCenterRight LocNorm"/><value type="direction" name="DirU"/>
    <value type="distance" name="DistShort"/></segment></dynamic>
</parallel></constraints></gesture></behaviorspec>"""


def test_an_absolute_stroke_too_soon_for_its_preparation_shortens_it_then_delays_the_absolute_clock():
    utt = parse_utterance(FOUR_CHUNKS % WAVE)
    result = schedule(utt, motor=FakeMotor(distances={"wave": 0.6}))  # a 0.99 s preparation (0.75 s at the budget) before 0.2 s
    assert result.failed_chunk is None
    data = result.timeline.to_json()
    wave = next(b for b in data["behaviors"] if b["id"] == "wave")
    delay = data["absolute_delay"]
    shortest = budget(None).shortest_duration(0.6)
    assert delay == pytest.approx(shortest - 0.2, abs=1e-6)
    assert wave["phases"]["stroke_start"] == pytest.approx(0.2 + delay, abs=1e-6)
    assert wave["phases"]["stroke_start"] - wave["phases"]["start"] == pytest.approx(shortest, abs=1e-6)
    assert wave["affiliate"] == {"onset": pytest.approx(0.2 + delay), "end": pytest.approx(0.9 + delay), "absolute": True}
    steps = [(r["step"], r["amount"]) for r in wave["relaxations"]]
    assert steps == [("shorter_preparation", pytest.approx(float(fitts_duration(0.6)) - shortest)), ("stretched_pause", pytest.approx(delay))]
    (warning,) = [w for w in data["warnings"] if "stretched_pause" in w]
    assert "wave: preparation takes" in warning and "wave: stroke onset at absolute 0.200 s" in warning
