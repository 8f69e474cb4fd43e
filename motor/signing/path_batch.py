"""Many wrist paths traced at once: the vectorized twins of :func:`motor.signing.lmp.smooth_pieces`
and :func:`motor.signing.lmp.law_fractions`.

A sequence of signs traces thousands of short wrist paths (every move, every transition).
One at a time, each costs a scipy spline and a few dozen small numpy calls, and the calls'
overhead is most of the synthesis time. Here the paths traced through their points are
grouped by their number of points and each group is traced in one pass over a ``(paths,
points, 3)`` array by the interpolating spline, a batched tridiagonal solve (the same
not-a-knot conditions and cubic Hermite pieces scipy's ``CubicSpline`` builds); the paths
traced within their hulls are laid end to end and traced in compiled loops over all their
points, the B-spline by its basis at the fixed parameters of a piece of each size; the law
time of all the paths of three or more points in compiled passes too
(:class:`motor.signing.law_time.DensePaths`).

The results equal the one-path functions within rounding (a few ulps: the spline's linear
solve orders its operations differently from LAPACK's); repeated points are dropped as
the one-path function drops them (paths traced through their points go through it when
they have any). ``tests/perf_equivalence/test_path_batch.py`` pins the equality.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Sequence
from functools import cache
from itertools import pairwise

import numba
import numpy as np
from scipy.interpolate import BSpline

from motor.kernel_types import READ1, READ2, READ_INTS1, READ_INTS2, WRITE1, WRITE2, WRITE_INTS1
from motor.signing.law_time import DensePaths, pairwise_sum
from motor.signing.lmp import (
    PATH_DENSITY,
    REVERSAL_ANGLE,
    Move,
    TracedChain,
    law_fractions,
    polyline_length,
    smooth_pieces,
    stopping_length,
    stopping_times,
)
from motor.trajectory.spline import DEGENERATE_CHORD, HOLD_LENGTH


def stopping_lengths(paths: Sequence[np.ndarray]) -> list[float]:
    """:func:`motor.signing.lmp.stopping_length` (m) of every path ``(m, 3)``, each distinct
    path's pieces traced at once (:func:`traced_within`)."""
    distinct, twins = distinct_paths([np.asarray(path, dtype=float) for path in paths])
    pieces, bounds = traced_within(distinct)
    return stopping_of(pieces.lengths(), bounds)[twins].tolist()


def stopping_of(lengths: np.ndarray, bounds: np.ndarray) -> np.ndarray:
    """The stopping length ``(Σ √lengthᵢ)²`` (m) of each path of pieces ``lengths`` (m),
    path ``i``'s at ``bounds[i]:bounds[i + 1]``, with
    :func:`motor.signing.lmp.stopping_length`'s arithmetic: numpy's pairwise sum, then
    ``pow`` (numpy's scalar ``**``), not a product."""
    roots = np.empty(bounds.size - 1)
    _root_sums(np.ascontiguousarray(lengths, dtype=float), np.ascontiguousarray(bounds, dtype=np.int64), roots)
    return np.float_power(roots, 2.0)


@numba.njit([numba.void(READ1, READ_INTS1, WRITE1)], cache=True, error_model="numpy")
def _root_sums(lengths, bounds, out):  # noqa: ANN001, ANN202
    """Per path of pieces ``bounds[i]:bounds[i + 1]``: the sum of the square roots of their
    lengths, in numpy's pairwise order."""
    roots = np.sqrt(lengths)
    for path in range(bounds.size - 1):
        out[path] = pairwise_sum(roots, bounds[path], bounds[path + 1] - bounds[path])


def stopping_length_of(points: np.ndarray) -> float:
    """:func:`motor.signing.lmp.stopping_length` of one path ``(m, 3)`` with the batch's
    arithmetic (the B-spline's basis kept per size) and without its grouping: what a
    sign's compiler asks for move by move, in as few numpy calls as the one path needs.
    A path with a hold goes through the one-path function, as in the batch."""
    points = np.asarray(points, dtype=float)
    if points.shape[0] < 3:
        return float(np.sqrt(np.float64(polyline_length(points))) ** 2)  # the sum of one root is that root
    steps = points[1:] - points[:-1]
    chords = np.sqrt(np.add.reduce(steps * steps, axis=1))  # np.linalg.norm's arithmetic
    if not (chords > HOLD_LENGTH).all():
        return stopping_length(points)
    denom = chords[:-1] * chords[1:]
    cos = np.divide(np.einsum("ij,ij->i", steps[:-1], steps[1:]), denom, out=np.ones_like(denom), where=denom > DEGENERATE_CHORD)
    if cos.min() > _NO_REVERSAL:  # no turn comes near a reversal: one piece
        return float(np.sqrt(np.float64(polyline_length(_traced_within(points)))) ** 2)
    reversals = np.flatnonzero(np.arccos(np.clip(cos, -1.0, 1.0)) >= REVERSAL_ANGLE) + 1
    cuts = [0, *reversals.tolist(), points.shape[0] - 1]
    return float(np.sum(np.sqrt([polyline_length(_traced_within(points[first : last + 1])) for first, last in pairwise(cuts)])) ** 2)


