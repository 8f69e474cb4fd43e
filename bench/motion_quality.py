"""Quality of the rendered movement: synchrony and naturalness on the example utterances.

Not a pass/fail test: ``run(quick)`` performs each utterance of ``specs/utterances`` (two
when ``quick``) with the scheduler, the motor control of the ``max`` avatar at 60 fps and
the fake speech, then measures the motion it produced (:mod:`bench.synchrony`,
:mod:`bench.quality`):

* per utterance: stroke onset and end errors (mean, max; seconds and frames);
* per dynamic stroke (between its detected onset and end): speed-profile symmetry,
  jerk ratio and, on curved strokes (median radius of curvature below
  :data:`CURVED_RADIUS`) whose radius varies (:data:`MIN_LOG_SPREAD`), the power-law
  exponent;
* the power-law exponent of a wrist trajectory planned directly through an ellipse's
  breakpoints (the law the trajectory former is built on, without IK or scheduling);
* over every motion: the largest velocity jump relative to the peak speed, joint-limit
  violations, torso penetrations, NaN.
"""

from __future__ import annotations

import statistics
from pathlib import Path

import numpy as np

from bench import quality, synchrony
from blackboard.clock import VirtualClock
from blackboard.scheduler import Scheduler
from motor.body.avatar import Avatar, load_avatar
from motor.body.kinematics import forward_kinematics
from motor.control import MotorControl
from motor.trajectory.guiding_strokes import ellipse_breakpoints
from motor.trajectory.spline import plan_wrist_trajectory
from mura.murml import load_utterance
from tts import FakeSynthesizer

UTTERANCES = Path(__file__).resolve().parents[1] / "specs" / "utterances"
QUICK_UTTERANCES = ("fig2_take_this_bar", "circle_wheel")
FPS = 60.0
#: A stroke whose median radius of curvature is below this (metres) counts as curved.
CURVED_RADIUS = 0.3
#: Least spread (standard deviation of log R) for the power law to be fitted: on a circle
#: the radius is constant and the exponent undefined.
MIN_LOG_SPREAD = 0.15


def _median(values: list[float]) -> float | None:
    return statistics.median(values) if values else None


