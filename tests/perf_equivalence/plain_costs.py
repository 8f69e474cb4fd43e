"""The numpy costs of the swivel candidates as they stood before they were compiled
(:func:`motor.arm.swivel_cost.candidate_costs` of the arm's own candidates, issue 19): the
plain path the compiled loop (``_cost_rows``) is held to by ``test_compiled_costs.py`` —
bit for bit without a hand rotation, within numba's ``atan2`` (the wrist state) with one.
Not used by mura itself."""

from __future__ import annotations

import numpy as np

from motor.arm.chain import ArmPlacement
from motor.arm.clearance import clearance
from motor.arm.swivel_cost import (
    CANDIDATES,
    DEVIATION_WEIGHT,
    FLEXION_WEIGHT,
    OUTSIDE,
    RANGE_WEIGHT,
    RESIDUAL_SATURATION,
    RESIDUAL_WEIGHT,
    SWIVEL_RANGE,
    SWIVEL_SCALE,
    candidate_elbows,
    measured_window,
)
from motor.body.avatar import Avatar
from motor.body.distance import Components
from tests.perf_equivalence.plain_wrist import wrist_state


def natural_cost(away: np.ndarray) -> np.ndarray:
    """The cost of being ``away`` radians (in [-π, π]) from the natural swivel."""
    beyond = np.maximum(np.abs(away) - SWIVEL_RANGE, 0.0)
    return away * away * (1.0 / SWIVEL_SCALE**2) + RANGE_WEIGHT * beyond * beyond


def candidate_costs(avatar: Avatar, placement: ArmPlacement, natural: np.ndarray, nearby: np.ndarray | None = None) -> np.ndarray:
    count = len(CANDIDATES)
    cells, psi = measured_window(natural)
    elbow, radial = candidate_elbows(placement, np.cos(psi), np.sin(psi))
    circle = placement.circle
    penalty, _ = clearance(avatar, placement.chain.side, circle.shoulder, circle.wrist, elbow, placement.body_frame, carried_frames=placement.carried_frames)
    if nearby is not None:
        penalty = np.maximum(penalty, np.take_along_axis(nearby, cells.astype(np.int64) % count, axis=1))
    measured = natural_cost(psi - natural[:, None]) + penalty
    if placement.hands is not None:
        measured += wrist_cost(placement, elbow, radial)
    costs = natural_cost((CANDIDATES[None, :] - natural[:, None] + np.pi) % (2.0 * np.pi) - np.pi) + OUTSIDE
    np.put_along_axis(costs, cells.astype(np.int64) % count, measured, axis=1)
    return costs


def wrist_cost(placement: ArmPlacement, elbow: Components, radial: Components) -> np.ndarray:
    """The wrist's load for elbows at ``elbow`` (directions ``radial`` from the circle's
    centre), the hand rotated as ``placement.hands``."""
    chain = placement.chain
    flexion, deviation, twist, _ = wrist_state(placement, elbow, radial)
    excess = lambda value, limits: value - np.minimum(np.maximum(value, limits[0]), limits[1])
    unreached = excess(flexion, chain.wrist_flexion) ** 2 + excess(deviation, chain.wrist_deviation) ** 2 + excess(twist, chain.twist_range) ** 2
    deviation = deviation / np.where(deviation >= 0, chain.wrist_deviation[1], -chain.wrist_deviation[0])
    flexion = flexion / np.where(flexion >= 0, chain.wrist_flexion[1], -chain.wrist_flexion[0])
    return DEVIATION_WEIGHT * deviation * deviation + FLEXION_WEIGHT * flexion * flexion + RESIDUAL_WEIGHT * unreached / (1.0 + unreached / RESIDUAL_SATURATION**2)


