"""Which way a hand turns between two rotations (:mod:`motor.arm.hand_turn`), over tables
of rotations on both sides of both avatars.

* Every turn starts at the first rotation, ends at the second and turns at an even rate
  about one axis.
* A turn of less than :data:`NEAR_HALF` keeps the short arc (a slerp's).
* A hand turned from the fingers up to the fingers down, whatever the palm does, keeps the
  fingers from pointing back toward the body on the way (the short arc may not).
* A gesture's hand retraction to rest turns that way too.
"""

from __future__ import annotations

import numpy as np
import pytest

from motor import quaternion as quat
from motor.arm import hand_turn
from motor.arm.hand_orientation import hand_rotations_from_vectors
from motor.arm.hand_turn import takes_long_way, turn_way
from motor.arm.wrist_rotation import HandRetractionLMP
from motor.body.avatar import load_avatar
from motor.program.lmp import ChannelState, RetractionLMP, TimePegs
from motor.trajectory.biocontrol import minimum_jerk

AVATARS = ("max", "makehuman")
SIDES = ("l", "r")
FRACTIONS = np.linspace(0.0, 1.0, 33)
#: Turns below this (radians) are short enough that no fingers can pay for the long arc.
NEAR_HALF = np.radians(120.0)
#: Most the fingers may point backward (negative forward component of the unit finger
#: axis) on the way from up to down.
BACKWARD = 0.02
_PALMS = {
    "in": [1.0, 0.0, 0.0],
    "out": [0.0, 0.0, 1.0],
    "back": [0.0, 0.0, -1.0],
    "side": [-1.0, 0.0, 0.0],
    "in_forward": [0.7, 0.0, 0.7],
    "out_side": [-0.6, 0.0, 0.8],
}


@pytest.fixture(scope="module", params=AVATARS)
def avatar(request):
    return load_avatar(request.param)


