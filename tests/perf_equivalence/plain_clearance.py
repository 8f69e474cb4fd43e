"""The numpy arm-against-body clearance as it stood before it was compiled
(:func:`motor.arm.clearance._body_clearance`, issue 19): the plain path the compiled
kernel is held to, bit for bit, by ``test_compiled_clearance.py``. Not used by mura itself."""

from __future__ import annotations

import numpy as np

from motor import quaternion as quat
from motor.arm.clearance import ArmCapsules, Obstacle, _boxes, _segments, overlap_penalty
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
