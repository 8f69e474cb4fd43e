"""The swivel track's clearance half way between its grid points (synthetic tables of
wrist targets across the chest).

* A half-way instant where the arm stands as at the grid points on either side adds
  nothing: the costs are those of the grid points alone.
* Where the arm passes the chest between two grid points, a candidate pays at least the
  clearance penalty it would pay half way, its elbow held: the deeper instant decides.
"""

from __future__ import annotations

import numpy as np
import pytest

from motor.arm.chain import natural_swivel, place_arm
from motor.arm.ik import midway_penalties, track_costs
from motor.arm.swivel_cost import CANDIDATES, body_penalties, measured_window
from motor.body.avatar import load_avatar

AVATARS = ("max", "makehuman")


@pytest.fixture(scope="module", params=AVATARS)
def avatar(request):
    return load_avatar(request.param)


def _sweep(avatar, side: str, count: int) -> tuple[np.ndarray, np.ndarray]:
    """Wrist targets ``(count, 3)`` sweeping across the chest close to it from the own
    side to the far side, and the hand rotations (identity)."""
    torso = avatar.torso
    far = -1.0 if side == "l" else 1.0
    x = far * np.linspace(-0.1, 0.25, count)
    y = np.full(count, torso.bottom + 0.8 * (torso.top - torso.bottom))
    z = np.full(count, torso.center[2] + torso.half_depth + 0.06)
    hands = np.tile([0.0, 0.0, 0.0, 1.0], (count, 1))
    return np.stack([x, y, z], axis=1), hands


@pytest.mark.parametrize("side", ["l", "r"])
@pytest.mark.parametrize("sample", [0, 4, 8])
def test_a_still_half_way_adds_nothing(avatar, side, sample):
    """An arm held at one place of the sweep (some across the chest, close to it): the
    costs with the half-way instants are the grid's alone, bit for bit."""
    targets, hands = _sweep(avatar, side, 9)
    still, still_hands = np.repeat(targets[sample : sample + 1], 6, axis=0), np.repeat(hands[:1], 6, axis=0)
    plain = track_costs(avatar, side, still, still_hands)
    with_half = track_costs(avatar, side, still, still_hands, None, (still, still_hands, None))
    np.testing.assert_array_equal(with_half.costs, plain.costs)


@pytest.mark.parametrize("side", ["l", "r"])
@pytest.mark.parametrize("step", [2, 3])
def test_a_candidate_pays_what_it_would_pay_half_way(avatar, side, step):
    """Grid instants every ``step``-th sample of a sweep, a sample between each two as
    the half-way instant: each candidate's cost with the half-way instants is at least its cost without
    them, and more wherever the half way is more penalized than the instant."""
    targets, hands = _sweep(avatar, side, 4 * step + 1 + step)
    grid, half = targets[::step], targets[step // 2 :: step]
    grid_hands, half_hands = hands[::step], hands[step // 2 :: step]
    count = min(len(grid), len(half))
    grid, half, grid_hands, half_hands = grid[:count], half[:count], grid_hands[:count], half_hands[:count]
    plain = track_costs(avatar, side, grid, grid_hands)
    with_half = track_costs(avatar, side, grid, grid_hands, None, (half, half_hands, None))
    assert np.all(with_half.costs >= plain.costs - 1e-9)
    placement = place_arm(avatar, side, grid, grid_hands)
    nearby = midway_penalties(avatar, side, placement, half, half_hands, None, None)
    natural = natural_swivel(placement.chain, placement.circle, placement.targets, placement.torso_q)[1:]
    own = body_penalties(avatar, placement.take(slice(1, None)), natural)
    assert np.any(nearby > own + 1.0), "the sweep must pass the chest between grid instants"
    measured = np.zeros_like(own, dtype=bool)
    np.put_along_axis(measured, measured_window(natural)[0].astype(int) % len(CANDIDATES), True, axis=1)
    more = measured & (nearby > own + 1e-6)
    assert np.any(more)
    assert np.all(with_half.costs[more] > plain.costs[more])
