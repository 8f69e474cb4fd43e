"""Vectorized unit-quaternion algebra in scipy's scalar-last order ``(x, y, z, w)``.

Forward and inverse kinematics run over thousands of frames at once; building scipy
``Rotation`` objects in the hot path costs more than the arithmetic itself, so these
functions work on raw arrays of shape ``(..., 4)`` (vectors ``(..., 3)``) and broadcast.
Angles are radians.

The products (:func:`multiply`, :func:`rotate`, :func:`cross`) and :func:`normalize` are
loops compiled by numba over the broadcast rows: the same operations in the same order as
numpy's arithmetic on whole arrays, so the same numbers bit for bit
(``tests/perf_equivalence/test_compiled_quaternion.py``), without its temporaries.
Functions with trigonometry stay numpy's over arrays; compiled callers turn about an axis
with :func:`about_axis`, whose C-library ``sin`` and ``cos`` round as numpy's do here (numba's
``arccos``, ``arctan2``, ``tanh`` and ``exp`` do not: they differ from numpy's in the last bit).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from motor.kernel_types import READ2, WRITE2

IDENTITY = np.array([0.0, 0.0, 0.0, 1.0])

#: Compiled once, cached on disk; division by zero gives inf or nan as in numpy. The
#: loops' signatures are stated (rows read-only, so that read-only views need no second
#: compilation), which compiles or loads them when this module is imported.
_products = numba.njit([numba.void(READ2, READ2, WRITE2)], cache=True, error_model="numpy")


def _result(*parts: np.ndarray, size: int) -> np.ndarray:
    """An empty float array of the broadcast shape of ``parts`` with a last axis of ``size``."""
    return np.empty(np.broadcast(*parts).shape + (size,))


def _pair(p: np.ndarray, q: np.ndarray, p_width: int, q_width: int) -> tuple[np.ndarray, np.ndarray, tuple[int, ...]]:
    """Two arrays as contiguous float rows ``(m, width)`` for the compiled loops, and
    their broadcast leading shape: an array with a single row (one quaternion or vector
    for all) is passed as that row, which the loops repeat, not copied ``m`` times."""
    p, q = np.asarray(p, dtype=float), np.asarray(q, dtype=float)
    if p.shape[-1:] != (p_width,) or q.shape[-1:] != (q_width,):
        raise ValueError(f"expected last axes of {p_width} and {q_width}, got shapes {p.shape} and {q.shape}")
    p_lead, q_lead = p.shape[:-1], q.shape[:-1]
    lead = p_lead if p_lead == q_lead else np.broadcast_shapes(p_lead, q_lead)
    return _as_rows(p, p_lead, lead), _as_rows(q, q_lead, lead), lead


def _as_rows(a: np.ndarray, own: tuple[int, ...], lead: tuple[int, ...]) -> np.ndarray:
    if own != lead and a.size > a.shape[-1]:
        a = np.broadcast_to(a, lead + a.shape[-1:])
    return np.ascontiguousarray(a).reshape(-1, a.shape[-1])


@numba.njit(cache=True, error_model="numpy", inline="always")
def multiplied(px, py, pz, pw, qx, qy, qz, qw):  # noqa: ANN001, ANN201
    """The Hamilton product ``p * q`` of two quaternions given by their components, for
    compiled callers (:func:`multiply` over arrays)."""
    return (
        pw * qx + px * qw + py * qz - pz * qy,
        pw * qy - px * qz + py * qw + pz * qx,
        pw * qz + px * qy - py * qx + pz * qw,
        pw * qw - px * qx - py * qy - pz * qz,
    )


@numba.njit(cache=True, error_model="numpy", inline="always")
def about_axis(ax, ay, az, angle):  # noqa: ANN001, ANN201
    """The rotation by ``angle`` (radians) about the unit axis ``(ax, ay, az)``, for
    compiled callers (:func:`from_axis_angle` over arrays; the C library's ``sin`` and
    ``cos``, which round as numpy's do on the machines measured:
    ``tests/perf_equivalence/test_compiled_quaternion.py``)."""
    half = 0.5 * angle
    sine = math.sin(half)
    return ax * sine, ay * sine, az * sine, math.cos(half)


@_products
def _multiply_rows(p, q, out):  # noqa: ANN001, ANN202
    p_step, q_step = p.shape[0] > 1, q.shape[0] > 1
    for i in range(out.shape[0]):
        j, k = i * p_step, i * q_step
        out[i, 0], out[i, 1], out[i, 2], out[i, 3] = multiplied(p[j, 0], p[j, 1], p[j, 2], p[j, 3], q[k, 0], q[k, 1], q[k, 2], q[k, 3])


@numba.njit(cache=True, error_model="numpy", inline="always")
def rotated(x, y, z, w, vx, vy, vz):  # noqa: ANN001, ANN201
    """The vector ``(vx, vy, vz)`` rotated by the unit quaternion ``(x, y, z, w)``, for
    compiled callers (:func:`rotate` over arrays): ``v + 2w (u × v) + u × (2 u × v)``."""
    tx = 2.0 * (y * vz - z * vy)
    ty = 2.0 * (z * vx - x * vz)
    tz = 2.0 * (x * vy - y * vx)
    return vx + w * tx + y * tz - z * ty, vy + w * ty + z * tx - x * tz, vz + w * tz + x * ty - y * tx


@_products
def _rotate_rows(q, v, out):  # noqa: ANN001, ANN202
    q_step, v_step = q.shape[0] > 1, v.shape[0] > 1
    for i in range(out.shape[0]):
        j, k = i * q_step, i * v_step
        out[i, 0], out[i, 1], out[i, 2] = rotated(q[j, 0], q[j, 1], q[j, 2], q[j, 3], v[k, 0], v[k, 1], v[k, 2])


@numba.njit(cache=True, error_model="numpy", inline="always")
def crossed(ux, uy, uz, vx, vy, vz):  # noqa: ANN001, ANN201
    """The cross product ``u × v`` of two vectors given by their components, for compiled
    callers (:func:`cross` over arrays)."""
    return uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx


@numba.njit(cache=True, error_model="numpy", inline="always")
def length3(x, y, z):  # noqa: ANN001, ANN201
    """The length of the vector ``(x, y, z)``, its squares summed first to last (the
    arithmetic of :func:`norm` and of ``np.linalg.norm`` over three numbers), for
    compiled callers."""
    return math.sqrt((x * x + y * y) + z * z)


@numba.njit(cache=True, error_model="numpy", inline="always")
def of_rotation_vector(x, y, z):  # noqa: ANN001, ANN201
    """The quaternion of the rotation vector ``(x, y, z)`` (axis times angle), for compiled
    callers: :func:`from_rotation_vector`'s arithmetic (the C library's ``sin`` and
    ``cos``, which round as numpy's do here)."""
    angle = length3(x, y, z)
    half = 0.5 * angle
    scale = math.sin(half) / angle if angle > 1e-12 else 0.5
    return x * scale, y * scale, z * scale, math.cos(half)


