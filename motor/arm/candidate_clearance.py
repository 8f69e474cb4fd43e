"""How close an arm comes to the body, measured per frame and candidate elbow, compiled.

The costs of :mod:`motor.arm.clearance` come from these loops: the arm's two segments
(:func:`motor.arm.clearance.segment_table`) against the body's volumes
(:func:`motor.arm.clearance.obstacle_table`), every
candidate elbow of a frame at once (:func:`clearance_rows`, whose frames are first
narrowed to the volumes that the box of all their candidates meets, :func:`row_meets`),
or one candidate at a time for compiled callers that measure only some
(:func:`candidate_penalty`, :func:`candidate_depth`: the cheapest swivel of a lone
posture). Each gives the numbers of the numpy arithmetic it replaced, the same operations
in the same order (``tests/perf_equivalence/plain_clearance.py``). Distances are metres.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from motor import quaternion as quat
from motor.body.distance import volume_distance
from motor.kernel_types import READ2, READ3, READ_FLAGS1, READ_INTS1, READ_INTS2, WRITE2

#: Clearance (m) a segment keeps from an obstacle before it is penalized.
CLEARANCE = 0.01
#: Penalty of a segment at the obstacle's surface; it grows with the square of the
#: distance inside the clearance, per :data:`CLEARANCE`.
CONTACT_PENALTY = 50.0
#: Further penalty of a segment deeper than :data:`TOLERATED_DEPTH` (m) inside the body
#: or the other arm's upper arm and forearm, per :data:`CLEARANCE` of the depth beyond it,
#: squared: a hand rotation the swivel leaves unachieved (up to 312,
#: :mod:`motor.arm.swivel_cost`) must not buy an upper arm a centimetre into the chest.
#: Tolerating a few millimetres keeps the cost of arms that merely touch as it was.
PENETRATION_PENALTY = 300.0
TOLERATED_DEPTH = 0.005


@numba.njit(cache=True, error_model="numpy")
def _to_rest(qx, qy, qz, qw, tx, ty, tz, px, py, pz):  # noqa: ANN001, ANN202
    """A point carried back by the placement ``(q, t)``: ``rotate(conjugate(q), p - t)``."""
    return quat.rotated(-qx, -qy, -qz, qw, px - tx, py - ty, pz - tz)


@numba.njit(cache=True, error_model="numpy")
def overlap_cost(distance):  # noqa: ANN001, ANN202
    """:func:`motor.arm.clearance.overlap_penalty` of one distance, the same operations in
    the same order; for compiled callers."""
    inside = max(CLEARANCE - distance, 0.0) * (1.0 / CLEARANCE)
    depth = max(-distance - TOLERATED_DEPTH, 0.0) * (1.0 / CLEARANCE)
    return CONTACT_PENALTY * inside * inside + PENETRATION_PENALTY * depth * depth


@numba.njit(cache=True, error_model="numpy")
def _boxes_meet(low, high, box):  # noqa: ANN001, ANN202
    """Whether the box from ``low`` to ``high`` meets ``box (2, 3)`` (touching counts)."""
    return low[0] <= box[1, 0] and high[0] >= box[0, 0] and low[1] <= box[1, 1] and high[1] >= box[0, 1] and low[2] <= box[1, 2] and high[2] >= box[0, 2]


@numba.njit(
    [numba.void(WRITE2, READ2, READ2)],
    cache=True,
    error_model="numpy",
)
def charge_trunk(cost, least_upper, least_fore):  # noqa: ANN001, ANN202
    """Add into ``cost`` the penalty of the trunk's least distances (:func:`overlap_penalty`),
    upper arm then forearm, where there is one."""
    for i in range(cost.shape[0]):
        for k in range(cost.shape[1]):
            for least in (least_upper[i, k], least_fore[i, k]):
                if least < math.inf:
                    cost[i, k] += overlap_cost(least)


@numba.njit(cache=True, error_model="numpy", inline="always")
def _segment_box(start, w0, w1, low, high, grow):  # noqa: ANN001, ANN202
    """The low and high corners (3-tuples) of the box of a segment whose ends lie at
    fractions ``w0``, ``w1`` of the way from ``start`` to any point of the box
    ``low``–``high`` (the candidate elbows'), grown by ``grow``: its ends are affine in
    that point with non-negative weights."""
    lower = lambda c: min(start[c] + w0 * (low[c] - start[c]), start[c] + w1 * (low[c] - start[c])) - grow
    upper = lambda c: max(start[c] + w0 * (high[c] - start[c]), start[c] + w1 * (high[c] - start[c])) + grow
    return (lower(0), lower(1), lower(2)), (upper(0), upper(1), upper(2))


@numba.njit(cache=True, error_model="numpy", inline="always")
def row_meets(s, w, low, high, segments, boxes, meets):  # noqa: ANN001, ANN201
    """Into ``meets (2, V)``: whether the box of the upper arm (row 0) and of the forearm
    (row 1) of an arm from shoulder ``s`` to wrist ``w`` (3-tuples), over all candidate
    elbows in the box ``low``–``high``, meets each obstacle's box ``boxes (V, 2, 3)``:
    the obstacles a frame's candidates are measured against."""
    for g in range(2):
        f0, f1, radius, from_shoulder = segments[g, 0], segments[g, 1], segments[g, 2], segments[g, 3] > 0.5
        start = s if from_shoulder else w
        w0, w1 = (f0, f1) if from_shoulder else (1.0 - f0, 1.0 - f1)
        box_low, box_high = _segment_box(start, w0, w1, low, high, radius + CLEARANCE)
        for v in range(boxes.shape[0]):
            meets[g, v] = _boxes_meet(box_low, box_high, boxes[v])


@numba.njit(cache=True, error_model="numpy", inline="always")
def segment_ends(s, w, ex_, ey_, ez_, f0, f1, from_shoulder):  # noqa: ANN001, ANN202
    """The ends of a segment at fractions ``f0``, ``f1`` of the way shoulder → elbow (the
    upper arm) or elbow → wrist (the forearm), for the elbow at ``ex_, ey_, ez_``."""
    if from_shoulder:
        return (s[0] + f0 * (ex_ - s[0]), s[1] + f0 * (ey_ - s[1]), s[2] + f0 * (ez_ - s[2]),
                s[0] + f1 * (ex_ - s[0]), s[1] + f1 * (ey_ - s[1]), s[2] + f1 * (ez_ - s[2]))  # fmt: skip
    return (ex_ + f0 * (w[0] - ex_), ey_ + f0 * (w[1] - ey_), ez_ + f0 * (w[2] - ez_),
            ex_ + f1 * (w[0] - ex_), ey_ + f1 * (w[1] - ey_), ez_ + f1 * (w[2] - ez_))  # fmt: skip


@numba.njit(cache=True, error_model="numpy", inline="always")
def _misses(box, grow, ax, ay, az, bx, by, bz):  # noqa: ANN001, ANN202
    """Whether the segment's box grown by ``grow`` misses ``box (2, 3)``: the segment is then
    more than ``grow`` less its radius from the volume (every distance here is at least
    the Euclidean one) and is not measured."""
    return (
        min(ax, bx) - grow > box[1, 0] or max(ax, bx) + grow < box[0, 0]
        or min(ay, by) - grow > box[1, 1] or max(ay, by) + grow < box[0, 1]
        or min(az, bz) - grow > box[1, 2] or max(az, bz) + grow < box[0, 2]
    )  # fmt: skip


@numba.njit(
    [numba.void(READ2, READ2, READ2, READ2, READ2, READ3, READ3, READ_FLAGS1, READ_INTS2, READ_INTS2, READ_FLAGS1, READ2, READ_INTS1, READ2, READ3, READ_FLAGS1, WRITE2, WRITE2, WRITE2, WRITE2)],
    cache=True,
    error_model="numpy",
)
def clearance_rows(shoulder, wrist, ex, ey, ez, rotations, translations, framed, groups, sets, turned, segments, kinds, parameters, boxes, in_trunk, cost, depth, least_upper, least_fore):  # noqa: ANN001, ANN202, E501
    """Per frame ``i``, into ``cost`` and ``depth (n, K)``: the penalty and depth of every
    candidate elbow ``ex, ey, ez (n, K)`` of the arm from ``shoulder`` to ``wrist (n, 3)``
    against the body's obstacles (a :func:`motor.arm.clearance.obstacle_table` of them
    all), group by group: the groups ``groups[sets[1, 0]:sets[1, 1]]`` where the trunk
    is ``turned[i]``, ``groups[sets[0, 0]:sets[0, 1]]`` where it is not, each a row
    ``(first obstacle, stop, frame)`` whose obstacles the placement ``rotations[frame, i]``,
    ``translations[frame, i]`` carries from their rest geometry (where ``framed[frame]``;
    else they stand at rest). Per group: the candidates (and shoulder and wrist) carried
    into the obstacles' rest frame, the box of each segment over all candidates (its
    ends are affine in the elbow with non-negative weights), and for every obstacle whose
    box it meets, the distance of each candidate segment whose own box meets it too;
    the trunk's volumes give ``least_upper`` and ``least_fore`` the least distance per
    segment from any of them, for :func:`charge_trunk` to charge once. The arithmetic of the
    numpy version (``tests/perf_equivalence/plain_clearance.py``), element by element,
    which measured every candidate of such a frame: the candidates not measured here
    added nothing there."""
    n, k_count = ex.shape
    local = np.empty((k_count, 3))
    meets = np.empty((2, kinds.size), dtype=np.bool_)
    for i in range(n):
        chosen = 1 if turned[i] else 0
        for group in range(sets[chosen, 0], sets[chosen, 1]):
            first, stop, frame = groups[group, 0], groups[group, 1], groups[group, 2]
            s = (shoulder[i, 0], shoulder[i, 1], shoulder[i, 2])
            w = (wrist[i, 0], wrist[i, 1], wrist[i, 2])
            if framed[frame]:
                q = (rotations[frame, i, 0], rotations[frame, i, 1], rotations[frame, i, 2], rotations[frame, i, 3])
                t = (translations[frame, i, 0], translations[frame, i, 1], translations[frame, i, 2])
                s = _to_rest(*q, *t, *s)
                w = _to_rest(*q, *t, *w)
                for k in range(k_count):
                    local[k, 0], local[k, 1], local[k, 2] = _to_rest(*q, *t, ex[i, k], ey[i, k], ez[i, k])
            else:
                for k in range(k_count):
                    local[k, 0], local[k, 1], local[k, 2] = ex[i, k], ey[i, k], ez[i, k]
            low = (local[:, 0].min(), local[:, 1].min(), local[:, 2].min())
            high = (local[:, 0].max(), local[:, 1].max(), local[:, 2].max())
            row_meets(s, w, low, high, segments, boxes[first:stop], meets)
            for g in range(2):
                f0, f1, radius, from_shoulder = segments[g, 0], segments[g, 1], segments[g, 2], segments[g, 3] > 0.5
                grow = radius + CLEARANCE
                least = least_upper if g == 0 else least_fore
                for v in range(first, stop):
                    if not meets[g, v - first]:
                        continue
                    box = boxes[v]
                    for k in range(k_count):
                        ax, ay, az, bx, by, bz = segment_ends(s, w, local[k, 0], local[k, 1], local[k, 2], f0, f1, from_shoulder)
                        # a candidate whose own segment's box misses the volume's adds nothing
                        if _misses(box, grow, ax, ay, az, bx, by, bz):
                            continue
                        distance = volume_distance(kinds[v], parameters[v], ax, ay, az, bx, by, bz, radius)
                        if in_trunk[v]:
                            least[i, k] = min(least[i, k], distance)
                        else:
                            cost[i, k] += overlap_cost(distance)
                        depth[i, k] = max(depth[i, k], -distance)


@numba.njit(cache=True, error_model="numpy", inline="always")
def candidate_penalty(s, w, ex_, ey_, ez_, segments, kinds, parameters, boxes, in_trunk, meets):  # noqa: ANN001, ANN201
    """:func:`clearance`'s penalty of one candidate elbow ``ex_, ey_, ez_`` of an arm from
    shoulder ``s`` to wrist ``w`` (3-tuples) against the obstacles of an
    :func:`motor.arm.clearance.obstacle_table` at rest that its frame's candidates meet (:func:`row_meets`),
    with the arm's :func:`motor.arm.clearance.segment_table`: the sums :func:`clearance_rows` and
    :func:`charge_trunk` make for it, in their order (the other obstacles by segment,
    then the trunk's least distances); for compiled callers that measure candidates one
    by one."""
    cost, least_upper, least_fore = 0.0, math.inf, math.inf
    for g in range(2):
        f0, f1, radius, from_shoulder = segments[g, 0], segments[g, 1], segments[g, 2], segments[g, 3] > 0.5
        grow = radius + CLEARANCE
        ax, ay, az, bx, by, bz = segment_ends(s, w, ex_, ey_, ez_, f0, f1, from_shoulder)
        for v in range(kinds.size):
            if not meets[g, v] or _misses(boxes[v], grow, ax, ay, az, bx, by, bz):
                continue
            distance = volume_distance(kinds[v], parameters[v], ax, ay, az, bx, by, bz, radius)
            if not in_trunk[v]:
                cost += overlap_cost(distance)
            elif g == 0:
                least_upper = min(least_upper, distance)
            else:
                least_fore = min(least_fore, distance)
    for least in (least_upper, least_fore):
        if least < math.inf:
            cost += overlap_cost(least)
    return cost


@numba.njit(cache=True, error_model="numpy")
def candidate_depth(s, w, ex_, ey_, ez_, segments, kinds, parameters, boxes, in_trunk, meets):  # noqa: ANN001, ANN201
    """How deep (m; 0 if clear) the arm from shoulder ``s`` to wrist ``w`` (3-tuples) with
    its elbow at ``ex_, ey_, ez_`` enters the obstacles of an :func:`motor.arm.clearance.obstacle_table` at rest:
    what :func:`clearance_rows` gives one frame of one candidate, the same comparisons
    in the same order; for compiled callers that place one elbow. ``meets (2, V)`` is
    scratch."""
    elbow = (ex_, ey_, ez_)
    row_meets(s, w, elbow, elbow, segments, boxes, meets)
    deepest = 0.0
    for g in range(2):
        f0, f1, radius, from_shoulder = segments[g, 0], segments[g, 1], segments[g, 2], segments[g, 3] > 0.5
        grow = radius + CLEARANCE
        for v in range(kinds.size):
            if not meets[g, v]:
                continue
            ax, ay, az, bx, by, bz = segment_ends(s, w, ex_, ey_, ez_, f0, f1, from_shoulder)
            if _misses(boxes[v], grow, ax, ay, az, bx, by, bz):
                continue
            deepest = max(deepest, -volume_distance(kinds[v], parameters[v], ax, ay, az, bx, by, bz, radius))
    return deepest
