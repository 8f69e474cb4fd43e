"""Vectorized unit-quaternion algebra in scipy's scalar-last order ``(x, y, z, w)``.

Forward and inverse kinematics run over thousands of frames at once; building scipy
``Rotation`` objects in the hot path costs more than the arithmetic itself, so these
functions work on raw arrays of shape ``(..., 4)`` (vectors ``(..., 3)``) and broadcast.
Angles are radians.
"""

from __future__ import annotations

import numpy as np

IDENTITY = np.array([0.0, 0.0, 0.0, 1.0])


def _result(*parts: np.ndarray, size: int) -> np.ndarray:
    """An empty float array of the broadcast shape of ``parts`` with a last axis of ``size``."""
    return np.empty(np.broadcast(*parts).shape + (size,))


def multiply(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Hamilton product ``p * q`` (apply ``q`` first, then ``p``)."""
    px, py, pz, pw = p[..., 0], p[..., 1], p[..., 2], p[..., 3]
    qx, qy, qz, qw = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    out = _result(px, qx, size=4)
    out[..., 0] = pw * qx + px * qw + py * qz - pz * qy
    out[..., 1] = pw * qy - px * qz + py * qw + pz * qx
    out[..., 2] = pw * qz + px * qy - py * qx + pz * qw
    out[..., 3] = pw * qw - px * qx - py * qy - pz * qz
    return out


def cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Cross product of 3-vectors along the last axis (the arithmetic of ``np.cross``
    without its per-call axis handling)."""
    u, v = np.asarray(u, dtype=float), np.asarray(v, dtype=float)
    ux, uy, uz = u[..., 0], u[..., 1], u[..., 2]
    vx, vy, vz = v[..., 0], v[..., 1], v[..., 2]
    out = _result(ux, vx, size=3)
    out[..., 0] = uy * vz - uz * vy
    out[..., 1] = uz * vx - ux * vz
    out[..., 2] = ux * vy - uy * vx
    return out


def norm(v: np.ndarray) -> np.ndarray:
    """Euclidean length along the last axis."""
    return np.sqrt(np.sum(v * v, axis=-1))


def conjugate(q: np.ndarray) -> np.ndarray:
    """The inverse of a unit quaternion."""
    return q * np.array([-1.0, -1.0, -1.0, 1.0])


def normalize(q: np.ndarray) -> np.ndarray:
    """Scale quaternions (or vectors) to unit length along the last axis."""
    return q / np.sqrt(np.sum(q * q, axis=-1, keepdims=True))


def rotate(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Rotate vectors ``v (..., 3)`` by unit quaternions ``q (..., 4)``."""
    x, y, z, w = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    vx, vy, vz = v[..., 0], v[..., 1], v[..., 2]
    tx = 2.0 * (y * vz - z * vy)
    ty = 2.0 * (z * vx - x * vz)
    tz = 2.0 * (x * vy - y * vx)
    out = _result(x, vx, size=3)
    out[..., 0] = vx + w * tx + y * tz - z * ty
    out[..., 1] = vy + w * ty + z * tx - x * tz
    out[..., 2] = vz + w * tz + x * ty - y * tx
    return out


def from_axis_angle(axis: np.ndarray, angle: np.ndarray | float) -> np.ndarray:
    """Rotation by ``angle`` about the unit ``axis``; broadcasts ``(..., 3)`` with ``(...)``."""
    half = 0.5 * np.asarray(angle, dtype=float)
    axis = np.asarray(axis, dtype=float)
    out = _result(axis[..., 0], half, size=4)
    out[..., :3] = axis * np.sin(half)[..., None]
    out[..., 3] = np.cos(half)
    return out


def from_rotation_vector(rotvec: np.ndarray) -> np.ndarray:
    """Quaternion of a rotation vector (axis times angle), safe at zero."""
    angle = norm(rotvec)
    half = 0.5 * angle
    scale = np.where(angle > 1e-12, np.sin(half) / np.where(angle > 1e-12, angle, 1.0), 0.5)
    out = _result(rotvec[..., 0], size=4)
    out[..., :3] = rotvec * scale[..., None]
    out[..., 3] = np.cos(half)
    return out


def canonical(q: np.ndarray) -> np.ndarray:
    """The sign of each quaternion that scipy's ``Rotation`` takes as canonical: ``w > 0``,
    or on a tie at zero the first non-zero of ``x, y, z`` positive. A half-turn (``w = 0``)
    thus gets the rotation vector scipy gives it."""
    w, x, y, z = q[..., 3], q[..., 0], q[..., 1], q[..., 2]
    flip = (w < 0.0) | ((w == 0.0) & ((x < 0.0) | ((x == 0.0) & ((y < 0.0) | ((y == 0.0) & (z < 0.0))))))
    return np.where(flip[..., None], -q, q)


def to_rotation_vector(q: np.ndarray) -> np.ndarray:
    """Rotation vector (axis times angle in ``[0, π]``) of unit quaternions."""
    q = np.where(q[..., 3:4] < 0.0, -q, q)
    sin_half = norm(q[..., :3])
    angle = 2.0 * np.arctan2(sin_half, q[..., 3])
    scale = np.where(sin_half > 1e-12, angle / np.where(sin_half > 1e-12, sin_half, 1.0), 2.0)
    return q[..., :3] * scale[..., None]


def angle_between(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Angle of the rotation taking ``p`` to ``q``, radians in ``[0, π]``."""
    dot = np.abs(np.sum(p * q, axis=-1))
    return 2.0 * np.arccos(np.clip(dot, 0.0, 1.0))


def between_vectors(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Shortest rotation taking unit vectors ``u`` to ``v`` (any axis ⟂ u when opposite)."""
    u = np.broadcast_to(u, np.broadcast_shapes(np.shape(u), np.shape(v)))
    v = np.broadcast_to(v, u.shape)
    cross = np.cross(u, v)
    dot = np.sum(u * v, axis=-1)
    q = np.concatenate((cross, (1.0 + dot)[..., None]), axis=-1)
    opposite = (1.0 + dot) < 1e-9
    if np.any(opposite):
        helper = np.where(np.abs(u[..., :1]) < 0.9, np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]))
        axis = normalize(np.cross(u, helper))
        q = np.where(opposite[..., None], np.concatenate((axis, np.zeros(axis.shape[:-1] + (1,))), axis=-1), q)
    return normalize(q)


def from_matrix(m: np.ndarray) -> np.ndarray:
    """Unit quaternions of rotation matrices ``(..., 3, 3)`` (columns are the rotated axes)."""
    m00, m11, m22 = m[..., 0, 0], m[..., 1, 1], m[..., 2, 2]
    candidates = np.stack(
        (
            np.stack((1 + m00 - m11 - m22, m[..., 0, 1] + m[..., 1, 0], m[..., 0, 2] + m[..., 2, 0], m[..., 2, 1] - m[..., 1, 2]), -1),
            np.stack((m[..., 0, 1] + m[..., 1, 0], 1 - m00 + m11 - m22, m[..., 1, 2] + m[..., 2, 1], m[..., 0, 2] - m[..., 2, 0]), -1),
            np.stack((m[..., 0, 2] + m[..., 2, 0], m[..., 1, 2] + m[..., 2, 1], 1 - m00 - m11 + m22, m[..., 1, 0] - m[..., 0, 1]), -1),
            np.stack((m[..., 2, 1] - m[..., 1, 2], m[..., 0, 2] - m[..., 2, 0], m[..., 1, 0] - m[..., 0, 1], 1 + m00 + m11 + m22), -1),
        ),
        axis=-2,
    )
    best = np.argmax(np.stack((m00, m11, m22, m00 + m11 + m22), -1), axis=-1)
    q = np.take_along_axis(candidates, best[..., None, None], axis=-2)[..., 0, :]
    return normalize(q)


def from_frames(rest: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Rotation taking an orthonormal frame ``rest (..., 3, 3)`` onto ``target`` (axes as columns)."""
    return from_matrix(target @ np.swapaxes(rest, -1, -2))


def swing_twist(q: np.ndarray, axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Split ``q = swing * twist`` with ``twist`` about unit ``axis`` and swing ⟂ to it.

    Returns ``(swing, twist_angle)``; the twist angle is signed about ``axis``, radians.
    """
    along = np.sum(q[..., :3] * axis, axis=-1)
    twist_angle = 2.0 * np.arctan2(along, q[..., 3])
    twist_angle = (twist_angle + np.pi) % (2.0 * np.pi) - np.pi
    twist = from_axis_angle(axis, twist_angle)
    return multiply(q, conjugate(twist)), twist_angle


def slerp(p: np.ndarray, q: np.ndarray, t: np.ndarray | float) -> np.ndarray:
    """Spherical linear interpolation from ``p`` (t = 0) to ``q`` (t = 1), shortest arc."""
    t = np.asarray(t, dtype=float)[..., None]
    dot = np.sum(p * q, axis=-1, keepdims=True)
    q = np.where(dot < 0.0, -q, q)
    dot = np.abs(dot)
    theta = np.arccos(np.clip(dot, -1.0, 1.0))
    sin_theta = np.sin(theta)
    small = sin_theta < 1e-9
    safe = np.where(small, 1.0, sin_theta)
    a = np.where(small, 1.0 - t, np.sin((1.0 - t) * theta) / safe)
    b = np.where(small, t, np.sin(t * theta) / safe)
    return normalize(a * p + b * q)


def continuous(quaternions: np.ndarray) -> np.ndarray:
    """A sequence ``(m, 4)`` with signs flipped so that consecutive quaternions share a
    hemisphere (the same rotations; interpolation between them takes the short way)."""
    q = np.array(quaternions, dtype=float)
    for i in range(1, len(q)):
        if q[i] @ q[i - 1] < 0.0:
            q[i] = -q[i]
    return q
