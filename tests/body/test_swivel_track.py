"""The swivel track and the trunk's turn: continuous by construction, the same piece by
piece as at once, and turning only where a hand reaches across the body."""

from __future__ import annotations

import numpy as np
import pytest

from motor.arm.reach_turn import MAX_TURN, trunk_turn
from motor.arm.swivel import MAX_STEP, SwivelState, smooth_swivels
from motor.arm.swivel_cost import CANDIDATES, SWIVEL_STEP
from motor.arm.swivel_track import twist_track, wrist_track

RNG = np.random.default_rng(5)


def _costs(targets: np.ndarray) -> np.ndarray:
    """Quadratic costs about moving targets (radians), wrapped round the circle."""
    away = (CANDIDATES[None, :] - targets[:, None] + np.pi) % (2.0 * np.pi) - np.pi
    return away**2


@pytest.mark.parametrize(
    "targets",
    [
        np.linspace(0.0, 3.0, 40),  # a steady drift
        np.where(np.arange(40) < 20, 0.2, 2.8),  # the cheapest candidate jumps
        RNG.uniform(-np.pi, np.pi, 40),  # noise: the per-point argmin jumps everywhere
    ],
    ids=["drift", "jump", "noise"],
)
def test_the_track_moves_a_bounded_step_whatever_the_costs(targets):
    cells, swivels = smooth_swivels(_costs(targets), CANDIDATES, None, 2)
    assert np.all(np.abs(np.diff(cells)) <= MAX_STEP)
    assert np.all(np.abs(np.diff(swivels)) <= (MAX_STEP + 1) * SWIVEL_STEP)


def test_the_track_settles_on_the_cheapest_swivel():
    cells, swivels = smooth_swivels(_costs(np.full(30, 1.234)), CANDIDATES, None, 2)
    assert swivels[-1] == pytest.approx(1.234, abs=0.01)  # the parabola through the cost to go


@pytest.mark.parametrize("pieces", [[10, 10, 10], [1, 29], [7, 3, 12, 8]])
def test_a_track_computed_piece_by_piece_is_the_track_computed_at_once(pieces):
    horizon = 2
    costs = _costs(RNG.uniform(-1.0, 1.0, 30 + horizon).cumsum() * 0.2)
    turns = RNG.normal(0.0, 0.05, 30 + horizon)
    cells, swivels = smooth_swivels(costs, CANDIDATES, None, horizon, None, turns)
    previous, start, parts = None, 0, []
    for size in pieces:
        rows = slice(start, start + size + horizon)
        part = smooth_swivels(costs[rows], CANDIDATES, previous, horizon, None, turns[rows])
        parts.append(part)
        previous = SwivelState(int(part[0][-1]), float(part[1][-1]))
        start += size
    np.testing.assert_array_equal(np.concatenate([p[0] for p in parts]), cells)
    np.testing.assert_allclose(np.concatenate([p[1] for p in parts]), swivels, rtol=0.0, atol=1e-12)


def test_a_turning_zero_costs_nothing():
    """Costs that turn with the swivel's zero: the track turns with them, keeping the elbow
    where it is, without a cost of change (no look ahead here, which would lead them)."""
    turns = np.full(20, 0.07)
    targets = 0.5 + np.cumsum(turns)
    _, swivels = smooth_swivels(_costs(targets), CANDIDATES, SwivelState(int(round((0.5 - CANDIDATES[0]) / SWIVEL_STEP)), 0.5), 0, None, turns)
    # within the step the cost of change holds it back, never falling behind
    np.testing.assert_allclose(swivels, targets[: len(swivels)], atol=0.6 * SWIVEL_STEP)
    assert swivels[-1] - swivels[0] == pytest.approx(targets[len(swivels) - 1] - targets[0], abs=0.6 * SWIVEL_STEP)


def test_the_twist_never_wraps_and_turns_over_gradually():
    limits = (-1.5, 1.5)
    wanted = (np.linspace(0.0, 4.5, 40) + np.pi) % (2.0 * np.pi) - np.pi  # the hand asks ever more, round the circle
    twists = twist_track(wanted, np.ones(40), None, limits)
    assert np.all((twists >= limits[0]) & (twists <= limits[1]))
    assert np.max(np.abs(np.diff(twists))) <= np.radians(60.0) + 1e-9


def test_the_wrist_holds_where_the_hand_is_undefined():
    targets = np.array([[0.1, 0.0], [1.0, -0.5], [1.0, -0.5]])
    held = wrist_track(targets, np.array([1.0, 0.0, 0.0]), None)
    np.testing.assert_allclose(held, [[0.1, 0.0]] * 3)


def test_the_trunk_turns_only_where_a_hand_reaches_across(avatar):
    front = avatar.grid.front
    own_side = np.array([[0.25, 0.3, front + 0.1]])
    across = np.array([[-0.3, 0.3, front + 0.1]])
    rest_right = avatar.postures["rest"]["r"].wrist[None]
    assert trunk_turn(avatar, own_side, rest_right) is None
    turn = trunk_turn(avatar, across, rest_right)
    assert turn is not None and -MAX_TURN <= turn.yaw[0] < -0.5 * MAX_TURN  # toward the avatar's right
    mirrored = trunk_turn(avatar, avatar.postures["rest"]["l"].wrist[None], across * [-1, 1, 1])
    assert mirrored.yaw[0] == pytest.approx(-turn.yaw[0])
    points = RNG.normal(0.0, 0.3, (1, 3))
    np.testing.assert_allclose(turn.from_trunk(turn.to_trunk(points)), points, atol=1e-12)


def _crossing_inputs(times: np.ndarray) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Synthetic wrist paths whose hands cross over in front of the chest and part again,
    the left a forearm's thickness lower (avatar frame, metres), hands unturned."""
    phase = np.sin(np.pi * np.clip(times / 4.0, 0.0, 1.0))
    right = np.stack([-0.25 + 0.45 * phase, 0.30 + 0.05 * phase, 0.30 + 0.05 * phase], axis=1)
    left = right * np.array([-1.0, 1.0, 1.0]) - np.array([0.0, 0.07, 0.0])
    hands = np.tile([0.0, 0.0, 0.0, 1.0], (times.size, 1))
    return {"right": (right, hands), "left": (left, hands)}


@pytest.mark.parametrize("pieces", [[40], [10, 20, 10], [1, 39], [7, 3, 12, 18]])
def test_both_arms_tracks_piece_by_piece_are_the_tracks_at_once_where_the_arms_crowd(avatar, pieces):
    """The tracks found twice where the arms cross (each going on from its own state) are
    the same whatever grid points a batch solves."""
    from motor.arm.swivel_track import SWIVEL_PERIOD, SwivelGrid

    def solved(batches: list[int]) -> SwivelGrid:
        grid, start = SwivelGrid(avatar), 0
        for size in batches:
            end = start + size - 1
            grid.solve(start, end, start == 0, _crossing_inputs(grid.times(start, end)))
            start = end + 1
        return grid

    times = np.arange(1, 38) * SWIVEL_PERIOD
    whole, split = solved([40]), solved(pieces)
    for arm in ("right", "left"):
        for a, b in zip(whole.sample(arm, times, 0, 39), split.sample(arm, times, 0, 39)):
            np.testing.assert_allclose(b, a, rtol=0.0, atol=1e-12)
