"""The chunk state machine and the within-chunk temporal network."""

from __future__ import annotations

import pytest

from blackboard import (
    TRANSITIONS,
    ChunkState,
    ChunkStateMachine,
    GestureDemands,
    GestureRequest,
    IllegalTransition,
    TimingConfig,
    TimingConflict,
    time_chunk,
)

S = ChunkState
RIGHT = frozenset({"right"})


@pytest.mark.parametrize("path", [
    [S.PENDING, S.LURKING, S.IN_EXEC, S.SUBSIDING, S.COMPLETED],
    [S.PENDING, S.LURKING, S.IN_EXEC, S.COMPLETED],
    [S.FAILED],
    [S.PENDING, S.FAILED],
])
def test_legal_paths_keep_every_timestamp(path):
    machine = ChunkStateMachine("chunk 1", 0.0)
    for k, state in enumerate(path, start=1):
        machine.move(state, k * 0.5)
    assert [t.state for t in machine.history] == [S.IN_PREP] + path
    assert [t.time for t in machine.history] == [k * 0.5 for k in range(len(path) + 1)]
    assert machine.finished


@pytest.mark.parametrize("before, after", [
    (S.IN_PREP, S.LURKING), (S.PENDING, S.IN_EXEC), (S.LURKING, S.SUBSIDING),
    (S.COMPLETED, S.IN_PREP), (S.FAILED, S.PENDING), (S.SUBSIDING, S.IN_EXEC),
])
def test_illegal_transitions_name_both_states(before, after):
    machine = ChunkStateMachine("chunk 2", 0.0)
    route = {S.IN_PREP: [], S.PENDING: [S.PENDING], S.LURKING: [S.PENDING, S.LURKING],
             S.SUBSIDING: [S.PENDING, S.LURKING, S.IN_EXEC, S.SUBSIDING],
             S.COMPLETED: [S.PENDING, S.LURKING, S.IN_EXEC, S.COMPLETED], S.FAILED: [S.FAILED]}[before]
    for state in route:
        machine.move(state, 1.0)
    assert after not in TRANSITIONS[before]
    with pytest.raises(IllegalTransition, match=f"chunk 2: cannot go from {before.value} to {after.value}"):
        machine.move(after, 2.0)


def demands(stroke=0.4, dynamic=True, repeatable=True):
    return GestureDemands(RIGHT, stroke, dynamic, repeatable, 0.3)


MARKS = {"t1": 0.7, "t2": 1.0}


def test_stroke_onset_one_syllable_before_the_affiliate_and_spans_it():
    timing = time_chunk(0, 0.0, "start", 0.0, "free", MARKS, [GestureRequest("g", demands(), 0.3, ("t1", "t2"))])
    g = timing.gestures[0]
    assert timing.speech_onset == 0.0 and timing.stretch is None
    assert g.stroke_start == pytest.approx(0.5, abs=1e-9)
    assert g.relax == pytest.approx(1.0, abs=1e-9) and g.prep_start == 0.0


def test_a_long_preparation_stretches_the_pause_and_says_why():
    timing = time_chunk(1, 2.0, "after the pause", 1.8, "arm free", MARKS, [GestureRequest("g", demands(), 1.2, ("t1", "t2"))])
    # the stroke must start at 1.8 + 1.2 = 3.0, i.e. speech at 3.0 + 0.2 − 0.7 = 2.5
    assert timing.speech_onset == pytest.approx(2.5, abs=1e-9)
    assert timing.stretch.amount == pytest.approx(0.5, abs=1e-9)
    assert timing.stretch.behavior == "g"
    assert "preparation takes 1.200 s" in timing.stretch.reason and "t1" in timing.stretch.reason
    assert timing.gestures[0].stroke_start == pytest.approx(timing.speech_onset + 0.7 - 0.2, abs=1e-9)


