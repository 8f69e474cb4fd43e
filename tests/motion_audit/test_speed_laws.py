"""β, jerk ratio and the movement segmentation on synthetic wrist paths with known answers."""

import numpy as np
import pytest

from bench.motion_audit import movement, speed_laws

from .synthetic import FPS, minimum_jerk


def ellipse_with_power_law(a: float, b: float, beta: float, laps: float = 1.5, fps: float = FPS) -> np.ndarray:
    """A synthetic wrist tracing an ellipse with speed ∝ R^beta, sampled at ``fps``."""
    theta = np.linspace(0.0, 2.0 * np.pi * laps, 40001)
    arc = np.hypot(a * np.sin(theta), b * np.cos(theta))
    radius = arc**3 / (a * b)
    speed = 0.6 * radius**beta / 0.1**beta
    time = np.concatenate(([0.0], np.cumsum(np.diff(theta) * 0.5 * (arc[1:] / speed[1:] + arc[:-1] / speed[:-1]))))
    angle = np.interp(np.arange(0.0, time[-1], 1.0 / fps), time, theta)
    return np.stack((a * np.cos(angle), 1.3 + b * np.sin(angle), np.full_like(angle, 0.35)), axis=1)


@pytest.mark.parametrize("beta", [0.15, 1 / 3, 0.45])
@pytest.mark.parametrize("axes", [(0.15, 0.06), (0.12, 0.08)])
def test_power_law_exponent_is_recovered(beta, axes):
    path = ellipse_with_power_law(*axes, beta)
    fit = speed_laws.power_law(path, FPS, 0, len(path) - 1, "synthetic", 0.0)
    assert fit is not None and fit.beta == pytest.approx(beta, abs=0.02)
    assert fit.r_squared > 0.9


def ellipse_from_rest(a: float, b: float, beta: float, laps: float, ramp: float, duration: float, still: int = 10) -> np.ndarray:
    """A synthetic wrist, still, then tracing an ellipse at speed ``g(t)·R^beta`` from rest
    to rest, then still: the gain ``g`` rises from 0 over ``ramp`` seconds (a smooth step),
    stays flat and falls over the last ``ramp`` seconds."""
    theta = np.linspace(0.0, 2.0 * np.pi * laps, 40001)
    arc = np.hypot(a * np.sin(theta), b * np.cos(theta))
    density = arc / (arc**3 / (a * b)) ** beta  # law time per radian: ds / R^beta
    law = np.concatenate(([0.0], np.cumsum(0.5 * (density[1:] + density[:-1]) * np.diff(theta))))
    t = np.arange(0.0, duration + 1e-9, 1.0 / FPS)
    x = np.clip(np.minimum(t, duration - t) / ramp, 0.0, 1.0)
    gain = x**3 * (10.0 - 15.0 * x + 6.0 * x * x)
    travelled = np.concatenate(([0.0], np.cumsum(0.5 * (gain[1:] + gain[:-1]))))
    angle = np.interp(travelled / travelled[-1] * law[-1], law, theta)
    path = np.stack((a * np.cos(angle), 1.3 + b * np.sin(angle), np.full_like(angle, 0.35)), axis=1)
    return np.concatenate((np.repeat(path[:1], still, axis=0), path, np.repeat(path[-1:], still, axis=0)))


@pytest.mark.parametrize("beta", [0.2, 1 / 3, 0.45])
@pytest.mark.parametrize("ramp", [0.1, 0.2])
def test_starting_and_stopping_at_rest_does_not_bias_the_exponent(beta, ramp):
    """Near rest the speed rises and falls whatever the curvature; the fit leaves it out."""
    path = ellipse_from_rest(0.15, 0.06, beta, 1.0, ramp, 1.2)
    fit = speed_laws.power_law(path, FPS, 0, len(path) - 1, "synthetic from rest", 0.0)
    assert fit is not None and fit.beta == pytest.approx(beta, abs=0.02)


@pytest.mark.parametrize("beta", [0.2, 1 / 3, 0.45])
def test_each_movement_between_stops_has_its_own_gain(beta):
    """Two strokes of the law, the second twice as slow, with a stop between them."""
    fast = ellipse_from_rest(0.15, 0.06, beta, 0.75, 0.1, 0.8)
    slow = ellipse_from_rest(0.15, 0.06, beta, 0.75, 0.1, 1.6)
    path = np.concatenate((fast, slow[1:] + (fast[-1] - slow[0])))
    fit = speed_laws.power_law(path, FPS, 0, len(path) - 1, "synthetic two gains", 0.0)
    assert fit is not None and fit.beta == pytest.approx(beta, abs=0.02)
    assert fit.r_squared > 0.9


def test_straight_stroke_is_not_curved():
    path = np.outer(minimum_jerk(40), [0.3, 0.1, 0.0]) + [0.0, 1.2, 0.3]
    assert speed_laws.power_law(path, FPS, 0, len(path) - 1, "synthetic straight", 0.0) is None


def test_circle_is_curved_but_has_no_exponent():
    angle = np.linspace(0.0, 3 * np.pi, 90)
    path = np.stack((0.1 * np.cos(angle), 1.2 + 0.1 * np.sin(angle), np.full_like(angle, 0.3)), axis=1)
    fit = speed_laws.power_law(path, FPS, 0, len(path) - 1, "synthetic circle", 0.0)
    assert fit is not None and fit.beta is None and fit.turn_degrees > 400


