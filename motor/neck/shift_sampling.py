"""A gaze timeline's shifts sampled in two compiled passes (:func:`motor.neck.gaze.sample_shifts`).

Per row, the eyes' point and the head's direction along each shift: the shortest turns
from where the shift found them toward its goals, taken as far as the minimum-jerk
fractions of the eyes and the head say, and the eyes' distance blended from where they
were to the goal's. In numpy these were some thirty calls over all rows; the loops here do
the same operations in the same order per row, so the same numbers bit for bit
(``tests/perf_equivalence/test_gaze_batch.py`` pins them to the numpy steps kept in
``tests/perf_equivalence/plain_gaze.py``). The slerps' ``arccos`` is numpy's, computed
between the two loops (numba's rounds otherwise); ``sin`` is the C library's, which rounds
as numpy's does here (:func:`motor.quaternion.about_axis`).
"""

from __future__ import annotations

import numba
import numpy as np

from motor import quaternion as quat
from motor.kernel_types import READ1, READ2, READ3, WRITE2, WRITE3


def shift_values(
    origin: np.ndarray,
    start: np.ndarray,
    from_head: np.ndarray,
    reach: np.ndarray,
    goal: np.ndarray,
    goal_head: np.ndarray,
    eyes_fraction: np.ndarray,
    head_fraction: np.ndarray,
) -> np.ndarray:
    """Gaze rows ``(n, 6)``: the point looked at (m) and the direction the head faces,
    each row from the eyes' ``origin``, the point looked at when the shift began as seen
    from there (``start``, ``reach`` its length), the head's direction then
    (``from_head``), the goals (``goal``, ``goal_head``) and how far along the eyes and
    the head are (``eyes_fraction``, ``head_fraction`` in [0, 1]); all ``(n, 3)`` or ``(n,)``."""
    count = origin.shape[0]
    turns, dots = np.empty((count, 2, 4)), np.empty((count, 2))
    _turn_rows(origin, start, from_head, goal, goal_head, turns, dots)
    theta = np.arccos(np.clip(np.abs(dots), -1.0, 1.0))
    values = np.empty((count, 6))
    _value_rows(origin, start, from_head, reach, goal, eyes_fraction, head_fraction, turns, dots, theta, values)
    return values


@numba.njit([numba.void(READ2, READ2, READ2, READ2, READ2, WRITE3, WRITE2)], cache=True, error_model="numpy")
def _turn_rows(origin, start, from_head, goal, goal_head, turns, dots):  # noqa: ANN001, ANN202
    """Per row: the eyes' whole turn and the head's whole swing, and each one's dot
    product with the identity (as :func:`motor.quaternion.slerp` reads it)."""
    for i in range(origin.shape[0]):
        wx, wy, wz = quat.normalized3(start[i, 0], start[i, 1], start[i, 2])
        gx, gy, gz = quat.normalized3(goal[i, 0] - origin[i, 0], goal[i, 1] - origin[i, 1], goal[i, 2] - origin[i, 2])
        tx, ty, tz, tw = quat.turn_between(wx, wy, wz, gx, gy, gz)
        sx, sy, sz, sw = quat.turn_between(from_head[i, 0], from_head[i, 1], from_head[i, 2], goal_head[i, 0], goal_head[i, 1], goal_head[i, 2])
        turns[i, 0, 0], turns[i, 0, 1], turns[i, 0, 2], turns[i, 0, 3] = tx, ty, tz, tw
        turns[i, 1, 0], turns[i, 1, 1], turns[i, 1, 2], turns[i, 1, 3] = sx, sy, sz, sw
        dots[i, 0], dots[i, 1] = quat.identity_dot(tx, ty, tz, tw), quat.identity_dot(sx, sy, sz, sw)


@numba.njit([numba.void(READ2, READ2, READ2, READ1, READ2, READ1, READ1, READ3, READ2, READ2, WRITE2)], cache=True, error_model="numpy")
def _value_rows(origin, start, from_head, reach, goal, eyes_fraction, head_fraction, turns, dots, theta, values):  # noqa: ANN001, ANN202
    """Per row: the turns taken as far as the fractions say (``theta``: numpy's arccos),
    the point looked at and the head's direction."""
    for i in range(origin.shape[0]):
        s = eyes_fraction[i]
        gap = quat.length3(goal[i, 0] - origin[i, 0], goal[i, 1] - origin[i, 1], goal[i, 2] - origin[i, 2])
        distance = (1.0 - s) * reach[i] + s * gap
        wx, wy, wz = quat.normalized3(start[i, 0], start[i, 1], start[i, 2])
        ex, ey, ez, ew = quat.slerped_from_identity(turns[i, 0, 0], turns[i, 0, 1], turns[i, 0, 2], turns[i, 0, 3], dots[i, 0], theta[i, 0], s)
        lx, ly, lz = quat.rotated(ex, ey, ez, ew, wx, wy, wz)
        values[i, 0], values[i, 1], values[i, 2] = origin[i, 0] + distance * lx, origin[i, 1] + distance * ly, origin[i, 2] + distance * lz
        hx, hy, hz, hw = quat.slerped_from_identity(turns[i, 1, 0], turns[i, 1, 1], turns[i, 1, 2], turns[i, 1, 3], dots[i, 1], theta[i, 1], head_fraction[i])
        values[i, 3], values[i, 4], values[i, 5] = quat.rotated(hx, hy, hz, hw, from_head[i, 0], from_head[i, 1], from_head[i, 2])


def load_kernels() -> None:
    """Run this module's compiled loops once (they load when it is imported):
    :func:`motor.compiled.warm_up`."""
    row, ahead = np.array([[0.0, 1.6, 0.1]]), np.array([[0.0, 0.0, 1.0]])
    shift_values(row, ahead, ahead, np.ones(1), row + ahead, ahead, np.full(1, 0.5), np.full(1, 0.5))
