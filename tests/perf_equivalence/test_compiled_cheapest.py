"""The compiled cheapest swivel (:func:`motor.arm.cheapest_swivel.cheapest_swivels`), which
measures only the candidates that can still be the least, gives the numbers of the
composition it replaces (:func:`motor.arm.cheapest_swivel.cheapest_by_costs`: every
candidate's cost, the first least, the parabola through it and its neighbours) bit for bit: over both avatars and
sides, targets near the body and far, with and without hand rotations, natural swivels
over several turns, and frames with NaN or infinite targets among finite ones."""

from __future__ import annotations

import numpy as np
import pytest

from motor import quaternion as quat
from motor.arm.chain import natural_swivel, place_arm
from motor.arm.clearance import arm_capsules, clearance, obstacle_table, segment_table, upright_obstacles
from motor.arm.ik import arm_reach
from motor.arm.cheapest_swivel import _cheapest_rows, cheapest_by_costs, cheapest_swivels
from motor.arm.swivel_cost import CANDIDATES, SWIVEL_STEP, _window_costs, candidate_elbows, measured_window, parabola_offset, wrist_constant_row
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


def test_reach_checks_read_the_same_penetration_as_before():
    """The reach check (whose planning calls made the pruning worth it) reads the depth at
    the cheapest swivel: the composed swivel gives the same elbows, so the same depth."""
    avatar = load_avatar("kim")
    targets = targets_about(avatar, "l", 0.12, "chest")
    reach = arm_reach(avatar, "l", targets)
    placement = place_arm(avatar, "l", targets)
    natural = natural_swivel(placement.chain, placement.circle, placement.targets, placement.torso_q)
    psi = cheapest_by_costs(avatar, placement, natural)
    circle = placement.circle
    elbow = circle.elbow(psi, circle.direction(psi))
    depth = clearance(avatar, "l", circle.shoulder, circle.wrist, tuple(c[:, None] for c in components(elbow)), None)[1][:, 0]
    assert np.array_equal(reach.penetration, depth)
    assert np.any(depth > 0.0)


@pytest.mark.parametrize("hands", [True, False], ids=["hand rotations", "no hand rotations"])
def test_a_nan_elbow_far_from_the_natural_swivel_is_still_the_first_least(hands):
    """``np.argmin`` picks the first NaN: a frame whose costly candidate (one never measured
    when everything is finite) has a NaN elbow gets what the composition gives it."""
    avatar = load_avatar("max")
    placement = place_arm(avatar, "r", targets_about(avatar, "r", 0.1, "front"), quat.normalize(RNG.normal(size=(N, 4))) if hands else None)
    natural = natural_swivel(placement.chain, placement.circle, placement.targets, placement.torso_q)
    cells, psi = measured_window(natural)
    elbow, radial = candidate_elbows(placement, np.cos(psi), np.sin(psi))
    for coordinate in elbow:
        coordinate[::3, -1] = np.nan  # the window's last candidate, 100° from the natural swivel
    circle = placement.circle
    penalty, _ = clearance(avatar, "r", circle.shoulder, circle.wrist, elbow, None)
    cost = _window_costs(placement, natural, cells, psi, penalty, elbow, radial, None)
    best = np.argmin(cost, axis=1)
    rows, count = np.arange(N), len(CANDIDATES)
    expected = CANDIDATES[best] + parabola_offset(cost[rows, (best - 1) % count], cost[rows, best], cost[rows, (best + 1) % count]) * SWIVEL_STEP
    got = np.empty(N)
    kinds, parameters, boxes, in_trunk = obstacle_table(upright_obstacles(avatar))
    rows_of = lambda value: np.ascontiguousarray(value, dtype=float)
    limits = np.array([*placement.chain.wrist_flexion, *placement.chain.wrist_deviation, *placement.chain.twist_range])
    _cheapest_rows(
        natural, cells, psi, np.zeros((0, 4)) if placement.hands is None else rows_of(placement.hands), rows_of(circle.shoulder),
        rows_of(circle.wrist), rows_of(circle.axis), *map(rows_of, elbow), *map(rows_of, radial), wrist_constant_row(placement.chain),
        limits, CANDIDATES, segment_table(arm_capsules(avatar, "r")), kinds, parameters, boxes, in_trunk, got,
    )  # fmt: skip
    assert np.array_equal(got, expected, equal_nan=True)
    if hands:  # the wrist's load of a NaN elbow is NaN (without it, NaN distances cost nothing)
        assert np.all(best[::3] == cells[::3, -1].astype(int) % count)
