"""Wrist trajectory formation: breakpoint velocities, Hermite curve, timing, accents."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import CubicHermiteSpline

from motor.trajectory.guiding_strokes import ellipse_breakpoints
from motor.trajectory.spline import (
    Accent,
    WristTrajectory,
    breakpoint_velocities,
    fitts_duration,
    plan_wrist_trajectory,
    time_breakpoints,
    turning_angles,
)

LINE = np.array([[0.0, 1.0, 0.3], [0.3, 1.1, 0.35]])


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


def test_single_linear_stroke_has_symmetric_bell(speed_peak_fraction) -> None:
    trajectory = plan_wrist_trajectory(LINE, np.array([0.0, 0.5]))
    assert speed_peak_fraction(trajectory) == pytest.approx(0.5, abs=0.05)
    t = np.linspace(0.0, 0.5, 201)
    speed = np.linalg.norm(trajectory.velocity(t), axis=1)
    assert speed[0] == pytest.approx(0.0) and speed[-1] == pytest.approx(0.0)
    np.testing.assert_allclose(speed, speed[::-1], atol=1e-9)
    assert trajectory.warnings == ()


@pytest.mark.parametrize("fraction", [0.3, 0.6, 0.7, 0.8])
def test_accent_places_the_speed_peak(speed_peak_fraction, fraction: float) -> None:
    trajectory = plan_wrist_trajectory(LINE, np.array([0.0, 0.5]), accents=[Accent(0, fraction)])
    assert speed_peak_fraction(trajectory) == pytest.approx(fraction, abs=0.05)
    np.testing.assert_allclose(trajectory.position(np.array([0.5])), LINE[1:], atol=1e-12)
    t = np.linspace(0.0, 0.5, 501)
    progress = (trajectory.position(t) - LINE[0]) @ (LINE[1] - LINE[0])
    assert np.all(np.diff(progress) >= -1e-12), "the accented stroke must not move backwards"


def test_accent_on_one_stroke_of_many(speed_peak_fraction) -> None:
    points = np.array([[0.0, 1.0, 0.3], [0.2, 1.0, 0.3], [0.2, 1.2, 0.3]])
    times = np.array([0.0, 0.4, 0.8])
    plain = plan_wrist_trajectory(points, times)
    accented = plan_wrist_trajectory(points, times, accents=[Accent(1, 0.75)])
    second = WristTrajectory(accented.breakpoints[1:], accented.times[1:], accented.velocities[1:])
    assert accented.breakpoints.shape[0] == plain.breakpoints.shape[0] + 1
    assert speed_peak_fraction(second) == pytest.approx(0.75, abs=0.05)


@pytest.mark.parametrize(
    ("accent", "message"),
    [(Accent(3, 0.7), "stroke 3"), (Accent(0, 0.99), "fraction"), (Accent(0, 0.01), "fraction")],
)
def test_bad_accents_are_named(accent: Accent, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        plan_wrist_trajectory(LINE, np.array([0.0, 0.5]), accents=[accent])


def _corner(angle: float) -> np.ndarray:
    corner = np.array([0.2, 1.0, 0.3])
    return np.array([[0.0, 1.0, 0.3], corner, corner + 0.2 * np.array([np.cos(angle), np.sin(angle), 0.0])])


def test_speed_at_a_breakpoint_drops_as_the_angle_grows() -> None:
    angles = np.radians([0.0, 20.0, 45.0, 90.0, 135.0, 170.0])
    times = np.array([0.0, 0.3, 0.6])
    speeds = [np.linalg.norm(plan_wrist_trajectory(_corner(a), times).velocity(np.array([0.3]))[0]) for a in angles]
    assert np.all(np.diff(speeds) < 0)
    mean_speed = 0.2 / 0.3
    assert speeds[0] == pytest.approx(mean_speed)
    assert speeds[3] == pytest.approx(mean_speed * 0.5 ** (1 / 3))


def test_breakpoint_velocity_direction_is_parallel_to_the_chord() -> None:
    points = _corner(np.pi / 2)
    velocities = breakpoint_velocities(points, np.array([0.0, 0.3, 0.6]))
    chord = points[2] - points[0]
    assert np.linalg.norm(np.cross(velocities[1], chord)) == pytest.approx(0.0, abs=1e-12)
    assert velocities[1] @ chord > 0
    np.testing.assert_allclose(velocities[[0, 2]], 0.0)


def test_curved_strokes_use_the_curved_gain() -> None:
    points = _corner(np.pi / 4)
    times = np.array([0.0, 0.3, 0.6])
    straight = breakpoint_velocities(points, times)
    curved = breakpoint_velocities(points, times, curved=[False, True])
    np.testing.assert_allclose(curved[1], 0.8 * straight[1])
    with pytest.raises(ValueError, match="one flag per stroke"):
        breakpoint_velocities(points, times, curved=[True])


def test_curve_interpolates_and_matches_scipy_hermite() -> None:
    rng = np.random.default_rng(3)
    points = rng.uniform(-0.3, 0.3, size=(6, 3))
    times = np.cumsum(rng.uniform(0.1, 0.4, size=6))
    trajectory = plan_wrist_trajectory(points, times, start_velocity=np.array([0.1, 0.0, -0.2]))
    t = np.linspace(times[0], times[-1], 777)
    reference = CubicHermiteSpline(trajectory.times, trajectory.breakpoints, trajectory.velocities)
    np.testing.assert_allclose(trajectory.position(t), reference(t), atol=1e-12)
    np.testing.assert_allclose(trajectory.velocity(t), reference(t, 1), atol=1e-9)
    np.testing.assert_allclose(trajectory.acceleration(t), reference(t, 2), atol=1e-6)
    np.testing.assert_allclose(trajectory.position(times), points, atol=1e-12)
    np.testing.assert_allclose(trajectory.velocity(times[:1]), [[0.1, 0.0, -0.2]])


def test_curve_is_c1_at_breakpoints_and_constant_outside() -> None:
    points = _corner(np.pi / 3)
    trajectory = plan_wrist_trajectory(points, np.array([1.0, 1.3, 1.6]))
    eps = 1e-7
    before, after = trajectory.velocity(np.array([1.3 - eps])), trajectory.velocity(np.array([1.3 + eps]))
    np.testing.assert_allclose(before, after, atol=1e-5)
    outside = np.array([-5.0, 0.99, 1.61, 9.0])
    np.testing.assert_allclose(trajectory.position(outside), points[[0, 0, 2, 2]])
    np.testing.assert_allclose(trajectory.velocity(outside), 0.0)
    np.testing.assert_allclose(trajectory.acceleration(outside), 0.0)


def test_zero_length_stroke_is_a_hold() -> None:
    points = np.array([[0.0, 1.0, 0.3], [0.2, 1.0, 0.3], [0.2, 1.0, 0.3], [0.2, 1.2, 0.3]])
    trajectory = plan_wrist_trajectory(points, np.array([0.0, 0.3, 0.5, 0.8]))
    np.testing.assert_allclose(trajectory.velocities[1:3], 0.0)
    held = trajectory.position(np.linspace(0.3, 0.5, 11))
    np.testing.assert_allclose(held, np.repeat(points[1:2], 11, axis=0), atol=1e-12)


def test_power_law_holds_on_a_traced_ellipse() -> None:
    per_lap, laps = 32, 3
    points = ellipse_breakpoints((0.0, 1.2, 0.3), (0.1, 0.04), (0.0, 0.0, 1.0), count=per_lap * laps, sweep=2 * np.pi * laps)
    trajectory = plan_wrist_trajectory(points, start=0.0, end=1.2 * laps)
    t = np.linspace(trajectory.times[per_lap], trajectory.times[2 * per_lap], 4000)
    v, a = trajectory.velocity(t), trajectory.acceleration(t)
    speed = np.linalg.norm(v, axis=1)
    radius = speed**3 / np.linalg.norm(np.cross(v, a), axis=1)
    slope = np.polyfit(np.log(radius), np.log(speed), 1)[0]
    assert slope == pytest.approx(1.0 / 3.0, abs=0.05)


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


def test_too_fast_stroke_is_slowed_with_a_warning() -> None:
    points = np.array([[-1.0, 1.0, 0.3], [1.0, 1.0, 0.3]])
    trajectory = plan_wrist_trajectory(points, np.array([0.0, 0.05]))
    assert len(trajectory.warnings) == 1 and "slowed" in trajectory.warnings[0]
    assert trajectory.peak_speed() == pytest.approx(3.0, rel=1e-3)
    assert trajectory.end == pytest.approx(2.0 * 1.5 / 3.0, rel=1e-3)
    t = np.linspace(-0.1, 2.0, 500)
    assert np.all(np.isfinite(trajectory.position(t))) and np.all(np.isfinite(trajectory.velocity(t)))


def test_turning_angles_table() -> None:
    points = np.array([[0.0, 0, 0], [1.0, 0, 0], [2.0, 0, 0], [2.0, 1.0, 0], [2.0, 0.5, 0]])
    np.testing.assert_allclose(turning_angles(points), [0.0, np.pi / 2, np.pi])
