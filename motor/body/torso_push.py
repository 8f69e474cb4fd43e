"""How far the torso pushes points out, compiled: the arithmetic of
:func:`motor.body.collision.kept_out_of_torso` point by point (:func:`ray`,
:func:`eased_gap`, :func:`landed`, which its loops call) and the rounds of
:func:`motor.body.collision.hand_push_out_of_torso` hand by hand.

Most points cannot be moved at all: :func:`reachable` (and :func:`beyond_box` for a hand's
capsule whole) tells them by a few comparisons, and only the others are cast their rays.
:func:`near_rows` finds the wrists whose hands can come near the torso. A round of the
hand's push is three loops: :func:`hand_rays` places the points along each hand's capsule
and casts their rays, :func:`hand_depths` pushes them out and finds each hand's deepest
push, :func:`hand_moved` moves the wrists pushed by the weighted average of their points'
pushes; :func:`hand_pushes` gives how far the wrists moved in all. Between the loops numpy
does the two operations a compiled loop rounds differently in the last bit on the
machines measured: the easing's ``exp`` (numba's is not numpy's SIMD one) and the
weights' eighth power (numpy's ``** 8`` is its own power routine; the C library's ``pow``
and repeated multiplication are not it). Each is taken only where it counts — the
exponentials of the points within :data:`SOFT_BAND` of the surface or inside it, the
powers of the hands pushed — since numpy rounds an element alike wherever it lies in an
array. Every other step is numpy's, element by element in its order
(``tests/perf_equivalence/plain_collision.py`` keeps the numpy version): a push's length
is its squares summed first to last (``np.linalg.norm`` along an axis of three), the
weights and the weighted pushes are summed first to last (``weight.sum(axis=1)``, and
``np.einsum("nk,nkd->nd")`` from zero).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from motor import quaternion as quat
from motor.kernel_types import READ1, READ2, READ_INTS1, WRITE1, WRITE2, WRITE_INTS1, clip, maximum, minimum

#: Width (m) of the band in front of the torso's margin in which a point is eased out
#: (:func:`motor.body.collision.kept_out_of_torso`), and of the bands beyond its top and
#: bottom over which that push fades.
SOFT_BAND = 0.02
EDGE_BAND = 0.08
#: How far behind the torso's axis, in its half depths, lies the point from which points
#: are pushed out along rays.
RAY_DEPTH = 3.0
TINY = 1e-12
#: How far past a surface a pushed point lands at least (m): beyond rounding.
LANDED = 1e-9
#: The columns :func:`hand_rays` keeps per point along a hand: its coordinates (3), then
#: :func:`ray`'s but the exponential's argument (6).
HAND_COLUMNS = 9
#: How much (m) farther than :func:`reachable`'s box reaches a point it lets through:
#: far beyond the rounding of :func:`ray`'s numbers.
_BOX_SLACK = 1e-3


@numba.njit(cache=True, error_model="numpy", inline="always")
def _faded(beyond):  # noqa: ANN001, ANN202
    """1 where ``beyond`` ≤ 0 (inside an edge), falling smoothly (smoothstep) to 0 at
    :data:`EDGE_BAND`."""
    u = clip(beyond / EDGE_BAND, 0.0, 1.0)
    return 1.0 - u * u * (3.0 - 2.0 * u)


@numba.njit(cache=True, error_model="numpy", inline="always")
def ray(x, y, z, cx, cz, a, b, bottom, top):  # noqa: ANN001, ANN201
    """The ray of the point ``(x, y, z)`` out of the torso's grown ellipse (centre ``cx``,
    ``cz``, half axes ``a``, ``b``; ``bottom`` and ``top``): the point in units of the
    ellipse from the ray's origin ``u``, ``w``, where the ray leaves it (a fraction of
    the way to the point), the ray's length (m), how far out along it the point lies
    (m, at most :data:`SOFT_BAND`; 0 or less inside the ellipse or in its shadow), the
    edges' fade and the argument of easing's exponential."""
    u = (x - cx) / a
    w = (z - cz) / b + RAY_DEPTH
    square = u * u + w * w
    ahead = RAY_DEPTH * w
    disc = ahead * ahead - square * (RAY_DEPTH**2 - 1.0)
    exit_ = (ahead + math.sqrt(maximum(disc, 0.0))) / maximum(square, TINY)
    across, deep = u * a, w * b
    length = math.sqrt(across * across + deep * deep)
    gap = (1.0 - exit_) * length if disc > 0.0 and w > 0.0 else math.inf
    near = minimum(gap, SOFT_BAND)
    fade = _faded(bottom - y) * _faded(y - top)
    return u, w, exit_, length, near, fade, 2.0 * (minimum(near, SOFT_BAND) / SOFT_BAND - 1.0)


@numba.njit(cache=True, error_model="numpy", inline="always")
def reach_box(cz, a, b, bottom, top):  # noqa: ANN001, ANN201
    """What :func:`reachable` tests against, for the torso's grown ellipse (as
    :func:`ray` takes it): its box (how far from the centre in x, the greatest z, the
    least and greatest y), the inverse half axes and the square of the greatest
    ellipse radius (in units of the half axes) of a point in front of the centre."""
    reach = SOFT_BAND + _BOX_SLACK
    return a + reach, cz + b + reach, bottom - EDGE_BAND - _BOX_SLACK, top + EDGE_BAND + _BOX_SLACK, 1.0 / a, 1.0 / b, (1.0 + reach / min(a, b)) ** 2


@numba.njit(cache=True, error_model="numpy", inline="always")
def reachable(x, y, z, cx, cz, box):  # noqa: ANN001, ANN201
    """Whether the point ``(x, y, z)`` can be moved out of the torso's grown ellipse
    (centre ``cx``, ``cz``, as :func:`ray` takes it) at all, by a test far cheaper than
    its ray (:func:`reach_box`): a point moved lies on its ray before the exit point
    from the ellipse or less than :data:`SOFT_BAND` past it, and less than
    :data:`EDGE_BAND` beyond the bottom and top. So it lies within that of the ellipse's
    sides and front or behind it; and in front of the centre (where the ray has entered
    the ellipse: its entry lies a third of the half depth behind the centre or more) its
    ellipse radius exceeds 1 by at most :data:`SOFT_BAND` over the shorter half axis.
    Every point it rejects would keep its place (:func:`eased_gap` no farther out, or no
    fade); NaN and infinite coordinates are rejected."""
    if not (abs(x - cx) < box[0] and z < box[1] and box[2] < y < box[3]):
        return False
    if z < cz:
        return True
    u, w = (x - cx) * box[4], (z - cz) * box[5]
    return u * u + w * w < box[6]


@numba.njit(cache=True, error_model="numpy", inline="always")
def beyond_box(x0, y0, z0, x1, y1, z1, cx, box):  # noqa: ANN001, ANN201
    """Whether two points lie beyond one face of :func:`reachable`'s box: then so does
    every point between them (a point computed between them rounds far less than the
    box's slack), and none can be moved."""
    return (
        (x0 - cx >= box[0] and x1 - cx >= box[0])
        or (cx - x0 >= box[0] and cx - x1 >= box[0])
        or (z0 >= box[1] and z1 >= box[1])
        or (y0 <= box[2] and y1 <= box[2])
        or (y0 >= box[3] and y1 >= box[3])
    )


@numba.njit(cache=True, error_model="numpy", inline="always")
def eased_gap(near, rise):  # noqa: ANN001, ANN201
    """How far out (m) a point ``near`` out is eased to: as far from :data:`SOFT_BAND`
    on, else by the C² ease of numpy's exponential ``rise`` of :func:`ray`'s argument
    (read only there); at least :data:`LANDED`. It moves where that is farther and
    :func:`ray`'s fade is positive."""
    return maximum(near if near >= SOFT_BAND else 2.0 * SOFT_BAND * rise / (1.0 + rise), LANDED)


@numba.njit(cache=True, error_model="numpy", inline="always")
def landed(u, w, exit_, length, near, fade, eased, cx, cz, a, b):  # noqa: ANN001, ANN201
    """Where (x, z) a point moved out lands, from :func:`ray`'s numbers and
    :func:`eased_gap`'s: measured from the exit point, so that a point pushed whole lands
    past the surface."""
    beyond = fade * eased + (1.0 - fade) * near
    return cx + (u * exit_ * a) + beyond * u * a / maximum(length, TINY), cz + (w * exit_ - RAY_DEPTH) * b + beyond * w * b / maximum(length, TINY)


@numba.njit([numba.int64(READ2, READ1, WRITE_INTS1)], cache=True, error_model="numpy")
def near_rows(wrists, bounds, near):  # noqa: ANN001, ANN201
    """Into ``near``, one after another: the rows of ``wrists`` ``(n, 3)`` within
    ``bounds`` (the torso's centre x, then the bounds on the distance from it in x, on y
    from below and above and on z from above; NaN rows are not). Returns how many."""
    count = 0
    for i in range(wrists.shape[0]):
        if abs(wrists[i, 0] - bounds[0]) < bounds[1] and wrists[i, 1] > bounds[2] and wrists[i, 1] < bounds[3] and wrists[i, 2] < bounds[4]:
            near[count] = i
            count += 1
    return count


@numba.njit([numba.types.UniTuple(numba.int64, 2)(READ2, READ2, READ_INTS1, READ_INTS1, READ2, READ1, READ1, WRITE_INTS1, WRITE2, WRITE1)], cache=True, error_model="numpy")
def hand_rays(wrists, hands, rows, hand_rows, ends, samples, shape, reached, table, arguments):  # noqa: ANN001, ANN201
    """The points at the fractions ``samples`` of the hand capsules of the ``rows`` of
    ``wrists`` ``(n, 3)`` and global hand rotations ``hands`` (a wrist's at its row of
    ``hand_rows``; ``ends``: the capsule's end points less the wrist at rest) and their
    rays out of the torso
    ``shape`` (centre x and z, grown half width and half depth, bottom and top), for the
    rows with a point :func:`reachable`, one after another: the row into ``reached``, its
    points into ``table`` (columns :data:`HAND_COLUMNS`; an unreachable point as no
    nearer than :data:`SOFT_BAND`, unfaded), the exponentials' arguments of the points
    :func:`eased_gap` eases into ``arguments``. Returns how many rows and how many
    arguments those are."""
    cx, cz, a, b, bottom, top = shape[0], shape[1], shape[2], shape[3], shape[4], shape[5]
    box = reach_box(cz, a, b, bottom, top)
    samples_per_row = samples.shape[0]
    count = eased = 0
    for i in range(rows.shape[0]):
        row = rows[i]
        hand = hand_rows[row]
        x, y, z, w = hands[hand, 0], hands[hand, 1], hands[hand, 2], hands[hand, 3]
        start_x, start_y, start_z = quat.rotated(x, y, z, w, ends[0, 0], ends[0, 1], ends[0, 2])
        end_x, end_y, end_z = quat.rotated(x, y, z, w, ends[1, 0], ends[1, 1], ends[1, 2])
        start_x, start_y, start_z = wrists[row, 0] + start_x, wrists[row, 1] + start_y, wrists[row, 2] + start_z
        end_x, end_y, end_z = wrists[row, 0] + end_x, wrists[row, 1] + end_y, wrists[row, 2] + end_z
        if beyond_box(start_x, start_y, start_z, end_x, end_y, end_z, cx, box):
            continue
        axis_x, axis_y, axis_z = end_x - start_x, end_y - start_y, end_z - start_z
        first = count * samples_per_row
        any_reached = False
        for k in range(samples_per_row):
            j = first + k
            px, py, pz = start_x + samples[k] * axis_x, start_y + samples[k] * axis_y, start_z + samples[k] * axis_z
            table[j, 0], table[j, 1], table[j, 2] = px, py, pz
            if not reachable(px, py, pz, cx, cz, box):
                table[j, 7], table[j, 8] = SOFT_BAND, 0.0
                continue
            any_reached = True
            u, w_, exit_, length, near, fade, argument = ray(px, py, pz, cx, cz, a, b, bottom, top)
            table[j, 3], table[j, 4], table[j, 5], table[j, 6], table[j, 7], table[j, 8] = u, w_, exit_, length, near, fade
            if not near >= SOFT_BAND:
                arguments[eased] = argument
                eased += 1
        if any_reached:
            reached[count] = row
            count += 1
    return count, eased


@numba.njit([numba.int64(READ2, READ1, READ_INTS1, READ1, WRITE2, WRITE1, WRITE_INTS1)], cache=True, error_model="numpy")
def hand_depths(table, rise, rows, shape, pushes, ratios, pushed):  # noqa: ANN001, ANN201
    """The pushes out of the torso ``shape`` of :func:`hand_rays`'s points of its ``rows``
    (those it reached), with numpy's exponentials ``rise`` of its arguments; for the rows
    pushed (deepest push > 0), one after another: the row into ``pushed``, its points'
    pushes into ``pushes`` and their lengths over the deepest's into ``ratios``. Returns
    how many rows were pushed."""
    cx, cz, a, b = shape[0], shape[1], shape[2], shape[3]
    samples = table.shape[0] // maximum(rows.shape[0], 1)
    used = count = 0
    for i in range(rows.shape[0]):
        deepest = 0.0
        for k in range(samples):
            j, slot = i * samples + k, count * samples + k
            px, py, pz, u, w, exit_, length, near, fade = table[j, 0], table[j, 1], table[j, 2], table[j, 3], table[j, 4], table[j, 5], table[j, 6], table[j, 7], table[j, 8]
            out_x, out_z = px, pz
            if not near >= SOFT_BAND:
                eased = eased_gap(near, rise[used])
                used += 1
                if eased > near and fade > 0.0:
                    out_x, out_z = landed(u, w, exit_, length, near, fade, eased, cx, cz, a, b)
            push_x, push_y, push_z = out_x - px, py - py, out_z - pz
            pushes[slot, 0], pushes[slot, 1], pushes[slot, 2] = push_x, push_y, push_z
            depth = quat.length3(push_x, push_y, push_z)
            ratios[slot] = depth
            deepest = depth if k == 0 else maximum(deepest, depth)
        if deepest > 0.0:
            for k in range(samples):
                ratios[count * samples + k] = ratios[count * samples + k] / deepest
            pushed[count] = rows[i]
            count += 1
    return count


@numba.njit([numba.void(READ_INTS1, READ2, READ1, WRITE2)], cache=True, error_model="numpy")
def hand_moved(pushed, pushes, weights, wrists):  # noqa: ANN001, ANN201
    """The ``pushed`` rows of ``wrists`` moved by the average of :func:`hand_depths`'s
    ``pushes`` weighted by ``weights`` (numpy's eighth powers of its ratios), summed
    first to last, over the weights' sum (at least 1)."""
    samples = weights.shape[0] // maximum(pushed.shape[0], 1)
    for i in range(pushed.shape[0]):
        first = i * samples
        total = weights[first]
        for k in range(1, samples):
            total += weights[first + k]
        total = maximum(total, 1.0)
        for d in range(3):
            weighted = 0.0
            for k in range(samples):
                weighted += weights[first + k] * pushes[first + k, d]
            wrists[pushed[i], d] = wrists[pushed[i], d] + weighted / total


@numba.njit([numba.void(READ_INTS1, READ2, READ2, WRITE2)], cache=True, error_model="numpy")
def hand_pushes(near, cleared, kept, push):  # noqa: ANN001, ANN201
    """Into the rows ``near`` of ``push``: how far the wrists ``kept`` moved to ``cleared``."""
    for i in range(near.shape[0]):
        for d in range(3):
            push[near[i], d] = cleared[i, d] - kept[i, d]


def load_kernels() -> None:
    """Run this module's compiled loops once (they load when it is imported):
    :func:`motor.compiled.warm_up`."""
    wrists, hands, rows, samples = np.zeros((1, 3)), np.array([[0.0, 0.0, 0.0, 1.0]]), np.zeros(1, dtype=np.int64), np.array([0.0, 1.0])
    shape, table, ratios, pushes = np.array([0.0, 0.0, 0.2, 0.1, 0.0, 1.0]), np.empty((2, HAND_COLUMNS)), np.empty(2), np.empty((2, 3))
    near_rows(wrists, np.ones(5), rows.copy())
    count, eased = hand_rays(wrists, hands, rows, rows, np.zeros((2, 3)), samples, shape, rows.copy(), table, np.empty(2))
    many = hand_depths(table, np.ones(eased), rows[:count], shape, pushes, ratios, rows.copy())
    hand_moved(rows[:many], pushes, np.ones(2 * many), wrists)
    hand_pushes(rows, wrists, wrists, np.empty((1, 3)))
