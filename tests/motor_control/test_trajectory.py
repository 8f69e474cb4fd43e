"""Wrist trajectory formation: phases, the power law, rest-to-rest ends, the quintic knots."""

from __future__ import annotations

import numpy as np
import pytest

from motor.trajectory.guiding_strokes import circle_from_start, curve_breakpoints, ellipse_breakpoints
from motor.trajectory.power_law import envelope
from motor.trajectory.spline import (
    WristTrajectory,
    approach,
    fitts_duration,
    phases,
    plan_wrist_trajectory,
    time_breakpoints,
    turning_angles,
)

LINE = np.array([[0.0, 1.0, 0.3], [0.3, 1.1, 0.35]])
FINE = 2000.0  # samples per second for derivatives of the planned curve


def _corner(angle: float) -> np.ndarray:
    corner = np.array([0.2, 1.0, 0.3])
    return np.array([[0.0, 1.0, 0.3], corner, corner + 0.2 * np.array([np.cos(angle), np.sin(angle), 0.0])])


def _fit_exponent(trajectory: WristTrajectory, inner: float = 0.8) -> float:
    """β of log v = β log R + c over the inner part of the trajectory, from its own
    velocity and acceleration (R below 1 m, speed above 5 % of the peak)."""
    span = trajectory.end - trajectory.start
    margin = 0.5 * (1.0 - inner) * span
    t = np.linspace(trajectory.start + margin, trajectory.end - margin, 4000)
    v, a = trajectory.velocity(t), trajectory.acceleration(t)
    speed = np.linalg.norm(v, axis=1)
    radius = speed**3 / np.maximum(np.linalg.norm(np.cross(v, a), axis=1), 1e-12)
    keep = (radius < 1.0) & (speed > 0.05 * speed.max())
    return float(np.polyfit(np.log(radius[keep]), np.log(speed[keep]), 1)[0])


@pytest.mark.parametrize(
    ("amplitude", "expected"),
    [(0.0, 0.0), (0.1, 0.24 * np.log(11.0)), (0.5, 0.24 * np.log(51.0))],
)
def test_fitts_duration_table(amplitude: float, expected: float) -> None:
    assert fitts_duration(amplitude) == pytest.approx(expected)


def test_fitts_duration_is_vectorized_and_rejects_negative_amplitudes() -> None:
    amplitudes = np.array([[0.0, 0.1], [0.2, 0.4]])
    assert fitts_duration(amplitudes).shape == (2, 2)
    assert np.all(np.diff(fitts_duration(np.linspace(0, 1, 20))) > 0)
    with pytest.raises(ValueError, match="non-negative"):
        fitts_duration(np.array([0.1, -0.2]))


def test_single_straight_stroke_is_the_minimum_jerk_movement() -> None:
    trajectory = plan_wrist_trajectory(LINE, np.array([0.0, 0.5]))
    t = np.linspace(0.0, 0.5, 201)
    tau = t / 0.5
    expected = LINE[0] + (tau**3 * (10 - 15 * tau + 6 * tau**2))[:, None] * (LINE[1] - LINE[0])
    np.testing.assert_allclose(trajectory.position(t), expected, atol=1e-6)
    assert trajectory.warnings == ()


@pytest.mark.parametrize(
    "points",
    [
        LINE,
        _corner(np.pi / 3),
        curve_breakpoints((0.0, 1.0, 0.3), (0.3, 1.0, 0.3), None, "LeftC", 0.5).points,
        curve_breakpoints((0.0, 1.0, 0.3), (0.3, 1.1, 0.3), (0.0, 0.0, 1.0), "RightS", 0.4, 1.0, 0.5).points,
        circle_from_start((0.0, 1.0, 0.3), (0.0, 0.0, 1.0), 0.06),
    ],
    ids=["line", "corner", "half-circle", "S-curve", "circle"],
)
def test_every_phase_starts_and_stops_at_rest_with_zero_acceleration(points: np.ndarray) -> None:
    trajectory = plan_wrist_trajectory(points, start=1.0, end=2.0)
    ends = np.array([1.0, 2.0])
    np.testing.assert_allclose(trajectory.velocity(ends), 0.0, atol=1e-12)
    np.testing.assert_allclose(trajectory.acceleration(ends), 0.0, atol=1e-9)
    np.testing.assert_allclose(trajectory.position(ends), points[[0, -1]], atol=1e-12)


@pytest.mark.parametrize("points", [LINE, _corner(np.pi / 4), circle_from_start((0.0, 1.0, 0.3), (0.0, 1.0, 0.0), 0.1)])
def test_the_trajectory_is_c2(points: np.ndarray) -> None:
    """Position, velocity and acceleration have no jumps: their changes over a tiny step
    stay tiny everywhere, knots included."""
    trajectory = plan_wrist_trajectory(points, start=0.0, end=0.8)
    t = np.concatenate([trajectory.times, np.linspace(0.0, 0.8, 997)])
    h = 1e-7
    for derivative in (trajectory.position, trajectory.velocity, trajectory.acceleration):
        jump = np.linalg.norm(derivative(t + h) - derivative(t - h), axis=1)
        assert jump.max() < 1e-3


