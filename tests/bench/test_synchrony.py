"""The stroke detector on synthetic wrist movements with known onsets and ends."""

import numpy as np
import pytest

from bench import quality, synchrony

REST = np.array([0.2, 0.9, 0.1])
READY = np.array([0.05, 1.25, 0.35])
AFTER = np.array([-0.2, 1.3, 0.4])


def piecewise(fps: float, pieces: list[tuple[float, float, np.ndarray, np.ndarray]], total: float) -> np.ndarray:
    """Minimum-jerk movements ``(start time, end time, from, to)``, holding in between."""
    times = np.arange(int(round(total * fps)) + 1) / fps
    positions = np.tile(pieces[0][2], (times.size, 1))
    for start, end, origin, target in pieces:
        tau = np.clip((times - start) / (end - start), 0.0, 1.0)[:, None]
        moving = times >= start
        positions[moving] = origin + (tau**3 * (10 - 15 * tau + 6 * tau**2))[moving] * (target - origin)
    return positions


def phases(start, ready, stroke_end, relax, stroke_start=None):
    return {"start": start, "ready": ready, "stroke_start": ready if stroke_start is None else stroke_start, "stroke": ready + 0.2, "stroke_end": stroke_end, "relax": relax, "end": relax + 0.8}


@pytest.mark.parametrize("fps", [25.0, 60.0])
@pytest.mark.parametrize("onset, lag", [(0.9, 0.0), (1.13, 0.0), (1.0, 0.07), (1.0, -0.05)])
def test_static_stroke_onset_within_a_frame(fps, onset, lag):
    # the plan expects the stroke at `onset`, the motion arrives `lag` seconds later
    arrival = onset + lag
    wrist = piecewise(fps, [(0.0, arrival, REST, READY), (2.5, 3.3, READY, REST)], 3.5)
    found = synchrony.detect_stroke(wrist, fps, 0.0, phases(0.0, onset, 2.0, 2.5), onset)
    assert not found.dynamic and found.end is None
    assert abs(found.onset - arrival) <= 1.0 / fps + 1e-9


@pytest.mark.parametrize("fps", [25.0, 60.0])
@pytest.mark.parametrize("onset, stroke_end, lag", [(0.9, 1.6, 0.0), (1.21, 1.8, 0.04), (1.0, 1.5, -0.06)])
def test_dynamic_stroke_onset_and_end_within_a_frame(fps, onset, stroke_end, lag):
    start, end = onset + lag, stroke_end + lag
    wrist = piecewise(fps, [(0.0, start, REST, READY), (start, end, READY, AFTER), (end + 0.3, end + 1.1, AFTER, REST)], end + 1.3)
    found = synchrony.detect_stroke(wrist, fps, 0.0, phases(0.0, onset, stroke_end, stroke_end + 0.3), onset)
    assert found.dynamic
    assert abs(found.onset - start) <= 1.0 / fps + 1e-9
    assert abs(found.end - end) <= 1.0 / fps + 1e-9


def test_stroke_after_a_planned_hold_starts_at_the_departure():
    fps = 60.0
    wrist = piecewise(fps, [(0.0, 0.8, REST, READY), (1.1, 1.7, READY, AFTER), (2.0, 2.8, AFTER, REST)], 3.0)
    found = synchrony.detect_stroke(wrist, fps, 0.0, phases(0.0, 0.8, 1.7, 2.0, stroke_start=1.1), 1.1)
    assert abs(found.onset - 1.1) <= 1.0 / fps + 1e-9


def test_motion_clock_offset_is_respected():
    fps = 60.0
    wrist = piecewise(fps, [(0.0, 0.9, REST, READY)], 2.0)
    found = synchrony.detect_stroke(wrist, fps, 5.0, phases(5.0, 5.9, 6.5, 7.0), 5.9)
    assert abs(found.onset - 5.9) <= 1.0 / fps + 1e-9


def test_boundaries_kinds():
    speed = np.array([0.0, 0.0, 0.2, 0.5, 0.2, 0.05, 0.3, 0.4, 0.1, 0.0, 0.0])
    kinds = [(b.frame, b.kind) for b in synchrony.boundaries(speed, 60.0) if b.kind != "kink"]
    assert kinds == [(1, "departure"), (5, "dip"), (9, "arrival")]


