"""Quality measures on synthetic movements whose answers are known."""

import numpy as np
import pytest

from bench import quality
from motor import quaternion as quat
from motor.body.avatar import load_avatar
from motor.motion import Motion


@pytest.fixture(scope="module")
def avatar():
    return load_avatar("max")


def ellipse_with_power_law(a: float, b: float, exponent: float, fps: float, laps: float = 1.0) -> np.ndarray:
    """An ellipse traced with speed ∝ R^exponent, sampled at fps."""
    theta = np.linspace(0.0, 2.0 * np.pi * laps, 20001)
    arc = np.sqrt((a * np.sin(theta)) ** 2 + (b * np.cos(theta)) ** 2)
    radius = arc**3 / (a * b)
    speed = 0.5 * radius**exponent
    dt = np.diff(theta) * 0.5 * (arc[1:] / speed[1:] + arc[:-1] / speed[:-1])
    time = np.concatenate(([0.0], np.cumsum(dt)))
    frames = np.arange(0.0, time[-1], 1.0 / fps)
    angle = np.interp(frames, time, theta)
    return np.stack((a * np.cos(angle), 1.2 + b * np.sin(angle), np.full_like(angle, 0.3)), axis=-1)


def motion_of(avatar, rotations: np.ndarray, fps: float = 60.0) -> Motion:
    return Motion(fps, avatar.joint_names, tuple(int(p) for p in avatar.parents), np.array(avatar.offsets), rotations, np.zeros((rotations.shape[0], 3)))


def rest(avatar, frames: int) -> np.ndarray:
    rotations = np.zeros((frames, avatar.joint_count, 4))
    rotations[..., 3] = 1.0
    return rotations


@pytest.mark.parametrize("fps", [25.0, 60.0, 120.0])
@pytest.mark.parametrize("duration", [0.4, 1.0])
def test_minimum_jerk_stroke_is_symmetric_and_smoothest(fps, duration):
    stroke = quality.minimum_jerk([0.1, 1.0, 0.2], [-0.2, 1.3, 0.4], int(round(duration * fps)) + 1)
    symmetry = quality.speed_symmetry(stroke, fps)
    assert symmetry.peak_fraction == pytest.approx(0.5, abs=1.0 / (duration * fps))
    assert symmetry.skewness == pytest.approx(0.0, abs=1e-6)
    assert quality.jerk_ratio(stroke, fps) == pytest.approx(1.0, abs=1e-9)


def test_late_peak_and_detour_are_detected():
    frames = 61
    tau = np.linspace(0.0, 1.0, frames)[:, None]
    late = np.array([0.0, 1.0, 0.2]) + (tau**3) * np.array([0.3, 0.0, 0.0])  # accelerates to the end
    symmetry = quality.speed_symmetry(late, 60.0)
    assert symmetry.peak_fraction > 0.9 and symmetry.skewness < 0
    straight = quality.minimum_jerk([0.0, 1.0, 0.2], [0.3, 1.0, 0.2], frames)
    detour = straight + np.sin(np.pi * tau) ** 2 * np.array([0.0, 0.1, 0.0]) * np.sin(4 * np.pi * tau)
    assert quality.jerk_ratio(detour, 60.0) > 2.0


@pytest.mark.parametrize("exponent", [1.0 / 3.0, 0.2, 0.5])
@pytest.mark.parametrize("fps", [60.0, 120.0])
def test_power_law_exponent_of_ellipse(exponent, fps):
    path = ellipse_with_power_law(0.15, 0.06, exponent, fps)
    fit = quality.power_law_exponent(path[2:-2], fps)
    assert fit.exponent == pytest.approx(exponent, abs=0.02)
    assert fit.r_squared > 0.95


def test_power_law_refuses_a_straight_line():
    with pytest.raises(ValueError, match="curved"):
        quality.power_law_exponent(quality.minimum_jerk([0, 1, 0], [0.3, 1, 0], 61), 60.0)


def test_velocity_jump_finds_a_kink_only_where_asked():
    t = np.arange(61)[:, None] / 60.0
    smooth = np.array([0.0, 1.0, 0.2]) + np.sin(2 * np.pi * t) * np.array([0.1, 0.0, 0.0])
    kinked = smooth.copy()
    kinked[30:] = kinked[30] + (kinked[30:] - kinked[30]) * -1.0  # velocity reverses at frame 30
    assert quality.velocity_jump(smooth, 60.0) < 0.15
    assert quality.velocity_jump(kinked, 60.0) > 1.0
    assert quality.velocity_jump(kinked, 60.0, frames=np.array([10])) < 0.15
    assert quality.velocity_jump(np.zeros((10, 3)), 60.0) == 0.0


@pytest.mark.parametrize(
    "angle, violations",
    [(-0.3, 10), (0.5, 0), (2.9, 10)],  # hyperextended, within, beyond full flexion
)
def test_elbow_flexion_outside_limits_counts_as_violation(avatar, angle, violations):
    rotations = rest(avatar, 10)
    elbow = avatar.joint_index("r_elbow")
    upper = avatar.offsets[elbow] / np.linalg.norm(avatar.offsets[elbow])
    hinge = np.cross(upper, [0.0, 0.0, 1.0])
    rotations[:, elbow] = quat.from_axis_angle(hinge / np.linalg.norm(hinge), angle)
    counts = quality.joint_limit_violations(motion_of(avatar, rotations), avatar)
    assert counts["r_elbow.flexion"] == violations
    assert sum(v for k, v in counts.items() if k != "r_elbow.flexion") == 0
    assert quality.arm_angles(motion_of(avatar, rotations), avatar, "r")["r_elbow.flexion"] == pytest.approx(np.full(10, angle))


def test_wrist_inside_torso_is_a_penetration(avatar):
    rotations = rest(avatar, 4)
    shoulder = avatar.joint_index("r_shoulder")
    # swing the right arm across the body: the straight arm passes through the chest
    rotations[2:, shoulder] = quat.from_axis_angle(np.array([0.0, 0.0, 1.0]), np.pi / 2 - 0.25)
    counts = quality.torso_penetrations(motion_of(avatar, rotations), avatar)
    assert counts["l_wrist"] == counts["l_elbow"] == 0
    assert counts["r_wrist"] + counts["r_elbow"] >= 2
    assert quality.torso_penetrations(motion_of(avatar, rest(avatar, 4)), avatar) == {"l_elbow": 0, "l_wrist": 0, "r_elbow": 0, "r_wrist": 0}


def test_nan_count(avatar):
    rotations = rest(avatar, 3)
    rotations[1, 5, :2] = np.nan
    assert quality.nan_count(motion_of(avatar, rotations)) == 2


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: quality.speeds(np.zeros((5, 2)), 60.0), r"shape \(n, 3\)"),
        (lambda: quality.speeds(np.zeros((5, 3)), 0.0), "fps must be positive"),
        (lambda: quality.speed_symmetry(np.zeros((5, 3)), 60.0), "does not move"),
        (lambda: quality.jerk_ratio(np.zeros((8, 3)), 60.0), "same point"),
        (lambda: quality.squared_jerk(np.zeros((2, 3)), 60.0), "at least 4 frames"),
    ],
)
def test_bad_input_is_named(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_motion_of_another_skeleton_is_refused(avatar):
    other = Motion(60.0, ("a",), (-1,), np.zeros((1, 3)), np.tile([0.0, 0.0, 0.0, 1.0], (2, 1, 1)), np.zeros((2, 3)))
    with pytest.raises(ValueError, match="do not match avatar"):
        quality.joint_limit_violations(other, avatar)
