"""The swivel track's numpy steps as they stood before they were compiled (issue 19): the
value tables (:func:`motor.arm.swivel._cost_to_go`), the walk along them
(:func:`motor.arm.swivel._walk`) and the forearm twist's and wrist's tracks along the grid
(:func:`motor.arm.swivel_track.twist_track`, :func:`motor.arm.swivel_track.wrist_track`),
the plain paths the compiled loops are held to, bit for bit, by
``test_compiled_swivel.py``. Not used by mura itself."""

from __future__ import annotations

import math

import numpy as np

from motor.arm.swivel import DISCOUNT, MAX_STEP
from motor.arm.swivel_track import TWIST_HYSTERESIS, TWIST_STEP, WRIST_STEP


def cost_to_go(costs: np.ndarray, base: np.ndarray, change: np.ndarray, horizon: int) -> np.ndarray:
    value = costs
    for _ in range(horizon):
        rows = value.shape[0] - 1
        value = costs[:rows] + DISCOUNT * _banded_minimum(value[1:], base[1 : rows + 1], change[1 : rows + 1])
    return value


def _banded_minimum(value: np.ndarray, base: np.ndarray, change: np.ndarray) -> np.ndarray:
    """``min_d change[:, d] + value[:, (i + base + d) mod K]`` over ``|d|`` ≤ :data:`MAX_STEP`."""
    count = value.shape[1]
    wrapped = _wrapped(_aligned(value, base))
    best = wrapped[:, :count] + change[:, :1]
    for k in range(1, 2 * MAX_STEP + 1):
        best = np.minimum(best, wrapped[:, k : k + count] + change[:, k : k + 1])
    return best


def walk(value: np.ndarray, base: np.ndarray, change: np.ndarray, cell: int, fresh: bool) -> np.ndarray:
    """The cells of the track: every cell's move from the banded options' ``np.argmin``,
    then the walk along them, one grid point at a time."""
    rows, count = value.shape
    wrapped = _wrapped(_aligned(value, base[:rows]))
    options = np.stack([wrapped[:, k : k + count] + change[:rows, k : k + 1] for k in range(2 * MAX_STEP + 1)], axis=1)
    moves = (base[:rows, None] + np.argmin(options, axis=1) - MAX_STEP).ravel().tolist()
    cells = [0] * rows
    begin = 1 if fresh else 0
    cells[0] = cell
    for row in range(begin, rows):
        cell += moves[row * count + cell % count]
        cells[row] = cell
    return np.array(cells)


def _aligned(value: np.ndarray, base: np.ndarray) -> np.ndarray:
    """``value (m, K)`` with row ``r`` turned so that column ``i`` holds candidate
    ``i + base[r]`` (mod K); rows that need no turn — most — are left as they are."""
    turned = np.flatnonzero(base)
    if turned.size == 0:
        return value
    count = value.shape[1]
    aligned = value.copy()
    aligned[turned] = np.take_along_axis(value[turned], (np.arange(count) + base[turned, None]) % count, axis=1)
    return aligned


def _wrapped(value: np.ndarray) -> np.ndarray:
    """``value (m, K)`` with :data:`MAX_STEP` columns of the other end on either side (the
    candidates go round the circle)."""
    return np.concatenate([value[:, -MAX_STEP:], value, value[:, :MAX_STEP]], axis=1)


def twist_track(wanted: np.ndarray, certainty: np.ndarray, previous: float | None, limits: tuple[float, float]) -> np.ndarray:
    """The twist's steps in Python floats, one grid point at a time."""
    low, high = limits
    turn = 2.0 * math.pi
    twists = []
    here = previous
    for value, sure in zip(wanted.tolist(), certainty.tolist()):
        if here is None:
            here = low if value < low else high if value > high else value
            twists.append(here)
            continue
        value += turn * round((here - value) / turn)
        other = value - turn if value > high else value + turn
        short = value - high if value > high else low - value if value < low else 0.0
        other_short = other - high if other > high else low - other if other < low else 0.0
        if short > other_short + TWIST_HYSTERESIS:
            value = other
        step = (low if value < low else high if value > high else value) - here
        here += sure * (-TWIST_STEP if step < -TWIST_STEP else TWIST_STEP if step > TWIST_STEP else step)
        twists.append(here)
    return np.array(twists)


def wrist_track(targets: np.ndarray, certainty: np.ndarray, previous: tuple[float, float] | None) -> np.ndarray:
    """The wrist's steps in Python floats, one grid point at a time."""
    values = targets.tolist()
    here = list(values[0]) if previous is None else list(previous)
    track = []
    for (flexion, deviation), sure in zip(values, certainty.tolist()):
        for i, target in enumerate((flexion, deviation)):
            step = target - here[i]
            here[i] += sure * (-WRIST_STEP if step < -WRIST_STEP else WRIST_STEP if step > WRIST_STEP else step)
        track.append(tuple(here))
    return np.array(track)


def grid_sample(rows: np.ndarray, times: np.ndarray, first: int, period: float) -> tuple[np.ndarray, np.ndarray]:
    """:meth:`motor.arm.swivel_track.SwivelGrid.sample` over grid states ``rows`` from index
    ``first`` on, as numpy's whole-array steps computed it."""
    positions = times / period
    at = np.floor(positions + 1e-9).astype(int) - first
    swivel, turn = rows[:, 1], rows[:, 2]
    points = (swivel[at - 1] + turn[at], swivel[at], swivel[at + 1] - turn[at + 1], swivel[at + 2] - turn[at + 1] - turn[at + 2])
    p0, p1, p2, p3 = points
    u = positions - (at + first)
    curve = p1 + 0.5 * u * ((p2 - p0) + u * ((2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) + u * (3.0 * (p1 - p2) + p3 - p0)))
    swivel = np.concatenate([curve[:, None], rows[at, 3:6]], axis=1)
    twist, wanted, wrist = rows[at, 6], rows[at, 7], rows[at, 8:10]
    change = (rows[at + 1, 7] - wanted + np.pi) % (2.0 * np.pi) - np.pi
    reference = np.column_stack([twist + u * (rows[at + 1, 6] - twist), wanted + u * change, wrist + u[:, None] * (rows[at + 1, 8:10] - wrist)])
    return swivel, reference
