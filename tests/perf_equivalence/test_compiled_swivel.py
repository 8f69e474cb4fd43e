"""The swivel track's compiled loops are the plain ones (``plain_swivel.py``) bit for bit:
the value tables (:func:`motor.arm.swivel._cost_to_go`) over horizons, candidate counts,
zero turns of either sign (rows turned past the circle's ends) and costs with ties; the
walk along them (:func:`motor.arm.swivel._walk`) with ties and NaNs; the forearm twist's
and the wrist's tracks along the grid."""

from __future__ import annotations

import numpy as np
import pytest

from motor.arm.swivel import DISCOUNT, HORIZON, MAX_STEP, SMOOTHNESS, _cost_to_go, _walk
from motor.arm.swivel_track import twist_track, wrist_track
from tests.perf_equivalence import plain_swivel as plain

RNG = np.random.default_rng(31)


def _change(turn: np.ndarray, step: float) -> tuple[np.ndarray, np.ndarray]:
    base = np.rint(turn).astype(np.int64)
    shifts = np.arange(-MAX_STEP, MAX_STEP + 1)
    return base, SMOOTHNESS * ((base[:, None] + shifts - turn[:, None]) * step) ** 2


@pytest.mark.parametrize("horizon", [0, 1, 3, HORIZON])
@pytest.mark.parametrize("count", [36, 12])
@pytest.mark.parametrize("turning", ["still", "turning", "far"])
@pytest.mark.parametrize("ties", [False, True])
def test_value_tables_are_the_numpy_ones_bit_for_bit(horizon, count, turning, ties):
    rows = 25 + horizon
    costs = RNG.uniform(0.0, 50.0, (rows, count))
    if ties:
        costs = np.round(costs / 10.0) * 10.0
    turn = {"still": np.zeros(rows), "turning": RNG.normal(0.0, 0.8, rows), "far": RNG.normal(0.0, 2.0 * count, rows)}[turning]
    base, change = _change(turn, 2.0 * np.pi / count)
    got = _cost_to_go(costs, base, change, horizon)
    expected = plain.cost_to_go(costs, base, change, horizon)
    assert got.shape == expected.shape == (rows - horizon, count)
    assert np.array_equal(got, expected)


def test_one_step_is_the_least_reachable_next_cost():
    """Independent of the numpy version: with no change cost, one step's table is each
    cost plus the discounted least of the next row within the step range, round the circle."""
    costs = np.zeros((2, 10))
    costs[1] = np.arange(10.0)
    base, change = np.zeros(2, dtype=np.int64), np.zeros((2, 2 * MAX_STEP + 1))
    table = _cost_to_go(costs, base, change, 1)
    reachable = [min(costs[1, (i + d) % 10] for d in range(-MAX_STEP, MAX_STEP + 1)) for i in range(10)]
    assert np.allclose(table[0], DISCOUNT * np.array(reachable))


def _values(rows: int, count: int, kind: str) -> np.ndarray:
    """Value tables: random, with ties (rounded), or with NaNs (a non-finite cost)."""
    value = RNG.uniform(0.0, 30.0, (rows, count))
    if kind == "ties":
        value = np.round(value / 10.0) * 10.0
    if kind == "nan":
        value[RNG.random((rows, count)) < 0.05] = np.nan
    return value


@pytest.mark.parametrize("count", [36, 12])
@pytest.mark.parametrize("turning", ["still", "turning", "far"])
@pytest.mark.parametrize("kind", ["plain", "ties", "nan"])
@pytest.mark.parametrize("start", [None, 0, -47, 1_000_003])
def test_the_walk_is_the_numpy_argmin_walk_bit_for_bit(count, turning, kind, start):
    """The compiled walk picks each grid point's move as ``np.argmin`` over the banded
    options does (first least, first NaN), from a fresh start or an unwrapped cell far off
    either end."""
    rows = 60
    turn = {"still": np.zeros(rows), "turning": RNG.normal(0.0, 0.8, rows), "far": RNG.normal(0.0, 2.0 * count, rows)}[turning]
    base, change = _change(turn, 2.0 * np.pi / count)
    value = _values(rows, count, kind)
    fresh = start is None
    cell = int(np.argmin(value[0])) if fresh else start
    got = _walk(value, base, np.ascontiguousarray(change), cell, fresh)
    assert got.dtype == np.int64
    assert np.array_equal(got, plain.walk(value, base, change, cell, fresh))


