"""The compiled wrist state of the swivel search (:func:`motor.arm.swivel_cost.wrist_state`)
gives the numpy version's angles (``plain_wrist.py``) to within 1e-12 rad — the same
arithmetic, but numba's ``atan2`` may round the last bit differently from numpy's — over
tables of arms: both avatars, both sides, hand rotations of every kind, targets near and
far, candidates over the whole circle and single chosen elbows ``(n, 1)``."""

from __future__ import annotations

import numpy as np
import pytest

from motor import quaternion as quat
from motor.arm.chain import ArmPlacement, place_arm
from motor.arm.swivel_cost import CANDIDATES, candidate_elbows, wrist_state
from motor.body.avatar import load_avatar
from tests.perf_equivalence import plain_wrist as plain

RNG = np.random.default_rng(41)
N = 30


def _placement(avatar_name: str, side: str, spread: float) -> ArmPlacement:
    avatar = load_avatar(avatar_name)
    shoulder = avatar.rest_positions[avatar.joint_index(f"{side}_shoulder")]
    targets = shoulder + np.array([0.0, -0.25, 0.25]) + RNG.normal(0.0, spread, (N, 3))
    hands = quat.normalize(RNG.normal(size=(N, 4)))
    return place_arm(avatar, side, targets, hands)


@pytest.mark.parametrize("avatar_name", ["max", "kim"])
@pytest.mark.parametrize("side", ["l", "r"])
@pytest.mark.parametrize("spread", [0.05, 0.2, 0.5])
@pytest.mark.parametrize("candidates", ["circle", "chosen"])
def test_wrist_state_is_the_numpy_one(avatar_name, side, spread, candidates):
    placement = _placement(avatar_name, side, spread)
    psi = np.broadcast_to(CANDIDATES, (N, len(CANDIDATES))) if candidates == "circle" else RNG.uniform(-np.pi, np.pi, (N, 1))
    elbow, radial = candidate_elbows(placement, np.cos(psi), np.sin(psi))
    got = wrist_state(placement, elbow, radial)
    expected = plain.wrist_state(placement, elbow, radial)
    for value, reference in zip(got, expected, strict=True):
        assert value.shape == reference.shape
        assert np.allclose(value, reference, rtol=0.0, atol=1e-12)