def _angle(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    return 2.0 * np.arccos(np.clip(np.abs(np.sum(p * q, axis=-1)), 0.0, 1.0))


def _random_pairs(seed: int, count: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    return quat.normalize(rng.normal(size=(count, 4))), quat.normalize(rng.normal(size=(count, 4)))


@pytest.mark.parametrize("side", SIDES)
@pytest.mark.parametrize("seed", range(4))
def test_a_turn_runs_evenly_from_the_first_rotation_to_the_second(avatar, side, seed):
    befores, afters = _random_pairs(seed, 25)
    for before, after in zip(befores, afters):
        way = turn_way(avatar, side, before, after, FRACTIONS)
        assert _angle(way[0], before) < 1e-6
        assert _angle(way[-1], after) < 1e-6
        steps = _angle(way[1:], way[:-1])
        np.testing.assert_allclose(steps, steps[0], atol=1e-6)


@pytest.mark.parametrize("side", SIDES)
@pytest.mark.parametrize("seed", range(4))
def test_a_turn_of_less_than_120_degrees_takes_the_short_arc(avatar, side, seed):
    befores, afters = _random_pairs(100 + seed, 200)
    short = _angle(befores, afters) < NEAR_HALF
    assert np.sum(short) > 10
    for before, after in zip(befores[short], afters[short]):
        assert not takes_long_way(avatar, side, before, after)
        way = turn_way(avatar, side, before, after, FRACTIONS)
        assert np.max(_angle(way, quat.slerp(before, after, FRACTIONS))) < 1e-6


@pytest.mark.parametrize("side", SIDES)
@pytest.mark.parametrize("palm_up", sorted(_PALMS))
@pytest.mark.parametrize("palm_down", sorted(_PALMS))
def test_a_hand_lowered_from_fingers_up_to_fingers_down_keeps_the_fingers_ahead(avatar, side, palm_up, palm_down):
    raised, lowered = hand_rotations_from_vectors(
        avatar, side, np.array([[0.0, 1.0, 0.0], [0.0, -1.0, 0.0]]), np.array([_PALMS[palm_up], _PALMS[palm_down]])
    )
    way = turn_way(avatar, side, raised, lowered, FRACTIONS)
    fingers = quat.rotate(way, avatar.hand_frames[side].finger_axis[None])
    assert -fingers[:, 2].min() <= BACKWARD, f"fingers point {-fingers[:, 2].min():.2f} backward on the way"


def test_the_short_arc_would_point_the_fingers_back_in_some_of_these_turns(avatar):
    """The cases the choice exists for: among the table's turns from fingers up to fingers
    down, a slerp sweeps the fingers back (through the hip, on the way to rest) in some."""
    finger = {side: avatar.hand_frames[side].finger_axis[None] for side in SIDES}
    backward = []
    for side in SIDES:
        for up in _PALMS.values():
            for down in _PALMS.values():
                raised, lowered = hand_rotations_from_vectors(avatar, side, np.array([[0.0, 1.0, 0.0], [0.0, -1.0, 0.0]]), np.array([up, down]))
                backward.append(-quat.rotate(quat.slerp(raised, lowered, FRACTIONS), finger[side])[:, 2].min())
    assert sum(b > 0.3 for b in backward) >= 4


@pytest.mark.parametrize("side", SIDES)
def test_the_hand_retracts_to_rest_the_way_of_least_cost(avatar, side):
    """A gesture's hand retraction (:class:`HandRetractionLMP`) runs along
    :func:`turn_way` on its time profile and ends at rest; where the short arc is the way
    of least cost it is the plain retraction's slerp."""
    arm = "left" if side == "l" else "right"
    rest = np.asarray(avatar.postures["rest"][side].hand_rotation, dtype=float)
    pegs = TimePegs.movement(1.0, 1.8)
    times = np.linspace(1.0, 1.8, 41)
    raised = hand_rotations_from_vectors(avatar, side, np.array([[0.0, 1.0, 0.0]] * len(_PALMS)), np.array(list(_PALMS.values())))
    befores, _ = _random_pairs(7, 20)
    # rest turned 170° about horizontal axes: back to rest, one way sweeps the fingers back
    axes = np.array([[np.cos(a), 0.0, np.sin(a)] for a in np.linspace(0.0, np.pi, 7)])
    swung = quat.multiply(quat.from_axis_angle(np.concatenate([axes, axes]), np.repeat([np.radians(170.0), -np.radians(170.0)], 7)), rest[None])
    long_ways = 0
    for before in [*raised, *befores, *swung]:
        state = ChannelState(before, np.zeros(3), 1.0)
        turned = HandRetractionLMP((arm, "hand_rotation"), pegs, rest, avatar=avatar).activate(state).sample(times)
        expected = turn_way(avatar, side, before, rest, minimum_jerk().fraction((times - 1.0) / 0.8))
        assert np.max(_angle(turned, expected)) < 1e-6
        assert _angle(turned[-1], rest) < 1e-6
        if takes_long_way(avatar, side, before, rest):
            long_ways += 1
            continue
        if _angle(before, rest) > np.pi - 1e-3:
            continue  # a half turn: either way is the short one
        plain = RetractionLMP((arm, "hand_rotation"), pegs, rest).activate(state).sample(times)
        assert np.max(_angle(turned, plain)) < 1e-6
    assert long_ways >= 1


@pytest.mark.parametrize("avatar_name", AVATARS)
def test_remembered_arcs_are_the_arcs_and_cannot_be_spoiled(avatar_name):
    """The arc per pair of rotations is remembered (a corpus turns the hand between the same
    pairs over and over): what it gives is what computing it again gives, and changing a
    returned axis changes nothing remembered."""
    avatar = load_avatar(avatar_name)
    rng = np.random.default_rng(37)
    pairs = quat.normalize(rng.normal(size=(12, 2, 4)))
    for side in "lr":
        for before, after in pairs:
            axis, turn = hand_turn._arc(avatar, side, before, after)
            axis[:] = 0.0
            again, turn_again = hand_turn._arc(avatar, side, before.copy(), after.copy())
            fresh, turn_fresh = hand_turn._remembered_arc.__wrapped__(avatar, side, before.tobytes(), after.tobytes())
            assert turn == turn_again == turn_fresh
            assert np.array_equal(again, fresh) and np.any(again != 0.0)
