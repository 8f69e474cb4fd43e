"""Hand orientation from EFD and palm: both hands, the degenerate cases, the relative form."""

from __future__ import annotations

import numpy as np
import pytest

from motor import quaternion as quat
from motor.arm.hand_orientation import hand_rotation, hand_rotations_from_vectors
from motor.body.kinematics import forward_kinematics, identity_rotations
from mura.murml_vocabulary import parse_direction, parse_palm_orientation
from mura.values import AXES, Direction, PalmOrientation, direction_from_letters

SIDES = ["l", "r"]
#: The 18 HamNoSys extended-finger directions (6 axes, 12 diagonals) …
EFDS = ["u", "d", "l", "r", "o", "i", "ul", "ur", "dl", "dr", "uo", "ui", "do", "di", "lo", "li", "ro", "ri"]
#: … and the 8 palm orientations (the four around the hand plus up/down and in/out).
PALMS = ["u", "d", "l", "r", "o", "i", "ul", "ur"]


def _palm_normal(avatar, side, rotation):
    return quat.rotate(rotation, avatar.hand_frames[side].palm_normal)


@pytest.mark.parametrize("side", SIDES)
@pytest.mark.parametrize("efd", EFDS)
def test_fingers_point_along_the_efd_and_the_palm_faces_the_palm_direction(avatar, side, efd):
    finger = np.array(direction_from_letters(efd))
    for palm in PALMS:
        wanted = np.array(direction_from_letters(palm))
        rotation = hand_rotation(avatar, side, Direction(tuple(finger)), PalmOrientation(tuple(wanted)))
        assert np.allclose(quat.rotate(rotation, avatar.hand_frames[side].finger_axis), finger, atol=1e-9)
        normal = _palm_normal(avatar, side, rotation)
        assert abs(normal @ finger) < 1e-9
        perpendicular = wanted - (wanted @ finger) * finger
        if np.linalg.norm(perpendicular) > 1e-6:
            assert np.allclose(normal, perpendicular / np.linalg.norm(perpendicular), atol=1e-9)


@pytest.mark.parametrize("side", SIDES)
def test_physical_palm_and_thumb_of_both_hands(avatar, side):
    """Fingers out, palm down: the palm site faces the floor, the thumb points to the midline."""
    rotation = hand_rotation(avatar, side, parse_direction("DirA"), parse_palm_orientation("PalmD"))
    frames = identity_rotations(avatar, 1)
    wrist = avatar.joint_index(f"{side}_wrist")
    frames[0, wrist] = rotation  # the forearm is at rest, so the wrist's local rotation is global
    pose = forward_kinematics(avatar, frames)
    palm = avatar.sites[f"{side}_palm"]
    assert np.allclose(quat.rotate(pose.orientations[0, palm.bone], palm.normal), [0, -1, 0], atol=1e-9)
    thumb_side = pose.positions[0, avatar.joint_index(f"{side}_index1")] - pose.positions[0, avatar.joint_index(f"{side}_pinky1")]
    toward_midline = -1.0 if side == "l" else 1.0
    assert thumb_side[0] * toward_midline > 0


@pytest.mark.parametrize(
    "efd, palm, expected",
    [("u", "u", "o"), ("u", "d", "i"), ("d", "u", "o"), ("o", "o", "d"), ("i", "i", "u"), ("l", "l", "d"), ("l", "r", "u")],
)
def test_palm_parallel_to_the_efd_uses_the_documented_convention(avatar, efd, palm, expected):
    for side in SIDES:
        rotation = hand_rotations_from_vectors(avatar, side, [AXES[efd]], [AXES[palm]])[0]
        assert np.allclose(_palm_normal(avatar, side, rotation), AXES[expected], atol=1e-9)


def test_relative_palm_turns_with_the_fingers(avatar):
    relative = PalmOrientation(AXES["d"], "hamorirelative d", relative=True)
    out = hand_rotation(avatar, "r", Direction(AXES["o"]), relative)
    assert np.allclose(_palm_normal(avatar, "r", out), AXES["d"], atol=1e-9)
    up = hand_rotation(avatar, "r", Direction(AXES["u"]), relative)
    assert np.allclose(_palm_normal(avatar, "r", up), AXES["o"], atol=1e-9)
    absolute = hand_rotation(avatar, "r", Direction(AXES["u"]), PalmOrientation(AXES["d"]))
    assert np.allclose(_palm_normal(avatar, "r", absolute), AXES["i"], atol=1e-9)


def test_vectorized_matches_single(avatar):
    rng = np.random.default_rng(0)
    fingers, palms = rng.normal(size=(50, 3)), rng.normal(size=(50, 3))
    many = hand_rotations_from_vectors(avatar, "l", fingers, palms)
    for k in (0, 17, 49):
        one = hand_rotation(avatar, "l", Direction(tuple(fingers[k] / np.linalg.norm(fingers[k]))), PalmOrientation(tuple(palms[k])))
        assert quat.angle_between(one, many[k]) < 1e-6


def test_zero_direction_is_refused(avatar):
    with pytest.raises(ValueError, match="extended-finger direction has zero length"):
        hand_rotations_from_vectors(avatar, "r", [[0.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
