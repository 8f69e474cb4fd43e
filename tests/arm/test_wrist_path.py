"""Key locations the arm reaches only through the body move forward until it need not
(synthetic table: hands across the belly and chest, near the body and farther out)."""

from __future__ import annotations

import numpy as np
import pytest

from motor.arm.ik import solve_arm
from motor.arm.wrist_path import CROWDING_TOLERANCE, placed, uncrowded_placement
from motor.body.avatar import load_avatar

AVATARS = ("max", "makehuman")


@pytest.fixture(scope="module", params=AVATARS)
def avatar(request):
    return load_avatar(request.param)


def _targets(avatar) -> np.ndarray:
    """Right-hand targets from the own side across the midline to the far side, at belly,
    stomach and chest height, just in front of the torso and 25 cm out (metres)."""
    torso = avatar.torso
    xs = np.linspace(-0.15, 0.2, 8)
    ys = torso.bottom + np.array([0.1, 0.25, 0.4]) * (torso.top - torso.bottom)
    zs = torso.center[2] + torso.half_depth + np.array([0.08, 0.25])
    return np.array([[x, y, z] for x in xs for y in ys for z in zs])


def test_keys_are_moved_until_the_arm_reaches_them_clear_of_the_body(avatar):
    points = _targets(avatar)
    before = placed(avatar, "r", points).points
    crowded = solve_arm(avatar, "r", before).penetration > CROWDING_TOLERANCE
    assert np.any(crowded), "the table reaches across the body close to it"
    after = uncrowded_placement(avatar, "r", points)
    assert after.crowded == int(np.sum(crowded))
    assert np.all(solve_arm(avatar, "r", after.points).penetration <= CROWDING_TOLERANCE)
    np.testing.assert_array_equal(after.points[~crowded], before[~crowded])
    assert np.all(after.points[crowded, 2] > before[crowded, 2]), "moved forward"
