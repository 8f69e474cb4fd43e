"""Sign moves given the time their *final* wrist paths need within the speed budget.

A sign's moves are timed while it is compiled, from the paths HamNoSys asks for
(:meth:`motor.signing.sign_compiler.SignCompiler.shortest`). Clearing those paths out of the
body and into reach (:mod:`motor.signing.reach`) can lengthen them, and the wrist does
not travel a path evenly: it advances in *law time* (:func:`motor.signing.lmp.law_fractions`),
slower in tight bends and faster along the straighter stretches, so its peak speed and
acceleration exceed those of an even traversal by the path's *law factor* — the largest
ratio of the share of the path travelled to the share of law time spent, over the path's
pieces (:func:`motor.signing.lmp.smooth_pieces`).

:func:`retimed` stretches each wrist move that would then leave its manner's budget
(:mod:`motor.trajectory.speed_budget`) to the least duration that keeps within it, for
the path's stopping length (:func:`motor.signing.lmp.stopping_length`) times its law
factor. The sign's clock is warped piecewise linearly so that every other channel's move
over the same stretch of time (the hand's turn, its shape) is stretched with it and the
moves after it follow; the plan says which moves were slowed and by how much.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numba
import numpy as np

from motor.body.conventions import ARMS
from motor.kernel_types import READ1, READ_INTS1, WRITE1
from motor.signing.lmp import Move, law_fractions, smooth_pieces, stopping_length
from motor.signing.path_batch import distinct_paths, stopping_of, traced_within
from motor.signing.plan import SignPlan, SignPlanningError
from motor.trajectory.biocontrol import shortest_duration, shortest_durations

#: Shortest path (m) whose law factor is measured; shorter pieces travel evenly enough.
_MEASURED = 1e-3
#: A move is stretched only when it needs more than this share longer (rounding).
_SLACK = 1e-6
#: Law time (share of the piece's) below which a stretch of a piece counts as not spent.
_MOVING = 1e-12


def law_factor(values: np.ndarray) -> float:
    """How much faster than an even traversal (≥ 1) the wrist goes at its fastest along
    the path ``values`` ``(m, 3)``: over its pieces, the largest ratio of the share of
    the piece travelled to the share of law time spent between two of its points."""
    factor = 1.0
    for piece in smooth_pieces(np.asarray(values, dtype=float), through=False):
        if piece.shape[0] < 3:
            continue
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(piece, axis=0), axis=1))])
        if arc[-1] < _MEASURED:
            continue
        spent = np.diff(law_fractions(piece))
        travelled = np.diff(arc) / arc[-1]
        moving = spent > _MOVING
        if np.any(moving):
            factor = max(factor, float(np.max(travelled[moving] / spent[moving])))
    return factor


def timing_length(values: np.ndarray) -> float:
    """The length (m) a wrist path ``values`` ``(m, 3)`` is timed on within a speed budget:
    its stopping length times its law factor (0 for a path that does not move)."""
    length = stopping_length(values)
    if length <= 0.0:
        return 0.0
    return length * law_factor(values)


def timing_lengths(paths: Sequence[np.ndarray]) -> list[float]:
    """:func:`timing_length` of every path ``(m, 3)``, with the arithmetic of the one-path
    functions — the same numbers, bit for bit: the pieces of all the distinct paths traced
    at once and laid end to end (:func:`motor.signing.path_batch.traced_within`), their
    lengths, law time and law factors in compiled passes over all their points."""
    distinct, twins = distinct_paths([np.asarray(path, dtype=float) for path in paths])
    pieces, bounds = traced_within(distinct)
    factors = np.empty(pieces.starts.size - 1)
    _law_factors(pieces.arc, pieces.law_fractions(), pieces.starts, factors)
    stopping = stopping_of(pieces.lengths(), bounds)
    largest = np.maximum.reduceat(factors, bounds[:-1]) if len(distinct) else np.ones(0)  # every path has a piece
    return np.where(stopping <= 0.0, 0.0, stopping * largest)[twins].tolist()


@numba.njit([numba.void(READ1, READ1, READ_INTS1, WRITE1)], cache=True, error_model="numpy")
def _law_factors(arc, fractions, starts, out):  # noqa: ANN001, ANN202
    """Each piece's share of the law factor (:func:`law_factor`'s loop body; 1 for a piece
    of fewer than three points or shorter than :data:`_MEASURED`) from the arc length and
    law-time fractions at its points, laid end to end."""
    for p in range(starts.size - 1):
        first, last = starts[p], starts[p + 1] - 1
        out[p] = 1.0
        if last - first < 2 or arc[last] < _MEASURED:
            continue
        for i in range(first, last):
            spent = fractions[i + 1] - fractions[i]
            if spent > _MOVING:
                out[p] = max(out[p], (arc[i + 1] - arc[i]) / arc[last] / spent)


def needed_duration(move: Move) -> float:
    """The least duration (s) of a wrist ``move`` within its manner's budget, for its
    path's :func:`timing_length`."""
    return shortest_duration(timing_length(move.values), move.manner)


