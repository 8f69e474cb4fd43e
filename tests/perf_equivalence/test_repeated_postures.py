"""The repeated postures found in a compiled hash pass
(:func:`motor.signing.repeats.first_of_repeats`) are ``np.unique``'s over the rows' bytes,
which the reach check used before: the same groups, each with the same first row, over
tables of postures repeated, signed zeros, NaNs of two payloads, rows differing in the
last bit of one coordinate, one row, no rows, all rows alike and a corpus's worth."""

from __future__ import annotations

import numpy as np
import pytest

from motor.signing.repeats import first_of_repeats

RNG = np.random.default_rng(31)


def _repeated(rows: int, distinct: int, width: int = 7) -> np.ndarray:
    return RNG.normal(size=(distinct, width))[RNG.integers(0, distinct, rows)]


def _last_bits() -> np.ndarray:
    rows = np.repeat(RNG.normal(size=(1, 7)), 40, axis=0)
    rows[1::2, 3] = np.nextafter(rows[1::2, 3], np.inf)
    return rows


def _zeros_and_nans() -> np.ndarray:
    quiet, payload = np.float64(np.nan), np.array([0x7FF8000000000001], dtype=np.int64).view(float)[0]
    values = np.array([0.0, -0.0, quiet, payload, 1.0])
    return values[RNG.integers(0, len(values), (300, 7))]


CASES = {
    "corpus": lambda: _repeated(60_000, 28_000),
    "few postures": lambda: _repeated(5_000, 12),
    "positions only": lambda: _repeated(2_000, 900, width=3),
    "last bit": _last_bits,
    "signed zeros and NaNs": _zeros_and_nans,
    "all alike": lambda: np.ones((50, 7)),
    "one row": lambda: np.ones((1, 7)),
    "no rows": lambda: np.zeros((0, 7)),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_the_hash_groups_rows_as_numpys_unique(case):
    rows = CASES[case]()
    first, group = first_of_repeats(rows)
    keys = np.ascontiguousarray(rows).view(np.dtype((np.void, rows.itemsize * rows.shape[1])))[:, 0]
    _, plain_first, plain_group = np.unique(keys, return_index=True, return_inverse=True)
    assert len(first) == len(plain_first)
    assert np.array_equal(first[group], plain_first[plain_group.ravel()])
    assert sorted(first.tolist()) == sorted(plain_first.tolist())
    assert np.array_equal(rows[first][group].view(np.int64), rows.view(np.int64))
