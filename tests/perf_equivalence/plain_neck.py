"""The neck's and the eyes' numpy steps as they stood before they were compiled
(issue 19): :meth:`motor.neck.control.NeckControl.pose` after the trunk and the channels'
samples — the head's orientation, the torso's pose down the chain, the neck joints'
shares and the eyes aimed — the plain path :mod:`motor.neck.posing` is held to, bit for
bit, by ``test_compiled_neck.py``. Not used by mura itself."""

from __future__ import annotations

import numpy as np

from motor import quaternion as quat
from motor.body.avatar import Avatar
from motor.neck.posing import EYE_RANGE, NECK_SHARES
from motor.neck.gaze import FORWARD


def pose(avatar: Avatar, path: tuple[int, ...], neck: tuple[int, int, int], eyes: tuple[int, ...],
         rotations: np.ndarray, gaze: np.ndarray, offsets: np.ndarray) -> np.ndarray:  # fmt: skip
    looked, facing = gaze[:, :3], quat.normalize(gaze[:, 3:6])
    head = quat.multiply(quat.between_vectors(FORWARD, facing), quat.from_rotation_vector(offsets[:, :3]))
    torso, torso_at = _chain(avatar, rotations, path)
    _neck_joints(neck, rotations, torso, head, offsets[:, 3])
    if eyes:
        _aim_eyes(avatar, neck, eyes, rotations, torso, torso_at, head, looked)
    return rotations


def _chain(avatar: Avatar, rotations: np.ndarray, path: tuple[int, ...]) -> tuple[np.ndarray, np.ndarray]:
    n = rotations.shape[0]
    orientation = np.broadcast_to(quat.IDENTITY, (n, 4))
    position = np.zeros((n, 3))
    for joint in path:
        position = position + quat.rotate(orientation, avatar.offsets[joint])
        orientation = quat.multiply(orientation, rotations[:, joint])
    return orientation, position


def _neck_joints(neck: tuple[int, int, int], rotations: np.ndarray, torso: np.ndarray, head: np.ndarray, protrusion: np.ndarray) -> None:
    relative = quat.to_rotation_vector(quat.multiply(quat.conjugate(torso), head))
    flex = protrusion[:, None] * np.array([1.0, 0.0, 0.0])
    lower = quat.from_rotation_vector(NECK_SHARES[0] * relative + flex)
    middle = quat.from_rotation_vector(NECK_SHARES[1] * relative)
    vc7, vc4, skull = neck
    rotations[:, vc7] = lower
    rotations[:, vc4] = middle
    above = quat.multiply(quat.multiply(torso, lower), middle)
    rotations[:, skull] = quat.normalize(quat.multiply(quat.conjugate(above), head))


def _aim_eyes(avatar: Avatar, neck: tuple[int, int, int], eyes: tuple[int, ...], rotations: np.ndarray,
              torso: np.ndarray, torso_at: np.ndarray, head: np.ndarray, looked: np.ndarray) -> None:  # fmt: skip
    orientation, position = torso, torso_at
    for joint in neck:
        position = position + quat.rotate(orientation, avatar.offsets[joint])
        orientation = quat.multiply(orientation, rotations[:, joint])
    skull = neck[2]
    for eye in eyes:
        centre = position + quat.rotate(orientation, avatar.rest_positions[eye] - avatar.rest_positions[skull])
        seen = quat.normalize(quat.rotate(quat.conjugate(head), looked - centre))
        turn = quat.between_vectors(FORWARD, seen)
        angle = quat.angle_between(quat.IDENTITY, turn)
        fraction = np.minimum(1.0, EYE_RANGE / np.maximum(angle, 1e-12))
        rotations[:, eye] = quat.slerp(quat.IDENTITY, turn, fraction)
