"""Numbers as fixed-point decimal text, compiled: the characters Python's ``"%.6f"`` gives.

A BVH file is mostly numbers — 168 per frame for a 55-joint skeleton — and formatting
them one by one in Python costs about half a microsecond each, as much as the synthesis
of the frames. :func:`fixed_lines` writes rows of them in one compiled pass, with
Python's rounding: the decimal nearest the number's exact binary value, ties to even.
The exact product of the number and 10⁶ is the rounded one plus its error, found without
loss (Dekker's two-product), so halfway cases are decided as Python decides them.
Numbers of 10⁹ or more (no joint angle or centimetre is) are left to Python's own
formatting, which gives the same text. The loop states its signature
(:mod:`motor.kernel_types`): it loads from numba's cache when this module is imported.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from motor.kernel_types import READ2

#: Decimals after the point, and the format whose text :func:`fixed_lines` writes.
DECIMALS = 6
FORMAT = f"%.{DECIMALS}f"
#: Numbers at least this large, in magnitude, are formatted by Python (and NaN, ±inf).
LARGEST = 1e9
#: Bytes a number and its separator may take: a sign, ten digits (10⁹ − 10⁻⁷ rounds up to
#: 10⁹), the point, six decimals, a space.
_WIDTH = 19
_SCALE = 10.0**DECIMALS
_SPLITTER = 134217729.0  # 2²⁷ + 1: Veltkamp's split of a double into two halves


def fixed_lines(values: np.ndarray) -> str:
    """Rows ``(n, m)`` as ``n`` lines of ``m`` numbers separated by single spaces, each
    line ending in a newline: ``(" ".join([FORMAT] * m) + "\\n") * n % values``, bit
    for bit. ``-0.0`` is written as Python writes it, ``-0.000000``."""
    values = np.ascontiguousarray(values, dtype=np.float64)
    if values.ndim != 2:
        raise ValueError(f"fixed_lines: rows must be a 2-d array, got shape {values.shape}")
    if values.size == 0:
        return "\n" * values.shape[0]
    if not np.all(np.abs(values) < LARGEST):
        row = " ".join([FORMAT] * values.shape[1]) + "\n"
        return (row * values.shape[0]) % tuple(values.ravel().tolist())
    out = np.empty(values.size * _WIDTH, dtype=np.uint8)
    return out[: _write_rows(values, out)].tobytes().decode("ascii")


@numba.njit(cache=True, error_model="numpy", inline="always")
def _two_product_error(a, b):  # noqa: ANN001, ANN202
    """The error ``a · b − fl(a · b)``, exactly (Dekker's product of Veltkamp halves)."""
    product = a * b
    c = _SPLITTER * a
    a_high = c - (c - a)
    a_low = a - a_high
    c = _SPLITTER * b
    b_high = c - (c - b)
    b_low = b - b_high
    return ((a_high * b_high - product) + a_high * b_low + a_low * b_high) + a_low * b_low


@numba.njit(cache=True, error_model="numpy", inline="always")
def _rounded(magnitude):  # noqa: ANN001, ANN202
    """``magnitude`` (≥ 0, < :data:`LARGEST`) times 10⁶ rounded to the nearest integer, ties
    (of the exact product) to even."""
    scaled = magnitude * _SCALE
    whole = math.floor(scaled)
    part = scaled - whole  # exact: both are multiples of the product's last place
    if part > 0.5:
        return int(whole) + 1
    if part < 0.5:
        return int(whole)
    error = _two_product_error(magnitude, _SCALE)
    if error > 0.0:
        return int(whole) + 1
    if error < 0.0:
        return int(whole)
    return int(whole) + (int(whole) & 1)


@numba.njit([numba.int64(READ2, numba.uint8[::1])], cache=True, error_model="numpy")
def _write_rows(values, out):  # noqa: ANN001, ANN202
    """Into ``out``: the text of :func:`fixed_lines`, as ASCII bytes; returns its length."""
    at = 0
    whole_digits = np.empty(10, dtype=np.uint8)
    columns = values.shape[1]
    for i in range(values.shape[0]):
        for j in range(columns):
            value = values[i, j]
            if value < 0.0 or (value == 0.0 and math.copysign(1.0, value) < 0.0):
                out[at] = 45  # "-"
                at += 1
            number = _rounded(abs(value))
            whole, part = number // 1000000, number % 1000000
            count = 0
            while True:
                whole_digits[count] = 48 + whole % 10
                whole //= 10
                count += 1
                if whole == 0:
                    break
            for k in range(count - 1, -1, -1):
                out[at] = whole_digits[k]
                at += 1
            out[at] = 46  # "."
            for k in range(DECIMALS, 0, -1):
                out[at + k] = 48 + part % 10
                part //= 10
            at += DECIMALS + 1
            out[at] = 32 if j + 1 < columns else 10  # " " or newline
            at += 1
    return at
