"""The cheapest swivel of a lone posture: where a reach check or a single frame puts the elbow.

Solving one posture on its own (:func:`motor.arm.ik.solve_arm` without a swivel track,
:func:`motor.arm.ik.arm_reach`: planning checks a quarter of a million wrist positions of
a corpus this way) takes the cheapest of the candidate swivels
(:func:`motor.arm.swivel_cost.candidate_costs`), refined by a parabola through it and
its neighbours (:func:`cheapest_by_costs`). Where the body stands upright at rest and no
other arm is kept clear of, a compiled search (:func:`cheapest_swivels`) gives the very
same numbers while measuring only the candidates that can still be the least.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from motor.arm.chain import ArmPlacement, natural_swivel
from motor.arm.candidate_clearance import candidate_depth, candidate_penalty, row_meets
from motor.arm.clearance import ArmSegments, arm_capsules, obstacle_table, segment_table, upright_obstacles
from motor.arm.swivel_cost import (
    CANDIDATES,
    OUTSIDE,
    SWIVEL_STEP,
    WINDOW,
    candidate_costs,
    hand_matrix,
    natural_cost,
    parabola_offset,
    turn_remainder,
    wrist_angles,
    wrist_constant_row,
    wrist_constants,
    wrist_load,
)
from motor.body.avatar import Avatar
from motor.kernel_types import READ1, READ2, READ3, READ_FLAGS1, READ_INTS1, WRITE1, WRITE2

#: The cells whose swivels' cosines and sines the search looks up (:func:`_cell_turns`):
#: those of natural swivels within two turns of the candidates'.
_FIRST_CELL = -2 * len(CANDIDATES)
_CELL_COUNT = 5 * len(CANDIDATES)


def cheapest_swivel(avatar: Avatar, placement: ArmPlacement, other: ArmSegments | None = None) -> np.ndarray:
    """The cheapest swivel (radians) of each frame of ``placement`` on its own, keeping
    clear of the ``other`` arm's capsules too: compiled where it can be
    (:func:`cheapest_swivels`), else :func:`cheapest_by_costs` — the same numbers."""
    natural = natural_swivel(placement.chain, placement.circle, placement.targets, placement.torso_q)
    swivels = None if other is not None else cheapest_swivels(avatar, placement, natural)
    return cheapest_by_costs(avatar, placement, natural, other) if swivels is None else swivels


def cheapest_by_costs(avatar: Avatar, placement: ArmPlacement, natural: np.ndarray, other: ArmSegments | None = None) -> np.ndarray:
    """The cheapest swivel of each frame from every candidate's cost
    (:func:`motor.arm.swivel_cost.candidate_costs` about the natural swivels ``natural
    (n,)``): the first least candidate, refined by a parabola through it and its
    neighbours (:func:`motor.arm.swivel_cost.parabola_offset`)."""
    cost = candidate_costs(avatar, placement, natural, other)
    best = np.argmin(cost, axis=1)
    rows = np.arange(len(best))
    count = len(CANDIDATES)
    left, middle, right = cost[rows, (best - 1) % count], cost[rows, best], cost[rows, (best + 1) % count]
    return CANDIDATES[best] + parabola_offset(left, middle, right) * SWIVEL_STEP


def cheapest_swivels(avatar: Avatar, placement: ArmPlacement, natural: np.ndarray) -> np.ndarray | None:
    """:func:`cheapest_by_costs` with no other arm, compiled: the very numbers of that
    composition, or None where the body does not stand upright at rest (the composition
    then carries it).

    Compiled (:func:`_cheapest_rows`), and cheaper than measuring every candidate: a
    candidate costs at least its distance from the natural swivel plus the wrist's load,
    so the window's candidates are measured against the body cheapest bound first, and
    those whose bound exceeds the best cost found (and are no neighbour of the best) are
    never measured: they cannot be the least, nor tie with it."""
    if placement.body_frame is not None or placement.carried_frames is not None:
        return None
    swivels, _, _ = _searched(avatar, placement, natural, with_depth=False)
    return swivels


def cheapest_reach(avatar: Avatar, placement: ArmPlacement, natural: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`cheapest_swivels` of a placement of the body upright at rest (as
    :func:`motor.arm.chain.place_arm` places it without a torso), and where the arm puts
    its elbows at them ``(n, 3)`` and how deep (m, ≥ 0) it then enters the body ``(n,)``:
    the numbers of :meth:`motor.arm.chain.ElbowCircle.elbow` and
    :func:`motor.arm.clearance.clearance` at those swivels, in the same compiled pass (a
    reach check reads the depth of a quarter of a million postures a corpus)."""
    if placement.body_frame is not None or placement.carried_frames is not None:
        raise ValueError("cheapest_reach measures the body upright at rest only")
    swivels, elbows, depth = _searched(avatar, placement, natural, with_depth=True)
    return swivels, elbows, np.maximum(depth, 0.0)