def test_quintic_knots_are_interpolated_with_their_derivatives() -> None:
    rng = np.random.default_rng(5)
    times = np.cumsum(rng.uniform(0.05, 0.2, size=6))
    p, v, a = (rng.normal(size=(6, 3)) for _ in range(3))
    trajectory = WristTrajectory(times, p, v, a)
    np.testing.assert_allclose(trajectory.position(times), p, atol=1e-12)
    np.testing.assert_allclose(trajectory.velocity(times), v, atol=1e-9)
    np.testing.assert_allclose(trajectory.acceleration(times), a, atol=1e-6)
    outside = np.array([times[0] - 1.0, times[-1] + 1.0])
    np.testing.assert_allclose(trajectory.position(outside), p[[0, -1]])
    np.testing.assert_allclose(trajectory.velocity(outside), 0.0)


@pytest.mark.parametrize(
    ("points", "expected"),
    [
        (LINE, [(0, 1)]),
        (_corner(np.pi / 3), [(0, 2)]),
        (_corner(0.8 * np.pi), [(0, 1), (1, 2)]),
        (np.array([[0.0, 1.0, 0.3], [0.2, 1.0, 0.3], [0.2, 1.0, 0.3], [0.2, 1.2, 0.3]]), [(0, 1), (2, 3)]),
    ],
    ids=["line", "gentle corner", "reversal", "hold"],
)
def test_phases_are_cut_at_holds_and_reversals(points: np.ndarray, expected: list) -> None:
    assert phases(points) == expected


def test_a_hold_between_phases_keeps_the_wrist_still() -> None:
    points = np.array([[0.0, 1.0, 0.3], [0.2, 1.0, 0.3], [0.2, 1.0, 0.3], [0.2, 1.2, 0.3]])
    trajectory = plan_wrist_trajectory(points, np.array([0.0, 0.3, 0.5, 0.8]))
    held = trajectory.position(np.linspace(0.3, 0.5, 11))
    np.testing.assert_allclose(held, np.repeat(points[1:2], 11, axis=0), atol=1e-12)
    np.testing.assert_allclose(trajectory.velocity(np.linspace(0.3, 0.5, 11)), 0.0, atol=1e-12)


def test_speed_slows_in_a_corner_and_the_path_passes_near_it() -> None:
    points = _corner(np.pi / 2)
    trajectory = plan_wrist_trajectory(points, start=0.0, end=1.0)
    t = np.linspace(0.0, 1.0, 2001)
    path = trajectory.position(t)
    nearest = int(np.argmin(np.linalg.norm(path - points[1], axis=1)))
    assert np.linalg.norm(path[nearest] - points[1]) < 1e-6
    speed = np.linalg.norm(trajectory.velocity(t), axis=1)
    assert speed[nearest] < 0.6 * speed.max()


@pytest.mark.parametrize(
    "points",
    [
        ellipse_breakpoints((0.0, 1.2, 0.3), (0.12, 0.05), (0.0, 0.0, 1.0), count=96, sweep=6 * np.pi),
        ellipse_breakpoints((0.0, 1.2, 0.3), (0.1, 0.04), (0.0, 0.0, 1.0), count=32),
        curve_breakpoints((0.0, 1.0, 0.3), (0.3, 1.0, 0.3), None, "LeftC", 0.2).points,
        curve_breakpoints((0.0, 1.0, 0.3), (0.3, 1.0, 0.3), None, "LeftC", 0.8, -1.0).points,
        curve_breakpoints((0.0, 1.0, 0.3), (0.3, 1.0, 0.3), None, "RightC", 0.5, 1.0, 0.6).points,
    ],
    ids=["3 laps", "1 lap", "shallow C", "sharp C", "broad skewed C"],
)
def test_the_power_law_holds_over_the_whole_curve(points: np.ndarray) -> None:
    trajectory = plan_wrist_trajectory(points, start=0.0, end=1.2)
    assert _fit_exponent(trajectory) == pytest.approx(1.0 / 3.0, abs=0.05)


def test_a_circle_is_traced_at_an_even_speed() -> None:
    """No braking at the breakpoints: speed ripple under 5 % between the ramps."""
    points = circle_from_start((0.0, 1.0, 0.3), (0.0, 0.0, 1.0), 0.08, count=16)
    trajectory = plan_wrist_trajectory(points, start=0.0, end=1.2)
    speed = np.linalg.norm(trajectory.velocity(np.linspace(0.15, 1.05, 1000)), axis=1)
    assert (speed.max() - speed.min()) / speed.mean() < 0.05


