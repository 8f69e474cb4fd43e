"""Where joined sign tracks are at given times, in one compiled loop.

:meth:`motor.signing.joined_tracks.JoinedTracks.sample` finds each sample's move by its
time, the fraction of the move's way by the move's manner table, the segment of the
move's values that fraction falls in and the fraction of the segment: as numpy passes some
twenty operations over the samples, for a few thousand samples a call. Here it is one loop
with numpy's operations in numpy's order (``np.clip`` and ``np.maximum`` keep a NaN, a
search puts a NaN after every number), so every number is the one the numpy passes gave
(``tests/perf_equivalence/test_track_batch.py`` holds the samples to the plain join's).
"""

from __future__ import annotations

import numba
import numpy as np

from motor.kernel_types import READ1, READ2, READ_INTS1, WRITE1, WRITE_INTS1, clip


def segments(
    owner: np.ndarray, times: np.ndarray, move_base: np.ndarray, value_base: np.ndarray, starts: np.ndarray, ends: np.ndarray,
    manners: np.ndarray, tables: np.ndarray, keys: np.ndarray, first: np.ndarray, last: np.ndarray, negligible: float,
) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """For each sample of track ``owner[i]`` at ``times[i]`` seconds: the row of the values
    its segment starts at (−1 before the track's first move) and the fraction of the
    segment ``(n,)``. The tracks' arrays are :class:`motor.signing.joined_tracks.JoinedTracks`'
    (``tables``: :func:`motor.signing.lmp.manner_tables`; ``negligible``: the width between
    keys below which a segment counts as none)."""
    if np.isnan(times).any():
        raise ValueError("sign tracks are sampled at times, not NaN")
    index, fraction = np.empty(owner.size, dtype=np.int64), np.empty(owner.size)
    ints = (np.ascontiguousarray(array, dtype=np.int64) for array in (move_base, value_base, manners, first, last))
    move_base, value_base, manners, first, last = ints
    _segment_rows(
        np.ascontiguousarray(owner, dtype=np.int64), np.ascontiguousarray(times, dtype=float), move_base, value_base,
        np.ascontiguousarray(starts, dtype=float), np.ascontiguousarray(ends, dtype=float), manners, tables, keys, first, last,
        negligible, index, fraction,
    )  # fmt: skip
    return index, fraction


@numba.njit(cache=True, error_model="numpy", inline="always")
def _after(sorted_, lo, hi, value):  # noqa: ANN001, ANN202
    """``np.searchsorted(sorted_[lo:hi], value, side="right") + lo``: the first index whose
    entry is above ``value`` (a NaN ``value`` above every entry)."""
    while lo < hi:
        middle = (lo + hi) >> 1
        if value < sorted_[middle]:
            hi = middle
        else:
            lo = middle + 1
    return lo


@numba.njit(
    [numba.void(READ_INTS1, READ1, READ_INTS1, READ_INTS1, READ1, READ1, READ_INTS1, READ2, READ1, READ_INTS1, READ_INTS1, numba.float64, WRITE_INTS1, WRITE1)],
    cache=True,
    error_model="numpy",
)
def _segment_rows(owner, times, move_base, value_base, starts, ends, manners, tables, keys, first, last, negligible, index, fraction):  # noqa: ANN001, ANN202
    """Into ``index`` and ``fraction``: :func:`segments` sample by sample."""
    span = tables.shape[1] - 1
    for i in range(owner.size):
        track, t = owner[i], times[i]
        found = _after(starts, move_base[track], move_base[track + 1], t) - 1
        if found < move_base[track]:
            index[i] = -1
            fraction[i] = 0.0
            continue
        move = found - move_base[track]
        start = starts[found]
        u = clip((t - start) / (ends[found] - start), 0.0, 1.0)
        position = u * span
        low = min(int(position), span - 1)
        weight = position - low
        row = manners[found]
        wanted = 2.0 * move + ((1.0 - weight) * tables[row, low] + weight * tables[row, low + 1])
        at = _after(keys, value_base[track], value_base[track + 1], wanted) - 1
        at = min(max(at, first[found]), last[found] - 1)
        width = keys[at + 1] - keys[at]
        index[i] = at
        fraction[i] = clip((wanted - keys[at]) / (width if width > negligible else 1.0), 0.0, 1.0)


def load_kernels() -> None:
    """Run this module's compiled loop once (it loads when the module is imported):
    :func:`motor.compiled.warm_up`."""
    ints = np.array([0, 1])
    segments(np.zeros(1, dtype=np.int64), np.ones(1), ints, np.array([0, 2]), np.zeros(1), np.ones(1), np.zeros(1, dtype=np.int64), np.ones((1, 3)), np.array([0.0, 1.0]), np.zeros(1, dtype=np.int64), np.ones(1, dtype=np.int64), 1e-12)
