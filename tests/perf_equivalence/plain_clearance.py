"""The numpy arm-against-body clearance as it stood before it was compiled
(:func:`motor.arm.clearance._body_clearance`, issue 19), and the numpy arm-against-the-other-arm
loop of :func:`motor.arm.clearance.clearance` (:func:`other_arm_clearance`): the plain
paths the compiled kernels are held to, bit for bit, by ``test_compiled_clearance.py``
and ``test_other_arm_clearance.py``. Not used by mura itself."""

from __future__ import annotations

import numpy as np

from motor import quaternion as quat
from motor.arm.clearance import CLEARANCE, ArmCapsules, ArmSegments, Obstacle, overlap_penalty, penalty
from motor.body.distance import segments_apart
from tests.perf_equivalence.plain_distance import Components, capsule_apart


def _body_clearance(
    capsules: ArmCapsules,
    obstacles: tuple[Obstacle, ...],
    shoulder: np.ndarray,
    wrist: np.ndarray,
    elbow: Components,
    frame: tuple[np.ndarray, np.ndarray] | None,
    cost: np.ndarray,
    depth: np.ndarray,
    trunk: list[np.ndarray],
) -> None:
    """:func:`clearance`'s penalty and depth of the arm against ``obstacles`` whose rest
    geometry ``frame`` carries to where they are, added into ``cost`` and ``depth``; the
    trunk's volumes (a torso and a chest: one body cut in two) are not penalized one by
    one but give ``trunk``, per segment, the least distance from any of them, so that a
    segment near the cut pays once."""
    if frame is not None:
        rotation, translation = frame
        inverse = quat.conjugate(rotation)
        shoulder, wrist = (quat.rotate(inverse, p - translation) for p in (shoulder, wrist))
        stacked = np.stack(elbow, axis=-1) - translation[:, None]
        elbow = tuple(np.moveaxis(quat.rotate(inverse[:, None], stacked), -1, 0))
    boxes = _boxes(capsules, shoulder, wrist, elbow)
    for (a, b, radius), (low, high), least in zip(_segments(capsules, shoulder, wrist, elbow), boxes, trunk):
        for obstacle in obstacles:
            near = np.all((low <= obstacle.box[1]) & (high >= obstacle.box[0]), axis=1)
            if not np.any(near):
                continue
            if np.all(near):
                distance = capsule_apart(obstacle.volume, a, b, radius)
                if obstacle.trunk:
                    np.minimum(least, distance, out=least)
                else:
                    cost += overlap_penalty(distance)
                np.maximum(depth, -distance, out=depth)
                continue
            rows = np.flatnonzero(near)
            distance = capsule_apart(obstacle.volume, tuple(c[rows] for c in a), tuple(c[rows] for c in b), radius)
            if obstacle.trunk:
                least[rows] = np.minimum(least[rows], distance)
            else:
                cost[rows] += overlap_penalty(distance)
            depth[rows] = np.maximum(depth[rows], -distance)


def body_costs(avatar, capsules, shoulder, wrist, elbow, body_frame, cost, depth) -> None:
    """The numpy ``_body_costs`` where the trunk turns nowhere (no carried frames): the
    upright obstacles into arrays of their own, the trunk's least distances charged
    after, then added into ``cost`` and ``depth``."""
    from motor.arm.clearance import upright_obstacles

    part_cost, part_depth = np.zeros(cost.shape), np.zeros(cost.shape)
    trunk = [np.full(part_cost.shape, np.inf), np.full(part_cost.shape, np.inf)]
    _body_clearance(capsules, upright_obstacles(avatar), shoulder, wrist, elbow, body_frame, part_cost, part_depth, trunk)
    for distance in trunk:
        near = np.isfinite(distance)
        part_cost[near] += overlap_penalty(distance[near])
    cost += part_cost
    np.maximum(depth, part_depth, out=depth)


def turned_body_costs(avatar, capsules, shoulder, wrist, elbow, body_frame, carried_frames) -> tuple[np.ndarray, np.ndarray]:
    """The ``_body_costs`` of :mod:`motor.arm.clearance` before its groups went into one
    compiled loop: per group of obstacles (upright where the trunk does not turn, by
    carrying joints where it does), the rows of its kind measured against them, the
    trunk's least distances charged after (with this module's numpy measurement)."""
    from motor.arm.clearance import _by_carriers, upright_obstacles

    shape = elbow[0].shape
    cost, depth = np.zeros(shape), np.zeros(shape)
    if carried_frames is None:
        body_costs(avatar, capsules, shoulder, wrist, elbow, body_frame, cost, depth)
        return cost, depth
    upright = np.all(carried_frames[0][0] == quat.IDENTITY, axis=1)
    for rows, obstacles in ((upright, None), (~upright, _by_carriers(avatar))):
        if not np.any(rows):
            continue
        every = bool(np.all(rows))
        pick = (lambda value: value) if every else (lambda value: value[rows])
        frame = lambda f: None if f is None else (pick(f[0]), pick(f[1]))
        if obstacles is None:
            groups = ((upright_obstacles(avatar), frame(body_frame)),)
        else:
            groups = tuple(zip(obstacles, (*(frame(f) for f in carried_frames), frame(body_frame))))
        part_cost, part_depth = np.zeros(pick(cost).shape), np.zeros(pick(cost).shape)
        trunk = [np.full(part_cost.shape, np.inf), np.full(part_cost.shape, np.inf)]
        for found, where in groups:
            if found:
                _body_clearance(capsules, found, pick(shoulder), pick(wrist), tuple(pick(c) for c in elbow), where, part_cost, part_depth, trunk)
        for distance in trunk:
            near = np.isfinite(distance)
            part_cost[near] += overlap_penalty(distance[near])
        if every:
            return part_cost, part_depth
        cost[rows], depth[rows] = part_cost, part_depth
    return cost, depth