def test_summary_counts_and_frames():
    errors = [
        synchrony.StrokeError("g1", "right", False, 1.0, 1.01, 0.01, 2.0, None, None),
        synchrony.StrokeError("g2", "left", True, 3.0, 2.97, -0.03, 4.0, 4.02, 0.02),
        synchrony.StrokeError("g3", "right", True, 5.0, None, None, 6.0, None, None),
    ]
    summary = synchrony.summarize(errors, 60.0)
    assert summary["strokes"] == 3 and summary["onset_measured"] == 2 and summary["onsets_missed"] == 1
    assert summary["onset_max_error_s"] == pytest.approx(0.03)
    assert summary["onset_max_error_frames"] == pytest.approx(1.8)
    assert summary["end_mean_error_s"] == pytest.approx(0.02)


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: synchrony.detect_stroke(np.zeros((5, 2)), 60.0, 0.0, phases(0, 1, 2, 3), 1.0), r"shape"),
        (lambda: synchrony.detect_stroke(np.zeros((5, 3)), 60.0, 0.0, {"start": 0.0}, 1.0), "phases lack ready"),
        (lambda: synchrony.boundaries(np.zeros((4, 2)), 60.0), r"shape \(n,\)"),
    ],
)
def test_bad_input_is_named(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_rendered_example_utterance(tmp_path):
    """The real pipeline end to end: fig2's strokes are found, the motion is clean."""
    from bench.machine import REPO_ROOT
    from blackboard.clock import VirtualClock
    from blackboard.scheduler import Scheduler
    from motor.body.avatar import load_avatar
    from motor.control import MotorControl
    from mura.murml import load_utterance
    from tts import FakeSynthesizer

    avatar = load_avatar("max")
    performed = Scheduler(FakeSynthesizer(), MotorControl(avatar, 60.0), VirtualClock()).run(
        load_utterance(REPO_ROOT / "specs" / "utterances" / "fig2_take_this_bar.xml")
    )
    errors = synchrony.stroke_errors(performed.motion, avatar, performed.timeline.to_json())
    assert [(e.behavior, e.arm) for e in errors] == [("gesture_1", "right"), ("gesture_2", "right"), ("gesture_2", "left")]
    assert all(e.detected_onset is not None for e in errors)
    assert quality.nan_count(performed.motion) == 0


@pytest.mark.parametrize("fps", [25.0, 60.0])
@pytest.mark.parametrize("joined", [0.35, 0.55])
def test_a_preparation_after_a_movement_flowing_into_it_ends_at_the_stroke(fps, joined):
    """The behaviour before skipped its retraction: its wider, faster movement is still
    under way at this behaviour's start (``joined`` s into it) and faster than the
    preparation that follows it; the onset is the preparation's end, not that movement's."""
    far = REST + np.array([-0.5, 0.3, 0.3])
    wrist = piecewise(fps, [(0.0, 0.8, far, REST), (0.8, 1.4, REST, READY), (1.4, 2.0, READY, AFTER), (2.3, 3.1, AFTER, REST)], 3.3)
    found = synchrony.detect_stroke(wrist, fps, 0.0, phases(joined, 1.4, 2.0, 2.3), 1.4)
    assert found.dynamic
    assert abs(found.onset - 1.4) <= 1.0 / fps + 1e-9


@pytest.mark.parametrize("fraction", [0.05, 0.1, 0.5])
def test_a_momentary_stop_is_found_at_its_speed_minimum(fraction):
    """A short preparation stops and the stroke starts at once, ``fraction`` of a frame
    after a frame time: over the frame before that one the wrist moves less than the still
    speed, a single still frame, which is no hold; the onset is the speed minimum's frame,
    within a frame of the stop (the still frame lies more than a frame before it)."""
    fps = 60.0
    onset = 1.0 + fraction / fps
    near = READY + 0.5 * (REST - READY)
    wrist = piecewise(fps, [(0.0, onset, near, READY), (onset, onset + 0.6, READY, AFTER), (onset + 0.9, onset + 1.7, AFTER, REST)], onset + 1.9)
    found = synchrony.detect_stroke(wrist, fps, 0.0, phases(0.0, onset, onset + 0.6, onset + 0.9), onset)
    assert abs(found.onset - onset) <= 1.0 / fps + 1e-9
