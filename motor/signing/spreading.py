"""Displacements shared smoothly along chains of wrist points (seed 000, section 4.4).

When sign planning moves wrist positions within reach or out of the body
(:func:`motor.signing.reach.clear_paths`), a path whose points each stepped aside on their
own would zigzag. What each point needs is instead spread over the points of its chain (a
hand's consecutive paths) within :data:`SPREAD` metres of arc, with a Gaussian weight
(:func:`spread_along_chains`). A collection of signs has tens of thousands of such points:
the pairs near enough to count are found in a compiled pass, their Gaussian weights
computed in one numpy pass (numba's ``exp`` may differ from numpy's in the last bit), and
the weighted sums added in a compiled loop in the order of the pairwise numpy passes it
replaced (one offset at a time, from the point before, then from the point after), so
the displacements are the same bit for bit (``tests/perf_equivalence/plain_spread.py``).
Arcs are metres along each chain, never decreasing within it.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from motor.kernel_types import READ1, READ2, READ_INTS1, WRITE1, WRITE2, WRITE_INTS1

#: Arc length (m) over which a point's displacement out of the body or into reach is
#: shared with its neighbours (wide enough that a circle or a short line needing to move
#: moves nearly whole: at 8 cm circles came out dented, and the audit's 200 sampled
#: signs had 7 wrist speed steps at such dents; at 24 cm, 1), the most neighbours on
#: either side that one point's displacement reaches, and the Gaussian weight below which
#: it reaches no farther.
SPREAD = 0.24
SPREAD_WINDOW = 48
SPREAD_CUT = 1e-4
#: The Gaussian's σ (m), and the arc between two points beyond which their weight is
#: surely below :data:`SPREAD_CUT` (1 % beyond where it equals it: the pairs nearer are
#: weighed, and the cut applied to the weights).
_SIGMA = SPREAD / 3.0
_REACH = 1.01 * _SIGMA * math.sqrt(-2.0 * math.log(SPREAD_CUT))
#: A need smaller than this (m, in every coordinate) makes a point count as not needy.
_NEEDY = 1e-12


def spread_along_chains(need: np.ndarray, arc: np.ndarray, chain: np.ndarray, anchored: np.ndarray) -> np.ndarray:
    """Displacements ``(n, 3)`` that vary smoothly along each chain: every point's
    ``need (n, 3)`` spread over the points of its chain (``chain (n,)``, each chain's
    points in a row) within :data:`SPREAD` metres of ``arc (n,)`` with a Gaussian weight
    (σ = SPREAD / 3), summed and divided by a smooth maximum of 1 and the weight w of the
    needy points around, (w⁴ + 1)^¼ (a plain maximum has a kink where w crosses 1, which
    bends a cleared line into a hook) — a lone needy point moves by what it needs and its
    neighbours by less and less, a stretch of points needing the same moves by it.
    ``anchored`` points ``(n,)`` stay: they count as needing no displacement, so the
    displacement fades toward them.

    Only the chains with a point that needs something (or an anchored one) are computed:
    every other point's displacement is 0, and a chain's sums read only its own points."""
    involved = np.isin(chain, chain[any_coordinate(need != 0.0) | anchored])
    if involved.all():
        return _spread_chains(need, arc, chain, anchored)
    spread = np.zeros_like(need)
    if involved.any():
        spread[involved] = _spread_chains(need[involved], arc[involved], chain[involved], anchored[involved])
    return spread


def any_coordinate(flags: np.ndarray) -> np.ndarray:
    """Which rows of ``flags (n, 3)`` hold a True (``np.any(flags, axis=1)``): the three
    columns or-ed, which costs a fifteenth of numpy's reduction over rows of three."""
    return flags[:, 0] | flags[:, 1] | flags[:, 2]