def test_the_walk_takes_the_cheapest_reachable_candidate():
    """Independent of numpy's: with no change cost and no turn, each step goes to the
    least value within :data:`MAX_STEP` candidates of the cell before, round the circle."""
    value = np.full((3, 12), 5.0)
    value[1, 10] = 1.0  # two steps down from 0, round the circle
    value[2, 2] = 0.0  # four steps up from 10: out of reach, the least reachable is a tie
    cells = _walk(value, np.zeros(3, dtype=np.int64), np.zeros((3, 2 * MAX_STEP + 1)), 0, True)
    assert cells.tolist() == [0, -2, -5]


@pytest.mark.parametrize("previous", [None, 0.3, -2.9, 2.9, 40.0])
@pytest.mark.parametrize("certainty", ["sure", "partly", "unsure"])
@pytest.mark.parametrize("ties", [False, True])
def test_the_twist_track_is_the_python_one_bit_for_bit(previous, certainty, ties):
    """Wanted twists round the circle and beyond it, half-turn ties of the nearest whole
    turn (Python's ``round`` takes the even one), and every kind of certainty."""
    count = 80
    wanted = RNG.uniform(-3.5 * np.pi, 3.5 * np.pi, count)
    if ties:
        wanted[::3] = (0.0 if previous is None else previous) + np.pi * RNG.choice([-3.0, -1.0, 1.0, 3.0], wanted[::3].size)
    sure = {"sure": np.ones(count), "partly": RNG.uniform(0.0, 1.0, count), "unsure": np.zeros(count)}[certainty]
    limits = (-1.6, 2.4)
    got = twist_track(wanted, sure, previous, limits)
    assert np.array_equal(got, plain.twist_track(wanted, sure, previous, limits))


@pytest.mark.parametrize("previous", [None, (0.2, -0.1), (3.0, -3.0)])
@pytest.mark.parametrize("certainty", ["sure", "partly", "unsure"])
def test_the_wrist_track_is_the_python_one_bit_for_bit(previous, certainty):
    count = 80
    targets = RNG.uniform(-1.5, 1.5, (count, 2))
    sure = {"sure": np.ones(count), "partly": RNG.uniform(0.0, 1.0, count), "unsure": np.zeros(count)}[certainty]
    got = wrist_track(targets, sure, previous)
    assert np.array_equal(got, plain.wrist_track(targets, sure, previous))


@pytest.mark.parametrize("fps", [25.0, 60.0, 240.0])
@pytest.mark.parametrize("kind", ["random", "wanted twist across ±π", "frame times on grid points", "one frame"])
def test_the_grid_samples_are_the_numpy_ones_bit_for_bit(fps, kind):
    """:meth:`SwivelGrid.sample` (a compiled loop) against numpy's whole-array steps, over
    grid states with swivels unwrapped over several turns and turning zeros."""
    from motor.arm.swivel_track import _COLUMNS, SWIVEL_PERIOD, SwivelGrid
    from motor.body.avatar import load_avatar

    rng = np.random.default_rng(int(fps) + len(kind))
    first, count = 7, 40
    rows = rng.normal(size=(count, len(_COLUMNS)))
    rows[:, 1] *= 8.0
    if kind == "wanted twist across ±π":
        rows[:, 7] = np.where(np.arange(count) % 2, np.pi - 1e-3, -np.pi + 1e-3)
    grid = SwivelGrid(load_avatar("max"))
    grid.first = first
    grid._arms["right"].rows = rows
    start, stop = (first + 1) * SWIVEL_PERIOD, (first + count - 3) * SWIVEL_PERIOD
    times = np.arange(np.ceil(start * fps), np.floor(stop * fps)) / fps
    if kind == "frame times on grid points":
        times = np.arange(first + 1, first + count - 2) * SWIVEL_PERIOD
    elif kind == "one frame":
        times = times[5:6]
    span = (int(np.floor(times[0] / SWIVEL_PERIOD + 1e-9)) - 1, int(np.floor(times[-1] / SWIVEL_PERIOD + 1e-9)) + 2)
    got = grid.sample("right", times, *span)
    expected = plain.grid_sample(rows[span[0] - first : span[1] - first + 1], times, span[0], SWIVEL_PERIOD)
    for a, b in zip(got, expected):
        np.testing.assert_array_equal(a, b)
