"""The trunk's turn for a hand reaching across the body (:func:`motor.arm.reach_turn.trunk_turn`),
its reach check worked out only where the other arm asks for a turn, gives the very
numbers of checking every instant (``plain_reach_turn.py``)."""

from __future__ import annotations

import numpy as np
import pytest
from plain_reach_turn import trunk_turn as plain_trunk_turn

from motor.arm.reach_turn import trunk_turn
from motor.body.avatar import load_avatar

RNG = np.random.default_rng(2026_12_02)


def _wrists(avatar, kind: str, count: int) -> tuple[np.ndarray, np.ndarray]:
    """Left and right wrist targets ``(n, 3)`` (avatar frame) of one kind of instant."""
    chest = np.array([0.0, avatar.rest_positions[avatar.joint_index("vt6")][1], avatar.grid.front])
    left = chest + np.array([0.25, -0.1, 0.3]) + 0.05 * RNG.normal(size=(count, 3))
    right = chest + np.array([-0.25, -0.1, 0.3]) + 0.05 * RNG.normal(size=(count, 3))
    if kind == "right hand across":
        right[:, 0] = chest[0] + 0.35 * RNG.random(count)
        right[:, 2] = chest[2] + 0.05 + 0.3 * RNG.random(count)
    elif kind == "both across":
        right[:, 0] = chest[0] + 0.35 * RNG.random(count)
        left[:, 0] = chest[0] - 0.35 * RNG.random(count)
    elif kind == "across, the other far out":
        right[:, 0] = chest[0] + 0.3
        left[:] = chest + np.array([0.8, 0.3, 0.5])
    elif kind == "mixed with NaN":
        right[::2, 0] = chest[0] + 0.2
        left[1::5] = np.nan
        right[3::7, 2] = np.nan
    return left, right


@pytest.mark.parametrize("count", [0, 1, 300])
@pytest.mark.parametrize("kind", ["at the sides", "right hand across", "both across", "across, the other far out", "mixed with NaN"])
@pytest.mark.parametrize("avatar_name", ["max", "makehuman"])
def test_the_turn_is_the_turn_of_checking_every_instant(avatar_name, kind, count):
    avatar = load_avatar(avatar_name)
    left, right = _wrists(avatar, kind, count)
    got, expected = trunk_turn(avatar, left, right), plain_trunk_turn(avatar, left, right)
    assert (got is None) == (expected is None)
    if expected is not None:
        np.testing.assert_array_equal(got.yaw, expected.yaw)
        np.testing.assert_array_equal(got.spine_rotations, expected.spine_rotations)
    if kind in ("right hand across", "both across") and count > 1:
        assert expected is not None and np.ptp(expected.yaw) > 0.0  # the table turns the trunk: the comparison can fail
