"""The compiled arm-against-the-other-arm clearance
(:func:`motor.arm.other_arm_clearance.other_arm_rows`, through
:func:`motor.arm.clearance.clearance`) adds the numbers the numpy loop it replaced
(``plain_clearance.other_arm_clearance``) adds, bit for bit: on both avatars, both arms,
with the other arm crossing this one, beside it and far away, alone and on top of the
body's costs, with NaN in the other arm's rows and in candidate elbows, one candidate,
and no frames at all; and the other arm's costs of a swivel search
(:func:`motor.arm.swivel_cost._other_arm_costs`: the frames near the other arm picked out,
their window's elbows placed and measured, compiled) are those of its numpy version
(``plain_clearance.other_arm_costs``)."""

from __future__ import annotations

import numpy as np
import pytest

from motor import quaternion as quat
from motor.arm.clearance import _body_costs, arm_capsules, arm_segments, clearance
from motor.arm.chain import natural_swivel, place_arm
from motor.arm.other_arm_clearance import near_frames, other_arm_rows, other_arm_window
from motor.arm.swivel_cost import _other_arm_costs
from motor.body.avatar import load_avatar
from motor.compiled import warm_up
from tests.perf_equivalence import plain_clearance as plain

N, K = 40, 18
#: How far (m) the other arm's joints scatter about this arm's: crossing it, beside it, away.
SPREADS = {"crossing": 0.05, "beside": 0.15, "away": 0.6}


def _case(avatar, side: str, spread: float, seed: int, n: int = N, k: int = K):
    rng = np.random.default_rng(seed)
    shoulder = avatar.rest_positions[avatar.joint_index(f"{side}_shoulder")]
    shoulders = shoulder + rng.normal(0.0, 0.01, (n, 3))
    wrists = np.array([0.0, shoulder[1] - 0.15, 0.2]) + rng.normal(0.0, 0.08, (n, 3))
    elbows = tuple(0.5 * (shoulders[:, i : i + 1] + wrists[:, i : i + 1]) + rng.normal(0.0, 0.08, (n, k)) for i in range(3))
    other_side = "r" if side == "l" else "l"
    middle = 0.5 * (shoulders + wrists)
    other_joints = [middle + rng.normal(0.0, spread, (n, 3)) for _ in range(3)]
    hands = quat.from_rotation_vector(rng.normal(0.0, 1.0, (n, 3)))
    other = arm_segments(arm_capsules(avatar, other_side), *other_joints, hands)
    return shoulders, wrists, elbows, other


def _with_nan(shoulders, wrists, elbows, other):
    """NaN in a few of the other arm's rows (each of its capsules), and in some candidate elbows."""
    upper, fore, hand = ([end.copy() for end in pair] for pair in (other.upper, other.fore, other.hand))
    upper[0][1, 0] = np.nan
    fore[1][3, 2] = np.nan
    hand[0][5, 1] = np.nan
    elbows = tuple(c.copy() for c in elbows)
    elbows[0][7, 4] = np.nan
    elbows[2][9, :] = np.nan
    return shoulders, wrists, elbows, type(other)(tuple(upper), tuple(fore), tuple(hand), other.radii)


def _expected(avatar, side, shoulders, wrists, elbows, other, body: bool) -> np.ndarray:
    capsules = arm_capsules(avatar, side)
    shape = elbows[0].shape
    cost = _body_costs(avatar, capsules, shoulders, wrists, elbows, None, None)[0] if body else np.zeros(shape)
    plain.other_arm_clearance(capsules, shoulders, wrists, elbows, other, cost)
    return cost


