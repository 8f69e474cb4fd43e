"""The compiled arm at a given swivel (:func:`motor.arm.given_swivel.arm_rotations`) poses
the arm as the numpy composition (:func:`motor.arm.ik.solve_arm` with ``swivel``,
``swivel_from`` and a four-column ``twist_reference``) does: within 1e-12 — the last bit
of numpy's ``arccos``, ``arctan2``, ``tanh`` and its BLAS 3×3 products, which the C
library's and the loop's may round differently — over both avatars and sides, targets
near the shoulder, in front, across the chest, raised and out of reach, hand rotations
and references of every kind, and swivels over several turns."""

from __future__ import annotations

import numpy as np
import pytest

from motor import quaternion as quat
from motor.arm.chain import arm_chain
from motor.arm.given_swivel import arm_rotations
from motor.arm.ik import solve_arm
from motor.body.avatar import load_avatar

RNG = np.random.default_rng(1912)
N = 200
TOLERANCE = 1e-12
#: Offsets from the shoulder (m) and the spread about them.
REACHES = {
    "in front": ((0.0, -0.3, 0.25), 0.05),
    "across the chest": ((None, -0.15, 0.12), 0.04),
    "raised": ((0.0, 0.35, 0.2), 0.05),
    "out of reach": ((0.0, 0.0, 0.9), 0.2),
    "anywhere": ((0.0, -0.2, 0.2), 0.6),
}


def _targets(avatar, side, reach):  # noqa: ANN001, ANN202
    shoulder = avatar.rest_positions[avatar.joint_index(f"{side}_shoulder")]
    (x, y, z), spread = REACHES[reach]
    offset = np.array([-shoulder[0] if x is None else x, y, z])
    return shoulder + offset + RNG.normal(0.0, spread, (N, 3))


def _composed(avatar, side, targets, hands, swivel, zeros, reference):  # noqa: ANN001, ANN202
    return solve_arm(avatar, side, targets, hands, swivel, twist_reference=reference, swivel_from=zeros).rotations


@pytest.mark.parametrize("avatar_name", ["max", "kim"])
@pytest.mark.parametrize("side", ["l", "r"])
@pytest.mark.parametrize("reach", sorted(REACHES))
@pytest.mark.parametrize("turns", [0, 2], ids=["swivel within a turn", "swivel over turns"])
def test_the_compiled_arm_is_the_composed_one(avatar_name, side, reach, turns):
    avatar = load_avatar(avatar_name)
    targets = _targets(avatar, side, reach)
    hands = quat.normalize(RNG.normal(size=(N, 4))) * RNG.uniform(0.5, 2.0, (N, 1))
    swivel = RNG.uniform(-np.pi, np.pi, N) + turns * 2.0 * np.pi * RNG.integers(-1, 2, N)
    zeros = RNG.normal(size=(N, 3))
    reference = np.column_stack([RNG.uniform(-2.0, 2.0, (N, 2)), RNG.uniform(-1.0, 1.0, (N, 2))])
    got = arm_rotations(avatar, side, targets, hands, swivel, zeros, reference)
    np.testing.assert_allclose(got, _composed(avatar, side, targets, hands, swivel, zeros, reference), rtol=0.0, atol=TOLERANCE)


@pytest.mark.parametrize("side", ["l", "r"])
def test_a_target_on_the_shoulder_and_a_hand_along_the_forearm_are_the_composed_ones(side):
    """The elbow circle's fallback axis (no reach to point along) and a hand in line with
    the forearm (no swing, the twist fully defined)."""
    avatar = load_avatar("max")
    chain = arm_chain(avatar, side)
    targets = np.array([chain.torso_joint_rest + chain.sc_offset + chain.clavicle, [0.1 if side == "l" else -0.1, 1.1, 0.3]])
    hands = np.array([[0.0, 0.0, 0.0, 1.0]] * 2)
    swivel, zeros, reference = np.zeros(2), np.array([[0.0, -1.0, 0.0]] * 2), np.zeros((2, 4))
    got = arm_rotations(avatar, side, targets, hands, swivel, zeros, reference)
    assert np.all(np.isfinite(got))
    np.testing.assert_allclose(got, _composed(avatar, side, targets, hands, swivel, zeros, reference), rtol=0.0, atol=TOLERANCE)


def test_no_rows_give_no_rotations():
    avatar = load_avatar("max")
    assert arm_rotations(avatar, "r", np.zeros((0, 3)), np.zeros((0, 4)), np.zeros(0), np.zeros((0, 3)), np.zeros((0, 4))).shape == (0, 4, 4)


def test_a_side_that_is_not_an_arm_is_refused():
    with pytest.raises(ValueError, match="side"):
        arm_rotations(load_avatar("max"), "x", np.zeros((1, 3)), np.array([[0.0, 0.0, 0.0, 1.0]]), np.zeros(1), np.ones((1, 3)), np.zeros((1, 4)))
