"""Each relaxation step on an utterance written for it: the step is taken, its amount
reported (in the timeline and as a warning), and the timeline keeps every other constraint."""

from __future__ import annotations

import json

import math

import pytest
from relaxation_cases import (
    AVATAR,
    CASES,
    TWO_ON_ONE_ARM,
    UNSATISFIABLE,
    check_timeline,
    perform,
    point,
    relaxed,
    spec,
)

from blackboard import RELAXATION_ORDER, OverlappingGestures, Scheduler, TimingConflict, VirtualClock
from blackboard.chunk_timing import preparation_times
from motor.control import MotorControl
from mura.murml import parse_utterance
from tts import EspeakSynthesizer, FakeSynthesizer


@pytest.fixture(params=CASES, ids=lambda case: case.step)
def case(request):
    return request.param


def test_the_cases_cover_every_step_of_the_order():
    assert [case.step for case in CASES] == [step.value for step in RELAXATION_ORDER]


def test_the_step_is_taken_and_its_amount_reported(case):
    performed = perform(case.document)
    check_timeline(performed)
    behavior = next(b for b in performed.timeline["behaviors"] if b["id"] == case.behavior)
    (entry, *_) = [r for r in behavior["relaxations"] if r["step"] == case.step]
    assert entry["amount"] > 0 and entry["unit"] == case.unit
    warnings = [w for w in performed.timeline["warnings"] if w.startswith(f"{case.behavior}: relaxed by {case.step}")]
    assert len(warnings) == 1
    amount = f"{entry['amount']:.3f} s" if case.unit == "s" else f"{entry['amount']:g} {case.unit}"
    assert amount in warnings[0]


def test_the_timeline_shows_what_each_step_did(case):
    performed = perform(case.document)
    data = performed.timeline
    behaviors = {b["id"]: b for b in data["behaviors"]}
    b = behaviors[case.behavior]
    amount = relaxed(b, case.step)
    if case.step == "co_articulation":
        a = behaviors["a"]
        assert b["phases"]["start"] == pytest.approx(a["phases"]["relax"]) and a["retraction_skipped"]
    elif case.step == "later_stroke_onset":
        assert b["affiliate"]["onset"] - b["phases"]["stroke_start"] == pytest.approx(0.2 - amount)
    elif case.step == "hold_instead_of_repeat":
        natural = performed.motor.demands(performed.utterance.behaviors[0]).stroke_duration
        span = b["phases"]["relax"] - b["phases"]["stroke_start"]
        assert b["repetitions"] + amount == math.floor(span / natural)  # the hold took the place of the others
    elif case.step == "stretched_pause":
        (stretch,) = [s for s in data["stretches"] if s["chunk"] == 1]
        assert stretch["amount"] == pytest.approx(amount) and stretch["behavior"] == "b"
        assert "b: preparation takes" in stretch["reason"]
    elif case.step == "longer_stroke":
        assert b["phases"]["relax"] - b["phases"]["stroke_start"] == pytest.approx(0.3 + amount)
    elif case.step == "dropped_repetition":
        assert amount == 1


def test_earlier_steps_are_used_up_before_a_later_one():
    """The pause is stretched only once the preparation is as short as the budget allows."""
    performed = perform(CASES[4].document)
    b = next(b for b in performed.timeline["behaviors"] if b["id"] == "b")
    assert [r["step"] for r in b["relaxations"]] == ["shorter_preparation", "stretched_pause"]
    gesture = next(x for x in performed.utterance.behaviors if x.id == "b")
    distances = performed.motor.preparation_distances(gesture, b["phases"]["start"])
    comfortable, shortest = preparation_times(distances, None)
    assert relaxed(b, "shorter_preparation") == pytest.approx(comfortable - shortest, abs=1e-6)
    assert b["phases"]["stroke_start"] - b["phases"]["start"] == pytest.approx(shortest, abs=1e-6)


@pytest.mark.parametrize("backend", ["fake", "espeak"])
def test_two_gestures_half_a_second_apart_on_one_arm_render_with_a_reported_relaxation(backend):
    tts = EspeakSynthesizer() if backend == "espeak" else None
    if tts is not None and not tts.available():
        pytest.skip(f"espeak-ng: {tts.unavailable_reason()}")
    performed = perform(TWO_ON_ONE_ARM, tts)
    check_timeline(performed)
    second = next(b for b in performed.timeline["behaviors"] if b["id"] == "point_that")
    assert second["relaxations"], "the second gesture needed a relaxation"
    assert any(w.startswith("point_that: relaxed by") for w in performed.timeline["warnings"])


def test_a_spec_no_relaxation_satisfies_fails_naming_its_constraints():
    result = perform(UNSATISFIABLE).result
    assert result.failed_chunk == 0 and isinstance(result.error, TimingConflict)
    names = result.error.constraints
    for name in ("a: stroke spans its affiliate up to t2", "b prepares after the stroke of a on the right arm",
                 "b: stroke onset 0.200 s before affiliate onset t2"):
        assert name in names
    assert any(n.startswith("b: preparation takes") for n in names)
    assert "no relaxation satisfies them" in str(result.error)


def test_overlapping_affiliates_on_one_arm_are_still_refused_before_planning():
    document = spec("Take [t1] this [t2] and [t3] that.", point("a", "t1", "t3", "$Loc-Bar_1"), point("b", "t2", "t3", "$Loc-Bar_2"))
    with pytest.raises(OverlappingGestures, match="'a' and 'b'"):
        Scheduler(FakeSynthesizer(), MotorControl(AVATAR), VirtualClock()).run(parse_utterance(document))


def test_relaxing_is_deterministic(case):
    first, second = perform(case.document), perform(case.document)
    assert json.dumps(first.timeline) == json.dumps(second.timeline)