def rest_move_rest(progress: np.ndarray, before: int = 10, after: int = 10, span=(0.25, 0.05, 0.1)) -> np.ndarray:
    """A synthetic wrist still, then moving along a line with ``progress`` (0 to 1), then still."""
    full = np.concatenate((np.zeros(before), progress, np.ones(after)))
    return np.outer(full, span) + [0.1, 1.0, 0.3]


@pytest.mark.parametrize("frames", [20, 36, 61])
@pytest.mark.parametrize("span", [(0.25, 0.05, 0.1), (0.0, 0.4, 0.0)])
def test_minimum_jerk_movement_has_jerk_ratio_one(frames, span):
    path = rest_move_rest(minimum_jerk(frames), span=span)
    units = movement.segment(path, FPS).units
    assert len(units) == 1 and units[0].from_rest and units[0].to_rest
    assert speed_laws.jerk_ratio(path, units[0], FPS) == pytest.approx(1.0, abs=0.05)


@pytest.mark.parametrize("seconds", [0.4, 0.6, 1.0])
@pytest.mark.parametrize("phase", [0.0, 0.3, 0.7])
def test_minimum_jerk_movement_starting_between_frames_has_jerk_ratio_one(seconds, phase):
    """A minimum-jerk movement that leaves and reaches rest between two frames: its unit
    spans whole frames (from the last still frame to the first), up to two frames more
    than the movement; the reference, fitted to a fraction of a frame, is the movement
    itself (spanning whole frames, a 0.4 s movement scored 1.2)."""
    t = np.arange(int(round(2.0 * FPS))) / FPS
    tau = np.clip((t - 0.5 - phase / FPS) / seconds, 0.0, 1.0)
    path = np.outer(tau**3 * (10 - 15 * tau + 6 * tau**2), (0.25, 0.05, 0.1)) + [0.1, 1.0, 0.3]
    (unit,) = movement.segment(path, FPS).units
    assert speed_laws.jerk_ratio(path, unit, FPS) == pytest.approx(1.0, abs=0.03)


def late_peak(tau: np.ndarray) -> np.ndarray:
    """A smooth start-to-stop profile whose speed peaks late (minimum jerk in warped time)."""
    warped = tau**1.4
    return warped**3 * (10 - 15 * warped + 6 * warped**2)


@pytest.mark.parametrize("phase", [0.0, 0.4, 0.8])
def test_a_movement_scores_the_same_whether_it_turns_back_or_stops(phase):
    """Out along a line and straight back, each 0.4 s with a late speed peak: turning back
    at once (the wrist stops for an instant, a speed valley, not a hold) or after 0.3 s
    still, the outward movement's jerk ratio is the same within 10 %: at the valley its
    reference stops where it does, as at a hold (with the valley's measured speed and
    acceleration as its end it scored 1.57-1.94 against 2.08-2.22)."""
    t = np.arange(int(round(2.5 * FPS))) / FPS

    def ratio(pause: float) -> float:
        out = np.clip((t - 0.5 - phase / FPS) / 0.4, 0.0, 1.0)
        back = np.clip((t - 0.9 - pause - phase / FPS) / 0.4, 0.0, 1.0)
        path = np.outer(late_peak(out) - late_peak(back), (0.2, 0.05, 0.0)) + [0.1, 1.0, 0.3]
        first = movement.segment(path, FPS).units[0]
        return speed_laws.jerk_ratio(path, first, FPS)

    assert ratio(0.0) == pytest.approx(ratio(0.3), rel=0.1)


@pytest.mark.parametrize(
    "profile, low",
    [
        (lambda tau: 3 * tau**2 - 2 * tau**3, 1.5),  # zero speed but a step in acceleration at both ends
        (lambda tau: tau, 3.0),  # a step in speed
        (lambda tau: np.where(tau < 0.5, 2 * tau**2, 1 - 2 * (1 - tau) ** 2), 1.5),
    ],
)
def test_starts_with_a_step_in_acceleration_have_a_high_jerk_ratio(profile, low):
    path = rest_move_rest(profile(np.linspace(0.0, 1.0, 40)))
    unit = movement.segment(path, FPS).units[0]
    assert unit.from_rest
    assert speed_laws.jerk_ratio(path, unit, FPS) > low


def two_movements(dip: float) -> np.ndarray:
    """Two synthetic reaches whose speed dips to ``dip`` of the peak between them (at frame 50)."""
    t = np.arange(101) / FPS
    speed = 0.6 * np.abs(np.sin(np.pi * t / (50 / FPS))) * (1 - dip) + 0.6 * dip * (t > 0) * (t < 100 / FPS)
    distance = np.concatenate(([0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) / FPS)))
    return np.outer(distance, [1.0, 0.0, 0.0]) + [0.0, 1.2, 0.3]


@pytest.mark.parametrize("dip, valleys", [(0.1, 1), (0.3, 1), (0.8, 0)])
def test_deep_speed_valleys_split_movements(dip, valleys):
    segmentation = movement.segment(two_movements(dip), FPS)
    assert len(segmentation.valleys) == valleys
    if valleys:
        assert segmentation.valleys[0].at == pytest.approx(50.0, abs=0.5)
        assert len(segmentation.units) == 2


def test_holds_arrive_and_depart_on_the_right_frames():
    path = np.concatenate((rest_move_rest(minimum_jerk(30), before=5, after=20), rest_move_rest(minimum_jerk(30), before=0, after=5)[1:] + [0.25, 0.05, 0.1]))
    holds = movement.segment(path, FPS).holds
    arrivals = [hold.first for hold in holds]
    departures = [hold.last for hold in holds]
    assert 34 in arrivals and 54 in departures  # moving frames 5..34, still to 54, then moving again
