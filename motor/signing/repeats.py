"""Postures a collection of signs repeats, found bit for bit in one compiled pass.

The reach check (:func:`motor.signing.reach.within_reach`) solves the arm for each
distinct wrist position and hand rotation once: a corpus repeats about half of its tens
of thousands of postures (a sign's first posture, the ends of moves). ``np.unique`` over
the rows' bytes finds them by sorting — a comparison of raw bytes per step, ~20 ms for
60,000 rows. Here the rows' bit patterns go into a hash table instead, in one pass:
rows are the same when every bit is (so 0.0 and -0.0 differ, as they do for
``np.unique``), and each group is represented by its first row, as ``np.unique``'s
``return_index`` gives it. The groups come in the order of their first rows, not sorted
(``tests/perf_equivalence/test_repeated_postures.py`` pins the grouping against
``np.unique``).
"""

from __future__ import annotations

import numba
import numpy as np

from motor.kernel_types import READ_INTS2, WRITE_INTS1

#: Odd constants of the rows' hash (64-bit, wrapping): a word's multiplier and the
#: finishing mix's (from the golden ratio's and the SplitMix64 finaliser's).
_WORD = -7046029254386353131
_MIX = -4658895280553007687


def first_of_repeats(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For float rows ``(n, k)``: the index of the first row of every group of rows equal
    bit for bit ``(g,)``, in order of those first rows, and the group of every row
    ``(n,)`` (``rows[first][group]`` is ``rows`` bit for bit)."""
    bits = np.ascontiguousarray(rows, dtype=float).view(np.int64)
    first = np.empty(len(bits), dtype=np.int64)
    group = np.empty(len(bits), dtype=np.int64)
    count = _group_rows(bits, first, group)
    return first[:count], group


@numba.njit([numba.int64(READ_INTS2, WRITE_INTS1, WRITE_INTS1)], cache=True, error_model="numpy")
def _group_rows(bits, first, group):  # noqa: ANN001, ANN202
    """Into ``group``: each row's group, numbered as first met; into ``first``: each
    group's first row; returns how many groups. An open-addressed table twice the rows'
    count (or more) holds the group of every hash slot taken."""
    rows, words = bits.shape
    size = 2
    while size < 2 * rows:
        size *= 2
    table = np.full(size, -1, dtype=np.int64)
    count = 0
    for i in range(rows):
        mixed = 0
        for w in range(words):
            mixed = (mixed ^ bits[i, w]) * _WORD
        mixed = (mixed ^ (mixed >> 31)) * _MIX
        slot = (mixed ^ (mixed >> 29)) & (size - 1)
        while True:
            taken = table[slot]
            if taken < 0:
                table[slot] = count
                first[count] = i
                group[i] = count
                count += 1
                break
            same = True
            for w in range(words):
                if bits[first[taken], w] != bits[i, w]:
                    same = False
                    break
            if same:
                group[i] = taken
                break
            slot = (slot + 1) & (size - 1)
    return count


def load_kernels() -> None:
    """Run this module's compiled loop once (it loads when the module is imported):
    :func:`motor.compiled.warm_up`."""
    first_of_repeats(np.zeros((2, 3)))
