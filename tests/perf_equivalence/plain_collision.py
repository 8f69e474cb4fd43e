"""The numpy steps of :func:`motor.body.collision.kept_out_of_torso` as they stood before
they were compiled (issue 19): the plain path the compiled loops are held to, bit for bit,
by ``test_compiled_torso.py``. Not used by mura itself."""

from __future__ import annotations

import numpy as np

from motor.body.avatar import Avatar
from motor.body.collision import _LANDED, _TINY, RAY_DEPTH, SOFT_BAND, TORSO_MARGIN, _eased, _fade


def kept_out_of_torso(avatar: Avatar, points: np.ndarray, margin: float = TORSO_MARGIN) -> np.ndarray:
    torso = avatar.torso
    a, b = torso.half_width + margin, torso.half_depth + margin
    u = (points[:, 0] - torso.center[0]) / a
    w = (points[:, 2] - torso.center[2]) / b + RAY_DEPTH
    square = u * u + w * w
    disc = (RAY_DEPTH * w) ** 2 - square * (RAY_DEPTH**2 - 1.0)
    exit_ = (RAY_DEPTH * w + np.sqrt(np.maximum(disc, 0.0))) / np.maximum(square, _TINY)
    length = np.sqrt((u * a) ** 2 + (w * b) ** 2)
    gap = np.where((disc > 0.0) & (w > 0.0), (1.0 - exit_) * length, np.inf)
    fade = _fade(torso.bottom - points[:, 1]) * _fade(points[:, 1] - torso.top)
    near = np.minimum(gap, SOFT_BAND)
    eased = np.maximum(_eased(near, SOFT_BAND), _LANDED)
    moved = (eased > near) & (fade > 0.0)
    if not np.any(moved):
        return points
    beyond = fade * eased + (1.0 - fade) * near
    out = np.array(points, dtype=float)
    out[:, 0] = np.where(moved, torso.center[0] + (u * exit_ * a) + beyond * u * a / np.maximum(length, _TINY), out[:, 0])
    out[:, 2] = np.where(moved, torso.center[2] + (w * exit_ - RAY_DEPTH) * b + beyond * w * b / np.maximum(length, _TINY), out[:, 2])
    return out