def _searched(avatar: Avatar, placement: ArmPlacement, natural: np.ndarray, with_depth: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_cheapest_rows` over the placement's frames: swivels, and with ``with_depth``
    the elbows there and the body's depth (else empty arrays)."""
    chain, circle = placement.chain, placement.circle
    rows = lambda value: np.ascontiguousarray(value, dtype=float)
    kinds, parameters, boxes, in_trunk = obstacle_table(upright_obstacles(avatar))
    limits = np.array([*chain.wrist_flexion, *chain.wrist_deviation, *chain.twist_range], dtype=float)
    count = len(natural) if with_depth else 0
    swivels, elbows, depth = np.empty(len(natural)), np.empty((count, 3)), np.empty(count)
    _cheapest_rows(
        rows(natural), np.zeros((0, 4)) if placement.hands is None else rows(placement.hands),
        rows(circle.shoulder), rows(circle.wrist), rows(circle.axis), rows(circle.center), rows(circle.radius),
        rows(circle.down), rows(circle.out), wrist_constant_row(chain), limits, CANDIDATES,
        segment_table(arm_capsules(avatar, chain.side)), kinds, parameters, boxes, in_trunk, swivels, elbows, depth,
    )  # fmt: skip
    return swivels, elbows, depth


@numba.njit(cache=True, error_model="numpy", inline="always")
def _parabola(left, middle, right):  # noqa: ANN001, ANN202
    """:func:`motor.arm.swivel_cost.parabola_offset` of one frame, the same operations (NaN
    passes through the clip)."""
    curvature = left - 2.0 * middle + right
    if not curvature > 1e-12:
        return 0.0
    step = 0.5 * (left - right) / curvature
    return step if step != step else min(max(step, -0.5), 0.5)


@numba.njit(cache=True, error_model="numpy", inline="always")
def _by_distance(distance, order):  # noqa: ANN001, ANN202
    """Into ``order``: the window's candidates by increasing ``distance`` cost (from the
    natural swivel), ties in window order (an insertion sort of ~21 numbers that the
    window, centred on the natural swivel, nearly sorts already once walked outward)."""
    width = order.size
    middle = width // 2
    for k in range(width):
        order[k] = middle + (k + 1) // 2 if k % 2 else middle - k // 2
    for k in range(1, width):
        held, j = order[k], k
        while j > 0 and (distance[order[j - 1]] > distance[held] or (distance[order[j - 1]] == distance[held] and order[j - 1] > held)):
            order[j] = order[j - 1]
            j -= 1
        order[j] = held


@numba.njit(cache=True, error_model="numpy", inline="always")
def _first_known_least(costs, known):  # noqa: ANN001, ANN202
    """``np.argmin`` among the measured ``costs`` (the first NaN, else the first least):
    every other candidate costs more than the least."""
    best = -1
    for j in range(costs.size):
        if not known[j]:
            continue
        if costs[j] != costs[j]:
            return j
        if best < 0 or costs[j] < costs[best]:
            best = j
    return best


@numba.njit(cache=True, error_model="numpy", inline="always")
def _finite(values):  # noqa: ANN001, ANN202
    """Whether every value of the tuple is finite."""
    for value in values:
        if not math.isfinite(value):
            return False
    return True


@numba.njit(cache=True, error_model="numpy", inline="always")
def _wrist_load_at(k, m, c, w, elbow, radial, fixed, limits):  # noqa: ANN001, ANN202
    """The wrist's load (:func:`motor.arm.swivel_cost.wrist_load`) of window candidate ``k``
    (its elbow and direction: columns of ``elbow`` and ``radial (3, W)``), the hand's matrix
    ``m``, the circle's axis ``c``, the wrist ``w``."""
    flexion, deviation, twist, _ = wrist_angles(m, c, w, (elbow[0, k], elbow[1, k], elbow[2, k]), (radial[0, k], radial[1, k], radial[2, k]), fixed)
    return wrist_load(flexion, deviation, twist, limits)


@numba.njit(cache=True, error_model="numpy", inline="always")
def _measured(k, distance, load, loaded, s, w, elbow, segments, kinds, parameters, boxes, in_trunk, meets):  # noqa: ANN001, ANN202
    """Window candidate ``k``'s whole cost in :func:`motor.arm.swivel_cost.candidate_costs`'s
    sums: its distance cost plus its body clearance penalty, then its wrist load."""
    cost = distance[k] + candidate_penalty(s, w, elbow[0, k], elbow[1, k], elbow[2, k], segments, kinds, parameters, boxes, in_trunk, meets)
    return cost + load[k] if loaded else cost


@numba.njit(cache=True, error_model="numpy", inline="always")
def _swivel_at(cell):  # noqa: ANN001, ANN202
    """The swivel (radians) of a window cell (unwrapped steps from the first candidate, a
    float): :func:`motor.arm.swivel_cost.measured_window`'s arithmetic."""
    return CANDIDATES[0] + cell * SWIVEL_STEP


@numba.njit(cache=True, error_model="numpy")
def _cell_turns():  # noqa: ANN202
    """The cosines and sines ``(2, C)`` of the swivels of the cells :data:`_FIRST_CELL`
    onward (a window's cells repeat from frame to frame: looked up, not computed again)."""
    turns = np.empty((2, _CELL_COUNT))
    for index in range(_CELL_COUNT):
        psi = _swivel_at(float(_FIRST_CELL + index))
        turns[0, index], turns[1, index] = math.cos(psi), math.sin(psi)
    return turns


@numba.njit(cache=True, error_model="numpy", inline="always")
def _window_of(i, natural, center, radius, down, out, turns, psi, elbow, radial):  # noqa: ANN001, ANN202
    """Into ``psi (W,)``, ``elbow`` and ``radial (3, W)``: frame ``i``'s measured window
    (:func:`motor.arm.swivel_cost.measured_window`) and its candidates' elbows and their
    directions from the circle's centre (:func:`motor.arm.swivel_cost.candidate_elbows`),
    the same operations, the cosines and sines from ``turns`` (:func:`_cell_turns`) where
    it holds the cells; returns the window's first cell."""
    centre = np.rint((natural[i] - CANDIDATES[0]) / SWIVEL_STEP)
    first = centre + float(-WINDOW)
    tabled = _FIRST_CELL <= first and first + 2 * WINDOW < _FIRST_CELL + _CELL_COUNT
    for k in range(psi.size):
        psi[k] = _swivel_at(centre + float(k - WINDOW))
        if tabled:
            index = int(first) - _FIRST_CELL + k
            cos, sin = turns[0, index], turns[1, index]
        else:
            cos, sin = math.cos(psi[k]), math.sin(psi[k])
        for a in range(3):
            radial[a, k] = down[i, a] * cos + out[i, a] * sin
            elbow[a, k] = center[i, a] + radius[i] * radial[a, k]
    return first


@numba.njit(
    [numba.void(READ1, *(READ2,) * 4, READ2, READ1, READ2, READ2, READ1, READ1, READ1, READ2, READ_INTS1, READ2, READ3, READ_FLAGS1, WRITE1, WRITE2, WRITE1)],
    cache=True,
    error_model="numpy",
)
def _cheapest_rows(natural, hands, shoulder, wrist, circle_axis, center, radius, down, out, constants, limits, candidates, segments, kinds, parameters, boxes, in_trunk, swivels, elbows, depth):  # noqa: ANN001, ANN202, E501
    """:func:`cheapest_swivels` per frame ``i``: every candidate's cost as
    :func:`motor.arm.swivel_cost.candidate_costs` sums it, with the body's clearance penalty
    (:func:`motor.arm.candidate_clearance.candidate_penalty`) for the window's candidates (their
    elbows placed on the circle here, :func:`_window_of`), measured lazily — by
    increasing distance cost from the natural swivel, until that alone exceeds the least
    cost found; the wrist's load only for those, and the penalty only where the two do
    not exceed it (each sum with the penalty and the load, both ≥ 0, rounds to at least
    the sum without them) — and the least one's neighbours too, then the parabola through
    the three. A frame with a NaN input has every candidate measured: ``np.argmin`` then
    picks the first NaN. Where ``depth`` has rows, the elbow at the chosen swivel
    (:meth:`motor.arm.chain.ElbowCircle.elbow`) goes into ``elbows`` and how deep the arm
    then enters the body (:func:`motor.arm.candidate_clearance.candidate_depth`, before its floor at 0) into ``depth``."""
    count, width = candidates.size, 2 * WINDOW + 1
    loaded = hands.shape[0] != 0
    fixed = wrist_constants(constants)
    costs, known = np.empty(count), np.empty(count, dtype=np.bool_)
    distance, load, order = np.empty(width), np.empty(width), np.empty(width, dtype=np.int64)
    cell_of, window = np.empty(width, dtype=np.int64), np.empty(count, dtype=np.int64)
    psi, elbow, radial = np.empty(width), np.empty((3, width)), np.empty((3, width))
    turns = _cell_turns()
    meets = np.empty((2, kinds.size), dtype=np.bool_)
    m = (0.0,) * 9
    c = (0.0, 0.0, 0.0)
    for i in range(natural.size):
        s = (shoulder[i, 0], shoulder[i, 1], shoulder[i, 2])
        w = (wrist[i, 0], wrist[i, 1], wrist[i, 2])
        if loaded:
            m = hand_matrix(hands, i)
            c = (circle_axis[i, 0], circle_axis[i, 1], circle_axis[i, 2])
        first = _window_of(i, natural, center, radius, down, out, turns, psi, elbow, radial)
        low, high = (elbow[0].min(), elbow[1].min(), elbow[2].min()), (elbow[0].max(), elbow[1].max(), elbow[2].max())
        whole = not _finite((natural[i], *s, *w, *m, *c, *low, *high))
        least = math.inf
        known[:] = True
        cell = int(first) % count - 1
        for k in range(width):
            cell = cell + 1 if cell + 1 < count else 0
            cell_of[k], window[cell], known[cell] = cell, k, False
            distance[k], load[k] = natural_cost(psi[k] - natural[i]), -1.0
            whole |= distance[k] != distance[k]
        for j in range(count):  # the candidates beyond the window cost their distance and OUTSIDE
            if known[j]:
                costs[j] = natural_cost(turn_remainder(candidates[j] - natural[i] + np.pi) - np.pi) + OUTSIDE
                least = min(least, costs[j])
        row_meets(s, w, low, high, segments, boxes, meets)
        _by_distance(distance, order)
        for k in order:
            if not whole and distance[k] > least:
                break
            if loaded:
                load[k] = _wrist_load_at(k, m, c, w, elbow, radial, fixed, limits)
                if not whole and distance[k] + load[k] > least:
                    continue
            cost = _measured(k, distance, load, loaded, s, w, elbow, segments, kinds, parameters, boxes, in_trunk, meets)
            costs[cell_of[k]], known[cell_of[k]] = cost, True
            least = min(least, cost)
        best = _first_known_least(costs, known)
        for j in ((best - 1) % count, (best + 1) % count):
            if known[j]:
                continue
            k = window[j]
            if loaded and load[k] < 0.0:
                load[k] = _wrist_load_at(k, m, c, w, elbow, radial, fixed, limits)
            costs[j], known[j] = _measured(k, distance, load, loaded, s, w, elbow, segments, kinds, parameters, boxes, in_trunk, meets), True
        swivels[i] = candidates[best] + _parabola(costs[(best - 1) % count], costs[best], costs[(best + 1) % count]) * SWIVEL_STEP
        if depth.size == 0:
            continue
        cos, sin = math.cos(swivels[i]), math.sin(swivels[i])
        for a in range(3):
            elbows[i, a] = center[i, a] + (down[i, a] * cos + out[i, a] * sin) * radius[i]
        depth[i] = candidate_depth(s, w, elbows[i, 0], elbows[i, 1], elbows[i, 2], segments, kinds, parameters, boxes, in_trunk, meets)


def load_kernels() -> None:
    """Run this module's compiled loop once (it loads when the module is imported):
    :func:`motor.compiled.warm_up`."""
    one, points = np.zeros(1), np.zeros((1, 3))
    constants, limits = np.ones(14), np.array([-1.0, 1.0, -1.0, 1.0, -1.0, 1.0])
    tables = np.zeros((2, 4)), np.zeros(0, dtype=np.int64), np.zeros((0, 7)), np.zeros((0, 2, 3)), np.zeros(0, dtype=np.bool_)
    _cheapest_rows(one, np.array([[0.0, 0.0, 0.0, 1.0]]), *(points,) * 4, one, *(points,) * 2, constants, limits, CANDIDATES, *tables, np.empty(1), np.empty((1, 3)), np.empty(1))
