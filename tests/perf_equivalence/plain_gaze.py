"""A gaze shift's sampling as it stood before a timeline's shifts were sampled in one pass
(issue 19): one shift at a time, each with its own numpy calls — the plain path
:func:`motor.neck.gaze.sample_shifts` is held to, bit for bit, by ``test_gaze_batch.py``.
Not used by mura itself."""

from __future__ import annotations

import numpy as np

from motor import quaternion as quat
from motor.neck.gaze import HEAD_LAG, GazeShift, head_duration, saccade_duration
from motor.trajectory.biocontrol import minimum_jerk


def sample(shift: GazeShift, times: np.ndarray) -> np.ndarray:
    t = np.asarray(times, dtype=float)
    eyes, head = shift.amplitudes
    ease = minimum_jerk()
    s_eye = ease.fraction((t - shift.time) / saccade_duration(eyes))
    s_head = ease.fraction((t - shift.time - HEAD_LAG) / head_duration(head))
    fixed = shift.lmp.target.fixed and (shift.lmp.head is None or shift.lmp.head.fixed)
    if fixed and t.size and t[0] >= shift.time + shift.duration:
        return np.broadcast_to(np.concatenate(shift._goal_at_start), (t.size, 6)).copy()
    goal, goal_head = (np.broadcast_to(v, (t.size, 3)) for v in shift._goal_at_start) if fixed else shift._goal(t)
    origin = shift.lmp.origin
    start = shift.from_point - origin
    distance = (1.0 - s_eye) * float(np.linalg.norm(start)) + s_eye * np.linalg.norm(goal - origin, axis=1)
    turn = quat.between_vectors(quat.normalize(start), quat.normalize(goal - origin))
    looked = origin + distance[:, None] * quat.rotate(quat.slerp(quat.IDENTITY, turn, s_eye), quat.normalize(start))
    swing = quat.between_vectors(shift.from_head, goal_head)
    facing = quat.rotate(quat.slerp(quat.IDENTITY, swing, s_head), shift.from_head)
    return np.concatenate([looked, facing], axis=1)


def sample_timeline(shifts: list[GazeShift], owner: np.ndarray, times: np.ndarray) -> np.ndarray:
    """Rows ``owner == k`` from shift ``k`` alone, as the neck's sampling asked them."""
    out = np.empty((times.size, 6))
    for index, shift in enumerate(shifts):
        rows = owner == index
        if np.any(rows):
            out[rows] = sample(shift, times[rows])
    return out