def retimed_all(drafts: list[SignPlan | SignPlanningError], batched: bool = True) -> list[SignPlan | SignPlanningError]:
    """:func:`retimed` of every plan; errors pass through. ``batched``: the timing lengths
    and least durations of all the plans' wrist moves in one pass (:func:`timing_lengths`,
    :func:`motor.trajectory.biocontrol.shortest_durations`), only the plans with a move
    that needs more retimed one by one; else plan by plan, move by move."""
    if not batched:
        return [retimed(draft) if isinstance(draft, SignPlan) else draft for draft in drafts]
    plans = [draft for draft in drafts if isinstance(draft, SignPlan)]
    chains = [_wrist_moves(plan) for plan in plans]
    moves = [move for chain in chains for move in chain]
    lengths = timing_lengths([move.values for move in moves])
    quick = _too_quick(shortest_durations(lengths, [move.manner for move in moves]), np.array([move.end - move.start for move in moves]))
    bounds = np.zeros(len(chains) + 1, dtype=np.int64)
    np.cumsum([len(chain) for chain in chains], out=bounds[1:])
    slowed = np.diff(np.concatenate([[0], np.cumsum(quick)])[bounds]) > 0
    timed = {id(plan): retimed(plan, lengths[first:end]) for plan, first, end, slow in zip(plans, bounds[:-1], bounds[1:], slowed) if slow}
    return [timed.get(id(draft), draft) for draft in drafts]


def _wrist_moves(plan: SignPlan) -> list[Move]:
    return [move for arm in ARMS for move in plan.moves.get((arm, "wrist_position"), ())]


def _too_quick(need: np.ndarray | float, given: np.ndarray | float) -> np.ndarray | bool:
    """Whether moves given ``given`` seconds need more (``need``, s), beyond rounding."""
    return need > given * (1.0 + _SLACK)


def retimed(plan: SignPlan, lengths: Sequence[float] | None = None) -> SignPlan:
    """The plan with its wrist moves stretched to what their paths need (module docstring),
    every channel's moves on the warped clock; the plan itself when none needs more.
    ``lengths``: the :func:`timing_length` of each wrist move (both arms' in order), if
    already known."""
    stretches: dict[tuple[float, float], float] = {}
    moves = _wrist_moves(plan)
    lengths = [timing_length(move.values) for move in moves] if lengths is None else lengths
    for move, length in zip(moves, lengths, strict=True):
        need = shortest_duration(length, move.manner)
        given = move.end - move.start
        if _too_quick(need, given):
            key = (move.start, move.end)
            stretches[key] = max(stretches.get(key, 1.0), need / given)
    if not stretches:
        return plan
    warp = _Warp.of(plan, stretches)
    times = iter(warp.at([plan.duration, *(time for channel in plan.moves.values() for move in channel for time in (move.start, move.end))]))
    duration = next(times)
    warped = {key: tuple(_moved(move, next(times), next(times)) for move in channel) for key, channel in plan.moves.items()}
    slowest = max(stretches.items(), key=lambda item: item[1])
    (start, end), factor = slowest
    note = (
        f"{plan.gloss}: {len(stretches)} move(s) slowed to keep the wrist within its speed budget, "
        f"the most from {end - start:.2f} s to {factor * (end - start):.2f} s"
    )
    return replace(plan, duration=duration, moves=warped, warnings=(*plan.warnings, note))


def _moved(move: Move, start: float, end: float) -> Move:
    """``move`` over ``[start, end]`` (s): itself where the warp left it."""
    return move if start == move.start and end == move.end else replace(move, start=start, end=end)


class _Warp:
    """A piecewise-linear, increasing map of a sign's clock: the stretches between
    consecutive move boundaries are scaled by the largest stretch asked of a wrist move
    covering them (1 elsewhere)."""

    def __init__(self, old: np.ndarray, new: np.ndarray) -> None:
        self.old, self.new = old, new

    @classmethod
    def of(cls, plan: SignPlan, stretches: dict[tuple[float, float], float]) -> _Warp:
        bounds = {0.0, float(plan.duration)}
        for channel in plan.moves.values():
            for move in channel:
                bounds.update((move.start, move.end))
        old = np.array(sorted(bounds))
        scale = np.ones(old.size - 1)
        middles = 0.5 * (old[1:] + old[:-1])
        for (start, end), factor in stretches.items():
            inside = (middles > start) & (middles < end)
            scale[inside] = np.maximum(scale[inside], factor)
        new = np.concatenate([[old[0]], old[0] + np.cumsum(np.diff(old) * scale)])
        return cls(old, new)

    def at(self, times: Sequence[float]) -> list[float]:
        """The warped ``times`` (s)."""
        return np.interp(times, self.old, self.new).tolist()


def load_kernels() -> None:
    """Run this module's compiled loops once (they load when the module is imported):
    :func:`motor.compiled.warm_up`."""
    timing_lengths([np.array([[0.0, 0.0, 0.0], [0.01, 0.0, 0.0], [0.01, 0.01, 0.0]])])
