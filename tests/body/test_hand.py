"""Hand shapes: fingertip geometry of the basic shapes on both avatars and both hands."""

from __future__ import annotations

import numpy as np
import pytest

from motor.body.conventions import LONG_FINGERS
from motor.body.kinematics import Pose, forward_kinematics, identity_rotations
from motor.hand.shape import PARAMETER_COUNT, hand_rotations, handshape_params
from mura.errors import SpecError
from mura.values import BASIC_HANDSHAPES, FingerBend, HandShape


def _pose(avatar, side: str, params: np.ndarray) -> Pose:
    params = np.atleast_2d(params)
    rotations = identity_rotations(avatar, params.shape[0])
    rotations[:, avatar.hand_joints(side)] = hand_rotations(avatar, side, params)
    return forward_kinematics(avatar, rotations)


def _site(avatar, pose: Pose, name: str) -> np.ndarray:
    site = avatar.sites[name]
    return pose.point(site.bone, site.offset)


def _shape(avatar, side, shape: HandShape) -> tuple[Pose, dict[str, np.ndarray]]:
    pose = _pose(avatar, side, handshape_params(shape))
    tips = {f: _site(avatar, pose, f"{side}_{f}_fingertip")[0] for f in ("thumb",) + LONG_FINGERS}
    return pose, tips


SIDES = ["l", "r"]


@pytest.mark.parametrize("side", SIDES)
def test_fist_fingertips_near_the_palm(avatar, side):
    pose, tips = _shape(avatar, side, HandShape("fist"))
    palm = _site(avatar, pose, f"{side}_palm")[0]
    hand = avatar.arm_length() / 0.58
    for finger in LONG_FINGERS:
        assert np.linalg.norm(tips[finger] - palm) < 0.035 * hand, finger


@pytest.mark.parametrize("side", SIDES)
def test_flat_hand_fingers_straight_and_adjacent(avatar, side):
    pose, tips = _shape(avatar, side, HandShape("flathand"))
    for finger in LONG_FINGERS:
        joints = [avatar.joint_index(f"{side}_{finger}{i}") for i in (1, 2, 3)]
        points = np.vstack([pose.positions[0, joints], tips[finger]])
        segments = np.diff(points, axis=0)
        segments /= np.linalg.norm(segments, axis=1, keepdims=True)
        assert np.all(segments[:-1] @ segments[1:].T > 0.999)
        assert segments[0] @ avatar.hand_frames[side].finger_axis > 0.99
    across = avatar.hand_frames[side].thumb_side
    for a, b in zip(LONG_FINGERS, LONG_FINGERS[1:]):
        gap = (tips[a] - tips[b]) @ across
        assert 0.008 < gap < 0.02, (a, b, gap)


@pytest.mark.parametrize("side", SIDES)
@pytest.mark.parametrize("shape, finger", [("pinch12", "index"), ("pinch12open", "index"), ("pinchall", "middle")])
def test_pinch_thumb_meets_finger(avatar, side, shape, finger):
    _, tips = _shape(avatar, side, HandShape(shape))
    assert np.linalg.norm(tips["thumb"] - tips[finger]) < 0.006


@pytest.mark.parametrize("side", SIDES)
@pytest.mark.parametrize("shape", ["cee12", "ceeall", "ceeopen"])
def test_cee_leaves_a_gap_that_the_opening_widens(avatar, side, shape):
    gaps = {}
    for opening in ("narrow", "normal", "wide"):
        _, tips = _shape(avatar, side, HandShape(shape, opening=opening))
        gaps[opening] = np.linalg.norm(tips["thumb"] - tips["index"])
    assert gaps["narrow"] > 0.015
    assert gaps["narrow"] < gaps["normal"] < gaps["wide"]


def test_left_hand_mirrors_right(avatar):
    for name in BASIC_HANDSHAPES:
        params = handshape_params(HandShape(name))
        left = _pose(avatar, "l", params).positions[0, avatar.hand_joints("l")]
        right = _pose(avatar, "r", params).positions[0, avatar.hand_joints("r")]
        assert np.allclose(left * [-1, 1, 1], right, atol=1e-9), name


def test_ring_and_pinky_cmc_move_only_with_bend_and_splay(avatar):
    ring0 = 9
    spread = hand_rotations(avatar, "l", handshape_params(HandShape("finger2345")))
    assert np.allclose(spread[0, ring0], [0, 0, 0, 1])
    params = handshape_params(HandShape("finger2345", bending="round"))
    cupped = hand_rotations(avatar, "l", params)
    assert not np.allclose(cupped[0, ring0], [0, 0, 0, 1])


def test_modifiers_change_the_right_fingers():
    plain = handshape_params(HandShape("finger2"))
    pinky = handshape_params(HandShape("finger2", extended=("pinky",)))
    index, last = slice(10, 14), slice(22, 26)
    assert np.allclose(pinky[last], plain[index]) and np.allclose(pinky[index], plain[last])
    hooked = handshape_params(HandShape("flathand", finger_bends=(FingerBend(("index",), "hooked"),)))
    assert np.allclose(hooked[10:14], [0, 0, 1, 1])
    assert np.allclose(hooked[14:18], 0)
    rounded = handshape_params(HandShape("flathand", bending="round"))
    assert np.allclose(rounded[10::4], 0.5)


def test_between_is_the_parameter_midpoint(avatar):
    flat, fist = handshape_params(HandShape("flathand")), handshape_params(HandShape("fist"))
    between = handshape_params(HandShape("flathand", between=HandShape("fist")))
    assert np.allclose(between, 0.5 * (flat + fist))
    frames = np.linspace(flat, fist, 7)
    assert hand_rotations(avatar, "r", frames).shape == (7, 17, 4)
    assert frames.shape[1] == PARAMETER_COUNT


@pytest.mark.parametrize(
    "shape, symbol",
    [
        (HandShape("claw", name="hamclaw"), "hamclaw"),
        (HandShape("flathand", bending="wiggly", name="BSflat(FBwiggly)"), "wiggly"),
        (HandShape("fist", thumb="sideways"), "sideways"),
        (HandShape("ceeall", opening="huge"), "huge"),
        (HandShape("finger2", extended=("toe",)), "toe"),
    ],
)
def test_unknown_symbols_are_spec_errors(shape, symbol):
    with pytest.raises(SpecError, match=symbol):
        handshape_params(shape)
