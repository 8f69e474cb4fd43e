"""Sign moves given the time their *final* wrist paths need within the speed budget.

A sign's moves are timed while it is compiled, from the paths HamNoSys asks for
(:meth:`motor.signing.planning._SignCompiler.shortest`). Clearing those paths out of the
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

from collections import defaultdict
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from motor.body.avatar import ARMS
from motor.signing.lmp import Move, law_fractions, smooth_pieces, stopping_length
from motor.signing.path_batch import (
    law_fractions_many,
    polyline_lengths,
    smooth_pieces_many,
)
from motor.signing.plan import SignPlan, SignPlanningError
from motor.trajectory.biocontrol import shortest_duration

#: Shortest path (m) whose law factor is measured; shorter pieces travel evenly enough.
_MEASURED = 1e-3
#: A move is stretched only when it needs more than this share longer (rounding).
_SLACK = 1e-6


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
        moving = spent > 1e-12
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
    """:func:`timing_length` of every path ``(m, 3)``, in vectorized passes
    (:mod:`motor.signing.path_batch`): the pieces of all the distinct paths traced at
    once, their lengths and law factors per group of pieces of one size, with the
    arithmetic of the one-path functions — the same numbers, bit for bit."""
    index: dict[bytes, int] = {}
    distinct: list[np.ndarray] = []
    twins = []
    for path in paths:
        values = np.ascontiguousarray(path, dtype=float)
        key = values.tobytes() + bytes(str(values.shape), "ascii")
        if key not in index:
            index[key] = len(distinct)
            distinct.append(values)
        twins.append(index[key])
    splits = smooth_pieces_many(distinct, through=False)
    pieces = [piece for split in splits for piece in split]
    lengths = polyline_lengths(pieces)
    factors = _law_factors(pieces)
    timed, first = [], 0
    for split in splits:
        rows = slice(first, first + len(split))
        first += len(split)
        length = float(np.sum(np.sqrt([float(value) for value in lengths[rows]])) ** 2)
        timed.append(0.0 if length <= 0.0 else length * max(1.0, *factors[rows]))
    return [timed[twin] for twin in twins]


def _law_factors(pieces: Sequence[np.ndarray]) -> list[float]:
    """Each piece's share of the law factor (:func:`law_factor`'s loop body; 1 for a piece
    of fewer than three points or shorter than :data:`_MEASURED`), per group of one size."""
    factors = [1.0] * len(pieces)
    groups: dict[int, list[int]] = defaultdict(list)
    for number, piece in enumerate(pieces):
        if piece.shape[0] >= 3:
            groups[piece.shape[0]].append(number)
    measured: list[tuple[list[int], np.ndarray]] = []  # per size: the pieces and their arcs
    for members in groups.values():
        chords = np.linalg.norm(np.diff(np.stack([pieces[number] for number in members]), axis=1), axis=2)
        arc = np.concatenate([np.zeros((len(members), 1)), np.cumsum(chords, axis=1)], axis=1)
        long = arc[:, -1] >= _MEASURED
        measured.append(([number for number, keep in zip(members, long) if keep], arc[long]))
    fractions = iter(law_fractions_many([pieces[number] for members, _ in measured for number in members]))
    for members, arc in measured:
        if not members:
            continue
        spent = np.diff(np.stack([next(fractions) for _ in members]), axis=1)
        travelled = np.diff(arc, axis=1) / arc[:, -1:]
        moving = spent > 1e-12
        ratios = np.where(moving, travelled / np.where(moving, spent, 1.0), -np.inf).max(axis=1)
        for number, ratio, any_moving in zip(members, ratios, moving.any(axis=1)):
            if any_moving:
                factors[number] = max(1.0, float(ratio))
    return factors


def needed_duration(move: Move) -> float:
    """The least duration (s) of a wrist ``move`` within its manner's budget, for its
    path's :func:`timing_length`."""
    return shortest_duration(timing_length(move.values), move.manner)


def retimed_all(drafts: list[SignPlan | SignPlanningError], batched: bool = True) -> list[SignPlan | SignPlanningError]:
    """:func:`retimed` of every plan; errors pass through. ``batched``: the timing lengths
    of all the plans' wrist moves in one pass (:func:`timing_lengths`), else move by move."""
    plans = [draft for draft in drafts if isinstance(draft, SignPlan)]
    paths = [move.values for plan in plans for move in _wrist_moves(plan)]
    lengths = iter(timing_lengths(paths) if batched else [timing_length(path) for path in paths])
    timed = {id(plan): retimed(plan, [next(lengths) for _ in _wrist_moves(plan)]) for plan in plans}
    return [timed[id(draft)] if isinstance(draft, SignPlan) else draft for draft in drafts]


def _wrist_moves(plan: SignPlan) -> list[Move]:
    return [move for arm in ARMS for move in plan.moves.get((arm, "wrist_position"), ())]


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
        if need > given * (1.0 + _SLACK):
            key = (move.start, move.end)
            stretches[key] = max(stretches.get(key, 1.0), need / given)
    if not stretches:
        return plan
    warp = _Warp.of(plan, stretches)
    warped = {key: tuple(replace(m, start=warp(m.start), end=warp(m.end)) for m in channel) for key, channel in plan.moves.items()}
    slowest = max(stretches.items(), key=lambda item: item[1])
    (start, end), factor = slowest
    note = (
        f"{plan.gloss}: {len(stretches)} move(s) slowed to keep the wrist within its speed budget, "
        f"the most from {end - start:.2f} s to {factor * (end - start):.2f} s"
    )
    return replace(plan, duration=warp(plan.duration), moves=warped, warnings=(*plan.warnings, note))


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

    def __call__(self, time: float) -> float:
        return float(np.interp(time, self.old, self.new))