@pytest.mark.parametrize("affiliate_end, stroke, dynamic, repeatable, mode, reps, slowdown", [
    (1.0, 0.4, True, True, "slowed", 1, 0.5 / 0.4),        # span 0.5 ≤ 1.5 × 0.4
    (1.5, 0.4, True, True, "repeated", 2, 1.0 / 0.8),      # span 1.0 = 2.5 × 0.4 → 2 strokes
    (2.1, 0.4, True, True, "repeated", 4, 1.6 / 1.6),      # span 1.6 = 4 × 0.4
    (1.5, 0.4, True, False, "held", 1, 1.5),              # not repeatable: slowed 1.5×, then held
    (1.2, 0.4, True, True, "held", 1, 1.5),               # f = 1.75 < 2: slowed 1.5×, then held
    (1.5, 0.0, False, False, "static", 1, 1.0),           # a static stroke holds
    (0.8, 0.5, True, True, "slowed", 1, 1.0),             # affiliate shorter than the stroke: natural
])
def test_how_a_stroke_fills_its_affiliate(affiliate_end, stroke, dynamic, repeatable, mode, reps, slowdown):
    marks = {"t1": 0.7, "t2": affiliate_end}
    timing = time_chunk(0, 0.0, "start", 0.0, "free", marks,
                        [GestureRequest("g", demands(stroke, dynamic, repeatable), 0.3, ("t1", "t2"))])
    g = timing.gestures[0]
    assert (g.mode, g.repetitions) == (mode, reps)
    assert g.slowdown == pytest.approx(slowdown, abs=1e-6)
    assert g.relax >= affiliate_end - 1e-9
    if mode == "held":
        assert g.stroke_end == pytest.approx(g.stroke_start + 1.5 * stroke) and g.stroke_end < g.relax
    else:
        assert g.stroke_end == g.relax


def test_absolute_timing_fixes_the_stroke_on_the_utterance_clock():
    timing = time_chunk(0, 0.0, "start", 0.0, "free", {}, [GestureRequest("g", demands(1.0), 0.5, absolute=(1.0, 3.0))])
    g = timing.gestures[0]
    assert (g.stroke_start, g.relax) == pytest.approx((1.0, 3.0)) and g.prep_start == pytest.approx(0.0)
    assert (g.mode, g.repetitions) == ("repeated", 2)


def test_absolute_timing_too_soon_for_its_preparation_delays_the_absolute_clock():
    timing = time_chunk(2, 0.0, "start", 0.5, "arm free at 0.5 s", {}, [GestureRequest("wave", demands(), 0.8, absolute=(1.0, 2.0))])
    g = timing.gestures[0]
    assert timing.absolute_delay == pytest.approx(0.3)
    assert (g.prep_start, g.stroke_start, g.relax) == pytest.approx((0.5, 1.3, 2.3))
    reason = timing.absolute_stretch.reason
    assert "arm free at 0.5 s" in reason and "wave: preparation takes 0.800 s" in reason
    assert "wave: stroke onset at absolute 1.000 s" in reason


def test_a_later_chunk_keeps_the_absolute_delay():
    timing = time_chunk(3, 4.0, "pause", 0.0, "free", {}, [GestureRequest("nod", demands(), 0.2, absolute=(5.0, 6.0))], absolute_delay=0.3)
    assert timing.absolute_delay == pytest.approx(0.3) and timing.absolute_stretch is None
    assert timing.gestures[0].stroke_start == pytest.approx(5.3)


def test_a_true_conflict_names_its_constraints():
    marks = {"t1": 0.5, "t2": 0.9, "t3": 1.6, "t4": 2.0}
    with pytest.raises(TimingConflict) as caught:
        time_chunk(2, 0.0, "start", 0.0, "free", marks, [
            GestureRequest("long", demands(), 0.5, ("t1", "t3")),
            GestureRequest("overlapping", demands(), 0.5, ("t2", "t4")),
        ])
    names = caught.value.constraints
    assert any("long: stroke spans its affiliate up to t3" in n for n in names)
    assert any("overlapping prepares after the stroke of long" in n for n in names)
    assert any("overlapping: stroke onset 0.200 s before affiliate onset t2" in n for n in names)
    assert str(caught.value).startswith("chunk 3:")


def test_same_arm_gestures_follow_each_other_without_retraction():
    marks = {"t1": 0.5, "t2": 0.9, "t3": 1.6, "t4": 2.0}
    timing = time_chunk(0, 0.0, "start", 0.0, "free", marks, [
        GestureRequest("second", demands(), 0.5, ("t3", "t4")),
        GestureRequest("first", demands(), 0.3, ("t1", "t2")),
    ])
    first, second = sorted(timing.gestures, key=lambda g: g.stroke_start)
    assert second.prep_start >= first.relax - 1e-9


def test_speech_onset_respects_the_minimal_pause():
    config = TimingConfig(min_pause=0.25)
    timing = time_chunk(1, 1.0 + config.min_pause, "pause", 0.0, "free", MARKS, [], config)
    assert timing.speech_onset == pytest.approx(1.25)