@pytest.mark.parametrize(("ramp", "duration"), [(0.5, 1.0), (0.1, 1.0), (0.2, 0.6), (0.05, 2.0)])
def test_envelope_rises_flat_and_falls(ramp: float, duration: float) -> None:
    t = np.linspace(0.0, duration, 5001)
    position, speed, acceleration = envelope(t, duration, ramp)
    assert position[0] == pytest.approx(0.0) and position[-1] == pytest.approx(1.0)
    assert speed[0] == pytest.approx(0.0, abs=1e-12) and speed[-1] == pytest.approx(0.0, abs=1e-12)
    inner = slice(1, -1)  # central differences only
    np.testing.assert_allclose(np.gradient(position, t)[inner], speed[inner], atol=2e-3 * speed.max())
    np.testing.assert_allclose(np.gradient(speed, t)[inner], acceleration[inner], atol=2e-2 * np.abs(acceleration).max())
    flat = (t > ramp + 1e-3) & (t < duration - ramp - 1e-3)
    assert np.ptp(speed[flat]) < 1e-12 if flat.any() else True


@pytest.mark.parametrize(
    ("velocity", "duration"),
    [((0.0, 0.0, 0.0), 0.5), ((0.5, 0.2, 0.0), 0.4), ((-0.3, 0.0, 0.4), 0.6)],
)
def test_approach_joins_the_current_state_and_arrives_at_rest(velocity: tuple, duration: float) -> None:
    here, target = np.array([0.2, 0.9, 0.1]), np.array([0.0, 1.2, 0.35])
    trajectory = approach(here, np.array(velocity), 1.0, target, 1.0 + duration)
    np.testing.assert_allclose(trajectory.position(np.array([1.0, 1.0 + duration])), [here, target], atol=1e-12)
    np.testing.assert_allclose(trajectory.velocity(np.array([1.0]))[0], velocity, atol=1e-12)
    np.testing.assert_allclose(trajectory.velocity(np.array([1.0 + duration])), 0.0, atol=1e-12)
    np.testing.assert_allclose(trajectory.acceleration(np.array([1.0, 1.0 + duration])), 0.0, atol=1e-9)


def test_time_breakpoints_spreads_collinear_strokes_by_length() -> None:
    points = np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.3, 0.0, 0.0], [0.4, 0.0, 0.0]])
    times = time_breakpoints(points, 2.0, 2.8)
    np.testing.assert_allclose(times, [2.0, 2.2, 2.6, 2.8])


@pytest.mark.parametrize(
    ("points", "start", "end", "message"),
    [
        (np.array([[0.0, 0, 0], [0.0, 0, 0], [1.0, 0, 0]]), 0.0, 1.0, "stroke 0"),
        (np.array([[0.0, 0, 0], [1.0, 0, 0]]), 1.0, 1.0, "end > start"),
        (np.array([[0.0, 0, 0]]), 0.0, 1.0, "n ≥ 2"),
        (np.array([[0.0, np.nan, 0], [1.0, 0, 0]]), 0.0, 1.0, "finite"),
    ],
)
def test_time_breakpoints_rejects_bad_input(points: np.ndarray, start: float, end: float, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        time_breakpoints(points, start, end)


def test_non_increasing_times_are_named() -> None:
    with pytest.raises(ValueError, match=r"t\[1\]"):
        plan_wrist_trajectory(_corner(0.5), np.array([0.0, 0.3, 0.3]))
    with pytest.raises(ValueError, match="times or a start"):
        plan_wrist_trajectory(_corner(0.5))


@pytest.mark.parametrize(
    ("max_speed", "max_acceleration"),
    [(3.0, None), (1.5, 15.0), (0.8, 6.0)],
)
def test_too_fast_movement_is_slowed_to_its_limits_with_a_warning(max_speed: float, max_acceleration: float | None) -> None:
    points = np.array([[-0.5, 1.0, 0.3], [0.5, 1.0, 0.3], [0.5, 1.3, 0.3]])
    trajectory = plan_wrist_trajectory(points, np.array([0.0, 0.1, 0.2]), max_speed=max_speed, max_acceleration=max_acceleration)
    assert len(trajectory.warnings) == 1 and "slowed" in trajectory.warnings[0]
    assert trajectory.peak_speed() <= max_speed * 1.001
    if max_acceleration is not None:
        assert trajectory.peak_acceleration() <= max_acceleration * 1.001
    t = np.linspace(-0.1, trajectory.end + 0.1, 500)
    assert np.all(np.isfinite(trajectory.position(t))) and np.all(np.isfinite(trajectory.velocity(t)))


def test_turning_angles_table() -> None:
    points = np.array([[0.0, 0, 0], [1.0, 0, 0], [2.0, 0, 0], [2.0, 1.0, 0], [2.0, 0.5, 0]])
    np.testing.assert_allclose(turning_angles(points), [0.0, np.pi / 2, np.pi])
