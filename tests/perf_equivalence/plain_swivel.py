"""The numpy value tables of the swivel track as they stood before they were compiled
(:func:`motor.arm.swivel._cost_to_go`, issue 19): the plain path the compiled loop is held
to, bit for bit, by ``test_compiled_swivel.py``. Not used by mura itself."""

from __future__ import annotations

import numpy as np

from motor.arm.swivel import DISCOUNT, MAX_STEP, _aligned, _wrapped


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
