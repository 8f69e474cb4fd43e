"""The compiled arm-against-body clearance (:func:`motor.arm.clearance._body_costs`: one
compiled loop over every group of obstacles, then the trunk's charge) gives the costs
and depths of the numpy composition (``plain_clearance.py``: a numpy measurement per
group of obstacles, the rows of each kind apart), bit for bit: on both avatars, both
arms, with the trunk upright at rest, upright and carried by a moved body's frame, and
turned toward a reach (at every instant, at some, at none but with the turn's frames
given), for arms at rest height, across the chest and deep in the body, with NaN among
the candidates."""

from __future__ import annotations

import numpy as np
import pytest

from motor import quaternion as quat
from motor.arm.chain import carried_frames
from motor.arm.clearance import _body_costs, arm_capsules
from motor.body.avatar import load_avatar
from tests.perf_equivalence import plain_clearance as plain

RNG = np.random.default_rng(29)
N, K = 40, 18
#: Trunk yaw (radians) per instant of a turned trunk's cases, cycled over the N instants.
YAWS = {"turned everywhere": [0.3, -0.25, 0.1], "turned at some instants": [0.0, 0.3, 0.0, -0.2], "turned nowhere, frames given": [0.0]}


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


def _carried(avatar, yaws: list[float]):
    yaw = np.resize(np.array(yaws), N)
    if not np.any(yaw):
        # a turn's frames at upright instants: those of a turn that is zero there
        return tuple((r[:N], t[:N]) for r, t in carried_frames(avatar, np.append(yaw, 0.3)))
    return carried_frames(avatar, yaw)


@pytest.mark.parametrize("avatar_name", ["max", "kim"])
@pytest.mark.parametrize("side", ["l", "r"])
@pytest.mark.parametrize("turn", list(YAWS))
@pytest.mark.parametrize("moved", [False, True], ids=["at rest", "body moved"])
@pytest.mark.parametrize("spread", [0.04, 0.12, 0.3])
def test_turned_body_costs_charge_what_the_numpy_ones_charge(avatar_name, side, turn, moved, spread):
    avatar = load_avatar(avatar_name)
    capsules = arm_capsules(avatar, side)
    shoulders, wrists, elbows = _arm(avatar, side, spread)
    frames, body_frame = _carried(avatar, YAWS[turn]), _frame(moved)
    expected = plain.turned_body_costs(avatar, capsules, shoulders, wrists, elbows, body_frame, frames)
    cost, depth = _body_costs(avatar, capsules, shoulders, wrists, elbows, body_frame, frames)
    assert np.array_equal(cost, expected[0]) and np.array_equal(depth, expected[1])
    assert np.count_nonzero(cost) > 0


@pytest.mark.parametrize("turn", [None, *YAWS])
def test_nan_candidates_cost_what_they_cost_in_numpy(turn):
    """A frame with a NaN candidate elbow has NaN boxes: numpy measured none of its
    candidates against any volume, and neither does the compiled loop."""
    avatar = load_avatar("max")
    capsules = arm_capsules(avatar, "r")
    shoulders, wrists, elbows = _arm(avatar, "r", 0.12)
    elbows = tuple(c.copy() for c in elbows)
    elbows[0][2, 5] = np.nan
    elbows[1][11, :] = np.nan
    frames = None if turn is None else _carried(avatar, YAWS[turn])
    expected = plain.turned_body_costs(avatar, capsules, shoulders, wrists, elbows, None, frames)
    got = _body_costs(avatar, capsules, shoulders, wrists, elbows, None, frames)
    for have, want in zip(got, expected):
        assert np.array_equal(have, want, equal_nan=True)


def test_the_tables_reach_the_body():
    """The arms of the table do come near the body: penalties and depths are charged."""
    avatar = load_avatar("max")
    shoulders, wrists, elbows = _arm(avatar, "r", 0.12)
    cost, depth = _body_costs(avatar, arm_capsules(avatar, "r"), shoulders, wrists, elbows, None, None)
    assert np.count_nonzero(cost) > N
    assert np.count_nonzero(depth) > N


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