def _spread_chains(need: np.ndarray, arc: np.ndarray, chain: np.ndarray, anchored: np.ndarray) -> np.ndarray:
    """:func:`spread_along_chains` of points whose chains are all whole."""
    arc = np.ascontiguousarray(arc, dtype=float)
    chain = np.ascontiguousarray(chain, dtype=np.int64)
    needy = (any_coordinate(np.abs(need) > _NEEDY) | anchored).astype(float)
    offsets = np.zeros(SPREAD_WINDOW + 1, dtype=np.int64)
    lower = np.empty(len(arc) * min(SPREAD_WINDOW, max(len(arc) - 1, 0)), dtype=np.int64)
    lower = lower[: _near_pairs(arc, chain, _REACH, offsets, lower)]
    upper = lower + np.repeat(np.arange(1, SPREAD_WINDOW + 1), np.diff(offsets))
    weight = np.exp(-0.5 * ((arc[upper] - arc[lower]) / _SIGMA) ** 2)
    weight = np.where(weight > SPREAD_CUT, weight, 0.0)
    total, sums = np.array(need, dtype=float), needy.copy()
    _add_weighted(weight, lower, offsets, np.ascontiguousarray(need, dtype=float), needy, total, sums)
    spread = total / ((sums**4 + 1.0) ** 0.25)[:, None]
    # a point repeated at the same arc (where one move ends and the next starts) moves as
    # its first copy, bit for bit (the sums above add its neighbours in another order)
    repeated = np.concatenate([[False], (chain[1:] == chain[:-1]) & (arc[1:] == arc[:-1])])
    return spread[np.maximum.accumulate(np.where(repeated, 0, np.arange(len(arc))))]


@numba.njit([numba.int64(READ1, READ_INTS1, numba.float64, WRITE_INTS1, WRITE_INTS1)], cache=True, error_model="numpy")
def _near_pairs(arc, chain, reach, offsets, lower):  # noqa: ANN001, ANN202
    """Into ``lower``: the first point of every pair of points ``offset`` apart
    (1 … :data:`SPREAD_WINDOW`) in one chain and less than ``reach`` metres of arc apart,
    offset by offset (``offsets[o]``: where offset ``o + 1``'s pairs start), each offset's
    in order; returns how many. Where one offset has no such pair, no farther one has (the
    arc never decreases along a chain): the pairs end there."""
    found = 0
    for offset in range(1, SPREAD_WINDOW + 1):
        offsets[offset - 1] = found
        for i in range(max(arc.size - offset, 0)):
            if chain[i + offset] == chain[i] and arc[i + offset] - arc[i] < reach:
                lower[found] = i
                found += 1
        if found == offsets[offset - 1]:
            break
    offsets[offset:] = found
    return found


@numba.njit([numba.void(READ1, READ_INTS1, READ_INTS1, READ2, READ1, WRITE2, WRITE1)], cache=True, error_model="numpy")
def _add_weighted(weight, lower, offsets, need, needy, total, sums):  # noqa: ANN001, ANN202
    """Into ``total (n, 3)`` and ``sums (n,)``: for every pair of points ``o`` apart, its
    ``weight`` (0 for the pairs not listed) times the need, and the neediness, of the other
    point — as the pairwise numpy passes added them, offset by offset, every point's from
    the point ``o`` before it, then from the point ``o`` after it, up to the first offset
    with no weight above 0 (zeros included: they decide the sign of a zero sum). One pass
    per offset adds all four: a point gets its sum from before at the pair ending on it,
    which comes before the pair starting on it."""
    n = needy.size
    for o in range(1, offsets.size):
        first, end = offsets[o - 1], offsets[o]
        if o >= n or not np.any(weight[first:end] > 0.0):
            return
        p = first
        for i in range(n - o):
            k = 0.0
            if p < end and lower[p] == i:
                k = weight[p]
                p += 1
            for a in range(3):
                total[i + o, a] += k * need[i, a]
            for a in range(3):
                total[i, a] += k * need[i + o, a]
            sums[i + o] += k * needy[i]
            sums[i] += k * needy[i + o]


def load_kernels() -> None:
    """Run this module's compiled loops once (they load when it is imported):
    :func:`motor.compiled.warm_up`."""
    spread_along_chains(np.array([[0.01, 0.0, 0.0], [0.0, 0.0, 0.0]]), np.array([0.0, 0.01]), np.zeros(2, dtype=np.int64), np.zeros(2, dtype=bool))