def _strokes(positions: dict[str, np.ndarray], errors: list[synchrony.StrokeError], motion_start: float) -> list[dict]:
    """Naturalness of every dynamic stroke whose onset and end were detected."""
    measured = []
    for error in errors:
        if error.detected_onset is None or error.detected_end is None:
            continue
        first = int(round((error.detected_onset - motion_start) * FPS))
        last = int(round((error.detected_end - motion_start) * FPS))
        path = positions[error.arm][first : last + 1]
        if path.shape[0] < 5 or np.linalg.norm(path[-1] - path[0]) == 0.0:
            continue
        symmetry = quality.speed_symmetry(path, FPS)
        entry = {
            "behavior": error.behavior,
            "arm": error.arm,
            "peak_fraction": symmetry.peak_fraction,
            "skewness": symmetry.skewness,
            "jerk_ratio": quality.jerk_ratio(path, FPS),
        }
        velocity = np.gradient(path, 1.0 / FPS, axis=0)
        bend = np.linalg.norm(np.cross(velocity, np.gradient(velocity, 1.0 / FPS, axis=0)), axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            radius = np.linalg.norm(velocity, axis=1) ** 3 / bend
        moving = np.linalg.norm(velocity, axis=1) > quality.MIN_SPEED_FRACTION * np.linalg.norm(velocity, axis=1).max()
        bent = moving & np.isfinite(radius) & (radius > 0) & (radius < quality.MAX_RADIUS)
        if np.nanmedian(radius) < CURVED_RADIUS and np.count_nonzero(bent) > 2 and np.std(np.log(radius[bent])) >= MIN_LOG_SPREAD:
            entry["power_law_exponent"] = quality.power_law_exponent(path, FPS).exponent
        measured.append(entry)
    return measured


def measure_utterance(path: Path, avatar: Avatar) -> dict:
    """Perform one utterance and measure its motion."""
    performed = Scheduler(FakeSynthesizer(), MotorControl(avatar, FPS), VirtualClock()).run(load_utterance(path), name=path.stem)
    if performed.error is not None:
        raise RuntimeError(f"{path.name}: chunk {performed.failed_chunk} failed: {performed.error}")
    motion = performed.motion
    errors = synchrony.stroke_errors(motion, avatar, performed.timeline.to_json())
    pose = forward_kinematics(avatar, motion.rotations, motion.root_translation)
    positions = {arm: pose.positions[:, avatar.joint_index(f"{side}_wrist")] for arm, side in synchrony.ARM_SIDES.items()}
    return {
        "frames": motion.frame_count,
        "synchrony": synchrony.summarize(errors, FPS),
        "strokes": [
            {"behavior": e.behavior, "arm": e.arm, "dynamic": e.dynamic, "onset_error_s": e.onset_error, "end_error_s": e.end_error}
            for e in errors
        ],
        "naturalness": _strokes(positions, errors, motion.start_time),
        "velocity_jump": max(quality.velocity_jump(p, FPS) for p in positions.values()),
        "joint_limit_violations": sum(quality.joint_limit_violations(motion, avatar).values()),
        "torso_penetrations": sum(quality.torso_penetrations(motion, avatar, pose).values()),
        "nan": quality.nan_count(motion),
    }


def ellipse_exponent() -> float:
    """Power-law exponent of a wrist trajectory planned through three laps of an ellipse."""
    points = ellipse_breakpoints((0.0, 1.2, 0.3), (0.12, 0.05), (0.0, 0.0, 1.0), count=96, sweep=6.0 * np.pi)
    trajectory = plan_wrist_trajectory(points, start=0.0, end=3.6)
    times = np.arange(int(3.6 * FPS) + 1) / FPS
    inner = times[(times > 1.2) & (times < 2.4)]  # the middle lap: away from starting and stopping
    return quality.power_law_exponent(trajectory.position(inner), FPS).exponent


def run(quick: bool) -> dict:
    """Synchrony and naturalness per utterance and over all of them."""
    avatar = load_avatar("max")
    names = QUICK_UTTERANCES if quick else tuple(sorted(p.stem for p in UTTERANCES.glob("*.xml")))
    per_utterance = {name: measure_utterance(UTTERANCES / f"{name}.xml", avatar) for name in names}
    onset_errors = [abs(s["onset_error_s"]) for u in per_utterance.values() for s in u["strokes"] if s["onset_error_s"] is not None]
    end_errors = [abs(s["end_error_s"]) for u in per_utterance.values() for s in u["strokes"] if s["end_error_s"] is not None]
    strokes = [s for u in per_utterance.values() for s in u["naturalness"]]
    exponents = [s["power_law_exponent"] for s in strokes if "power_law_exponent" in s]
    return {
        "fps": FPS,
        "utterances": per_utterance,
        "stroke_onset_mean_error_frames": FPS * statistics.fmean(onset_errors) if onset_errors else None,
        "stroke_onset_max_error_frames": FPS * max(onset_errors) if onset_errors else None,
        "stroke_end_mean_error_frames": FPS * statistics.fmean(end_errors) if end_errors else None,
        "stroke_end_max_error_frames": FPS * max(end_errors) if end_errors else None,
        "power_law_exponent_ellipse": ellipse_exponent(),
        "power_law_exponent_rendered_median": _median(exponents),
        "curved_strokes": len(exponents),
        "peak_fraction_median": _median([s["peak_fraction"] for s in strokes]),
        "jerk_ratio_median": _median([s["jerk_ratio"] for s in strokes]),
        "velocity_jump_max": max(u["velocity_jump"] for u in per_utterance.values()),
        "joint_limit_violations": sum(u["joint_limit_violations"] for u in per_utterance.values()),
        "torso_penetrations": sum(u["torso_penetrations"] for u in per_utterance.values()),
        "nan": sum(u["nan"] for u in per_utterance.values()),
    }
