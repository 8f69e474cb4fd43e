"""Avatar files: the shipped avatars load, and broken files are refused naming the field."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Callable

import numpy as np
import pytest

from motor.body.avatar import load_avatar
from motor.body.conventions import AVATAR_DIR, AvatarError, required_joints


def test_shipped_avatars_have_a_full_skeleton(avatar):
    assert avatar.joint_count >= 50
    assert set(required_joints()) <= set(avatar.joint_names)
    for joint, parent in enumerate(avatar.parents):
        assert parent < joint


def test_avatars_differ_in_proportions(avatars):
    tall, small = avatars["max"], avatars["kim"]
    assert tall.stature > small.stature + 0.2
    shoulder_height = lambda a: a.rest_positions[a.joint_index("l_shoulder"), 1]
    relative_arm = lambda a: a.arm_length("l") / shoulder_height(a)
    assert relative_arm(small) < relative_arm(tall) - 0.05


@pytest.mark.parametrize("side", ["l", "r"])
def test_hand_frames_are_right_handed_mirrors(avatar, side):
    frame = avatar.hand_frames[side]
    sign = 1.0 if side == "l" else -1.0
    assert np.allclose(frame.finger_axis, [0, -1, 0], atol=0.05)
    assert np.allclose(frame.palm_normal, [-sign, 0, 0], atol=0.05)
    assert np.allclose(np.cross(frame.bend_axis, frame.finger_axis), frame.palm_normal)
    assert np.allclose(np.cross(frame.splay_axis, frame.finger_axis), frame.thumb_side)


def _write(tmp_path: Path, data: dict[str, Any]) -> Path:
    path = tmp_path / "kim.json"
    path.write_text(json.dumps(data))
    return path


def _drop_joint(data):
    data["joints"] = [j for j in data["joints"] if j["name"] != "l_ring0"]
    for j in data["joints"]:
        if j["parent"] == "l_ring0":
            j["parent"] = "l_wrist"


def _cycle(data):
    joints = {j["name"]: j for j in data["joints"]}
    joints["vl5"]["parent"] = "vt1"


def _set(path: str, value: Any) -> Callable[[dict], None]:
    def edit(data: dict) -> None:
        *head, last = path.split("/")
        node = data
        for key in head:
            node = node[int(key)] if key.isdigit() else node[key]
        node[last] = value

    return edit


def _delete(path: str) -> Callable[[dict], None]:
    def edit(data: dict) -> None:
        *head, last = path.split("/")
        node = data
        for key in head:
            node = node[key]
        del node[last]

    return edit


BROKEN = [
    (_drop_joint, "joints: missing joint 'l_ring0'"),
    (_cycle, "joints: cycle in the joint hierarchy"),
    (_set("joints/3/parent", "nowhere"), "joints[3].parent: joint 'vl3' has unknown parent 'nowhere'"),
    (_set("locations/nose/bone", "skul"), "kim.json: locations.nose.bone: unknown bone 'skul'"),
    (_set("postures/rest/l/hand_rotation", [0.0, 0.0, 0.5, 0.5]), "postures.rest.l.hand_rotation: a quaternion must have unit length"),
    (_delete("grid/heights/LocShoulder"), "grid.heights.LocShoulder: missing required field"),
    (_delete("stature"), "kim.json: stature: missing required field"),
    (_delete("thumb/positions/pinch"), "thumb.positions.pinch: missing required field"),
    (_set("limits/l_elbow/flexion", [2.0, 0.0]), "limits.l_elbow.flexion: min 2.0 exceeds max 0.0"),
    (_delete("limits/r_wrist"), "limits.r_wrist.flexion: missing required field"),
    (_set("joints/2/offset", [0.0, "x", 0.0]), "joints[2].offset[1]: expected a finite number"),
    (_set("locations/l_ear/normal", [0.0, 0.0, 0.0]), "locations.l_ear.normal: a normal must have unit length"),
]


@pytest.mark.parametrize("edit, message", BROKEN)
def test_broken_avatar_files_are_refused_naming_the_field(tmp_path, edit, message):
    data = json.loads((AVATAR_DIR / "kim.json").read_text())
    edit(data)
    with pytest.raises(AvatarError) as caught:
        load_avatar(_write(tmp_path, data))
    assert message in str(caught.value)


def test_unknown_avatar_name_lists_the_known_ones():
    with pytest.raises(AvatarError, match="known avatars: .*kim.*max"):
        load_avatar("nobody")


def test_invalid_json_names_line(tmp_path):
    path = tmp_path / "bad.json"
    path.write_text('{"name": "x",\n "joints": [}')
    with pytest.raises(AvatarError, match=r"bad.json:2:\d+: not valid JSON"):
        load_avatar(path)


def test_joint_index_names_the_missing_joint(avatar):
    with pytest.raises(KeyError, match="l_thumb9"):
        avatar.joint_index("l_thumb9")
