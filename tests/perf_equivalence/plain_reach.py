"""The reach check's steps as numpy passes over the open rows, as
:func:`motor.signing.reach.within_reach` computed them before its compiled steps
(:mod:`motor.signing.reach_steps`): the plain path they are held to, bit for bit, by
``test_reach_steps.py``. Not used by mura itself."""

from __future__ import annotations

import numpy as np

from motor.arm.ik import ArmReach
from motor.body.avatar import Avatar
from motor.body.conventions import AVATAR_SIDE
from motor.signing.reach import CROSS_STEP, CROSS_STEPS, PENETRATION_TOLERANCE, REACH_MARGIN, REACH_TOLERANCE, _solve_in_chunks


def within_reach(avatar: Avatar, arm: str, points: np.ndarray, rotations: np.ndarray | None, across: bool = True) -> tuple[np.ndarray, np.ndarray, float]:
    """Every row's position, which moved and the largest shortfall."""
    side = AVATAR_SIDE[arm]
    shoulder = avatar.rest_positions[avatar.joint_index(f"{side}_shoulder")]
    outward = np.array([-1.0 if arm == "right" else 1.0, 0.0, 1.0]) * CROSS_STEP
    forward = np.array([0.0, 0.0, CROSS_STEP])
    fixed = np.array(points, dtype=float)
    moved = np.zeros(len(fixed), dtype=bool)
    open_ = np.arange(len(fixed))
    worst = 0.0
    for _ in range(CROSS_STEPS):
        if open_.size == 0:
            break
        here = fixed[open_]
        turns = None if rotations is None else np.asarray(rotations)[open_]
        away = here - shoulder
        away /= np.maximum(np.linalg.norm(away, axis=1, keepdims=True), 1e-9)
        both = _solve_in_chunks(
            avatar, side, np.concatenate([here + REACH_MARGIN * away, here - REACH_MARGIN * away]),
            None if turns is None else np.concatenate([turns, turns]),
        )
        far, near = (ArmReach(*(column[rows] for column in both)) for rows in (slice(0, len(here)), slice(len(here), None)))
        outer = np.linalg.norm(here - shoulder, axis=1) > 0.5 * avatar.arm_length(side)
        short = (far.shortfall > REACH_TOLERANCE) | (near.shortfall > REACH_TOLERANCE)
        too_far = short & outer
        too_near = short & ~outer
        crossing = (np.maximum(far.penetration, near.penetration) > PENETRATION_TOLERANCE) & across
        bad = too_far | too_near | crossing
        worst = max(worst, float(np.max(far.shortfall - REACH_MARGIN, initial=0.0)))
        here = np.where(too_far[:, None], far.wrist - REACH_MARGIN * away, here)
        lacking = np.maximum(np.maximum(far.shortfall, near.shortfall), CROSS_STEP)
        around = away + forward / CROSS_STEP
        around /= np.maximum(np.linalg.norm(around, axis=1, keepdims=True), 1e-9)
        here = here + (too_near * lacking)[:, None] * around + crossing[:, None] * outward
        fixed[open_] = here
        moved[open_[bad]] = True
        open_ = open_[bad]
    return fixed, moved, max(worst, 0.0)
