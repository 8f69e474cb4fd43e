"""The numpy quaternion products as they stood before they were compiled
(:mod:`motor.quaternion`, issue 19): the plain path the compiled loops are held to, bit for
bit, by ``test_compiled_quaternion.py``. The Hamilton product and the rotation of vectors
are the bench's bare floor (:mod:`bench.motion_speed`), which is that numpy arithmetic.
Not used by mura itself."""

from __future__ import annotations

import numpy as np

from bench.motion_speed import numpy_product as multiply
from bench.motion_speed import numpy_rotated as rotate

__all__ = ["cross", "multiply", "normalize", "rotate"]


def cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    ux, uy, uz = u[..., 0], u[..., 1], u[..., 2]
    vx, vy, vz = v[..., 0], v[..., 1], v[..., 2]
    out = np.empty(np.broadcast_shapes(u.shape, v.shape))
    out[..., 0] = uy * vz - uz * vy
    out[..., 1] = uz * vx - ux * vz
    out[..., 2] = ux * vy - uy * vx
    return out


def normalize(q: np.ndarray) -> np.ndarray:
    return q / np.sqrt(np.sum(q * q, axis=-1, keepdims=True))
