"""The compiled value tables of the swivel track (:func:`motor.arm.swivel._cost_to_go`)
are the numpy ones (``plain_swivel.py``) bit for bit: over horizons, candidate counts,
zero turns of either sign (rows turned past the circle's ends) and costs with ties."""

from __future__ import annotations

import numpy as np
import pytest

from motor.arm.swivel import DISCOUNT, HORIZON, MAX_STEP, SMOOTHNESS, _cost_to_go
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
