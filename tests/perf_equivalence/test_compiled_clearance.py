"""The compiled arm-against-body clearance (:func:`motor.arm.clearance._body_clearance`)
adds into its cost and depth arrays the numbers the numpy version
(``plain_clearance.py``) adds, bit for bit, and leaves in its trunk arrays distances of
the same penalty (it does not measure candidates beyond the clearance, which the numpy
version measured and which cost nothing): on both avatars, both arms, every group of
obstacles the swivel search measures (all, upright, carried by 0 … 3 turning joints),
with the trunk upright and carried by a turned frame, for arms at rest height, across the
chest and deep in the body."""

from __future__ import annotations

import numpy as np
import pytest

from motor import quaternion as quat
from motor.arm.clearance import _body_clearance, _body_costs, _by_carriers, arm_capsules, body_obstacles, overlap_penalty, upright_obstacles
from motor.body.avatar import load_avatar
from tests.perf_equivalence import plain_clearance as plain

RNG = np.random.default_rng(29)
N, K = 40, 18


def _groups(avatar):
    return {"all": body_obstacles(avatar), "upright": upright_obstacles(avatar), **{f"carried by {i}": g for i, g in enumerate(_by_carriers(avatar)) if g}}


def _arm(avatar, side: str, spread: float):
    shoulder = avatar.rest_positions[avatar.joint_index(f"{side}_shoulder")]
    shoulders = shoulder + RNG.normal(0.0, 0.01, (N, 3))
    chest = np.array([0.0, shoulder[1] - 0.15, 0.1])
    wrists = chest + RNG.normal(0.0, spread, (N, 3))
    elbows = tuple(0.5 * (shoulders[:, i : i + 1] + wrists[:, i : i + 1]) + RNG.normal(0.0, spread, (N, K)) for i in range(3))
    return shoulders, wrists, elbows


def _frame(turned: bool):
    if not turned:
        return None
    rotation = quat.from_rotation_vector(RNG.normal(0.0, 0.2, (N, 3)))
    return rotation, RNG.normal(0.0, 0.02, (N, 3))


def _start():
    cost = RNG.uniform(0.0, 5.0, (N, K))
    depth = RNG.uniform(0.0, 0.01, (N, K))
    trunk = [np.where(RNG.random((N, K)) < 0.5, np.inf, RNG.normal(0.0, 0.05, (N, K))) for _ in range(2)]
    return cost, depth, trunk


@pytest.mark.parametrize("avatar_name", ["max", "kim"])
@pytest.mark.parametrize("side", ["l", "r"])
@pytest.mark.parametrize("turned", [False, True], ids=["upright", "turned"])
@pytest.mark.parametrize("spread", [0.04, 0.12, 0.3])
def test_clearance_adds_what_the_numpy_version_adds(avatar_name, side, turned, spread):
    avatar = load_avatar(avatar_name)
    capsules = arm_capsules(avatar, side)
    for name, obstacles in _groups(avatar).items():
        shoulders, wrists, elbows = _arm(avatar, side, spread)
        frame = _frame(turned)
        cost, depth, trunk = _start()
        expected = (cost.copy(), depth.copy(), [t.copy() for t in trunk])
        plain._body_clearance(capsules, obstacles, shoulders, wrists, elbows, frame, *expected)
        _body_clearance(capsules, obstacles, shoulders, wrists, elbows, frame, cost, depth, trunk)
        for got, want in zip((cost, depth, *map(_trunk_penalty, trunk)), (expected[0], expected[1], *map(_trunk_penalty, expected[2]))):
            assert np.array_equal(got, want), (name, np.nanmax(np.abs(got - want)))


def _trunk_penalty(least: np.ndarray) -> np.ndarray:
    """What :func:`motor.arm.clearance._body_costs` charges for the trunk's least distances."""
    finite = np.isfinite(least)
    return np.where(finite, overlap_penalty(np.where(finite, least, 1.0)), 0.0)


def test_the_tables_reach_the_body():
    """The arms of the table do come near the body: penalties and depths are added."""
    avatar = load_avatar("max")
    shoulders, wrists, elbows = _arm(avatar, "r", 0.12)
    cost, depth = np.zeros((N, K)), np.zeros((N, K))
    trunk = [np.full((N, K), np.inf), np.full((N, K), np.inf)]
    _body_clearance(arm_capsules(avatar, "r"), body_obstacles(avatar), shoulders, wrists, elbows, None, cost, depth, trunk)
    assert np.count_nonzero(cost) > N
    assert np.count_nonzero(depth) > N
    assert np.isfinite(trunk[0]).sum() > N and np.isfinite(trunk[1]).sum() > N


def test_arrays_that_are_not_contiguous_are_refused():
    avatar = load_avatar("max")
    shoulders, wrists, elbows = _arm(avatar, "r", 0.12)
    cost = np.zeros((K, N)).T
    with pytest.raises(ValueError, match="contiguous"):
        _body_clearance(arm_capsules(avatar, "r"), body_obstacles(avatar), shoulders, wrists, elbows, None, cost, np.zeros((N, K)), [np.zeros((N, K))] * 2)


@pytest.mark.parametrize("avatar_name", ["max", "kim"])
@pytest.mark.parametrize("side", ["l", "r"])
@pytest.mark.parametrize("moved", [False, True], ids=["at rest", "body moved"])
@pytest.mark.parametrize("spread", [0.04, 0.12, 0.3])
def test_upright_body_costs_charge_what_the_numpy_ones_charge(avatar_name, side, moved, spread):
    """Where the trunk turns nowhere, the costs go straight into the arrays returned and the
    trunk's least distances are charged by a compiled loop: the costs and depths of the
    numpy composition, bit for bit."""
    avatar = load_avatar(avatar_name)
    capsules = arm_capsules(avatar, side)
    shoulders, wrists, elbows = _arm(avatar, side, spread)
    frame = _frame(moved)
    expected = (np.zeros((N, K)), np.zeros((N, K)))
    plain.body_costs(avatar, capsules, shoulders, wrists, elbows, frame, *expected)
    cost, depth = _body_costs(avatar, capsules, shoulders, wrists, elbows, frame, None)
    assert np.array_equal(cost, expected[0]) and np.array_equal(depth, expected[1])
    assert np.count_nonzero(cost) > 0
