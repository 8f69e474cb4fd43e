"""Global hand rotation from extended-finger direction and palm orientation.

HamNoSys and MURML give a hand's orientation as two directions: where the fingers point
if they were straight (the *extended-finger direction*, EFD) and which way the palm faces.
The rotation returned takes the avatar's hand at rest (finger axis λ = wrist → middle
finger base, palm normal σ, see :class:`motor.body.avatar.HandFrame`) to one whose finger axis
points along the EFD and whose palm normal points along the palm direction's component
perpendicular to the EFD. The palm normal of each hand is its own (the left hand's mirrors
the right's), so the same spec turns both palms the same way in space.

Conventions for the cases the two directions do not decide:

* palm direction parallel to the EFD (EFD up with palm up, …): the palm direction is
  turned by 90° about the avatar's left–right axis, up → out → down → in → up (so with
  the EFD vertical, palm "up" reads as palm out and "down" as palm in); with the EFD
  left or right and the palm along it, the palm faces down if it named the EFD's own
  direction and up if the opposite;
* HamNoSys's relative form (``PalmOrientation.relative``): the palm direction is given
  for fingers pointing out (away from the body) and turns with the EFD, by the shortest
  rotation taking "out" onto the EFD (a half turn about the vertical for EFD "in").
"""

from __future__ import annotations

import numpy as np

from motor import quaternion as quat
from motor.body.avatar import Avatar, check_side
from mura.values import Direction, PalmOrientation

_OUT = np.array([0.0, 0.0, 1.0])
_UP = np.array([0.0, 1.0, 0.0])
_PARALLEL = 1e-6


def hand_rotation(avatar: Avatar, side: str, direction: Direction, palm: PalmOrientation) -> np.ndarray:
    """Global hand rotation ``(4,)`` of one hand for an EFD and a palm orientation."""
    finger = np.asarray(direction.vector, dtype=float)[None]
    palm_direction = np.asarray(palm.direction, dtype=float)[None]
    if palm.relative:
        palm_direction = quat.rotate(quat.between_vectors(_OUT, quat.normalize(finger)), palm_direction)
    return hand_rotations_from_vectors(avatar, side, finger, palm_direction)[0]


def hand_rotations_from_vectors(avatar: Avatar, side: str, fingers: np.ndarray, palms: np.ndarray) -> np.ndarray:
    """Global hand rotations ``(n, 4)`` from EFD vectors and palm directions ``(n, 3)``.

    Raises ValueError for a zero vector.
    """
    frame = avatar.hand_frames[check_side(side)]
    fingers = _unit(np.atleast_2d(np.asarray(fingers, dtype=float)), "extended-finger direction")
    palms = _unit(np.atleast_2d(np.asarray(palms, dtype=float)), "palm direction")
    palms = _resolve_parallel(fingers, palms)
    normal = quat.normalize(palms - np.sum(palms * fingers, axis=-1, keepdims=True) * fingers)
    rest = np.stack((frame.finger_axis, frame.palm_normal, np.cross(frame.finger_axis, frame.palm_normal)), axis=-1)
    target = np.stack((fingers, normal, np.cross(fingers, normal)), axis=-1)
    return quat.from_frames(rest, target)


def _unit(vectors: np.ndarray, what: str) -> np.ndarray:
    norm = np.linalg.norm(vectors, axis=-1, keepdims=True)
    if np.any(norm < 1e-12):
        raise ValueError(f"{what} has zero length")
    return vectors / norm


def _resolve_parallel(fingers: np.ndarray, palms: np.ndarray) -> np.ndarray:
    """Replace palm directions parallel to the EFD by the documented convention."""
    along = np.sum(fingers * palms, axis=-1)
    parallel = np.linalg.norm(np.cross(fingers, palms), axis=-1) < _PARALLEL
    if not np.any(parallel):
        return palms
    turned = np.stack((palms[:, 0], -palms[:, 2], palms[:, 1]), axis=-1)  # 90° about x: up → out
    still = np.linalg.norm(np.cross(fingers, turned), axis=-1) < _PARALLEL
    sideways = -np.sign(along)[:, None] * _UP
    replacement = np.where(still[:, None], sideways, turned)
    return np.where(parallel[:, None], replacement, palms)