#: A cosine of turning above which the turn is surely short of a reversal
#: (:data:`motor.signing.lmp.REVERSAL_ANGLE`): a millionth above the reversal's cosine
#: is two millionths of a radian short of it, far beyond the rounding of ``arccos``.
_NO_REVERSAL = float(np.cos(REVERSAL_ANGLE)) + 1e-6


def _traced_within(piece: np.ndarray) -> np.ndarray:
    """One piece ``(k, 3)`` traced within its hull, starting with its first point (the
    batch's :func:`_traced`)."""
    if piece.shape[0] < 3:
        return piece
    first, weights = _basis(piece.shape[0])
    dense = np.empty((first.size + 1, 3))
    piece = np.ascontiguousarray(piece, dtype=float)
    row = np.zeros((1, _COLUMNS), dtype=np.int64)  # one piece of kept points, from row 0, its basis from row 0
    row[0, _POINTS] = piece.shape[0]
    _traced(piece, piece, row, first, weights, dense)
    return dense


def trace_chains(transitions: Sequence[tuple[float, float, str, np.ndarray]], moves: Sequence[Sequence[Move]]) -> list[TracedChain]:
    """The wrist chains :meth:`motor.signing.lmp.SignChannelLMP.activate` would make, for
    many LMPs at once: each a transition ``(start, ready, manner, way)`` — the way from the
    activation's wrist position through the via points to the sign's first, traced through
    them — then the sign's wrist moves, traced within their hulls; every move split at its
    reversals (:func:`motor.signing.lmp.stopping_times`)."""
    flat = [move for chain in moves for move in chain]
    traced = iter(smooth_pieces_many([move.values for move in flat], through=False))
    parts = []  # per chain: (start, end, manner, pieces) of its transition and moves
    for (start, ready, manner, _), pieces, chain in zip(transitions, smooth_pieces_many([way for _, _, _, way in transitions], through=True), moves):
        parts.append([(start, ready, manner, pieces), *((m.start, m.end, m.manner, next(traced)) for m in chain)])
    lengths = iter(polyline_lengths([piece for chain in parts for _, _, _, pieces in chain for piece in pieces]))
    timed = []
    for chain in parts:
        split = []
        for start, end, manner, pieces in chain:
            if len(pieces) == 1:  # stopping_times of one piece
                next(lengths)
                split.append((start, float(start + (end - start) * 1.0), manner, pieces[0]))
                continue
            times = stopping_times(np.array([next(lengths) for _ in pieces]), start, end)
            split.extend((float(a), float(b), manner, piece) for a, b, piece in zip(times[:-1], times[1:], pieces))
        timed.append(split)
    fractions = iter(law_fractions_many([piece for split in timed for _, _, _, piece in split]))
    return [
        TracedChain(
            time=transition[0],
            here=np.asarray(transition[3][0], dtype=float),
            starts=np.array([a for a, _, _, _ in split]),
            ends=np.array([b for _, b, _, _ in split]),
            manners=tuple(manner for _, _, manner, _ in split),
            values=tuple(piece for _, _, _, piece in split),
            fractions=tuple(next(fractions) for _ in split),
        )
        for transition, split in zip(transitions, timed)
    ]


def polyline_lengths(pieces: Sequence[np.ndarray]) -> np.ndarray:
    """Length (m) of every polyline ``(k, 3)``: its chords summed as numpy sums one."""
    out = np.empty(len(pieces))
    for k, members in _groups(pieces).items():
        out[members] = np.linalg.norm(np.diff(np.stack([pieces[index] for index in members]), axis=1), axis=2).sum(axis=1)
    return out


def _groups(arrays: Sequence[np.ndarray]) -> dict[int, list[int]]:
    """Indices of ``arrays`` by their number of rows."""
    groups: dict[int, list[int]] = defaultdict(list)
    for index, array in enumerate(arrays):
        groups[array.shape[0]].append(index)
    return groups


