"""Naturalness of rendered movement: measures on wrist trajectories and on whole motions.

Every trajectory measure takes wrist positions ``(n, 3)`` in metres sampled at ``fps``
frames per second; derivatives are finite differences (``numpy.gradient``, second order
inside, so a polynomial movement of degree ≤ 2 is differentiated exactly). Motion
measures take a :class:`motor.motion.Motion` and its :class:`motor.body.avatar.Avatar`.

* :func:`speed_symmetry` — where the speed peak of a single stroke lies (0.5 for the
  bell-shaped profile of a minimum-jerk reach) and the skewness of the profile.
* :func:`power_law_exponent` — β in ``v ∝ R^β`` fitted on a curved stroke (1/3 for the
  two-thirds power law that the wrist trajectories are built on).
* :func:`jerk_ratio` — integrated squared jerk over that of the minimum-jerk straight
  movement with the same endpoints and duration (1 is the smoothest possible).
* :func:`velocity_jump` — the largest change of velocity between consecutive frames
  relative to the peak speed: a hand-over between motor programs that is not C¹ shows a
  jump far above the ``a·dt`` of smooth movement.
* :func:`joint_limit_violations`, :func:`torso_penetrations`, :func:`nan_count` — counts
  that should all be zero.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from motor import quaternion as quat
from motor.body.avatar import Avatar
from motor.body.kinematics import Pose, forward_kinematics
from motor.motion import Motion

#: Curvature-law fit: points slower than this fraction of the peak speed are dropped
#: (curvature is noise there), and so are radii above this many metres (straight parts).
MIN_SPEED_FRACTION = 0.05
MAX_RADIUS = 1.0
#: A wrist never faster than this (m/s) has no velocity jumps worth measuring.
MOVING_SPEED = 0.01
#: Joint angles beyond a limit by less than this (radians) are rounding, not violations.
LIMIT_TOLERANCE = 1e-6


@dataclass(frozen=True)
class SpeedSymmetry:
    """Shape of one stroke's speed profile: ``peak_fraction`` is the time of the speed peak
    over the duration (0.5 = symmetric); ``skewness`` the third standardized moment of the
    time distribution weighted by speed (0 = symmetric, > 0 = late tail)."""

    peak_fraction: float
    skewness: float


@dataclass(frozen=True)
class PowerLawFit:
    """``v ∝ R^exponent`` fitted by least squares on log speed against log radius of
    curvature; ``points`` kept after dropping slow or straight frames; ``r_squared`` of the fit."""

    exponent: float
    r_squared: float
    points: int


def _checked(positions: np.ndarray, fps: float, minimum: int = 3) -> np.ndarray:
    positions = np.asarray(positions, dtype=float)
    if positions.ndim != 2 or positions.shape[1] != 3:
        raise ValueError(f"wrist positions must have shape (n, 3), got {positions.shape}")
    if positions.shape[0] < minimum:
        raise ValueError(f"need at least {minimum} frames, got {positions.shape[0]}")
    if not fps > 0:
        raise ValueError(f"fps must be positive, got {fps}")
    return positions


def velocities(positions: np.ndarray, fps: float) -> np.ndarray:
    """Velocity ``(n, 3)`` in m/s by finite differences."""
    return np.gradient(_checked(positions, fps), 1.0 / fps, axis=0)


def speeds(positions: np.ndarray, fps: float) -> np.ndarray:
    """Speed ``(n,)`` in m/s."""
    return np.linalg.norm(velocities(positions, fps), axis=1)


def speed_symmetry(positions: np.ndarray, fps: float) -> SpeedSymmetry:
    """Symmetry of the speed profile of one stroke spanning the whole array (rest to rest)."""
    speed = speeds(positions, fps)
    total = float(speed.sum())
    if total <= 0.0:
        raise ValueError("the wrist does not move: a stroke's speed profile needs movement")
    times = np.arange(speed.size) / fps
    duration = times[-1]
    weights = speed / total
    mean = float(weights @ times)
    spread = float(np.sqrt(weights @ (times - mean) ** 2))
    skewness = float(weights @ ((times - mean) / spread) ** 3) if spread > 0 else 0.0
    return SpeedSymmetry(peak_fraction=float(times[np.argmax(speed)] / duration), skewness=skewness)


def power_law_exponent(positions: np.ndarray, fps: float) -> PowerLawFit:
    """Fit ``log v = β log R + c`` on a curved stroke; β should be 1/3.

    The radius of curvature is ``R = |v|³ / |v × a|``. Frames slower than
    :data:`MIN_SPEED_FRACTION` of the peak speed and radii above :data:`MAX_RADIUS` are
    dropped: there the curvature is dominated by differentiation noise.
    """
    positions = _checked(positions, fps, minimum=5)
    velocity = np.gradient(positions, 1.0 / fps, axis=0)
    acceleration = np.gradient(velocity, 1.0 / fps, axis=0)
    speed = np.linalg.norm(velocity, axis=1)
    bend = np.linalg.norm(np.cross(velocity, acceleration), axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        radius = speed**3 / bend
    keep = (speed > MIN_SPEED_FRACTION * speed.max()) & np.isfinite(radius) & (radius > 0) & (radius < MAX_RADIUS)
    if np.count_nonzero(keep) < 3:
        raise ValueError("fewer than 3 curved frames with enough speed: not a curved stroke")
    log_radius, log_speed = np.log(radius[keep]), np.log(speed[keep])
    slope, intercept = np.polyfit(log_radius, log_speed, 1)
    residual = log_speed - (slope * log_radius + intercept)
    variance = float(np.sum((log_speed - log_speed.mean()) ** 2))
    r_squared = 1.0 - float(residual @ residual) / variance if variance > 0 else 1.0
    return PowerLawFit(exponent=float(slope), r_squared=r_squared, points=int(np.count_nonzero(keep)))


def minimum_jerk(start: np.ndarray, end: np.ndarray, frames: int) -> np.ndarray:
    """The minimum-jerk straight movement ``(frames, 3)`` from ``start`` to ``end``
    (Flash & Hogan: ``s(τ) = 10τ³ − 15τ⁴ + 6τ⁵``), frames spanning the whole duration."""
    tau = np.linspace(0.0, 1.0, frames)[:, None]
    progress = tau**3 * (10.0 - 15.0 * tau + 6.0 * tau**2)
    return np.asarray(start, float) + progress * (np.asarray(end, float) - np.asarray(start, float))


def squared_jerk(positions: np.ndarray, fps: float) -> float:
    """Integrated squared jerk ``∫|d³x/dt³|² dt`` in m²/s⁵."""
    jerk = _checked(positions, fps, minimum=4)
    for _ in range(3):
        jerk = np.gradient(jerk, 1.0 / fps, axis=0)
    return float(np.sum(jerk**2) / fps)


def jerk_ratio(positions: np.ndarray, fps: float) -> float:
    """Squared jerk of the stroke over that of the minimum-jerk straight movement between
    its endpoints in the same time, differentiated the same way (≥ about 1; 1 = smoothest)."""
    positions = _checked(positions, fps, minimum=4)
    reference = squared_jerk(minimum_jerk(positions[0], positions[-1], positions.shape[0]), fps)
    if reference <= 0.0:
        raise ValueError("the stroke starts and ends at the same point: no minimum-jerk reference")
    return squared_jerk(positions, fps) / reference


def velocity_jump(positions: np.ndarray, fps: float, frames: np.ndarray | None = None) -> float:
    """Largest ``|v[i+1] − v[i]|`` over the peak speed, between every pair of consecutive
    frames or only the pairs starting at ``frames`` (e.g. hand-overs); 0 for a wrist never
    faster than :data:`MOVING_SPEED` (its jumps would be rounding over rounding).

    Velocities here are one-sided (``(x[i+1] − x[i])·fps``) so that a kink is not smeared.
    """
    positions = _checked(positions, fps)
    velocity = np.diff(positions, axis=0) * fps
    peak = float(np.linalg.norm(velocity, axis=1).max())
    if peak < MOVING_SPEED:
        return 0.0
    jumps = np.linalg.norm(np.diff(velocity, axis=0), axis=1)
    if frames is not None:
        chosen = np.asarray(frames, dtype=int) - 1
        jumps = jumps[chosen[(chosen >= 0) & (chosen < jumps.size)]]
    return float(jumps.max() / peak) if jumps.size else 0.0


def arm_angles(motion: Motion, avatar: Avatar, side: str) -> dict[str, np.ndarray]:
    """Per-frame arm angles (radians) named as in ``avatar.limits``.

    Elbow: its local rotation splits into a twist about the forearm (pronation) and a
    swing whose component about the elbow hinge (perpendicular to the upper arm and to the
    facing direction) is the flexion, 0 straight and negative when hyperextended. Wrist:
    its swing about the forearm split into flexion (about the hand's bend axis) and
    deviation (about its splay axis). Sternoclavicular: the angle of its local rotation.
    """
    _check_motion(motion, avatar)
    sc, _, elbow, wrist = avatar.arm_joints(side)
    hand = avatar.hand_frames[side]
    upper = avatar.offsets[elbow] / np.linalg.norm(avatar.offsets[elbow])
    hinge = np.cross(upper, [0.0, 0.0, 1.0])
    hinge /= np.linalg.norm(hinge)
    elbow_swing, elbow_twist = quat.swing_twist(motion.rotations[:, elbow], hand.twist_axis)
    wrist_swing, _ = quat.swing_twist(motion.rotations[:, wrist], hand.twist_axis)
    elbow_vector = quat.to_rotation_vector(elbow_swing)
    wrist_vector = quat.to_rotation_vector(wrist_swing)
    clavicle = motion.rotations[:, sc]
    return {
        f"{side}_sternoclavicular.swing": 2.0 * np.arctan2(np.linalg.norm(clavicle[:, :3], axis=1), np.abs(clavicle[:, 3])),
        f"{side}_elbow.flexion": elbow_vector @ hinge,
        f"{side}_elbow.twist": elbow_twist,
        f"{side}_wrist.flexion": wrist_vector @ hand.bend_axis,
        f"{side}_wrist.deviation": wrist_vector @ hand.splay_axis,
    }


def joint_limit_violations(motion: Motion, avatar: Avatar) -> dict[str, int]:
    """Frames outside ``avatar.limits`` per ``"joint.limit"`` (both arms), by more than
    :data:`LIMIT_TOLERANCE`; limits the avatar does not define are not checked."""
    counts: dict[str, int] = {}
    for side in ("l", "r"):
        for name, angles in arm_angles(motion, avatar, side).items():
            joint, kind = name.split(".")
            if kind not in avatar.limits.get(joint, {}):
                continue
            low, high = avatar.limit(joint, kind)
            counts[name] = int(np.count_nonzero((angles < low - LIMIT_TOLERANCE) | (angles > high + LIMIT_TOLERANCE)))
    return counts


def torso_penetrations(motion: Motion, avatar: Avatar, pose: Pose | None = None) -> dict[str, int]:
    """Frames in which each elbow and wrist lies inside the torso's elliptic cylinder.

    The torso moves with the clavicles' parent joint (the upper spine), so joint positions
    are taken into that joint's rest frame before the test. ``pose`` may be given when
    forward kinematics was already run on ``motion``.
    """
    _check_motion(motion, avatar)
    pose = pose or forward_kinematics(avatar, motion.rotations, motion.root_translation)
    torso = avatar.torso
    carrier = int(avatar.parents[avatar.joint_index("r_sternoclavicular")])
    inverse = quat.conjugate(pose.orientations[:, carrier])
    counts: dict[str, int] = {}
    for side in ("l", "r"):
        for joint in ("elbow", "wrist"):
            index = avatar.joint_index(f"{side}_{joint}")
            local = quat.rotate(inverse, pose.positions[:, index] - pose.positions[:, carrier]) + avatar.rest_positions[carrier]
            across = ((local[:, 0] - torso.center[0]) / torso.half_width) ** 2 + ((local[:, 2] - torso.center[2]) / torso.half_depth) ** 2
            inside = (across < 1.0) & (local[:, 1] > torso.bottom) & (local[:, 1] < torso.top)
            counts[f"{side}_{joint}"] = int(np.count_nonzero(inside))
    return counts


def nan_count(motion: Motion) -> int:
    """Non-finite numbers among the motion's rotations and root translation."""
    return int(np.count_nonzero(~np.isfinite(motion.rotations)) + np.count_nonzero(~np.isfinite(motion.root_translation)))


def _check_motion(motion: Motion, avatar: Avatar) -> None:
    if tuple(motion.joint_names) != tuple(avatar.joint_names):
        raise ValueError(f"motion joints do not match avatar {avatar.name!r} ({len(motion.joint_names)} vs {avatar.joint_count} joints)")