def _capsules(other: ArmSegments) -> tuple[tuple[np.ndarray, np.ndarray, float], ...]:
    """The other arm's capsules: end points ``(n, 3)`` and radius, upper arm, forearm, hand."""
    return tuple((a, b, r) for (a, b), r in zip((other.upper, other.fore, other.hand), other.radii))


def other_arm_clearance(capsules: ArmCapsules, shoulder: np.ndarray, wrist: np.ndarray, elbow: Components, other: ArmSegments, cost: np.ndarray) -> None:
    """The numpy loop of :func:`motor.arm.clearance.clearance` that added into ``cost`` the
    penalty of the candidates coming near the ``other`` arm's capsules."""
    boxes = _boxes(capsules, shoulder, wrist, elbow)
    for (a, b, radius), (low, high) in zip(_segments(capsules, shoulder, wrist, elbow), boxes):
        for part, (a_other, b_other, r_other) in zip(("upper", "fore", "hand"), _capsules(other)):
            near = np.all((low <= np.maximum(a_other, b_other) + r_other) & (high >= np.minimum(a_other, b_other) - r_other), axis=1)
            if not np.any(near):
                continue
            rows = np.flatnonzero(near)
            ends = tuple(a_other[rows, i : i + 1] for i in range(3)), tuple(b_other[rows, i : i + 1] for i in range(3))
            distance = segments_apart(tuple(c[rows] for c in a), tuple(c[rows] for c in b), *ends)
            # hands may touch the other arm (where it is asked): theirs is the plain penalty
            cost[rows] += (penalty if part == "hand" else overlap_penalty)(distance - radius - r_other)


def other_arm_costs(avatar, placement, natural: np.ndarray, other: ArmSegments) -> np.ndarray:
    """``motor.arm.swivel_cost._other_arm_costs`` before it was compiled: the frames near
    the other arm picked out in numpy, their placements taken, their window's elbows
    placed and measured by :func:`other_arm_clearance`, and put in their cells."""
    from motor.arm.clearance import arm_capsules
    from motor.arm.swivel_cost import CANDIDATES, candidate_elbows, measured_window

    count = len(CANDIDATES)
    costs = np.zeros((len(natural), count))
    circle = placement.circle
    own = arm_capsules(avatar, placement.chain.side)
    reach = circle.radius[:, None] + max(other.radii) + max(own.upper_radius, own.fore_radius) + CLEARANCE
    low = np.minimum(np.minimum(circle.shoulder, circle.wrist), circle.center - reach)
    high = np.maximum(np.maximum(circle.shoulder, circle.wrist), circle.center + reach)
    near = np.zeros(len(natural), dtype=bool)
    for a, b, radius in _capsules(other):
        near |= np.all((low <= np.maximum(a, b) + radius) & (high >= np.minimum(a, b) - radius), axis=1)
    if not np.any(near):
        return costs
    rows = np.flatnonzero(near)
    cells, psi = measured_window(natural[rows])
    subset = placement.take(rows)
    elbow, _ = candidate_elbows(subset, np.cos(psi), np.sin(psi))
    penalty = np.zeros(elbow[0].shape)
    other_arm_clearance(own, subset.circle.shoulder, subset.circle.wrist, elbow, other.take(rows), penalty)
    window = np.zeros((len(rows), count))
    np.put_along_axis(window, cells.astype(np.int64) % count, penalty, axis=1)
    costs[rows] = window
    return costs


def _boxes(capsules: ArmCapsules, shoulder: np.ndarray, wrist: np.ndarray, elbow: Components) -> list[tuple[np.ndarray, np.ndarray]]:
    """Per frame, the boxes ``(n, 3)`` (low and high corners) holding the upper arm's and
    the forearm's capsules, grown by :data:`CLEARANCE`, for every candidate elbow: the
    capsules' ends are affine in the elbow with non-negative weights, so the box of the
    candidate elbows bounds them."""
    low = np.stack([c.min(axis=1) for c in elbow], axis=1)
    high = np.stack([c.max(axis=1) for c in elbow], axis=1)
    boxes = []
    for (u0, u1), start, from_start, radius in (
        (capsules.upper_ends, shoulder, True, capsules.upper_radius),
        (capsules.fore_ends, wrist, False, capsules.fore_radius),
    ):
        # an end at fraction f from the shoulder toward the elbow, or from the elbow toward the wrist
        weight = lambda f: f if from_start else 1.0 - f
        ends_low = [start + weight(f) * (low - start) for f in (u0, u1)]
        ends_high = [start + weight(f) * (high - start) for f in (u0, u1)]
        grow = radius + CLEARANCE
        boxes.append((np.minimum(*ends_low) - grow, np.maximum(*ends_high) + grow))
    return boxes


def _segments(capsules: ArmCapsules, shoulder: np.ndarray, wrist: np.ndarray, elbow: Components):
    """The upper arm's and forearm's capsules as coordinate arrays (``(n, K)``; ends that
    do not move with the elbow ``(n, 1)``) and radii."""
    s = tuple(shoulder[:, i : i + 1] for i in range(3))
    w = tuple(wrist[:, i : i + 1] for i in range(3))
    (u0, u1), (f0, f1) = capsules.upper_ends, capsules.fore_ends
    yield tuple(s[i] + u0 * (elbow[i] - s[i]) for i in range(3)), tuple(s[i] + u1 * (elbow[i] - s[i]) for i in range(3)), capsules.upper_radius
    yield tuple(elbow[i] + f0 * (w[i] - elbow[i]) for i in range(3)), tuple(elbow[i] + f1 * (w[i] - elbow[i]) for i in range(3)), capsules.fore_radius
