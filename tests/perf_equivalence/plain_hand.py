"""The hand's joint rotations composed of numpy's operations on whole arrays, finger by
finger, as :func:`motor.hand.shape.hand_rotations` computed them before its compiled loop
(issue 19): the plain path that loop is held to, bit for bit, by ``test_compiled_hand.py``.
Not used by mura itself."""

from __future__ import annotations

import numpy as np

from motor import quaternion as quat
from motor.body.avatar import Avatar
from motor.body.conventions import LONG_FINGERS
from motor.hand.shape import _CMC_MAX, _TOWARD_THUMB, FINGER_START, thumb_angles, thumb_axes


def hand_rotations(avatar: Avatar, side: str, params: np.ndarray) -> np.ndarray:
    """Local rotations ``(n, 17, 4)`` of one hand's joints for parameters ``(n, 26)``."""
    frame = avatar.hand_frames[side]
    calibration = avatar.calibration
    rotations = np.empty((params.shape[0], 17, 4))
    rotations[:, 0:3] = _thumb(avatar, side, thumb_angles(avatar, params))
    slot = 3
    for k, finger in enumerate(LONG_FINGERS):
        columns = params[:, FINGER_START + 4 * k : FINGER_START + 4 * k + 4]
        bend, middle, end = (columns[:, (0, 2, 3)] * calibration.max_bend[k]).T
        splay = columns[:, 1] * calibration.max_splay[k]
        b_prime = np.clip(2.0 * bend / np.pi, 0.0, 1.0)
        if finger in _CMC_MAX:
            axis = quat.normalize(frame.bend_axis + 0.35 * frame.twist_axis)
            rotations[:, slot] = quat.from_axis_angle(axis, _CMC_MAX[finger] * b_prime * np.clip(np.abs(columns[:, 1]), 0.0, 1.0))
            slot += 1
        toward = _TOWARD_THUMB[k]
        spread = quat.from_axis_angle(frame.splay_axis, toward * splay * (1.0 - b_prime))
        bent = quat.from_axis_angle(frame.bend_axis, bend)
        taper = calibration.theta_flat[k] * (1.0 - b_prime) + calibration.theta_fist1[k] * b_prime
        tapered = quat.from_axis_angle(frame.splay_axis, toward * taper)
        twisted = quat.from_axis_angle(frame.twist_axis, calibration.theta_fist2[k] * b_prime)
        rotations[:, slot] = quat.multiply(quat.multiply(spread, bent), quat.multiply(tapered, twisted))
        rotations[:, slot + 1] = quat.from_axis_angle(frame.bend_axis, middle)
        rotations[:, slot + 2] = quat.from_axis_angle(frame.bend_axis, end)
        slot += 3
    return rotations


def _thumb(avatar: Avatar, side: str, angles: np.ndarray) -> np.ndarray:
    abduction, palmar, twist = thumb_axes(avatar, side)
    base = quat.multiply(
        quat.multiply(quat.from_axis_angle(abduction, angles[:, 0]), quat.from_axis_angle(palmar, angles[:, 1])),
        quat.from_axis_angle(twist, angles[:, 2]),
    )
    return np.stack((base, quat.from_axis_angle(palmar, angles[:, 3]), quat.from_axis_angle(palmar, angles[:, 4])), axis=1)
