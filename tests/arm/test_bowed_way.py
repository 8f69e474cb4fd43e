"""Straight wrist ways bowed around the body where they would crowd the arm
(:mod:`motor.arm.bowed_way`), over a synthetic table: hands held across the body close
to the upper chest and face, on both sides of both avatars, taken back to rest (the
retraction) and brought there from rest (the preparation).

* The bow is C² and vanishes with its slope at both ends: the wrist leaves and arrives
  as the straight way does.
* A way that crowds the arm is bowed so that it crowds it less, and not at all wherever a
  bow of the sizes tried can clear it; a way that does not is left straight.
* The retraction and the preparation LMPs follow the bowed way: from the activation state
  to the target, their velocities agreeing with their positions.
"""

from __future__ import annotations

import numpy as np
import pytest

from motor.arm.bowed_way import BOW_STEPS, CROWDING_TOLERANCE, SAMPLES, bow, bowed_trajectory, find_bow
from motor.arm.ik import solve_arm
from motor.arm.wrist_position import WristPositionLMP
from motor.arm.wrist_retraction import WristRetractionLMP
from motor.body.avatar import load_avatar
from motor.body.collision import kept_out_of_torso
from motor.program.lmp import ChannelState, TimePegs
from motor.trajectory.spline import approach

AVATARS = ("max", "makehuman")
SIDES = ("l", "r")
ARM = {"l": "left", "r": "right"}
WINDOWS = [((0.0, 0.25), (0.75, 1.0)), ((0.0, 0.4), (0.4, 1.0)), ((0.0, 0.3), (0.5, 1.0))]


@pytest.fixture(scope="module", params=AVATARS)
def avatar(request):
    return load_avatar(request.param)


def _holds(avatar, side: str) -> np.ndarray:
    """Wrist positions across the body (from the midline to 20 cm past it), from the top
    of the chest to 15 cm above it, 3 to 9 cm in front of the chest (metres)."""
    torso = avatar.torso
    across = -1.0 if side == "l" else 1.0
    front = torso.center[2] + torso.half_depth
    return np.array([
        [across * x, torso.top + y, front + z]
        for x in np.linspace(0.0, 0.2, 5) for y in (-0.05, 0.05, 0.15) for z in (0.03, 0.06, 0.09)
    ])  # fmt: skip


def _crowding(avatar, side: str, way: np.ndarray) -> float:
    """How much deeper (m) the arm goes into the body along ``way`` than at its deeper end
    (or than the tolerance): what a bow, which leaves the ends, can spare it."""
    depth = solve_arm(avatar, side, kept_out_of_torso(avatar, way)).penetration
    return float(depth.max() - max(CROWDING_TOLERANCE, depth[0], depth[-1]))


def _way(start: np.ndarray, end: np.ndarray) -> np.ndarray:
    return start + np.linspace(0.0, 1.0, SAMPLES)[:, None] * (end - start)


@pytest.mark.parametrize("window", WINDOWS)
def test_the_bow_is_smooth_and_vanishes_with_its_slope_at_both_ends(window):
    u = np.linspace(0.0, 1.0, 4001)
    shape, slope = bow(u, window)
    assert shape[0] == 0.0 and shape[-1] == 0.0 and slope[0] == 0.0 and slope[-1] == 0.0
    assert np.all((shape >= 0.0) & (shape <= 1.0)) and shape.max() == 1.0
    np.testing.assert_allclose(np.gradient(shape, u), slope, atol=2e-3)
    curvature = np.gradient(slope, u)
    assert np.max(np.abs(np.diff(curvature))) < 0.02 * np.max(np.abs(curvature)), "no step in the bow's curvature"


@pytest.mark.parametrize("side", SIDES)
def test_a_way_that_crowds_the_arm_is_bowed_around_the_body(avatar, side):
    rest = np.asarray(avatar.postures["rest"][side].wrist, dtype=float)
    crowded = 0
    for hold in _holds(avatar, side):
        for way in (_way(hold, rest), _way(rest, hold)):
            before = _crowding(avatar, side, way)
            found = find_bow(avatar, side, way)
            if before <= 0.0:
                assert found is None
                continue
            crowded += 1
            if found is None:
                continue
            assert np.linalg.norm(found.displacement) <= BOW_STEPS[-1] + 1e-9
            assert abs(found.displacement @ (way[-1] - way[0])) < 1e-9, "across the way"
            shape = bow(np.linspace(0.0, 1.0, SAMPLES), found.window)[0]
            after = _crowding(avatar, side, way + shape[:, None] * found.displacement)
            assert after < before
    assert crowded >= 3, "the table crosses the body where the arm is crowded"


