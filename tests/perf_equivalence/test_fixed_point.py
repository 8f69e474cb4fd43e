"""The compiled fixed-point text (:func:`agent.export.fixed_point.fixed_lines`) is the
text of Python's ``%`` formatting, character for character: numbers of every scale a BVH
file holds and beyond, exact halfway cases (binary fractions whose seventh decimal is a
5 and nothing after it, which round to even), numbers just off them, negative numbers
that round to zero, ``-0.0``, and what is left to Python (10⁹ and more, NaN)."""

from __future__ import annotations

import numpy as np
import pytest

from agent.export.fixed_point import FORMAT, _write_rows, fixed_lines

RNG = np.random.default_rng(6)


def python_lines(values: np.ndarray) -> str:
    row = " ".join([FORMAT] * values.shape[1]) + "\n"
    return (row * values.shape[0]) % tuple(values.ravel().tolist())


def halfway(denominator: int, count: int) -> np.ndarray:
    """Binary fractions ``k / denominator`` (odd ``k``) about zero: exact ties at six decimals
    where ``denominator`` is 2⁷ (their seventh decimal is the last, a 5)."""
    return np.arange(-count, count, dtype=float).reshape(-1, 8) / denominator


CASES = {
    **{f"normal, scale {scale:g}": RNG.normal(0.0, scale, (64, 9)) for scale in (1e-9, 1e-7, 1e-6, 1e-3, 1.0, 180.0, 1e4, 1e8)},
    "degrees in range": RNG.uniform(-180.0, 180.0, (128, 12)),
    "ties at 1/128": halfway(128, 4096),
    "ties at 1/2^20": halfway(2**20, 2048),
    "next to ties": np.nextafter(halfway(128, 512), np.inf),
    "before ties": np.nextafter(halfway(128, 512), -np.inf),
    "decimal halves": np.array([[5e-7, -5e-7, 1.5e-6, 2.5e-6, 1.0000005, 0.1234565, -0.1234565, 999999.9999995]]),
    "zeros and tiny": np.array([[0.0, -0.0, 1e-300, -1e-300, 4.9999999e-7, -4.9999999e-7, 5e-324, -5e-324]]),
    "largest compiled": np.array([[999999999.999999, -999999999.999999, 999999999.9999995]]),
    "left to python": np.array([[1e9, -3.5, 1e20], [2.0, np.nan, np.inf]]),
    "one column": RNG.normal(0.0, 50.0, (33, 1)),
    "no columns": np.zeros((3, 0)),
    "no rows": np.zeros((0, 5)),
}


@pytest.mark.parametrize("values", CASES.values(), ids=CASES.keys())
def test_fixed_lines_are_pythons_text(values):
    assert fixed_lines(values) == python_lines(values)


def test_rows_must_be_two_dimensional():
    with pytest.raises(ValueError, match="2-d"):
        fixed_lines(np.zeros(4))


def test_the_loop_is_compiled_once_whatever_it_is_given():
    """Read-only, strided and integer rows take the one stated signature (no compilation
    in the middle of a render)."""
    frozen = np.broadcast_to(np.array([1.5, -2.25, 3.0]), (4, 3))
    strided = RNG.normal(0.0, 90.0, (10, 6))[::3, ::2]
    integers = np.arange(12).reshape(3, 4)
    for values in (frozen, strided, integers):
        assert fixed_lines(values) == python_lines(np.asarray(values, dtype=float))
    assert len(_write_rows.signatures) == 1
