"""BVH export: the file reads back (with the independent ``bvh`` package) to the same motion."""

from __future__ import annotations

import dataclasses
import os

import numpy as np
import pytest
from bvh import Bvh
from scipy.spatial.transform import Rotation

from agent.export.bvh import bvh_text, write_bvh
from motor.motion import Motion

ROTATION_CHANNELS = ["Zrotation", "Xrotation", "Yrotation"]


@pytest.fixture(scope="module")
def parsed(motion: Motion) -> Bvh:
    return Bvh(bvh_text(motion))


@pytest.fixture(scope="module")
def table(parsed: Bvh) -> np.ndarray:
    """All channel values, one row per frame, as the ``bvh`` package split them."""
    return np.array(parsed.frames, dtype=float)


def _channels(parsed: Bvh, table: np.ndarray, joint: str, channels: list[str]) -> np.ndarray:
    """``(frames, len(channels))`` values of one joint, located through the ``bvh`` package's layout."""
    first = parsed.get_joint_channels_index(joint)
    names = parsed.joint_channels(joint)
    return table[:, [first + names.index(channel) for channel in channels]]


def _axis_matrix(axis: str, degrees: np.ndarray) -> np.ndarray:
    """Rotation matrices about one axis, built by hand so the check does not trust scipy's Euler code."""
    angle = np.radians(degrees)
    c, s = np.cos(angle), np.sin(angle)
    one, zero = np.ones_like(angle), np.zeros_like(angle)
    rows = {
        "X": [[one, zero, zero], [zero, c, -s], [zero, s, c]],
        "Y": [[c, zero, s], [zero, one, zero], [-s, zero, c]],
        "Z": [[c, -s, zero], [s, c, zero], [zero, zero, one]],
    }[axis]
    return np.moveaxis(np.array(rows), (0, 1), (-2, -1))


def test_hierarchy_matches_skeleton(motion: Motion, parsed: Bvh) -> None:
    assert sorted(parsed.get_joints_names()) == sorted(motion.joint_names)
    assert parsed.get_joints_names()[0] == "humanoid_root"
    for joint, name in enumerate(motion.joint_names):
        if joint == 0:
            assert parsed.joint_channels(name) == ["Xposition", "Yposition", "Zposition", *ROTATION_CHANNELS]
            assert parsed.joint_offset(name) == (0.0, 0.0, 0.0)
            continue
        assert parsed.joint_channels(name) == ROTATION_CHANNELS
        assert parsed.joint_parent(name).name == motion.joint_names[motion.parents[joint]]
        np.testing.assert_allclose(parsed.joint_offset(name), motion.offsets[joint] * 100.0, atol=1e-6)


def test_every_leaf_has_an_end_site(motion: Motion) -> None:
    leaves = set(range(len(motion.joint_names))) - set(motion.parents)
    assert bvh_text(motion).count("End Site") == len(leaves)


def test_frames_and_frame_time(motion: Motion, parsed: Bvh, table: np.ndarray) -> None:
    assert parsed.nframes == motion.frame_count
    assert parsed.frame_time == pytest.approx(1.0 / motion.fps, abs=1e-8)
    assert table.shape == (motion.frame_count, 6 + 3 * (len(motion.joint_names) - 1))


def test_root_position_in_centimetres(motion: Motion, parsed: Bvh, table: np.ndarray) -> None:
    position = _channels(parsed, table, "humanoid_root", ["Xposition", "Yposition", "Zposition"])
    np.testing.assert_allclose(position, motion.root_translation * 100.0, atol=1e-6)


def test_euler_angles_compose_back_to_the_quaternions(motion: Motion, parsed: Bvh, table: np.ndarray) -> None:
    """BVH semantics: channels ``Z X Y`` are applied in order as intrinsic rotations, R = Rz·Rx·Ry."""
    for joint, name in enumerate(motion.joint_names):
        angles = _channels(parsed, table, name, ROTATION_CHANNELS)
        composed = _axis_matrix("Z", angles[:, 0]) @ _axis_matrix("X", angles[:, 1]) @ _axis_matrix("Y", angles[:, 2])
        expected = Rotation.from_quat(motion.rotations[:, joint]).as_matrix()
        np.testing.assert_allclose(composed, expected, atol=1e-6, err_msg=name)


def test_motion_actually_moves(parsed: Bvh, table: np.ndarray) -> None:
    """Guards the round-trip test against a motion that is all identity."""
    angles = _channels(parsed, table, "r_shoulder", ROTATION_CHANNELS)
    assert np.ptp(angles, axis=0).max() > 45.0


def test_write_bvh_renames_a_complete_file(motion: Motion, tmp_path) -> None:
    target = tmp_path / "take.bvh"
    write_bvh(motion, target)
    assert target.read_text() == bvh_text(motion)
    assert os.listdir(tmp_path) == ["take.bvh"]


def test_failed_write_leaves_nothing(motion: Motion, tmp_path) -> None:
    broken = dataclasses.replace(motion, rotations=np.where(np.arange(4) == 3, np.nan, motion.rotations))
    with pytest.raises(ValueError, match="non-finite value in rotations"):
        write_bvh(broken, tmp_path / "take.bvh")
    assert os.listdir(tmp_path) == []


def _renamed(motion: Motion, joint: int, name: str) -> Motion:
    names = list(motion.joint_names)
    names[joint] = name
    return dataclasses.replace(motion, joint_names=tuple(names))


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda m: _renamed(m, 5, "neck base"), r"joint 5 has name 'neck base'"),
        (lambda m: _renamed(m, 5, ""), r"joint 5 has name ''"),
        (lambda m: dataclasses.replace(m, parents=(-1, 0, -1, *m.parents[3:])), r"exactly one root"),
        (lambda m: dataclasses.replace(m, parents=(*m.parents[:3], 5, *m.parents[4:])),
         r"joint 3 \(vt10\) has parent 5"),
        (lambda m: dataclasses.replace(m, rotations=np.zeros_like(m.rotations)), r"zero quaternion at frame 0, joint 0"),
        (lambda m: dataclasses.replace(m, root_translation=m.root_translation + np.inf),
         r"non-finite value in root_translation"),
    ],
    ids=["space-in-name", "empty-name", "two-roots", "child-before-parent", "zero-quaternion", "infinite-root"],
)
def test_bad_motion_is_rejected_naming_the_fault(motion: Motion, change, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        bvh_text(change(motion))


def test_non_depth_first_joint_order_keeps_channels_with_their_joints(motion: Motion) -> None:
    """Motion lists joints parents-first but not necessarily depth-first; BVH must regroup."""
    order = sorted(range(len(motion.joint_names)), key=lambda j: (_depth(motion.parents, j), j))
    position = {old: new for new, old in enumerate(order)}
    shuffled = Motion(
        fps=motion.fps,
        joint_names=tuple(motion.joint_names[j] for j in order),
        parents=tuple(-1 if motion.parents[j] < 0 else position[motion.parents[j]] for j in order),
        offsets=motion.offsets[order],
        rotations=motion.rotations[:, order],
        root_translation=motion.root_translation,
    )
    assert shuffled.joint_names != motion.joint_names
    assert bvh_text(shuffled) == bvh_text(motion)


def _depth(parents: tuple[int, ...], joint: int) -> int:
    depth = 0
    while parents[joint] >= 0:
        joint, depth = parents[joint], depth + 1
    return depth


def test_empty_motion_writes_a_valid_header(motion: Motion) -> None:
    empty = dataclasses.replace(motion, rotations=motion.rotations[:0], root_translation=motion.root_translation[:0])
    assert Bvh(bvh_text(empty)).nframes == 0
