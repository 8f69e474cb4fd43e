"""Forward kinematics: local joint rotations of many frames to global joint poses.

Vectorized over frames; the only Python loop runs over the depth levels of the joint tree
(about 16), each level computing all its joints of all frames at once, in a joint-major
memory layout so that every gather copies contiguous blocks.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from motor import quaternion as quat
from motor.body.avatar import Avatar


@dataclass(frozen=True, eq=False)
class Pose:
    """Global joint poses of ``n`` frames in the avatar frame.

    ``positions (n, J, 3)`` metres; ``orientations (n, J, 4)`` global rotations
    (scalar-last unit quaternions) of each joint's frame relative to the rest pose.
    """

    positions: np.ndarray
    orientations: np.ndarray

    def point(self, joint: int, offset: np.ndarray) -> np.ndarray:
        """Positions ``(n, 3)`` of a point fixed to a joint's frame at ``offset`` (rest frame)."""
        return self.positions[:, joint] + quat.rotate(self.orientations[:, joint], offset)


def forward_kinematics(avatar: Avatar, rotations: np.ndarray, root_translation: np.ndarray | None = None) -> Pose:
    """Global positions and orientations of every joint.

    Args:
        rotations: ``(n, J, 4)`` local rotations (identity = rest pose).
        root_translation: ``(n, 3)`` root position, metres; zeros (root at origin) if None.
    """
    rotations = np.asarray(rotations, dtype=float)
    if rotations.ndim != 3 or rotations.shape[1:] != (avatar.joint_count, 4):
        raise ValueError(f"rotations shape {rotations.shape}, expected (n, {avatar.joint_count}, 4)")
    # joint-major layout: each level gathers whole contiguous blocks of frames
    local = np.ascontiguousarray(rotations.transpose(1, 0, 2))
    positions = np.empty((avatar.joint_count, rotations.shape[0], 3))
    orientations = np.empty_like(local)
    root = avatar.levels[0]
    orientations[root] = local[root]
    positions[root] = avatar.offsets[root][:, None, :]
    if root_translation is not None:
        positions[root] += np.asarray(root_translation, dtype=float)[None, :, :]
    for level in avatar.levels[1:]:
        parent = avatar.parents[level]
        parent_orientation = orientations[parent]
        orientations[level] = quat.multiply(parent_orientation, local[level])
        positions[level] = positions[parent] + quat.rotate(parent_orientation, avatar.offsets[level][:, None, :])
    return Pose(positions.transpose(1, 0, 2), orientations.transpose(1, 0, 2))


def identity_rotations(avatar: Avatar, frames: int) -> np.ndarray:
    """Rest-pose local rotations ``(frames, J, 4)``."""
    rotations = np.zeros((frames, avatar.joint_count, 4))
    rotations[..., 3] = 1.0
    return rotations
