"""LMPs: time pegs, self-activation from the channel state, hand-over on a timeline."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from motor.arm.swivel import SwivelLMP
from motor.arm.wrist_position import PRE_STROKE_HOLD, WristPositionLMP, preparation_timing
from motor.arm.wrist_rotation import WristRotationLMP
from motor.hand.lmp import HandShapeLMP
from motor.program.lmp import (
    ChannelState,
    ChannelTimeline,
    RetractionLMP,
    TimePegs,
    VectorKeyframeLMP,
)
from motor.trajectory.guiding_strokes import curve_breakpoints
from motor.trajectory.speed_budget import budget
from motor.trajectory.spline import fitts_duration

FPS = 120.0
REST = np.array([0.2, 0.9, 0.1])
WRIST = ("right", "wrist_position")
ROTATION = ("right", "hand_rotation")
STROKE = np.array([[0.0, 1.2, 0.35], [-0.15, 1.25, 0.4], [-0.3, 1.15, 0.35]])


def frames(start: float, end: float) -> np.ndarray:
    return np.arange(start, end, 1.0 / FPS)


def gesture_then_retraction(second_start: float) -> list:
    """Gesture 1, its retraction at relax, and gesture 2 starting at ``second_start``, in
    activation order."""
    first = WristPositionLMP("right", TimePegs(0.2, 0.8, 0.8, 1.0, 1.3, 1.5, 1.5), STROKE)
    retract = RetractionLMP(WRIST, TimePegs.movement(1.5, 2.3), REST)
    second = WristPositionLMP(
        "right", TimePegs(*(second_start + np.array([0.0, 0.5, 0.5, 0.6, 0.7, 0.9, 0.9]))),
        np.array([[0.1, 1.3, 0.3], [0.2, 1.1, 0.3]]),
    )
    return [first, retract, second]


def assert_continuous(values: np.ndarray, times: np.ndarray, handovers: np.ndarray) -> None:
    """The step between frames around each hand-over stays within one frame at peak speed."""
    steps = np.linalg.norm(np.diff(values, axis=0), axis=1)
    peak_step = float(np.max(steps))
    peak_speed = peak_step * FPS
    for handover in handovers:
        k = int(np.searchsorted(times, handover)) - 1
        assert steps[k] <= peak_speed / FPS + 1e-12
        assert steps[k] <= 2.0 * max(steps[k - 1], steps[k + 1]) + 1e-9, f"jump at hand-over {handover}"


def test_time_pegs_must_be_ordered_and_finite() -> None:
    with pytest.raises(ValueError, match="stroke_start=0.5 before ready=0.8"):
        TimePegs(0.0, 0.8, 0.5, 1.0, 1.1, 1.2, 1.3)
    with pytest.raises(ValueError, match="time peg end must be finite"):
        TimePegs(0.0, 0.1, 0.2, 0.3, 0.4, 0.5, np.nan)
    pegs = TimePegs.movement(1.0, 1.5, 2.0)
    assert (pegs.stroke_start, pegs.stroke_end, pegs.relax, pegs.end) == (1.5, 1.5, 2.0, 2.0)


def _passes(path: np.ndarray, point: np.ndarray) -> bool:
    return bool(np.min(np.linalg.norm(path - point, axis=1)) < 1e-3)


def test_wrist_lmp_from_rest_waits_moves_in_natural_time_holds_and_passes_its_breakpoints() -> None:
    arrival = 1.2 - PRE_STROKE_HOLD
    lmp = WristPositionLMP("right", TimePegs(0.0, arrival, 1.2, 1.4, 1.6, 1.8, 1.8), STROKE)
    realization = lmp.activate(ChannelState.at_rest(REST, 0.0))
    natural = float(fitts_duration(np.linalg.norm(STROKE[0] - REST)))
    assert realization.warnings == ()
    np.testing.assert_allclose(realization.sample(np.array([0.0, arrival - natural - 0.01])), [REST, REST], atol=1e-12)
    assert np.linalg.norm(realization.sample(np.array([arrival - natural + 0.02]))[0] - REST) > 1e-5
    held = realization.sample(np.linspace(arrival, 1.2, 5))
    np.testing.assert_allclose(held, np.repeat(STROKE[:1], 5, axis=0), atol=1e-12)
    path = realization.sample(np.linspace(1.2, 1.6, 801))
    assert all(_passes(path, point) for point in STROKE)
    np.testing.assert_allclose(realization.sample(np.array([1.6, 5.0])), STROKE[[-1, -1]], atol=1e-12)


@pytest.mark.parametrize(
    ("amplitude", "window", "expected"),
    [
        (0.0, 1.0, (0.0, 0.0)),
        (0.2, 2.0, (float(fitts_duration(0.2)), PRE_STROKE_HOLD)),
        (0.2, float(fitts_duration(0.2)) + 0.05, (float(fitts_duration(0.2)), 0.05)),
        (0.2, 0.3, (0.3, 0.0)),
        (1.2, 5.0, (budget(None).shortest_duration(1.2), PRE_STROKE_HOLD)),
    ],
    ids=["no move", "room for the hold", "some room", "squeezed", "budget over Fitts"],
)
def test_preparation_timing_rule(amplitude: float, window: float, expected: tuple) -> None:
    assert preparation_timing(amplitude, window) == pytest.approx(expected)


@pytest.mark.parametrize("window", [0.4, 0.8, 1.5])
def test_the_stroke_starts_from_rest_exactly_at_its_first_breakpoint_time(window: float) -> None:
    """The visible stroke onset: whatever the window, the wrist is at rest at the stroke's
    first breakpoint when the stroke starts, and moves right after."""
    onset = 0.3 + window
    lmp = WristPositionLMP("right", TimePegs(0.3, onset, onset, onset + 0.2, onset + 0.4, onset + 0.4, onset + 0.4), STROKE)
    realization = lmp.activate(ChannelState(REST, np.array([0.3, 0.0, 0.1]), 0.3))
    state = realization.state(onset)
    np.testing.assert_allclose(state.value, STROKE[0], atol=1e-12)
    np.testing.assert_allclose(state.velocity, 0.0, atol=1e-12)
    assert np.linalg.norm(realization.state(onset + 0.05).velocity) > 0.01


def test_wrist_lmp_started_while_moving_keeps_the_velocity() -> None:
    moving = ChannelState(REST, np.array([0.4, 0.3, 0.0]), 0.5)
    realization = WristPositionLMP("right", TimePegs(0.5, 0.9, 0.9, 1.0, 1.2, 1.2, 1.2), STROKE).activate(moving)
    state = realization.state(0.5)
    np.testing.assert_allclose(state.value, REST)
    np.testing.assert_allclose(state.velocity, [0.4, 0.3, 0.0])


def test_curve_warnings_reach_the_realization() -> None:
    curve = curve_breakpoints(STROKE[0], STROKE[2])
    lmp = WristPositionLMP("right", TimePegs(0.0, 0.8, 0.8, 1.0, 1.3, 1.3, 1.3), curve.points, warnings=curve.warnings)
    timeline = ChannelTimeline.build(WRIST, [lmp], ChannelState.at_rest(REST))
    assert any("no normal" in w for w in timeline.warnings)


def test_impossible_preparation_starts_the_stroke_late_and_never_too_fast() -> None:
    far = np.array([[-0.6, 1.3, 0.4], [-0.4, 1.3, 0.4]])
    lmp = WristPositionLMP("right", TimePegs(0.0, 0.05, 0.05, 0.1, 0.2, 0.2, 0.2), far)
    timeline = ChannelTimeline.build(WRIST, [lmp], ChannelState.at_rest(REST))
    assert any("late" in w for w in timeline.warnings)
    values = timeline.sample(frames(0.0, 2.0))
    speeds = np.linalg.norm(np.diff(values, axis=0), axis=1) * FPS
    assert speeds.max() <= 3.0 * 1.01


def test_too_fast_stroke_is_slowed_and_never_nan() -> None:
    far = np.array([[-1.0, 1.0, 0.3], [1.0, 1.0, 0.3]])
    lmp = WristPositionLMP("right", TimePegs(0.0, 0.5, 0.5, 0.52, 0.55, 0.6, 0.6), far)
    timeline = ChannelTimeline.build(WRIST, [lmp], ChannelState.at_rest(REST))
    assert any("slowed" in w for w in timeline.warnings)
    values = timeline.sample(frames(0.0, 3.0))
    assert np.all(np.isfinite(values))
    speeds = np.linalg.norm(np.diff(values, axis=0), axis=1) * FPS
    assert speeds.max() <= 3.0 * 1.01


@pytest.mark.parametrize("second_start", [0.9, 1.2, 1.5])
def test_a_retraction_is_dropped_when_a_later_gesture_starts_first(second_start: float) -> None:
    """The second gesture was activated after the first (and its retraction) but starts
    before the retraction would: the arm goes straight on to it."""
    first, retract, second = gesture_then_retraction(second_start)
    timeline = ChannelTimeline.build(WRIST, [first, retract, second], ChannelState.at_rest(REST))
    assert timeline.lmps == (first, second)
    values = timeline.sample(frames(second.pegs.ready, second.pegs.ready + 0.5))
    assert np.min(np.linalg.norm(values - REST, axis=1)) > 0.05


def test_timeline_hands_over_with_coarticulation() -> None:
    lmps = gesture_then_retraction(second_start=1.9)
    timeline = ChannelTimeline.build(WRIST, lmps, ChannelState.at_rest(REST))
    first, retract, second = timeline.lmps
    assert [lmp.pegs.start for lmp in timeline.lmps] == [0.2, 1.5, 1.9]
    assert timeline.in_control(0.1) is None and timeline.in_control(1.0) is first
    assert timeline.in_control(1.7) is retract and timeline.in_control(2.0) is second
    times = frames(0.0, 3.0)
    values = timeline.sample(times)
    assert np.all(np.isfinite(values))
    assert np.linalg.norm(values[int(2.25 * FPS)] - REST) > 0.05, "the retraction's remainder is skipped"
    np.testing.assert_allclose(values[0], REST)
    np.testing.assert_allclose(timeline.sample(np.array([2.4, 2.6])), [[0.1, 1.3, 0.3], [0.2, 1.1, 0.3]], atol=1e-12)
    assert_continuous(values, times, timeline.starts)


@pytest.mark.parametrize("second_start", [1.6, 1.9, 2.1])
def test_velocity_is_continuous_at_every_handover(second_start: float) -> None:
    timeline = ChannelTimeline.build(WRIST, gesture_then_retraction(second_start), ChannelState.at_rest(REST))
    h = 1e-4
    for index in range(1, len(timeline.lmps)):
        t = timeline.starts[index]
        before = timeline.realizations[index - 1].state(t)
        after = timeline.realizations[index].state(t)
        np.testing.assert_allclose(after.value, before.value, atol=1e-9)
        np.testing.assert_allclose(after.velocity, before.velocity, atol=1e-6)
        x = timeline.sample(np.array([t - h, t, t + h]))
        left, right = (x[1] - x[0]) / h, (x[2] - x[1]) / h
        assert np.linalg.norm(left - right) < 0.05 * max(np.linalg.norm(before.velocity), 0.1)


def test_timeline_samples_unsorted_times_like_sorted_ones() -> None:
    timeline = ChannelTimeline.build(WRIST, gesture_then_retraction(1.9), ChannelState.at_rest(REST))
    times = np.random.default_rng(0).uniform(-1.0, 4.0, 500)
    order = np.argsort(times)
    np.testing.assert_allclose(timeline.sample(times)[order], timeline.sample(times[order]))


def _angles(quaternions: np.ndarray) -> np.ndarray:
    r = Rotation.from_quat(quaternions)
    return np.linalg.norm((r[1:] * r[:-1].inv()).as_rotvec(), axis=1)


def test_rotation_timeline_is_continuous_and_reaches_its_keys() -> None:
    keys = Rotation.from_euler("xyz", [[0.0, 0.0, 0.0], [0.0, 80.0, 20.0], [60.0, 10.0, 0.0]], degrees=True).as_quat()
    rotate = WristRotationLMP("right", TimePegs(0.2, 0.8, 0.8, 1.0, 1.4, 1.6, 1.6), keys[1:])
    retract = RetractionLMP(ROTATION, TimePegs.movement(1.6, 2.4), keys[0])
    again = WristRotationLMP("right", TimePegs(1.9, 2.5, 2.5, 2.6, 2.7, 2.8, 2.8), keys[1:2])
    timeline = ChannelTimeline.build(ROTATION, [again, rotate, retract], ChannelState.at_rest(keys[0], rotation=True))
    times = frames(0.0, 3.0)
    values = timeline.sample(times)
    np.testing.assert_allclose(np.linalg.norm(values, axis=1), 1.0)
    assert np.all(np.einsum("ij,ij->i", values[1:], values[:-1]) > 0.99), "quaternion sign flips between frames"
    reached = Rotation.from_quat(timeline.sample(np.array([0.8, 1.4, 2.5])))
    expected = Rotation.from_quat(keys[[1, 2, 1]])
    assert np.all((reached * expected.inv()).magnitude() < 1e-6)
    steps = _angles(values)
    for handover in timeline.starts[1:]:
        k = int(np.searchsorted(times, handover)) - 1
        assert steps[k] <= steps.max() + 1e-12
        assert steps[k] <= 2.0 * max(steps[k - 1], steps[k + 1]) + 1e-9
    before = timeline.realizations[1].state(1.9)
    after = timeline.realizations[2].state(1.9)
    np.testing.assert_allclose(after.velocity, before.velocity, atol=1e-3 * max(1.0, np.linalg.norm(before.velocity)))


@pytest.mark.parametrize("lmp_type", ["handshape", "swivel"])
def test_vector_channels_blend_the_incoming_velocity(lmp_type: str) -> None:
    if lmp_type == "handshape":
        first = HandShapeLMP("left", TimePegs.movement(0.0, 0.6), np.array([[1.0, 0.5, 0.0, 0.2]]))
        second = HandShapeLMP("left", TimePegs.movement(0.3, 0.9), np.array([[0.0, 0.0, 1.0, 0.0]]), time_profile="targetted")
        initial = ChannelState.at_rest(np.zeros(4))
    else:
        first = SwivelLMP("left", TimePegs.movement(0.0, 0.6), [1.2])
        second = SwivelLMP("left", TimePegs.movement(0.3, 0.9), [-0.4], time_profile="lax")
        initial = ChannelState.at_rest([0.0])
    timeline = ChannelTimeline.build(first.channel, [second, first], initial)
    before = timeline.realizations[0].state(0.3)
    after = timeline.realizations[1].state(0.3)
    assert np.linalg.norm(before.velocity) > 0.1
    np.testing.assert_allclose(after.velocity, before.velocity, atol=1e-9)
    np.testing.assert_allclose(timeline.sample(np.array([0.9, 2.0])), np.repeat(second.keys, 2, axis=0), atol=1e-12)
    times = frames(0.0, 1.2)
    assert_continuous(timeline.sample(times), times, timeline.starts)


def test_retraction_is_minimum_jerk_and_arrives_at_ready() -> None:
    retraction = RetractionLMP(WRIST, TimePegs.movement(1.0, 1.5, 2.0), REST)
    realization = retraction.activate(ChannelState.at_rest(STROKE[0], 1.0))
    np.testing.assert_allclose(realization.sample(np.array([1.5, 1.8])), [REST, REST], atol=1e-12)
    t = np.linspace(1.0, 1.5, 501)
    speed = np.linalg.norm(np.diff(realization.sample(t), axis=0), axis=1)
    assert abs(t[np.argmax(speed)] - 1.25) < 0.05


@pytest.mark.parametrize(
    ("build", "message"),
    [
        (lambda: ChannelTimeline.build(WRIST, [SwivelLMP("right", TimePegs.movement(0, 1), [0.0])], ChannelState.at_rest(REST)),
         "was given an LMP on"),
        (lambda: WristPositionLMP("right", TimePegs.movement(1.0, 1.0), STROKE), "ready 1.0 must follow start"),
        (lambda: WristPositionLMP("right", TimePegs.movement(0.0, 1.0), np.zeros((2, 2))), "breakpoints must be finite"),
        (lambda: WristRotationLMP("right", TimePegs.movement(0.0, 1.0), np.zeros((1, 4))), "non-zero"),
        (lambda: SwivelLMP("right", TimePegs.movement(0.0, 1.0), [0.1, 0.2], key_times=[0.5, 0.4]), "increase"),
        (lambda: VectorKeyframeLMP(("right", "swivel"), TimePegs.movement(0.0, 1.0), np.zeros((1, 2))), "takes 1"),
        (lambda: RetractionLMP(WRIST, TimePegs.movement(1.0, 1.0), REST), "must follow start"),
        (lambda: VectorKeyframeLMP(ROTATION, TimePegs.movement(0.0, 1.0), np.zeros((1, 4))), "use WristRotationLMP"),
        (lambda: HandShapeLMP("left", TimePegs.movement(1.0, 2.0), [[0.0]], key_times=[1.0]), "after the start peg"),
    ],
)
def test_bad_lmps_are_named(build, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        build()


def test_activation_after_the_first_target_is_refused() -> None:
    lmp = WristPositionLMP("right", TimePegs.movement(0.0, 0.5), STROKE[:1])
    with pytest.raises(ValueError, match="activated at 0.7, not before its first target time 0.5"):
        lmp.activate(ChannelState.at_rest(REST, 0.7))
    with pytest.raises(ValueError, match="not before its first target"):
        SwivelLMP("right", TimePegs.movement(0.0, 0.5), [0.3]).activate(ChannelState.at_rest([0.0], 0.5))