def _turning(points: np.ndarray) -> np.ndarray:
    """:func:`motor.trajectory.spline.turning_angles` of every row of ``(g, m ≥ 3, 3)``."""
    d = np.diff(points, axis=1)
    a, b = d[:, :-1].reshape(-1, 3), d[:, 1:].reshape(-1, 3)
    denom = np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1)
    cos = np.divide(np.einsum("ij,ij->i", a, b), denom, out=np.ones_like(denom), where=denom > DEGENERATE_CHORD)
    return np.arccos(np.clip(cos, -1.0, 1.0)).reshape(points.shape[0], -1)


def distinct_paths(arrays: Sequence[np.ndarray]) -> tuple[list[np.ndarray], list[int]]:
    """The distinct arrays (bit for bit; a corpus repeats many moves) and, for each array,
    the index of its twin among them."""
    seen: dict[tuple, int] = {}
    twins = [seen.setdefault((array.shape, array.tobytes()), len(seen)) for array in arrays]
    distinct: list[np.ndarray | None] = [None] * len(seen)
    for array, twin in zip(arrays, twins):
        if distinct[twin] is None:
            distinct[twin] = array
    return distinct, twins


def smooth_pieces_many(paths: Sequence[np.ndarray], through: bool) -> list[list[np.ndarray]]:
    """:func:`motor.signing.lmp.smooth_pieces` of every path ``(m, 3)`` (each distinct path
    once): within the hull by :func:`traced_within`, through the points in one pass per size."""
    distinct, twins = distinct_paths([np.asarray(path) for path in paths])
    if through:
        traced = _through_pieces_many(distinct)
    else:
        dense, bounds = traced_within(distinct)
        pieces = dense.split(dense.points)
        traced = [pieces[first:end] for first, end in pairwise(bounds.tolist())]
    return [traced[twin] for twin in twins]


def _through_pieces_many(paths: Sequence[np.ndarray]) -> list[list[np.ndarray]]:
    out: list[list[np.ndarray] | None] = [None] * len(paths)
    pieces: list[tuple[int, int, np.ndarray]] = []  # (path, order, piece)
    kept = _without_holds(paths)
    batched = []
    for index, (path, points) in enumerate(zip(paths, kept)):
        if points is not path:  # a hold: scipy's spline, as the transitions always had
            out[index] = smooth_pieces(path, through=True)
        elif points.shape[0] < 3:  # fewer than three distinct points: the path as it is
            out[index] = [path]
        else:
            batched.append(index)
    for m, positions in _groups([kept[index] for index in batched]).items():
        members = [batched[position] for position in positions]
        stacked = np.stack([kept[index] for index in members])
        angles = _turning(stacked)
        for row, index in enumerate(members):
            cuts = np.concatenate([[0], np.flatnonzero(angles[row] >= REVERSAL_ANGLE) + 1, [m - 1]])
            out[index] = [None] * (cuts.size - 1)
            for order, (first, last) in enumerate(zip(cuts[:-1], cuts[1:])):
                pieces.append((index, order, stacked[row, first : last + 1]))
    traced = _trace_through([piece for _, _, piece in pieces])
    for (index, order, _), dense in zip(pieces, traced):
        out[index][order] = dense
    return out


def traced_within(paths: Sequence[np.ndarray]) -> tuple[DensePaths, np.ndarray]:
    """:func:`motor.signing.lmp.smooth_pieces` within the hull of every path ``(m, 3)`` at
    once: the pieces of all the paths laid end to end, and each path's range of them
    (``bounds[i]:bounds[i + 1]``). The holds dropped, the cuts at reversals and the
    B-spline traced in compiled passes over all the points (the turns' arccos by numpy)."""
    given = DensePaths.of(paths)
    kept = _kept(given)
    pieces = np.zeros((max(given.points.shape[0], 1), _COLUMNS), dtype=np.int64)
    bounds = np.empty(len(paths) + 1, dtype=np.int64)
    totals = np.empty(2, dtype=np.int64)  # pieces, dense points
    _cut_at_reversals(np.arccos(kept.turning_cosines()), kept.starts, given.starts, pieces, bounds, totals)
    pieces = pieces[: totals[0]]
    first, weights = _basis_table(pieces)
    dense = np.empty((totals[1], 3))
    _traced(given.points, kept.points, pieces, first, weights, dense)
    return DensePaths(dense, np.append(pieces[:, _DENSE], totals[1])), bounds


