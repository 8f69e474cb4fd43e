"""The chunk state machine and the within-chunk temporal network (its rules; relaxation steps: tests/relaxation)."""

from __future__ import annotations

import pytest
from scipy.optimize import brentq

from blackboard import (
    TRANSITIONS,
    ChunkState,
    ChunkStateMachine,
    GestureDemands,
    GestureRequest,
    IllegalTransition,
    RelaxationStep,
    TagAnchor,
    TimingConfig,
    TimingConflict,
    time_chunk,
)
from blackboard.chunk_timing import preparation_times

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


def demands(stroke=0.4, dynamic=True, repeatable=True, back=0.0):
    return GestureDemands(RIGHT, stroke, dynamic, repeatable, 0.3, repetition_return=back, stroke_distance=0.05 if dynamic else 0.0)


def anchors(**times):
    """Tags at word boundaries with no pause: mark, onset and end coincide (seconds into the speech)."""
    return {name: TagAnchor(t, t, t) for name, t in times.items()}


def prep(seconds):
    """Per-arm distance (m) whose comfortable preparation (Fitts' law, within the budget) takes ``seconds``."""
    distance = brentq(lambda d: preparation_times({"right": d}, None)[0] - seconds, 0.0, 10.0)
    return {"right": distance}


MARKS = anchors(t1=0.7, t2=1.0)


def test_stroke_onset_one_syllable_before_the_affiliate_and_spans_it():
    timing = time_chunk(0, 0.0, "start", 0.0, "free", MARKS, [GestureRequest("g", demands(), prep(0.3), ("t1", "t2"))])
    g = timing.gestures[0]
    assert timing.speech_onset == 0.0 and timing.stretch is None and g.relaxations == ()
    assert g.stroke_start == pytest.approx(0.5, abs=1e-9)
    assert g.relax == pytest.approx(1.0, abs=1e-9) and g.prep_start == 0.0  # prepares as soon as the arm is free


def test_the_acoustic_onset_not_the_mark_anchors_the_stroke():
    tags = {"t1": TagAnchor(0.64, 0.685, 0.648), "t2": TagAnchor(1.30, 1.35, 1.30)}  # espeak: mark before the emphasis pause
    timing = time_chunk(0, 0.0, "start", 0.0, "free", tags, [GestureRequest("g", demands(), prep(0.3), ("t1", "t2"))])
    g = timing.gestures[0]
    assert g.stroke_start == pytest.approx(0.685 - 0.2) and g.stroke == pytest.approx(0.685) and g.relax == pytest.approx(1.30)


def test_a_long_preparation_is_shortened_within_the_budget_then_stretches_the_pause_and_says_why():
    distances = prep(0.9)
    comfortable, shortest = preparation_times(distances, None)
    assert shortest < comfortable
    timing = time_chunk(1, 2.0, "after the pause", 2.2, "arm free", MARKS, [GestureRequest("g", demands(), distances, ("t1", "t2"))])
    g = timing.gestures[0]
    # the stroke must start at 2.2 + shortest, i.e. speech at 2.2 + shortest + 0.2 − 0.7
    assert timing.speech_onset == pytest.approx(2.2 + shortest - 0.5, abs=1e-9)
    assert [(r.step, r.amount) for r in g.relaxations] == [
        (RelaxationStep.SHORTER_PREPARATION, pytest.approx(comfortable - shortest)),
        (RelaxationStep.STRETCHED_PAUSE, pytest.approx(timing.speech_onset - 2.0)),
    ]
    assert timing.stretch.amount == pytest.approx(timing.speech_onset - 2.0) and timing.stretch.behavior == "g"
    assert f"preparation takes {comfortable:.3f} s" in timing.stretch.reason and "t1" in timing.stretch.reason
    assert g.stroke_start == pytest.approx(timing.speech_onset + 0.7 - 0.2, abs=1e-9)
    assert g.stroke_start - g.prep_start == pytest.approx(shortest)


@pytest.mark.parametrize("affiliate_end, stroke, dynamic, repeatable, back, mode, reps, slowdown, held", [
    (1.0, 0.4, True, True, 0.0, "slowed", 1, 0.5 / 0.4, 0),        # span 0.5 ≤ 1.5 × 0.4
    (1.5, 0.4, True, True, 0.0, "repeated", 2, 1.0 / 0.8, 0),      # span 1.0 = 2.5 × 0.4 → 2 strokes
    (2.1, 0.4, True, True, 0.0, "repeated", 4, 1.6 / 1.6, 0),      # span 1.6 = 4 × 0.4
    (2.1, 0.4, True, True, 0.2, "repeated", 3, 1.6 / 1.6, 1),      # 3 strokes and 2 returns fill 1.6: one held instead
    (1.5, 0.4, True, True, 0.4, "held", 1, 1.5, 1),                # 2 strokes and a return take 1.2 > 1.0: held instead
    (1.5, 0.4, True, False, 0.0, "held", 1, 1.5, 0),               # not repeatable: slowed 1.5×, then held
    (1.2, 0.4, True, True, 0.0, "held", 1, 1.5, 0),                # f = 1.75 < 2: slowed 1.5×, then held
    (1.5, 0.0, False, False, 0.0, "static", 1, 1.0, 0),            # a static stroke holds
    (0.8, 0.5, True, True, 0.0, "slowed", 1, 1.0, 0),              # affiliate shorter than the stroke: natural
])
def test_how_a_stroke_fills_its_affiliate(affiliate_end, stroke, dynamic, repeatable, back, mode, reps, slowdown, held):
    tags = anchors(t1=0.7, t2=affiliate_end)
    timing = time_chunk(0, 0.0, "start", 0.0, "free", tags,
                        [GestureRequest("g", demands(stroke, dynamic, repeatable, back), prep(0.3), ("t1", "t2"))])
    g = timing.gestures[0]
    assert (g.mode, g.repetitions) == (mode, reps)
    assert g.slowdown == pytest.approx(slowdown, abs=1e-6)
    assert g.relax >= affiliate_end - 1e-9
    holds = [r for r in g.relaxations if r.step is RelaxationStep.HOLD_INSTEAD_OF_REPEAT]
    assert sum(r.amount for r in holds) == held and all(r.unit == "repetitions" for r in holds)
    performed = reps * stroke + (reps - 1) * back
    if mode == "held":
        assert g.stroke_end == pytest.approx(g.stroke_start + 1.5 * stroke) and g.stroke_end < g.relax
    elif mode != "static":
        assert g.stroke_end == pytest.approx(g.stroke_start + performed * slowdown)


