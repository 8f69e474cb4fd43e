"""Keeping the hands out of the torso (seed 000, section 4.4).

The avatar's torso is an upright elliptic cylinder (``Avatar.torso``). A wrist target
inside it — or behind it within its width, where no hand goes — is pushed forward onto
the front surface of the cylinder grown by :data:`TORSO_MARGIN`, where the surface
normal points into signing space. Gesture and sign planning both use it, so no planned
wrist position lies in the body.
"""

from __future__ import annotations

import numpy as np

from motor.body.avatar import Avatar

#: Clearance of the wrist from the torso surface, metres.
TORSO_MARGIN = 0.04


def outside_torso(avatar: Avatar, points: np.ndarray) -> np.ndarray:
    """Wrist positions ``(n, 3)`` (avatar frame at rest, metres) inside the torso's
    elliptic cylinder grown by :data:`TORSO_MARGIN`, or behind it within its width,
    pushed forward onto its front surface; the others unchanged."""
    torso = avatar.torso
    a, b = torso.half_width + TORSO_MARGIN, torso.half_depth + TORSO_MARGIN
    dx = (points[:, 0] - torso.center[0]) / a
    front = torso.center[2] + b * np.sqrt(np.clip(1.0 - dx * dx, 0.0, 1.0))
    inside = (np.abs(dx) < 1.0) & (points[:, 2] < front) & (points[:, 1] > torso.bottom) & (points[:, 1] < torso.top)
    if not np.any(inside):
        return points
    out = points.copy()
    out[:, 2] = np.where(inside, front, out[:, 2])
    return out
