"""A small turn of the trunk where a hand reaches across the body close to it.

A hand far across the midline and near the chest cannot be reached by any elbow swivel
without the upper arm passing through the chest: people turn the upper trunk toward the
reach, bringing that shoulder forward. Only reach asks for it here: the turn is a smooth
function of the wrist targets (C¹), zero unless a wrist is across the midline and within
reach of the chest, growing to :data:`MAX_TURN` (opposite turns of the two arms cancel,
and an arm that reaches far keeps the trunk from turning its shoulder back).

The turn is spread evenly over :data:`TURN_JOINTS` (the thoracic spine, about the
vertical), so the clavicles' parent turns by the whole of it. The arms are then solved
in the trunk's own frame (:meth:`TrunkTurn.to_trunk`): targets and hand rotations carried
into it, where the trunk is upright and the body's collision volumes are at rest — the
arm joints' local rotations are the same in either frame.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from motor import quaternion as quat
from motor.body.avatar import Avatar

#: Spine joints that share the turn, and its largest amount (radians).
TURN_JOINTS: tuple[str, ...] = ("vt10", "vt6", "vt1")
MAX_TURN = float(np.radians(25.0))
#: How far across the midline (m) a wrist must be for the turn to start and to be whole,
#: and how far in front of the chest (m) it still is whole and no longer is at all.
ACROSS = (0.0, 0.3)
NEAR = (0.1, 0.4)
#: Reach (fractions of the arm's length from the shoulder) and how much farther (m) the
#: turn takes the hand, over which an arm that would go out of reach with the trunk turned
#: keeps it from turning away from it.
FAR = (0.97, 1.05)
AWAY = (0.0, 0.04)
_UP = np.array([0.0, 1.0, 0.0])


@dataclass(frozen=True, eq=False)
class TrunkTurn:
    """The trunk's turn at ``n`` instants: ``yaw (n,)`` radians about the vertical
    (positive toward the avatar's left), the clavicles' parent's global ``rotation
    (n, 4)`` and ``position (n, 3)``, and its ``rest`` position; ``spine_rotations
    (n, k, 4)`` and ``spine_positions (n, k, 3)`` are those of every turning joint
    (:data:`TURN_JOINTS`, the last being the clavicles' parent), ``spine_rest (k, 3)``
    their rest positions."""

    yaw: np.ndarray
    rotation: np.ndarray
    position: np.ndarray
    rest: np.ndarray
    spine_rotations: np.ndarray
    spine_positions: np.ndarray
    spine_rest: np.ndarray

    def to_trunk(self, points: np.ndarray) -> np.ndarray:
        """Points ``(n, 3)`` in the frame in which the trunk stands upright at rest."""
        return quat.rotate(quat.conjugate(self.rotation), points - self.position) + self.rest

    def from_trunk(self, points: np.ndarray) -> np.ndarray:
        """Points ``(n, 3)`` from the trunk's frame back into the avatar's."""
        return quat.rotate(self.rotation, points - self.rest) + self.position

    def hands_to_trunk(self, rotations: np.ndarray) -> np.ndarray:
        """Global rotations ``(n, 4)`` as seen in the trunk's frame."""
        return quat.multiply(quat.conjugate(self.rotation), rotations)

    def carried_frames(self) -> tuple[tuple[np.ndarray, np.ndarray], ...]:
        """Where the body's volumes are, seen from the trunk's frame, by how many of the
        turning joints carry them: one (rotation ``(n, 4)``, translation ``(n, 3)``) pair
        taking their rest geometry into the trunk's frame for the volumes that stay with
        the hips (first), then for those carried by each turning joint but the last (whose
        volumes are at rest in the trunk's frame)."""
        inverse = quat.conjugate(self.rotation)
        frames = [(inverse, self.rest - quat.rotate(inverse, self.position))]
        for joint in range(self.spine_rotations.shape[1] - 1):
            rotation = quat.multiply(inverse, self.spine_rotations[:, joint])
            moved = quat.rotate(inverse, self.spine_positions[:, joint] - self.position)
            frames.append((rotation, self.rest + moved - quat.rotate(rotation, self.spine_rest[joint])))
        return tuple(frames)

    def local_rotations(self) -> np.ndarray:
        """Local rotations ``(n, len(TURN_JOINTS), 4)`` of the turning spine joints."""
        share = quat.from_axis_angle(np.broadcast_to(_UP, (len(self.yaw), 3)), self.yaw / len(TURN_JOINTS))
        return np.repeat(share[:, None, :], len(TURN_JOINTS), axis=1)


def trunk_turn(avatar: Avatar, left: np.ndarray, right: np.ndarray) -> TrunkTurn | None:
    """The trunk's turn for the left and right wrist targets ``(n, 3)`` (avatar frame);
    None where no instant needs one."""
    front = avatar.grid.front
    # turning toward one arm's reach takes the other shoulder back: not as far as to take
    # that arm's hand out of reach
    toward_left = MAX_TURN * _demand(right, -1.0, front)
    toward_right = MAX_TURN * _demand(left, 1.0, front)
    toward_left = _held_in_reach(avatar, "l", left, toward_left, toward_left)
    toward_right = _held_in_reach(avatar, "r", right, toward_right, -toward_right)
    return turned(avatar, toward_left - toward_right)


def _held_in_reach(avatar: Avatar, side: str, wrists: np.ndarray, toward: np.ndarray, yaw: np.ndarray) -> np.ndarray:
    """``toward (n,)`` less as far as the turn ``yaw (n,)`` would take one arm's wrists
    out of reach (:func:`_out_of_reach`), worked out only at the instants where that can
    change it: where the other arm asks for a turn, or a wrist is not finite (elsewhere it
    is 0 either way)."""
    rows = np.flatnonzero((toward != 0.0) | ~np.isfinite(wrists).all(axis=1))
    if rows.size == 0:
        return toward
    held = toward.copy()
    held[rows] = toward[rows] * (1.0 - _out_of_reach(avatar, side, wrists[rows], yaw[rows]))
    return held


def turned(avatar: Avatar, yaw: np.ndarray) -> TrunkTurn | None:
    """The trunk turned by ``yaw (n,)`` radians; None where it is 0 throughout."""
    if not np.any(yaw != 0.0):
        return None
    rest, offsets, parent = _spine(avatar)
    share = quat.from_axis_angle(np.broadcast_to(_UP, (len(yaw), 3)), yaw / len(TURN_JOINTS))
    rotation = np.broadcast_to(quat.IDENTITY, share.shape)
    position = np.broadcast_to(parent, (len(yaw), 3))
    rotations, positions = [], []
    for offset in offsets:
        position = position + quat.rotate(rotation, offset)
        rotation = quat.multiply(rotation, share)
        rotations.append(rotation)
        positions.append(position)
    spine_rest = avatar.rest_positions[[avatar.joint_index(name) for name in TURN_JOINTS]]
    return TrunkTurn(yaw, rotation, position, rest, np.stack(rotations, axis=1), np.stack(positions, axis=1), spine_rest)


@functools.lru_cache(maxsize=16)
def _spine(avatar: Avatar) -> tuple[np.ndarray, tuple[np.ndarray, ...], np.ndarray]:
    """The clavicles' parent's rest position, the offsets of the turning joints from the
    first one's parent up to the clavicles' parent, and that parent's rest position."""
    indices = [avatar.joint_index(name) for name in TURN_JOINTS]
    offsets = tuple(np.asarray(avatar.offsets[i]) for i in indices)
    return avatar.rest_positions[indices[-1]], offsets, avatar.rest_positions[avatar.parents[indices[0]]]


def _demand(wrists: np.ndarray, side_sign: float, front: float) -> np.ndarray:
    """0 … 1: how much one arm's wrists ``(n, 3)`` ask the trunk to turn."""
    across = _ramp(-side_sign * wrists[:, 0], ACROSS)
    near = 1.0 - _ramp(wrists[:, 2] - front, NEAR)
    return across * near


def _out_of_reach(avatar: Avatar, side: str, wrists: np.ndarray, yaw: np.ndarray) -> np.ndarray:
    """0 … 1: how far out of reach one arm's wrists ``(n, 3)`` would go with the trunk
    turned by ``yaw``: their distance from the turned shoulder beyond :data:`FAR` of the
    arm's length, as far as the turn takes them away (a resting hand near the limit of
    its reach may swing a little with the trunk)."""
    rest, _, _ = _spine(avatar)
    shoulder = avatar.rest_positions[avatar.joint_index(f"{side}_shoulder")]
    relative = shoulder - rest
    cos, sin = np.cos(yaw), np.sin(yaw)
    turned_shoulder = np.stack([relative[0] * cos + relative[2] * sin, np.full_like(yaw, relative[1]), -relative[0] * sin + relative[2] * cos], axis=1) + rest
    distance = np.linalg.norm(wrists - turned_shoulder, axis=1)
    away = distance - np.linalg.norm(wrists - shoulder, axis=1)
    return _ramp(distance / avatar.arm_length(side), FAR) * _ramp(away, AWAY)


def _ramp(value: np.ndarray, edges: tuple[float, float]) -> np.ndarray:
    u = np.minimum(np.maximum((value - edges[0]) / (edges[1] - edges[0]), 0.0), 1.0)
    return u * u * (3.0 - 2.0 * u)