@numba.njit(cache=True, error_model="numpy", inline="always")
def normalized3(x, y, z):  # noqa: ANN001, ANN201
    """The vector ``(x, y, z)`` scaled to unit length, :func:`normalize`'s arithmetic."""
    length = math.sqrt(((0.0 + x * x) + y * y) + z * z)
    return x / length, y / length, z / length


@numba.njit(cache=True, error_model="numpy", inline="always")
def normalized4(x, y, z, w):  # noqa: ANN001, ANN201
    """The quaternion ``(x, y, z, w)`` scaled to unit length, :func:`normalize`'s arithmetic."""
    length = math.sqrt((((0.0 + x * x) + y * y) + z * z) + w * w)
    return x / length, y / length, z / length, w / length


@numba.njit(cache=True, error_model="numpy", inline="always")
def turn_between(ux, uy, uz, vx, vy, vz):  # noqa: ANN001, ANN201
    """The shortest rotation taking the unit vector ``u`` to ``v``, for compiled callers:
    :func:`between_vectors`' arithmetic, its axis perpendicular to ``u`` where they are
    opposite."""
    cx, cy, cz = crossed(ux, uy, uz, vx, vy, vz)
    w = 1.0 + ((ux * vx + uy * vy) + uz * vz)
    if w < 1e-9:
        hx, hy = (1.0, 0.0) if abs(ux) < 0.9 else (0.0, 1.0)
        ax, ay, az = crossed(ux, uy, uz, hx, hy, 0.0)
        cx, cy, cz = normalized3(ax, ay, az)
        w = 0.0
    return normalized4(cx, cy, cz, w)


