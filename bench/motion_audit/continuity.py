"""Discontinuities a viewer sees first: elbow pops, wrist speed steps, joints that turn too far.

All three look at consecutive frames (one-sided differences, so a jump is not smeared
over two frames):

* **Elbow pop** — between frames ``i`` and ``i+1`` the elbow moves faster than
  :data:`POP_SPEED` relative to the shoulder *and* more than :data:`POP_RATIO` times as
  fast as the wrist relative to the shoulder: the arm's swivel flips while the hand
  stays. Reported at frame ``i+1``.
* **Wrist speed step** — the wrist's velocity vector (world frame, ``(x[i+1] − x[i])·fps``)
  changes by more than :data:`STEP` between consecutive frame pairs, i.e.
  ``|x[i+2] − 2x[i+1] + x[i]|·fps > STEP + STEP_NOISE_FLOOR``. At 60 fps smooth motion
  only exceeds it above 30 m/s² (far beyond human gesture); a velocity discontinuity
  exceeds it whatever the rate. The noise floor :data:`STEP_NOISE_FLOOR` covers the
  rounding of the BVH text (6 decimals of degrees and centimetres put each wrist
  position within about 1e-7 m, i.e. at most 1e-4 m/s of velocity change at 60 fps; the
  floor is ten times that). Reported at the middle frame ``i+1``.
* **Joint rotation per frame** — for every joint the angle of ``q_t⁻¹ q_{t+1}`` (its local
  rotation from one frame to the next), in degrees; the target is at most
  :data:`TURN_LIMIT` at 60 fps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bench.motion_audit.findings import EventCount, Worst, count_events
from bench.motion_audit.kinematics import Kinematics

POP_SPEED = 3.0
POP_RATIO = 2.0
STEP = 0.5
STEP_NOISE_FLOOR = 1e-3
TURN_LIMIT = 25.0


def _track(kinematics: Kinematics, name: str) -> np.ndarray:
    return kinematics.positions[:, kinematics.index(name)]


def elbow_pops(kinematics: Kinematics, side: str, start: float = 0.0) -> EventCount:
    """Elbow pops of one arm (``side`` ``"l"``/``"r"``); worst value the elbow's speed, m/s."""
    shoulder = _track(kinematics, f"{side}_shoulder")
    elbow = np.diff(_track(kinematics, f"{side}_elbow") - shoulder, axis=0) * kinematics.fps
    wrist = np.diff(_track(kinematics, f"{side}_wrist") - shoulder, axis=0) * kinematics.fps
    elbow_speed, wrist_speed = np.linalg.norm(elbow, axis=1), np.linalg.norm(wrist, axis=1)
    flags = (elbow_speed > POP_SPEED) & (elbow_speed > POP_RATIO * wrist_speed)
    if not flags.any():
        return EventCount(0, 0, None)
    worst = int(np.argmax(np.where(flags, elbow_speed, -np.inf)))
    what = f"{side}_elbow ({elbow_speed[worst]:.2f} m/s, wrist {wrist_speed[worst]:.2f} m/s, {100 * elbow_speed[worst] / kinematics.fps:.1f} cm in a frame)"
    return EventCount(int(flags.sum()), count_events(flags), Worst(float(elbow_speed[worst]), start + (worst + 1) / kinematics.fps, what))


def wrist_steps(kinematics: Kinematics, side: str, start: float = 0.0) -> EventCount:
    """Wrist speed steps of one arm; worst value the velocity change, m/s."""
    wrist = _track(kinematics, f"{side}_wrist")
    if wrist.shape[0] < 3:
        return EventCount(0, 0, None)
    change = np.linalg.norm(np.diff(wrist, n=2, axis=0), axis=1) * kinematics.fps
    flags = change > STEP + STEP_NOISE_FLOOR
    if not flags.any():
        return EventCount(0, 0, None)
    worst = int(np.argmax(change))
    what = f"{side}_wrist (velocity changes by {change[worst]:.2f} m/s in one frame)"
    return EventCount(int(flags.sum()), count_events(flags), Worst(float(change[worst]), start + (worst + 1) / kinematics.fps, what))


@dataclass(frozen=True)
class JointTurns:
    """The largest per-frame local rotation (degrees) and where; ``frames_over`` the
    frame transitions in which some joint turns more than :data:`TURN_LIMIT`;
    ``joints_over`` each such joint's largest turn."""

    largest: Worst | None
    frames_over: int
    joints_over: dict[str, float]

    def as_json(self) -> dict:
        return {
            "largest": self.largest.as_json() if self.largest else None,
            "frames_over": self.frames_over,
            "joints_over": {name: round(value, 2) for name, value in self.joints_over.items()},
        }


def turn_angles(local: np.ndarray) -> np.ndarray:
    """Angles ``(frames−1, joints)`` in degrees of ``q_t⁻¹ q_{t+1}`` for local rotations
    ``(frames, joints, 4)`` (scalar-last quaternions)."""
    a, b = local[:-1], local[1:]
    # The scalar and vector parts of conj(a)·b; the angle is 2·atan2(|vector|, |scalar|).
    scalar = np.sum(a * b, axis=-1)
    vector = a[..., 3:4] * b[..., :3] - b[..., 3:4] * a[..., :3] - np.cross(a[..., :3], b[..., :3])
    return np.degrees(2.0 * np.arctan2(np.linalg.norm(vector, axis=-1), np.abs(scalar)))


def joint_turns(kinematics: Kinematics, start: float = 0.0) -> JointTurns:
    """The largest rotation of any joint between two consecutive frames."""
    if kinematics.frame_count < 2:
        return JointTurns(None, 0, {})
    angles = turn_angles(kinematics.local)
    frame, joint = np.unravel_index(int(np.argmax(angles)), angles.shape)
    largest = Worst(float(angles[frame, joint]), start + (frame + 1) / kinematics.fps, kinematics.names[joint])
    over = angles > TURN_LIMIT
    joints_over = {kinematics.names[j]: float(angles[:, j].max()) for j in np.flatnonzero(over.any(axis=0))}
    return JointTurns(largest, int(np.count_nonzero(over.any(axis=1))), joints_over)