def test_absolute_timing_fixes_the_stroke_on_the_utterance_clock():
    timing = time_chunk(0, 0.0, "start", 0.0, "free", {}, [GestureRequest("g", demands(1.0), prep(0.5), absolute=(1.0, 3.0))])
    g = timing.gestures[0]
    assert (g.stroke_start, g.relax) == pytest.approx((1.0, 3.0)) and g.prep_start == 0.0
    assert (g.mode, g.repetitions) == ("repeated", 2) and g.relaxations == ()


def test_absolute_timing_too_soon_for_its_preparation_delays_the_absolute_clock():
    distances = prep(0.8)
    _, shortest = preparation_times(distances, None)
    timing = time_chunk(2, 0.0, "start", 0.5, "arm free at 0.5 s", {}, [GestureRequest("wave", demands(), distances, absolute=(0.6, 2.0))])
    g = timing.gestures[0]
    assert timing.absolute_delay == pytest.approx(0.5 + shortest - 0.6)
    assert (g.prep_start, g.stroke_start, g.relax) == pytest.approx((0.5, 0.5 + shortest, 2.0 + timing.absolute_delay))
    assert [r.step for r in g.relaxations] == [RelaxationStep.SHORTER_PREPARATION, RelaxationStep.STRETCHED_PAUSE]
    reason = timing.absolute_stretch.reason
    assert "arm free at 0.5 s" in reason and "wave: preparation takes 0.800 s" in reason
    assert "wave: stroke onset at absolute 0.600 s" in reason


def test_a_later_chunk_keeps_the_absolute_delay():
    timing = time_chunk(3, 4.0, "pause", 0.0, "free", {}, [GestureRequest("nod", demands(), prep(0.2), absolute=(5.0, 6.0))], absolute_delay=0.3)
    assert timing.absolute_delay == pytest.approx(0.3) and timing.absolute_stretch is None
    assert timing.gestures[0].stroke_start == pytest.approx(5.3)


def test_an_absolute_stroke_too_fast_for_its_budget_ends_later():
    fast = GestureDemands(RIGHT, 0.2, True, False, 0.3, stroke_distance=0.9)  # 0.9 m: 1.125 s at 1.5 m/s
    timing = time_chunk(0, 0.0, "start", 0.0, "free", {}, [GestureRequest("sweep", fast, prep(0.3), absolute=(1.0, 1.5))])
    g = timing.gestures[0]
    (longer,) = g.relaxations
    assert longer.step is RelaxationStep.LONGER_STROKE and longer.amount == pytest.approx(1.125 - 0.5)
    assert g.relax == pytest.approx(1.0 + 1.125) and g.stroke_start == pytest.approx(1.0)


def test_a_true_conflict_names_its_constraints():
    tags = anchors(t1=0.5, t2=0.9, t3=1.6, t4=2.0)
    with pytest.raises(TimingConflict) as caught:
        time_chunk(2, 0.0, "start", 0.0, "free", tags, [
            GestureRequest("long", demands(), prep(0.5), ("t1", "t3")),
            GestureRequest("overlapping", demands(), prep(0.5), ("t2", "t4")),
        ])
    names = caught.value.constraints
    assert any("long: stroke spans its affiliate up to t3" in n for n in names)
    assert any("overlapping prepares after the stroke of long" in n for n in names)
    assert any("overlapping: stroke onset 0.200 s before affiliate onset t2" in n for n in names)
    assert str(caught.value).startswith("chunk 3:") and "no relaxation satisfies them" in str(caught.value)


def test_same_arm_gestures_follow_each_other_without_retraction():
    tags = anchors(t1=0.5, t2=0.9, t3=1.6, t4=2.0)
    timing = time_chunk(0, 0.0, "start", 0.0, "free", tags, [
        GestureRequest("second", demands(), prep(0.5), ("t3", "t4")),
        GestureRequest("first", demands(), prep(0.3), ("t1", "t2")),
    ])
    first, second = sorted(timing.gestures, key=lambda g: g.stroke_start)
    assert second.prep_start >= first.relax - 1e-9


def test_speech_onset_respects_the_minimal_pause():
    config = TimingConfig(min_pause=0.25)
    timing = time_chunk(1, 1.0 + config.min_pause, "pause", 0.0, "free", MARKS, [], config)
    assert timing.speech_onset == pytest.approx(1.25)
