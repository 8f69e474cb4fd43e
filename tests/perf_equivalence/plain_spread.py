"""Displacements spread along chains by numpy's pairwise passes over whole arrays, one pass
per neighbour offset, as :func:`motor.signing.spreading.spread_along_chains` computed them
before its compiled sums (issue 19): the plain path it is held to, bit for bit, by
``test_planning_fast_paths.py``. Not used by mura itself."""

from __future__ import annotations

import numpy as np

from motor.signing.spreading import SPREAD, SPREAD_CUT, SPREAD_WINDOW


def spread_chains(need: np.ndarray, arc: np.ndarray, chain: np.ndarray, anchored: np.ndarray) -> np.ndarray:
    """The displacements ``(n, 3)`` of points whose chains are all whole."""
    sigma = SPREAD / 3.0
    needy = (np.any(np.abs(need) > 1e-12, axis=1) | anchored).astype(float)
    total = need.copy()
    weight = needy.copy()
    count = len(arc)
    for offset in range(1, SPREAD_WINDOW + 1):
        if offset >= count:
            break
        same = chain[offset:] == chain[:-offset]
        kernel = np.exp(-0.5 * ((arc[offset:] - arc[:-offset]) / sigma) ** 2)
        kernel = np.where(same & (kernel > SPREAD_CUT), kernel, 0.0)
        if not np.any(kernel):
            break
        total[offset:] += kernel[:, None] * need[:-offset]
        total[:-offset] += kernel[:, None] * need[offset:]
        weight[offset:] += kernel * needy[:-offset]
        weight[:-offset] += kernel * needy[offset:]
    spread = total / ((weight**4 + 1.0) ** 0.25)[:, None]
    repeated = np.concatenate([[False], (chain[1:] == chain[:-1]) & (arc[1:] == arc[:-1])])
    return spread[np.maximum.accumulate(np.where(repeated, 0, np.arange(count)))]
