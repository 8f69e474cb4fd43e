"""Forward kinematics of a BVH file, written for the audit (no code shared with mura's motor).

Conventions of the BVH format, as read here:

* A joint's rotation channels, in the order the file lists them, are *intrinsic*
  rotations: ``Zrotation Xrotation Yrotation`` with angles ``(z, x, y)`` is
  ``R = R_z(z) · R_x(x) · R_y(y)`` acting on column vectors of the joint's frame, i.e.
  ``scipy.spatial.transform.Rotation.from_euler("ZXY", (z, x, y), degrees=True)``
  (upper-case axes are intrinsic in scipy). Each joint is converted with its own order.
* A joint with position channels is placed by their values (its ``OFFSET`` is then
  ignored, as mocap tools do for the root); a joint without them by its ``OFFSET``.
* Global placement: ``R_j = R_parent · R_local_j`` and
  ``p_j = p_parent + R_parent · t_j`` with ``t_j`` the joint's translation.

Every operation runs on all frames at once; the only loop is over the joints, parents
first. Lengths are multiplied by ``scale`` to give metres.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from bench.motion_audit.bvh_reader import BvhMotion

_AXES = {"Xrotation": "X", "Yrotation": "Y", "Zrotation": "Z"}
_POSITIONS = ("Xposition", "Yposition", "Zposition")


@dataclass(frozen=True)
class Kinematics:
    """The skeleton in every frame, in metres and the file's world frame.

    ``local`` ``(frames, joints, 4)`` local rotations as quaternions, scalar last
    ``(x, y, z, w)``; ``orientations`` the same, global; ``positions`` ``(frames, joints, 3)``
    joint positions; ``rest_positions`` ``(joints, 3)`` the joints with every rotation at
    identity and the root at the origin (the avatar's frame at rest); ``fps`` frames per
    second; ``names`` the joint names; ``parents`` their parents' indices (-1: root).
    """

    names: tuple[str, ...]
    parents: tuple[int, ...]
    fps: float
    local: np.ndarray
    orientations: np.ndarray
    positions: np.ndarray
    rest_positions: np.ndarray
    offsets: np.ndarray

    @property
    def frame_count(self) -> int:
        return int(self.positions.shape[0])

    def index(self, name: str) -> int:
        """The index of joint ``name``; KeyError naming it if absent."""
        try:
            return self.names.index(name)
        except ValueError:
            raise KeyError(f"the skeleton has no joint {name!r}") from None

    def times(self, start: float = 0.0) -> np.ndarray:
        """Frame times ``(frames,)`` in seconds from ``start``."""
        return start + np.arange(self.frame_count) / self.fps


def local_rotations(motion: BvhMotion) -> np.ndarray:
    """Local rotations ``(frames, joints, 4)`` (scalar-last quaternions) from each joint's
    rotation channels in its own order; identity for a joint without rotation channels.
    Joints sharing a channel order are converted together."""
    frames = motion.frame_count
    quaternions = np.zeros((frames, len(motion.joints), 4))
    quaternions[..., 3] = 1.0
    by_order: dict[str, list[int]] = {}
    for index, joint in enumerate(motion.joints):
        order = "".join(_AXES[channel] for channel in joint.channels if channel in _AXES)
        if order:
            by_order.setdefault(order, []).append(index)
    for order, joints in by_order.items():
        columns = [[motion.joints[j].first_channel + motion.joints[j].channels.index(f"{axis}rotation") for axis in order] for j in joints]
        angles = motion.values[:, np.array(columns)]  # (frames, joints, axes)
        rotations = Rotation.from_euler(order, angles.reshape(-1, len(order)), degrees=True)
        quaternions[:, joints] = rotations.as_quat().reshape(frames, len(joints), 4)
    return quaternions


def forward_kinematics(motion: BvhMotion, scale: float) -> Kinematics:
    """Global joint positions and orientations of every frame; lengths times ``scale``."""
    frames, count = motion.frame_count, len(motion.joints)
    local = local_rotations(motion)
    offsets = np.array([joint.offset for joint in motion.joints], dtype=float) * scale
    positions = np.zeros((frames, count, 3))
    orientations = np.zeros((frames, count, 4))
    rest = np.zeros((count, 3))
    global_rotations: list[Rotation] = []
    for index, joint in enumerate(motion.joints):
        translation = _translation(motion, index, offsets[index], scale)
        rotation = Rotation.from_quat(local[:, index])
        if joint.parent < 0:
            positions[:, index] = translation
            global_rotations.append(rotation)
        else:
            parent = global_rotations[joint.parent]
            positions[:, index] = positions[:, joint.parent] + parent.apply(translation)
            global_rotations.append(parent * rotation)
            rest[index] = rest[joint.parent] + offsets[index]
        orientations[:, index] = global_rotations[-1].as_quat()
    return Kinematics(
        names=motion.joint_names,
        parents=tuple(joint.parent for joint in motion.joints),
        fps=motion.fps,
        local=local,
        orientations=orientations,
        positions=positions,
        rest_positions=rest,
        offsets=offsets,
    )


def _translation(motion: BvhMotion, index: int, offset: np.ndarray, scale: float) -> np.ndarray:
    """The joint's translation from its parent ``(frames, 3)``: position channels if it has
    any (a missing axis reads as the offset's), else the offset."""
    joint = motion.joints[index]
    translation = np.broadcast_to(offset, (motion.frame_count, 3)).copy()
    for axis, channel in enumerate(_POSITIONS):
        values = motion.channel_values(index, channel)
        if values is not None:
            translation[:, axis] = values * scale
    return translation