def _kept(given: DensePaths) -> DensePaths:
    """The paths without the points :func:`motor.signing.lmp.smooth_pieces` drops (those
    within :data:`motor.trajectory.spline.HOLD_LENGTH` of the point before)."""
    n = given.points.shape[0]
    keep = np.ones(n, dtype=bool)
    keep[1:] = given.chords[:-1] > HOLD_LENGTH
    firsts = given.starts[:-1]
    keep[firsts[firsts < n]] = True
    counted = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(keep, out=counted[1:])
    return DensePaths(given.points[keep], counted[given.starts])


def _basis_table(pieces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The bases (:func:`_basis`) of every size of piece traced within its hull, one after
    another — each dense point's first control point ``(r,)`` and weights ``(r, 4)`` — with
    each such piece's first row of them written into its :data:`_BASIS` column."""
    traced = (pieces[:, _GIVEN] == 0) & (pieces[:, _POINTS] >= 3)
    sizes = np.unique(pieces[traced, _POINTS])
    bases = [_basis(int(k)) for k in sizes]
    rows = np.zeros(sizes.size + 1, dtype=np.int64)
    np.cumsum(np.array([first.size for first, _ in bases], dtype=np.int64), out=rows[1:])
    pieces[traced, _BASIS] = rows[np.searchsorted(sizes, pieces[traced, _POINTS])]
    first = np.concatenate([np.zeros(0, dtype=np.int64), *(first for first, _ in bases)])
    return first, np.concatenate([np.zeros((0, 4)), *(weights for _, weights in bases)])


#: Columns of a piece's row in :func:`traced_within`: as given (1: fewer than three distinct
#: points) or of the kept points (0), its first row and number of points there, its first
#: dense row, its basis's first row (:func:`_basis_table`).
_GIVEN, _FIRST, _POINTS, _DENSE, _BASIS = range(5)
_COLUMNS = 5


@numba.njit([numba.void(READ1, READ_INTS1, READ_INTS1, numba.int64[:, ::1], WRITE_INTS1, WRITE_INTS1)], cache=True, error_model="numpy")
def _cut_at_reversals(angles, kept, given, pieces, bounds, totals):  # noqa: ANN001, ANN202
    """Each path's pieces (rows of :data:`_GIVEN` … :data:`_BASIS`): the path as given when fewer than three
    of its points are kept, else its kept points cut where they turn by
    :data:`motor.signing.lmp.REVERSAL_ANGLE` or more; ``totals``: the pieces and their
    dense points."""
    count, rows = 0, 0
    for p in range(given.size - 1):
        bounds[p] = count
        first, end = kept[p], kept[p + 1]
        if end - first < 3:
            pieces[count, _GIVEN], pieces[count, _FIRST], pieces[count, _POINTS], pieces[count, _DENSE] = 1, given[p], given[p + 1] - given[p], rows
            rows += given[p + 1] - given[p]
            count += 1
            continue
        cut = first
        for i in range(first + 1, end):
            if i == end - 1 or angles[i] >= REVERSAL_ANGLE:
                k = i - cut + 1
                pieces[count, _GIVEN], pieces[count, _FIRST], pieces[count, _POINTS], pieces[count, _DENSE] = 0, cut, k, rows
                rows += k if k < 3 else PATH_DENSITY * (k - 1) + 1
                count += 1
                cut = i
    bounds[given.size - 1] = count
    totals[0], totals[1] = count, rows


def _without_holds(paths: Sequence[np.ndarray]) -> list[np.ndarray]:
    """Each path without the points :func:`motor.signing.lmp.smooth_pieces` drops (those
    within :data:`motor.trajectory.spline.HOLD_LENGTH` of the point before), per size."""
    out: list[np.ndarray | None] = [None] * len(paths)
    for m, members in _groups(paths).items():
        if m < 2:
            for index in members:
                out[index] = paths[index]
            continue
        stacked = np.stack([paths[index] for index in members])
        moving = np.linalg.norm(np.diff(stacked, axis=1), axis=2) > HOLD_LENGTH
        for row, index in enumerate(members):
            out[index] = paths[index] if moving[row].all() else paths[index][np.concatenate([[True], moving[row]])]
    return out


def _trace_through(pieces: list[np.ndarray]) -> list[np.ndarray]:
    """Each piece ``(k, 3)`` densely through its points, starting with its first point
    (:func:`smooth_pieces`), per size."""
    out: list[np.ndarray | None] = [None] * len(pieces)
    for k, members in _groups(pieces).items():
        stacked = np.stack([pieces[index] for index in members])
        if k < 3:
            dense = stacked.copy()
        else:
            dense = np.empty((len(members), PATH_DENSITY * (k - 1) + 1, 3))
            dense[:, 0] = stacked[:, 0]
            dense[:, 1:] = _through(stacked)
        for row, index in enumerate(members):
            out[index] = dense[row]
    return out


def _through(pieces: np.ndarray) -> np.ndarray:
    """The not-a-knot cubic spline by chord length through every row of ``(g, k ≥ 3, 3)``,
    :data:`PATH_DENSITY` points per chord without the first (``lmp._through``)."""
    g, k, _ = pieces.shape
    dx = np.linalg.norm(np.diff(pieces, axis=1), axis=2)
    x = np.concatenate([np.zeros((g, 1)), np.cumsum(dx, axis=1)], axis=1)
    dx = np.diff(x, axis=1)
    slope = np.diff(pieces, axis=1) / dx[..., None]
    slopes = _derivatives(x, dx, slope) if k > 3 else _parabola(dx, slope)
    t = (slopes[:, :-1] + slopes[:, 1:] - 2 * slope) / dx[..., None]
    c0 = t / dx[..., None]
    c1 = (slope - slopes[:, :-1]) / dx[..., None] - t
    c2, c3 = slopes[:, :-1], pieces[:, :-1]
    fractions = np.linspace(0.0, 1.0, PATH_DENSITY + 1)[1:]
    at = x[:, :-1, None] + dx[:, :, None] * fractions
    s = (at - x[:, :-1, None])[..., None]  # (g, k - 1, density, 1)
    z2 = s * s
    dense = ((c3[:, :, None] + c2[:, :, None] * s) + c1[:, :, None] * z2) + c0[:, :, None] * (z2 * s)
    dense[:, :, -1] = pieces[:, 1:]
    return dense.reshape(g, -1, 3)


def _parabola(dx: np.ndarray, slope: np.ndarray) -> np.ndarray:
    """Derivatives at the three points of the parabola through them (scipy's case of three
    points with not-a-knot ends)."""
    g = dx.shape[0]
    a = np.zeros((g, 3, 3))
    a[:, 0, 0] = a[:, 0, 1] = a[:, 2, 1] = a[:, 2, 2] = 1.0
    a[:, 1, 0] = dx[:, 1]
    a[:, 1, 1] = 2 * (dx[:, 0] + dx[:, 1])
    a[:, 1, 2] = dx[:, 0]
    b = np.stack([2 * slope[:, 0], 3 * (dx[:, 0, None] * slope[:, 1] + dx[:, 1, None] * slope[:, 0]), 2 * slope[:, 1]], axis=1)
    return np.linalg.solve(a, b)


def _derivatives(x: np.ndarray, dx: np.ndarray, slope: np.ndarray) -> np.ndarray:
    """Derivatives ``(g, k, 3)`` at the points of not-a-knot cubic splines (k ≥ 4): scipy's
    tridiagonal system, solved row by row of the batch (Thomas algorithm)."""
    g, k = x.shape
    lower = np.zeros((g, k))  # a[i, i - 1]
    diag = np.empty((g, k))
    upper = np.zeros((g, k))  # a[i, i + 1]
    rhs = np.empty((g, k, 3))
    diag[:, 1:-1] = 2 * (dx[:, :-1] + dx[:, 1:])
    upper[:, 1:-1] = dx[:, :-1]
    lower[:, 1:-1] = dx[:, 1:]
    rhs[:, 1:-1] = 3 * (dx[:, 1:, None] * slope[:, :-1] + dx[:, :-1, None] * slope[:, 1:])
    d = x[:, 2] - x[:, 0]
    diag[:, 0], upper[:, 0] = dx[:, 1], d
    rhs[:, 0] = ((dx[:, 0, None] + 2 * d[:, None]) * dx[:, 1, None] * slope[:, 0] + dx[:, 0, None] ** 2 * slope[:, 1]) / d[:, None]
    d = x[:, -1] - x[:, -3]
    diag[:, -1], lower[:, -1] = dx[:, -2], d
    rhs[:, -1] = (dx[:, -1, None] ** 2 * slope[:, -2] + (2 * d[:, None] + dx[:, -1, None]) * dx[:, -2, None] * slope[:, -1]) / d[:, None]
    for i in range(1, k):
        factor = lower[:, i] / diag[:, i - 1]
        diag[:, i] = diag[:, i] - factor * upper[:, i - 1]
        rhs[:, i] = rhs[:, i] - factor[:, None] * rhs[:, i - 1]
    out = np.empty((g, k, 3))
    out[:, -1] = rhs[:, -1] / diag[:, -1, None]
    for i in range(k - 2, -1, -1):
        out[:, i] = (rhs[:, i] - upper[:, i, None] * out[:, i + 1]) / diag[:, i, None]
    return out


@cache
def _basis(k: int) -> tuple[np.ndarray, np.ndarray]:
    """The clamped B-spline of a ``k``-point control polygon (``lmp._within``) at its dense
    parameters: the first control point each parameter depends on ``(n,)`` and the weights
    of it and the next ``degree`` points ``(n, 4)``, as scipy's de Boor gives them (zeros
    past ``degree + 1 = min(4, k)``, never read)."""
    degree = min(3, k - 1)
    interior = k - degree - 1
    knots = np.concatenate([np.zeros(degree + 1), np.arange(1, interior + 1) / (interior + 1), np.ones(degree + 1)])
    at = np.linspace(0.0, 1.0, PATH_DENSITY * (k - 1) + 1)[1:]
    matrix = BSpline(knots, np.eye(k), degree)(at)
    interval = np.clip(np.searchsorted(knots, at, side="right") - 1, degree, knots.size - degree - 2)
    first = interval - degree
    weights = np.zeros((at.size, 4))
    weights[:, : degree + 1] = matrix[np.arange(at.size)[:, None], first[:, None] + np.arange(degree + 1)]
    return first, weights


@numba.njit([numba.void(READ2, READ2, READ_INTS2, READ_INTS1, READ2, WRITE2)], cache=True, error_model="numpy")
def _traced(given, kept, pieces, first, weights, dense):  # noqa: ANN001, ANN202
    """Into ``dense``: each piece (rows of :data:`_GIVEN` … :data:`_BASIS`) of fewer than three points or as
    given copied, each other one traced within its hull — its first point, then each
    dense point as the sum from zero over the basis's ``min(4, k)`` weights of the control
    points from ``first`` on, in the weights' order, the last point exactly the piece's last."""
    for q in range(pieces.shape[0]):
        start, k, at, basis = pieces[q, _FIRST], pieces[q, _POINTS], pieces[q, _DENSE], pieces[q, _BASIS]
        source = given if pieces[q, _GIVEN] == 1 else kept
        if pieces[q, _GIVEN] == 1 or k < 3:
            for i in range(k):
                for c in range(3):
                    dense[at + i, c] = source[start + i, c]
            continue
        n, width = PATH_DENSITY * (k - 1), min(4, k)
        for c in range(3):
            dense[at, c] = source[start, c]
        for r in range(n):
            control = start + first[basis + r]
            for c in range(3):
                total = 0.0
                for a in range(width):
                    total = total + source[control + a, c] * weights[basis + r, a]
                dense[at + 1 + r, c] = total
        for c in range(3):
            dense[at + n, c] = source[start + k - 1, c]


def law_fractions_many(paths: Sequence[np.ndarray]) -> list[np.ndarray]:
    """:func:`motor.signing.lmp.law_fractions` of every dense path ``(m, 3)``: those of three
    or more points laid end to end in compiled passes (:class:`motor.signing.law_time.DensePaths`;
    each distinct path once, the fractions views of one array)."""
    distinct, twins = distinct_paths([np.asarray(path) for path in paths])
    fractions = _law_fractions_many(distinct)
    return [fractions[twin] for twin in twins]


def _law_fractions_many(paths: Sequence[np.ndarray]) -> list[np.ndarray]:
    out: list[np.ndarray | None] = [None] * len(paths)
    long = []
    for index, path in enumerate(paths):
        if path.shape[0] >= 3:
            long.append(index)
        else:  # two points: the way's two ends, [0, 1] (none: as given)
            out[index] = np.array([0.0, 1.0]) if path.shape[0] == 2 and np.all(np.isfinite(path)) else law_fractions(path)
    dense = DensePaths.of([paths[index] for index in long])
    for index, fractions in zip(long, dense.split(dense.law_fractions())):
        out[index] = fractions
    return out


def load_kernels() -> None:
    """Run this module's compiled loops once (they load when the module is imported):
    :func:`motor.compiled.warm_up`."""
    stopping_lengths([np.array([[0.0, 0.0, 0.0], [0.01, 0.0, 0.0], [0.01, 0.01, 0.0]])])
