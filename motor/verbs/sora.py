"""Hand orientation as simultaneous orthogonal rotation angles (SORA, seed 001 section 3.2).

SORA writes a rotation as three angles ``(φx, φy, φz)`` of simultaneous rotations about the
frame's axes — the rotation vector, ``Rotation.as_rotvec``: the rotation by ``|φ|`` about
``φ/|φ|``. Each component can then be modelled on its own. Near a half turn the vector
jumps (a rotation by π about ``n`` is also one about ``−n``), so orientations are taken
*relative to the verb's mean orientation* (per hand and keyframe; the chordal L2 mean of
``Rotation.mean``): ``q = exp(φ) · q̄``, with ``φ`` small for any sensible performance. The
angles are in the signer frame's axes (a left multiplication), radians.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation


def mean_orientation(quaternions: np.ndarray) -> np.ndarray:
    """The mean of unit quaternions ``(n, 4)`` as one quaternion ``(4,)``."""
    return Rotation.from_quat(quaternions).mean().as_quat()


def to_sora(quaternions: np.ndarray, mean: np.ndarray) -> np.ndarray:
    """SORA angles ``(n, 3)``, radians, of orientations relative to ``mean``."""
    return (Rotation.from_quat(quaternions) * Rotation.from_quat(mean).inv()).as_rotvec()


def from_sora(angles: np.ndarray, mean: np.ndarray) -> np.ndarray:
    """Orientations ``(n, 4)`` from SORA angles ``(n, 3)`` relative to ``mean``."""
    return (Rotation.from_rotvec(np.atleast_2d(angles)) * Rotation.from_quat(mean)).as_quat()


def angle_between(first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """Angles ``(n,)`` in radians between orientations ``(n, 4)`` (the geodesic distance)."""
    dot = np.abs(np.sum(np.asarray(first) * np.asarray(second), axis=-1))
    return 2.0 * np.arccos(np.clip(dot, 0.0, 1.0))