@numba.njit(cache=True, error_model="numpy", inline="always")
def identity_dot(x, y, z, w):  # noqa: ANN001, ANN201
    """The dot product of the quaternion ``(x, y, z, w)`` with the identity, summed first to
    last as :func:`slerp` and :func:`angle_between` sum it."""
    return ((0.0 * x + 0.0 * y) + 0.0 * z) + 1.0 * w


@numba.njit(cache=True, error_model="numpy", inline="always")
def slerped_from_identity(x, y, z, w, dot, theta, t):  # noqa: ANN001, ANN201
    """:func:`slerp` from the identity (``t = 0``) toward the quaternion ``(x, y, z, w)``,
    for compiled callers given its :func:`identity_dot` ``dot`` and ``theta``, numpy's
    ``arccos`` of that dot's absolute value clipped to [-1, 1] (numba's rounds otherwise)."""
    if dot < 0.0:
        x, y, z, w = -x, -y, -z, -w
    sine = math.sin(theta)
    if sine < 1e-9:
        a, b = 1.0 - t, t
    else:
        a, b = math.sin((1.0 - t) * theta) / sine, math.sin(t * theta) / sine
    return normalized4(a * 0.0 + b * x, a * 0.0 + b * y, a * 0.0 + b * z, a * 1.0 + b * w)


@_products
def _cross_rows(u, v, out):  # noqa: ANN001, ANN202
    u_step, v_step = u.shape[0] > 1, v.shape[0] > 1
    for i in range(out.shape[0]):
        j, k = i * u_step, i * v_step
        out[i, 0], out[i, 1], out[i, 2] = crossed(u[j, 0], u[j, 1], u[j, 2], v[k, 0], v[k, 1], v[k, 2])


@numba.njit([numba.void(READ2, WRITE2)], cache=True, error_model="numpy")
def _normalize_rows(q, out):  # noqa: ANN001, ANN202
    for i in range(out.shape[0]):
        square = 0.0
        for k in range(q.shape[1]):
            square += q[i, k] * q[i, k]
        length = np.sqrt(square)
        for k in range(q.shape[1]):
            out[i, k] = q[i, k] / length


def multiply(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Hamilton product ``p * q`` (apply ``q`` first, then ``p``)."""
    p, q, lead = _pair(p, q, 4, 4)
    out = np.empty((math.prod(lead), 4))
    _multiply_rows(p, q, out)
    return out.reshape(lead + (4,))


def cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Cross product of 3-vectors along the last axis (the arithmetic of ``np.cross``
    without its per-call axis handling)."""
    u, v, lead = _pair(u, v, 3, 3)
    out = np.empty((math.prod(lead), 3))
    _cross_rows(u, v, out)
    return out.reshape(lead + (3,))


def norm(v: np.ndarray) -> np.ndarray:
    """Euclidean length along the last axis."""
    return np.sqrt(np.sum(v * v, axis=-1))


def length(v: np.ndarray) -> float:
    """The Euclidean length of one float vector: :func:`numpy.linalg.norm`'s arithmetic
    (the square root of the flattened vector's dot product with itself, the same number
    bit for bit) without its per-call checks, for code that measures single vectors
    thousands of times (:func:`norm` sums instead, which can differ in the last bit)."""
    flat = v.ravel(order="K")
    return math.sqrt(flat.dot(flat))


def conjugate(q: np.ndarray) -> np.ndarray:
    """The inverse of a unit quaternion."""
    return q * np.array([-1.0, -1.0, -1.0, 1.0])


def normalize(q: np.ndarray) -> np.ndarray:
    """Scale quaternions (or vectors) to unit length along the last axis."""
    q = np.asarray(q, dtype=float)
    rows = np.ascontiguousarray(q).reshape(-1, q.shape[-1])
    out = np.empty(rows.shape)
    _normalize_rows(rows, out)
    return out.reshape(q.shape)


def rotate(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Rotate vectors ``v (..., 3)`` by unit quaternions ``q (..., 4)``."""
    q, v, lead = _pair(q, v, 4, 3)
    out = np.empty((math.prod(lead), 3))
    _rotate_rows(q, v, out)
    return out.reshape(lead + (3,))


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


def load_kernels() -> None:
    """Run this module's compiled loops once (they load when it is imported):
    :func:`motor.compiled.warm_up`."""
    rotation = normalize(np.ones((1, 4)))
    multiply(rotation, rotation)
    rotate(rotation, np.zeros((1, 3)))
    cross(np.zeros((1, 3)), np.zeros((1, 3)))