def test_a_way_clear_of_the_body_stays_straight(avatar):
    for side in SIDES:
        rest = np.asarray(avatar.postures["rest"][side].wrist, dtype=float)
        out = np.array([0.3 if side == "l" else -0.3, avatar.torso.top - 0.1, avatar.torso.center[2] + 0.35])
        assert find_bow(avatar, side, _way(rest, out)) is None


@pytest.mark.parametrize("side", SIDES)
def test_the_retraction_follows_the_bowed_way_from_the_hold_to_rest(avatar, side):
    rest = np.asarray(avatar.postures["rest"][side].wrist, dtype=float)
    pegs = TimePegs.movement(1.0, 2.2)
    spared = []
    for hold in _holds(avatar, side):
        lmp = WristRetractionLMP((ARM[side], "wrist_position"), pegs, rest, avatar=avatar)
        realized = lmp.activate(ChannelState(hold, np.zeros(3), 1.0))
        times = np.linspace(1.0, 2.2, 241)
        path = realized.sample(times)
        np.testing.assert_allclose(path[0], hold, atol=1e-12)
        np.testing.assert_allclose(path[-1], rest, atol=1e-12)
        velocities = np.array([realized.state(t).velocity for t in times[1:-1]])
        np.testing.assert_allclose(velocities, np.gradient(path, times, axis=0)[1:-1], atol=2e-3)
        if not hasattr(realized, "bowed"):
            continue
        straight = WristRetractionLMP((ARM[side], "wrist_position"), pegs, rest).activate(ChannelState(hold, np.zeros(3), 1.0))
        before, after = _crowding(avatar, side, straight.sample(times)), _crowding(avatar, side, path)
        assert after <= max(before, 0.0) + 1e-4
        spared.append(max(before, 0.0) - max(after, 0.0))
    assert sum(spared) > 0.01, "bowed retractions spare the arm centimetres in all"


@pytest.mark.parametrize("side", SIDES)
def test_the_preparation_is_bowed_only_where_its_way_crowds_the_arm(avatar, side):
    rest = np.asarray(avatar.postures["rest"][side].wrist, dtype=float)
    pegs = TimePegs(0.0, 1.2, 1.2, 1.3, 1.4, 1.5, 1.6)
    still = ChannelState(rest, np.zeros(3), 0.0)
    times = np.linspace(0.0, 1.2, 241)
    bowed = 0
    for hold in _holds(avatar, side):
        plain = WristPositionLMP(ARM[side], pegs, hold[None]).activate(still).sample(times)
        with_body = WristPositionLMP(ARM[side], pegs, hold[None], avatar=avatar).activate(still).sample(times)
        found = find_bow(avatar, side, approach(rest, np.zeros(3), 0.0, hold, 1.2).position(np.linspace(0.0, 1.2, SAMPLES)))
        if found is None:
            np.testing.assert_array_equal(with_body, plain)
            continue
        np.testing.assert_allclose(with_body[[0, -1]], plain[[0, -1]], atol=1e-12)
        assert _crowding(avatar, side, with_body) <= max(_crowding(avatar, side, plain), 0.0) + 1e-4
        bowed += 1
    assert bowed >= 1


def test_a_bowed_trajectory_is_the_piece_plus_the_bow(avatar):
    rest = np.asarray(avatar.postures["rest"]["l"].wrist, dtype=float)
    times = np.linspace(0.5, 1.5, 301)
    checked = 0
    for hold in _holds(avatar, "l"):
        piece = approach(rest, np.zeros(3), 0.5, hold, 1.5)
        found = find_bow(avatar, "l", piece.position(np.linspace(0.5, 1.5, SAMPLES)))
        if found is None:
            continue
        checked += 1
        expected = piece.position(times) + bow(times - 0.5, found.window)[0][:, None] * found.displacement
        np.testing.assert_allclose(bowed_trajectory(piece, found).position(times), expected, atol=1e-9)
    assert checked >= 1
