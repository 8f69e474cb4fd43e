"""Polynomials in the subject's and the object's arc positions, fitted by least squares.

Seed 001 models every coordinate of a verb (a keyframe location, a movement vector, a
SORA angle) as a 3rd-order polynomial of where its subject ``s`` and object ``o`` are on
the arc. The basis is every monomial ``sⁱ oʲ`` with ``i + j ≤ 3`` — ten terms: 1, o, o²,
o³, s, s·o, s·o², s², s²·o, s³ — for verbs that indicate subject and object, and the four
terms 1, o, o², o³ for verbs that indicate their object only. All outputs share the basis,
so one least-squares solve (``numpy.linalg.lstsq``) fits them together.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Highest total degree of the monomials.
DEGREE = 3


def exponents(object_only: bool, degree: int = DEGREE) -> tuple[tuple[int, int], ...]:
    """The basis as ``(i, j)`` exponent pairs of ``sⁱ oʲ``, in a fixed order."""
    if object_only:
        return tuple((0, j) for j in range(degree + 1))
    return tuple((i, j) for i in range(degree + 1) for j in range(degree + 1 - i))


def design_matrix(subject: np.ndarray, obj: np.ndarray, terms: tuple[tuple[int, int], ...]) -> np.ndarray:
    """The basis evaluated at each arrangement: ``(n, T)``."""
    s = np.asarray(subject, dtype=float)[:, None]
    o = np.asarray(obj, dtype=float)[:, None]
    i = np.array([t[0] for t in terms])[None, :]
    j = np.array([t[1] for t in terms])[None, :]
    return s**i * o**j


class TooFewExamples(ValueError):
    """Fewer arrangements than the basis has terms: the fit would not be determined."""


@dataclass(frozen=True, eq=False)
class Polynomial:
    """Outputs ``(D,)`` as polynomials of ``(s, o)``: ``coefficients`` ``(T, D)`` on ``terms``."""

    terms: tuple[tuple[int, int], ...]
    coefficients: np.ndarray

    @classmethod
    def fit(cls, subject: np.ndarray, obj: np.ndarray, targets: np.ndarray, terms: tuple[tuple[int, int], ...]) -> Polynomial:
        """Least-squares fit of ``targets`` ``(n, D)`` at arrangements ``(n,)``.

        Raises :class:`TooFewExamples` when the distinct arrangements are fewer than the
        terms (for object-only verbs, distinct object positions)."""
        basis = design_matrix(subject, obj, terms)
        rank = np.linalg.matrix_rank(basis)
        if rank < len(terms):
            raise TooFewExamples(f"{basis.shape[0]} examples span {rank} of the {len(terms)} polynomial terms")
        coefficients, *_ = np.linalg.lstsq(basis, np.asarray(targets, dtype=float), rcond=None)
        return cls(terms, coefficients)

    def __call__(self, subject: np.ndarray | float, obj: np.ndarray | float) -> np.ndarray:
        """Outputs ``(n, D)`` at arrangements (scalars give ``n = 1``)."""
        s = np.atleast_1d(np.asarray(subject, dtype=float))
        o = np.atleast_1d(np.asarray(obj, dtype=float))
        s, o = np.broadcast_arrays(s, o)
        return design_matrix(s, o, self.terms) @ self.coefficients