@pytest.mark.parametrize("avatar_name", ["max", "kim"])
@pytest.mark.parametrize("side", ["l", "r"])
@pytest.mark.parametrize("where", list(SPREADS))
@pytest.mark.parametrize("body", [False, True], ids=["other arm alone", "with the body"])
@pytest.mark.parametrize("nan", [False, True], ids=["finite", "NaN rows"])
def test_other_arm_costs_are_the_numpy_ones(avatar_name, side, where, body, nan):
    avatar = load_avatar(avatar_name)
    case = _case(avatar, side, SPREADS[where], seed=len(where) + 7 * body + 31 * (side == "l"))
    if nan:
        case = _with_nan(*case)
    cost, _ = clearance(avatar, side, *case[:3], other=case[3], body=body)
    expected = _expected(avatar, side, *case, body)
    assert np.array_equal(cost, expected, equal_nan=True)
    if where == "crossing" and not nan:
        assert np.count_nonzero(cost) > N, "the crossing arms come near each other"


@pytest.mark.parametrize("n, k", [(0, K), (1, 1), (3, 1), (5, 36)], ids=["no frames", "one candidate", "one candidate per frame", "the whole circle"])
def test_shapes_at_the_edges(n, k):
    avatar = load_avatar("max")
    case = _case(avatar, "r", SPREADS["crossing"], seed=3, n=n, k=k)
    cost, _ = clearance(avatar, "r", *case[:3], other=case[3], body=False)
    assert cost.shape == (n, k)
    assert np.array_equal(cost, _expected(avatar, "r", *case, body=False), equal_nan=True)


@pytest.mark.parametrize("avatar_name", ["max", "kim"])
@pytest.mark.parametrize("side", ["l", "r"])
@pytest.mark.parametrize("where", list(SPREADS))
@pytest.mark.parametrize("turned", [False, True], ids=["upright", "trunk turned"])
@pytest.mark.parametrize("nan", [False, True], ids=["finite", "NaN rows"])
@pytest.mark.filterwarnings("ignore:invalid value encountered in cast")  # a NaN swivel's cell, in both versions
def test_a_swivel_search_pays_the_numpy_costs_of_the_other_arm(avatar_name, side, where, turned, nan):
    avatar = load_avatar(avatar_name)
    shoulders, wrists, _, other = _case(avatar, side, SPREADS[where], seed=len(where) + 5 * turned + 13 * (side == "l"))
    hands = quat.from_rotation_vector(np.random.default_rng(4).normal(0.0, 0.5, (N, 3)))
    placement = place_arm(avatar, side, wrists, hands, trunk_yaw=np.linspace(-0.3, 0.3, N) if turned else None)
    natural = natural_swivel(placement.chain, placement.circle, placement.targets, placement.torso_q)
    if nan:
        natural = natural.copy()
        natural[4] = np.nan
        _, _, _, other = _with_nan(shoulders, wrists, (np.zeros((N, K)),) * 3, other)
    expected = plain.other_arm_costs(avatar, placement, natural, other)
    costs = _other_arm_costs(avatar, placement, natural, other)
    assert np.array_equal(costs, expected, equal_nan=True)
    if where == "crossing":
        assert np.count_nonzero(costs) > N, "the crossing arms come near each other"
    if where == "away":
        assert np.count_nonzero(costs.any(axis=1)) < N, "some frames are not near"


def test_no_frame_near_the_other_arm_costs_nothing():
    avatar = load_avatar("max")
    _, wrists, _, other = _case(avatar, "r", SPREADS["away"], seed=2)
    far = type(other)(*(tuple(end + 5.0 for end in pair) for pair in (other.upper, other.fore, other.hand)), other.radii)
    placement = place_arm(avatar, "r", wrists)
    natural = natural_swivel(placement.chain, placement.circle, placement.targets, placement.torso_q)
    assert not np.any(_other_arm_costs(avatar, placement, natural, far))


@pytest.mark.parametrize("loop", [other_arm_rows, near_frames, other_arm_window], ids=lambda loop: loop.__name__)
def test_the_loops_load_with_their_one_signature(loop):
    assert warm_up() >= 0.0
    assert len(loop.signatures) == 1
