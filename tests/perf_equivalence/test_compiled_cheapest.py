"""The compiled cheapest swivel (:func:`motor.arm.cheapest_swivel.cheapest_swivels`), which
measures only the candidates that can still be the least, gives the numbers of the
composition it replaces (:func:`motor.arm.cheapest_swivel.cheapest_by_costs`: every
candidate's cost, the first least, the parabola through it and its neighbours) bit for
bit, and the reach check's pass (:func:`motor.arm.cheapest_swivel.cheapest_reach`) the
composition's elbows and depth there: over both avatars and sides, targets near the body
and far, with and without hand rotations, natural swivels over several turns, and frames
with NaN or infinite targets or hand rotations among finite ones."""

from __future__ import annotations

import numpy as np
import pytest

from motor import quaternion as quat
from motor.arm.chain import natural_swivel, place_arm
from motor.arm.clearance import clearance
from motor.arm.ik import arm_reach, solve_arm
from motor.arm.upright_placement import upright_placement
from motor.arm.cheapest_swivel import cheapest_by_costs, cheapest_reach, cheapest_swivels
from motor.body.avatar import load_avatar
from motor.body.distance import components

RNG = np.random.default_rng(19)
N = 64


def targets_about(avatar, side, spread, toward):  # noqa: ANN001, ANN201
    """Wrist targets scattered about a point in front of the shoulder or across the chest."""
    shoulder = avatar.rest_positions[avatar.joint_index(f"{side}_shoulder")]
    across = np.array([-shoulder[0], -0.15, 0.12]) if toward == "chest" else np.array([0.0, -0.3, 0.25])
    return shoulder + across + RNG.normal(0.0, spread, (N, 3))


@pytest.mark.parametrize("avatar_name", ["max", "kim"])
@pytest.mark.parametrize("side", ["l", "r"])
@pytest.mark.parametrize(("spread", "toward"), [(0.05, "front"), (0.3, "front"), (0.04, "chest"), (0.15, "chest")])
@pytest.mark.parametrize("hands", [True, False], ids=["hand rotations", "no hand rotations"])
@pytest.mark.parametrize("turns", [0, 1], ids=["natural", "natural over turns"])
def test_cheapest_swivels_are_the_composed_ones(avatar_name, side, spread, toward, hands, turns):
    avatar = load_avatar(avatar_name)
    placement = place_arm(avatar, side, targets_about(avatar, side, spread, toward), quat.normalize(RNG.normal(size=(N, 4))) if hands else None)
    natural = natural_swivel(placement.chain, placement.circle, placement.targets, placement.torso_q)
    natural = natural + turns * RNG.integers(-2, 3, N) * 2.0 * np.pi
    assert np.array_equal(cheapest_swivels(avatar, placement, natural), cheapest_by_costs(avatar, placement, natural))


@pytest.mark.parametrize("bad", [np.nan, np.inf], ids=["NaN", "infinite"])
@pytest.mark.parametrize("hands", [True, False], ids=["hand rotations", "no hand rotations"])
def test_frames_with_bad_targets_are_the_composed_ones_and_leave_the_others_alone(bad, hands):
    avatar = load_avatar("max")
    targets = targets_about(avatar, "r", 0.1, "chest")
    targets[[3, 17]] = bad
    rotations = quat.normalize(RNG.normal(size=(N, 4))) if hands else None
    with np.errstate(all="ignore"):
        placement = place_arm(avatar, "r", targets, rotations)
        natural = natural_swivel(placement.chain, placement.circle, placement.targets, placement.torso_q)
        got, expected = cheapest_swivels(avatar, placement, natural), cheapest_by_costs(avatar, placement, natural)
    assert np.array_equal(got, expected, equal_nan=True)
    fine = np.setdiff1d(np.arange(N), [3, 17])
    assert np.all(np.isfinite(got[fine]))


def test_a_turned_body_is_left_to_the_composition():
    avatar = load_avatar("max")
    turned = np.broadcast_to(quat.from_axis_angle(np.array([0.0, 1.0, 0.0]), 0.3), (N, 4))
    placement = place_arm(avatar, "r", targets_about(avatar, "r", 0.1, "front"), torso_rotations=turned)
    natural = natural_swivel(placement.chain, placement.circle, placement.targets, placement.torso_q)
    assert cheapest_swivels(avatar, placement, natural) is None


