"""The array types compiled kernels state in their signatures, and numpy's rules for the
least and greatest of two numbers they follow, stated once.

Every loop compiled with numba (:mod:`motor.compiled` loads them) declares the one
signature it takes, so that a process loads it from the cache at import and never
compiles it in the middle of an utterance. Its inputs are read-only C-contiguous arrays
(what a broadcast or a frozen table is), its outputs writable C-contiguous ones. A loop
that replaces numpy's ``np.maximum`` or ``np.minimum`` (or ``np.clip``) of an element
uses :func:`maximum` and :func:`minimum` (:func:`clip` of both): a NaN in either number
wins, as in numpy (Python's ``max`` and ``min`` keep the first number instead).
"""

from __future__ import annotations

import numba

#: Read-only C-contiguous float64 arrays of one, two and three dimensions.
READ1, READ2, READ3 = (numba.types.Array(numba.float64, dims, "C", readonly=True) for dims in (1, 2, 3))
#: Read-only C-contiguous int64 arrays (indices, counts, kinds) and booleans (flags).
READ_INTS1, READ_INTS2 = (numba.types.Array(numba.int64, dims, "C", readonly=True) for dims in (1, 2))
READ_FLAGS1 = numba.types.Array(numba.boolean, 1, "C", readonly=True)
#: Writable C-contiguous float64 arrays of one, two and three dimensions, and int64 rows.
WRITE1, WRITE2, WRITE3 = numba.float64[::1], numba.float64[:, ::1], numba.float64[:, :, ::1]
WRITE_INTS1 = numba.int64[::1]


@numba.njit(cache=True, error_model="numpy", inline="always")
def maximum(a, b):  # noqa: ANN001, ANN201
    """``np.maximum`` of two numbers: a NaN in either wins, a tie gives the first."""
    return a if a >= b or a != a else b


@numba.njit(cache=True, error_model="numpy", inline="always")
def minimum(a, b):  # noqa: ANN001, ANN201
    """``np.minimum`` of two numbers: a NaN in either wins, a tie gives the first."""
    return a if a <= b or a != a else b


@numba.njit(cache=True, error_model="numpy", inline="always")
def clip(x, low, high):  # noqa: ANN001, ANN201
    """``np.clip`` of one number, as :func:`minimum` of :func:`maximum`: a NaN stays."""
    return minimum(maximum(x, low), high)
