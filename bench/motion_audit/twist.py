"""Forearm twist pinned at its limit: pronation/supination stuck at the end of its range.

The forearm's twist is the twist component, about the forearm's own axis (the direction
of the wrist's offset from the elbow at rest), of the elbow joint's local rotation: for a
quaternion ``(v, w)`` and unit axis ``u`` it is ``2·atan2(v·u, w)``, wrapped to (−π, π].
That is where the avatar files put pronation (``{side}_elbow.twist`` limits).

A frame counts when the arm gestures — its wrist more than :data:`GESTURE_DISTANCE`
from where the rest pose (every rotation zero) puts it, in the root's frame — and the
twist is pinned when it lies within :data:`PINNED_MARGIN` of a limit or beyond it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from bench.motion_audit.findings import Worst
from bench.motion_audit.kinematics import Kinematics

GESTURE_DISTANCE = 0.10
PINNED_MARGIN = np.radians(3.0)


@dataclass(frozen=True)
class TwistPinning:
    """Gesture frames and pinned ones of one arm; ``worst`` the longest pinned run
    (value in seconds, at its start)."""

    gesture_frames: int
    pinned_frames: int
    worst: Worst | None


def forearm_twist(kinematics: Kinematics, side: str) -> np.ndarray:
    """The forearm's twist angle ``(frames,)`` in radians."""
    elbow, wrist = kinematics.index(f"{side}_elbow"), kinematics.index(f"{side}_wrist")
    axis = kinematics.offsets[wrist] / np.linalg.norm(kinematics.offsets[wrist])
    quaternion = kinematics.local[:, elbow]
    angle = 2.0 * np.arctan2(quaternion[:, :3] @ axis, quaternion[:, 3])
    return (angle + np.pi) % (2.0 * np.pi) - np.pi


def gesture_frames(kinematics: Kinematics, side: str) -> np.ndarray:
    """Frames ``(frames,)`` in which the arm's wrist is away from its rest place."""
    root = int(np.flatnonzero(np.array(kinematics.parents) < 0)[0])
    wrist = kinematics.index(f"{side}_wrist")
    relative = kinematics.positions[:, wrist] - kinematics.positions[:, root]
    in_root = Rotation.from_quat(kinematics.orientations[:, root]).apply(relative, inverse=True)
    rest = kinematics.rest_positions[wrist] - kinematics.rest_positions[root]
    return np.linalg.norm(in_root - rest, axis=1) > GESTURE_DISTANCE


def twist_pinning(kinematics: Kinematics, side: str, limits: tuple[float, float], start: float = 0.0) -> TwistPinning:
    """How often the forearm twist of one arm sits at its ``limits`` (radians) while it gestures."""
    twist = forearm_twist(kinematics, side)
    gesturing = gesture_frames(kinematics, side)
    low, high = limits
    pinned = gesturing & ((twist <= low + PINNED_MARGIN) | (twist >= high - PINNED_MARGIN))
    if not pinned.any():
        return TwistPinning(int(gesturing.sum()), 0, None)
    edges = np.diff(np.concatenate(([0], pinned.astype(np.int8), [0])))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    longest = int(np.argmax(ends - starts))
    first = int(starts[longest])
    what = f"{side}_elbow twist {np.degrees(twist[first]):+.0f}° (limits {np.degrees(low):+.0f}°/{np.degrees(high):+.0f}°)"
    worst = Worst(float((ends[longest] - first) / kinematics.fps), start + first / kinematics.fps, what)
    return TwistPinning(int(gesturing.sum()), int(pinned.sum()), worst)
