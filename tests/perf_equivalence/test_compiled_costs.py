"""The compiled costs of the swivel candidates (:func:`motor.arm.swivel_cost.candidate_costs`
of an arm's own candidates) are the numpy version's (``plain_costs.py``): bit for bit
where no hand rotation is asked (natural swivel, clearance, nearby penalties), within
1e-12 relative where the wrist's load counts (numba's ``atan2`` may round the last bit
differently) — over both avatars and sides, targets near and far, natural swivels over
several turns (the candidates' distance from them wraps round the circle) and nearby
penalties or none."""

from __future__ import annotations

import numpy as np
import pytest

from motor import quaternion as quat
from motor.arm.chain import natural_swivel, place_arm
from motor.arm.swivel_cost import CANDIDATES, candidate_costs
from motor.body.avatar import load_avatar
from tests.perf_equivalence import plain_costs as plain

RNG = np.random.default_rng(43)
N = 48


@pytest.mark.parametrize("avatar_name", ["max", "kim"])
@pytest.mark.parametrize("side", ["l", "r"])
@pytest.mark.parametrize("spread", [0.05, 0.3])
@pytest.mark.parametrize("hands", [True, False], ids=["hand rotations", "no hand rotations"])
@pytest.mark.parametrize("nearby", [True, False], ids=["nearby", "alone"])
def test_candidate_costs_are_the_numpy_ones(avatar_name, side, spread, hands, nearby):
    avatar = load_avatar(avatar_name)
    shoulder = avatar.rest_positions[avatar.joint_index(f"{side}_shoulder")]
    targets = shoulder + np.array([0.0, -0.3, 0.25]) + RNG.normal(0.0, spread, (N, 3))
    placement = place_arm(avatar, side, targets, quat.normalize(RNG.normal(size=(N, 4))) if hands else None)
    natural = natural_swivel(placement.chain, placement.circle, placement.targets, placement.torso_q) + RNG.integers(-2, 3, N) * 2.0 * np.pi
    around = RNG.uniform(0.0, 80.0, (N, len(CANDIDATES))) if nearby else None
    got = candidate_costs(avatar, placement, natural, nearby=around)
    expected = plain.candidate_costs(avatar, placement, natural, nearby=around)
    if hands:
        assert np.allclose(got, expected, rtol=1e-12, atol=0.0)
    else:
        assert np.array_equal(got, expected)