@pytest.mark.parametrize("avatar_name", ["max", "kim"])
@pytest.mark.parametrize("side", ["l", "r"])
@pytest.mark.parametrize(("spread", "toward"), [(0.05, "front"), (0.3, "front"), (0.04, "chest"), (0.15, "chest")])
@pytest.mark.parametrize("hands", [True, False], ids=["hand rotations", "no hand rotations"])
def test_reach_checks_read_the_composed_elbows_and_depth(avatar_name, side, spread, toward, hands):
    """The reach check's pass (:func:`cheapest_reach`, which places the elbow at the
    cheapest swivel and measures the body's depth there) gives what the composition gives:
    the composed swivel's elbows (:meth:`ElbowCircle.elbow`) and their depth
    (:func:`clearance`), and :func:`arm_reach` reads that depth; without the depth it
    reaches the same wrists with the same shortfalls, the penetration not measured."""
    avatar = load_avatar(avatar_name)
    targets = targets_about(avatar, side, spread, toward)
    rotations = quat.normalize(RNG.normal(size=(N, 4))) if hands else None
    placement = place_arm(avatar, side, targets, rotations)
    natural = natural_swivel(placement.chain, placement.circle, placement.targets, placement.torso_q)
    psi = cheapest_by_costs(avatar, placement, natural)
    circle = placement.circle
    elbow = circle.elbow(psi, circle.direction(psi))
    depth = clearance(avatar, side, circle.shoulder, circle.wrist, tuple(c[:, None] for c in components(elbow)), None)[1][:, 0]
    swivels, elbows, depths = cheapest_reach(avatar, placement, natural)
    assert np.array_equal(swivels, psi)
    assert np.array_equal(elbows, elbow)
    assert np.array_equal(depths, depth)
    reach = arm_reach(avatar, side, targets, rotations)
    assert np.array_equal(reach.penetration, depth)
    unmeasured = arm_reach(avatar, side, targets, rotations, with_depth=False)
    assert np.array_equal(unmeasured.wrist, reach.wrist)
    assert np.array_equal(unmeasured.shortfall, reach.shortfall)
    assert np.isnan(unmeasured.penetration).all()


def test_the_reach_checks_measure_arms_in_the_body():
    """The table above meets the body: some of its arms are measured inside it."""
    avatar = load_avatar("kim")
    assert np.any(arm_reach(avatar, "l", targets_about(avatar, "l", 0.12, "chest")).penetration > 0.0)


@pytest.mark.parametrize("avatar_name", ["max", "kim"])
@pytest.mark.parametrize("side", ["l", "r"])
@pytest.mark.parametrize(("spread", "toward"), [(0.05, "front"), (0.3, "front"), (0.04, "chest"), (0.15, "chest"), (1.0, "front")])
@pytest.mark.parametrize("bad", [None, np.nan, np.inf], ids=["finite", "NaN", "infinite"])
def test_what_a_placement_reads_of_the_solved_arm_is_the_solved_arms(avatar_name, side, spread, toward, bad):
    """Gesture locations and ways read only the solved arm's shoulder, wrist and body
    depth of the body upright at rest (:mod:`motor.arm.wrist_path`,
    :mod:`motor.arm.bowed_way`): the arm's placement (:func:`upright_placement`) and the
    reach pass (:func:`arm_reach`) give those very numbers without solving the joints."""
    avatar = load_avatar(avatar_name)
    targets = targets_about(avatar, side, spread, toward)
    if bad is not None:
        targets[[2, 30]] = bad
    with np.errstate(all="ignore"):
        solution = solve_arm(avatar, side, targets)
        circle = upright_placement(avatar, side, targets)[0].circle
        penetration = arm_reach(avatar, side, targets).penetration
    assert np.array_equal(circle.shoulder, solution.shoulder, equal_nan=True)
    assert np.array_equal(circle.wrist, solution.wrist, equal_nan=True)
    assert np.array_equal(penetration, solution.penetration, equal_nan=True)


@pytest.mark.parametrize("bad", [np.nan, np.inf], ids=["NaN", "infinite"])
def test_frames_with_bad_hand_rotations_are_the_composed_ones(bad):
    """A frame whose hand rotation is not finite has every candidate's wrist load NaN: every
    candidate is measured and the first NaN is the least, as ``np.argmin`` picks it."""
    avatar = load_avatar("max")
    rotations = quat.normalize(RNG.normal(size=(N, 4)))
    rotations[[5, 40]] = bad
    with np.errstate(all="ignore"):
        placement = place_arm(avatar, "r", targets_about(avatar, "r", 0.1, "front"), rotations)
        natural = natural_swivel(placement.chain, placement.circle, placement.targets, placement.torso_q)
        got, expected = cheapest_swivels(avatar, placement, natural), cheapest_by_costs(avatar, placement, natural)
    assert np.array_equal(got, expected, equal_nan=True)
    assert np.all(np.isfinite(np.delete(got, [5, 40])))


def test_a_turned_body_is_refused_by_the_reach_pass():
    avatar = load_avatar("max")
    turned = np.broadcast_to(quat.from_axis_angle(np.array([0.0, 1.0, 0.0]), 0.3), (N, 4))
    placement = place_arm(avatar, "r", targets_about(avatar, "r", 0.1, "front"), torso_rotations=turned)
    natural = natural_swivel(placement.chain, placement.circle, placement.targets, placement.torso_q)
    with pytest.raises(ValueError, match="upright"):
        cheapest_reach(avatar, placement, natural)
