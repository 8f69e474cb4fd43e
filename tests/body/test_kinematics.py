"""Forward kinematics against a per-frame scipy reference and the rest pose."""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from motor.body.kinematics import forward_kinematics, identity_rotations


def _reference(avatar, rotations, root):
    positions = np.zeros((avatar.joint_count, 3))
    globals_: list[Rotation] = []
    for joint, parent in enumerate(avatar.parents):
        local = Rotation.from_quat(rotations[joint])
        if parent < 0:
            globals_.append(local)
            positions[joint] = root + avatar.offsets[joint]
            continue
        globals_.append(globals_[parent] * local)
        positions[joint] = positions[parent] + globals_[parent].apply(np.array(avatar.offsets[joint]))
    return positions, np.array([g.as_quat() for g in globals_])


def test_rest_pose_reproduces_rest_positions(avatar):
    pose = forward_kinematics(avatar, identity_rotations(avatar, 2))
    assert np.allclose(pose.positions, avatar.rest_positions[None])
    assert np.allclose(pose.orientations[..., 3], 1.0)


def test_random_rotations_match_reference(avatar):
    frames = 4
    rotations = Rotation.random(frames * avatar.joint_count, random_state=3).as_quat().reshape(frames, avatar.joint_count, 4)
    root = np.random.default_rng(1).normal(size=(frames, 3))
    pose = forward_kinematics(avatar, rotations, root)
    for frame in range(frames):
        positions, orientations = _reference(avatar, rotations[frame], root[frame])
        assert np.allclose(pose.positions[frame], positions, atol=1e-12)
        assert np.allclose(np.abs(np.sum(pose.orientations[frame] * orientations, axis=-1)), 1.0)


def test_bad_shape_is_refused(avatar):
    import pytest

    with pytest.raises(ValueError, match="expected"):
        forward_kinematics(avatar, np.zeros((3, 5, 4)))
