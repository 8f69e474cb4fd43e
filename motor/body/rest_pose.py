"""Normalising a humanoid's rest pose to mura's.

mura's rest pose (see :mod:`motor.body.avatar`) has straight arms hanging at the sides,
palms facing the thighs, thumbs forward, fingers straight and parallel. A body in another
rest pose (the MakeHuman A-pose, a VRM T-pose) is brought into it by a global rotation per
arm joint, so that:

* the hand's long axis λ (wrist to middle-finger base) points along the arm's rest
  direction — down, tilted outward by the given angle so the hand clears the thigh — and
  its thumb side faces forward;
* the forearm and upper arm carry the hand's turn, each swung minimally onto the arm's
  rest direction (so straightening the elbow is a hinge motion and the twist is shared);
* every finger phalanx is swung onto λ (straight, parallel fingers); the thumb's two
  distal phalanges onto the direction of its proximal one.

Spine, head and legs keep their pose. Joint positions follow by forward kinematics.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

#: Outward tilt of the hanging arm when the body gives none to measure, radians.
DEFAULT_ABDUCTION = np.radians(8.0)
LONG_FINGERS = ("index", "middle", "ring", "pinky")
FINGERS = ("thumb", *LONG_FINGERS)


@dataclass(frozen=True, eq=False)
class RestPose:
    """Joint positions ``(J, 3)`` and fingertips in mura's rest pose, and the global
    rotation of each joint ``(J,)`` that takes the body's rest pose there."""

    positions: np.ndarray
    tips: dict[str, np.ndarray]
    rotations: Rotation


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def _swing(rotation: Rotation, direction: np.ndarray, target: np.ndarray) -> Rotation:
    """``rotation`` followed by the smallest rotation taking ``rotation(direction)`` onto ``target``."""
    moved = _unit(rotation.apply(direction))
    axis = np.cross(moved, target)
    sine, cosine = np.linalg.norm(axis), float(moved @ target)
    if sine < 1e-12:
        return rotation
    return Rotation.from_rotvec(axis / sine * np.arctan2(sine, cosine)) * rotation


def _frame_rotation(axis: np.ndarray, side_axis: np.ndarray, target_axis: np.ndarray, target_side: np.ndarray) -> Rotation:
    """The rotation taking the orthonormal frame (axis, side) onto (target_axis, target_side)."""

    def frame(a: np.ndarray, s: np.ndarray) -> np.ndarray:
        a = _unit(a)
        s = _unit(s - a * (s @ a))
        return np.column_stack((a, s, np.cross(a, s)))

    matrix = frame(target_axis, target_side) @ frame(axis, side_axis).T
    return Rotation.from_matrix(matrix)


def fingertips(names: tuple[str, ...], positions: np.ndarray, tips: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The given fingertips, the missing ones continuing the last phalanx by 75% of its length."""
    at = {name: positions[i] for i, name in enumerate(names)}
    out = dict(tips)
    for side in ("l", "r"):
        for finger in FINGERS:
            key = f"{side}_{finger}"
            if key not in out:
                out[key] = at[f"{key}3"] + 0.75 * (at[f"{key}3"] - at[f"{key}2"])
    return out


def normalised_rest(names: tuple[str, ...], parents: np.ndarray, positions: np.ndarray, tips: dict[str, np.ndarray],
                    tilts: tuple[float, float] = (DEFAULT_ABDUCTION, DEFAULT_ABDUCTION)) -> RestPose:  # fmt: skip
    """The skeleton in mura's rest pose; ``tilts`` the (left, right) arms' outward tilt."""
    index = {name: i for i, name in enumerate(names)}
    tips = fingertips(names, positions, tips)
    rotations = [Rotation.identity() for _ in names]
    for side, tilt in zip(("l", "r"), tilts):
        for name, rotation in arm_rotations(names, positions, tips, side, tilt).items():
            rotations[index[name]] = rotation
    stacked = Rotation.concatenate(rotations)
    posed = positions.copy()
    for joint in _parents_first(parents):
        parent = parents[joint]
        if parent >= 0:
            posed[joint] = posed[parent] + stacked[parent].apply(positions[joint] - positions[parent])
    moved = {}
    for finger, tip in tips.items():
        last = index[f"{finger}3"]
        moved[finger] = posed[last] + stacked[last].apply(tip - positions[last])
    return RestPose(posed, moved, stacked)


def _parents_first(parents: np.ndarray) -> list[int]:
    order = [i for i in range(len(parents)) if parents[i] < 0]
    for joint in order:
        order.extend(int(c) for c in np.flatnonzero(parents == joint))
    return order


def arm_rotations(names: tuple[str, ...], positions: np.ndarray, tips: dict[str, np.ndarray], side: str, tilt: float) -> dict[str, Rotation]:
    """Global rotations of one arm's joints taking its rest pose to mura's (module docstring)."""
    at = {name: positions[i] for i, name in enumerate(names)}
    at.update({f"{finger}_tip": point for finger, point in tips.items()})
    sign = 1.0 if side == "l" else -1.0
    down = np.array([sign * np.sin(tilt), -np.cos(tilt), 0.0])
    p = lambda name: at[f"{side}_{name}"]  # noqa: E731
    finger_axis = p("middle1") - p("wrist")
    thumb_side = p("index1") - p("pinky1")
    hand = _frame_rotation(finger_axis, thumb_side, down, np.array([0.0, 0.0, 1.0]))
    forearm = _swing(hand, _unit(p("wrist") - p("elbow")), down)
    upper = _swing(forearm, _unit(p("elbow") - p("shoulder")), down)
    out = {f"{side}_shoulder": upper, f"{side}_elbow": forearm, f"{side}_wrist": hand,
           f"{side}_ring0": hand, f"{side}_pinky0": hand}  # fmt: skip
    for finger in LONG_FINGERS:
        chain = [p(f"{finger}1"), p(f"{finger}2"), p(f"{finger}3"), p(f"{finger}_tip")]
        for segment in range(3):
            out[f"{side}_{finger}{segment + 1}"] = _swing(hand, _unit(chain[segment + 1] - chain[segment]), down)
    thumb = [p("thumb1"), p("thumb2"), p("thumb3"), p("thumb_tip")]
    out[f"{side}_thumb1"] = hand
    proximal = hand.apply(_unit(thumb[1] - thumb[0]))
    for segment in (1, 2):
        out[f"{side}_thumb{segment + 1}"] = _swing(hand, _unit(thumb[segment + 1] - thumb[segment]), proximal)
    return out
