"""An arm's joint rotations at a given swivel, compiled: what a frame's arm is posed with.

Once the swivel track has chosen the elbow's swivel, every frame solves its arm
(:func:`motor.arm.ik.solve_arm` with ``swivel``, ``swivel_from`` and a four-column
``twist_reference``) only for the joint rotations, and the motor control does so again
for the few frames where the hands may meet, a few rows at a time. The numpy composition
costs about 0.8 ms a call whatever the rows; :func:`arm_rotations` makes the same
arithmetic one compiled loop over the rows for a body standing upright at rest.

It follows :func:`motor.arm.chain.place_arm`, :meth:`motor.arm.chain.ElbowCircle.of`
and ``ik._arm_at`` operation by operation. Where numpy's own routines round differently
from the C library's that numba calls (``arccos``, ``arctan2``, ``tanh``) and where numpy
hands the frames' 3×3 products to BLAS, the last bit may differ:
``tests/perf_equivalence/test_given_swivel.py`` holds the two within 1e-12.
"""

from __future__ import annotations

import functools
import math

import numba
import numpy as np

from motor import quaternion as quat
from motor.arm.chain import CLAVICLE_REACH, DOWN_BACK, RAISED, REACH_EASE, arm_chain, farthest_reach, nearest_reach
from motor.arm.ik import SURE_SWING
from motor.body.avatar import Avatar, check_side
from motor.kernel_types import READ1, READ2, WRITE3


#: Rows of the chain's vector table (:func:`_chain_tables`).
_CLAVICLE, _SC_POSITION, _UPPER_REST, _HINGE_REST, _REST_NORMAL, _PRONATION, _FLEXION, _DEVIATION = range(8)
#: Entries of the chain's scalar table (:func:`_chain_tables`).
(
    _SIDE_SIGN, _UPPER, _UPPER_SQUARED, _FORE_SQUARED, _TWICE_UPPER, _BOTH_TWICE, _ARM_LENGTH, _CLAVICLE_LENGTH,
    _CLAVICLE_MAX, _NEAREST, _FARTHEST, _TWIST_LOW, _TWIST_HIGH, _WRIST_FLEXION_LOW, _WRIST_FLEXION_HIGH,
    _DEVIATION_LOW, _DEVIATION_HIGH,
) = range(17)  # fmt: skip


def arm_rotations(
    avatar: Avatar,
    side: str,
    wrist_targets: np.ndarray,
    hand_rotations: np.ndarray,
    swivel: np.ndarray,
    swivel_from: np.ndarray,
    twist_reference: np.ndarray,
) -> np.ndarray:
    """The arm's local joint rotations ``(n, 4, 4)`` (sternoclavicular, shoulder, elbow,
    wrist) with the body upright at rest: :func:`motor.arm.ik.solve_arm`'s ``rotations``
    for the same arguments, ``swivel_from`` and a four-column ``twist_reference`` given.

    Args:
        wrist_targets: ``(n, 3)`` wrist positions in the avatar frame, metres.
        hand_rotations: ``(n, 4)`` global hand rotations to reach (normalized here).
        swivel: ``(n,)`` swivel angles, radians, counted from ``swivel_from``.
        swivel_from: ``(n, 3)`` directions from which ``swivel`` is counted.
        twist_reference: ``(n, 4)`` forearm twist of a nearby instant, the twist the hand
            asked for there, and the wrist's flexion and deviation there (radians).
    """
    vectors, scalars = _chain_tables(avatar, check_side(side))
    rows = np.ascontiguousarray(wrist_targets, dtype=float).reshape(-1, 3)
    count = rows.shape[0]
    out = np.empty((count, 4, 4))
    _posed_rows(
        rows,
        np.ascontiguousarray(hand_rotations, dtype=float).reshape(count, 4),
        np.ascontiguousarray(swivel, dtype=float).reshape(count),
        np.ascontiguousarray(swivel_from, dtype=float).reshape(count, 3),
        np.ascontiguousarray(twist_reference, dtype=float).reshape(count, 4),
        vectors,
        scalars,
        out,
    )
    return out


@functools.lru_cache(maxsize=32)
def _chain_tables(avatar: Avatar, side: str) -> tuple[np.ndarray, np.ndarray]:
    """The arm's constants as the compiled loop reads them: unit vectors and points
    ``(8, 3)`` and scalars ``(17,)``, each computed as the numpy composition computes it."""
    chain = arm_chain(avatar, side)
    upper, fore = chain.upper, chain.fore
    vectors = np.stack(
        (
            chain.clavicle,
            chain.torso_joint_rest + chain.sc_offset,
            chain.upper_rest,
            chain.hinge_rest,
            quat.cross(chain.upper_rest, chain.hinge_rest),
            chain.pronation_axis,
            chain.flexion_axis,
            chain.deviation_axis,
        )
    ).astype(float)
    scalars = np.array(
        [
            chain.side_sign, upper, upper**2, fore**2, 2.0 * upper, 2.0 * upper * fore, upper + fore,
            quat.norm(chain.clavicle), chain.clavicle_max,
            nearest_reach(chain), farthest_reach(chain),
            *chain.twist_range, *chain.wrist_flexion, *chain.wrist_deviation,
        ],
        dtype=float,
    )  # fmt: skip
    vectors.flags.writeable = scalars.flags.writeable = False
    return vectors, scalars


_inline = numba.njit(cache=True, error_model="numpy", inline="always")


@_inline
def _wrapped(angle):  # noqa: ANN001, ANN202
    return (angle + np.pi) % (2.0 * np.pi) - np.pi


@_inline
def _swing(qx, qy, qz, qw, ax, ay, az):  # noqa: ANN001, ANN202
    """:func:`motor.quaternion.swing_twist` of one quaternion: the swing and the twist angle."""
    along = qx * ax + qy * ay + qz * az
    angle = _wrapped(2.0 * math.atan2(along, qw))
    tx, ty, tz, tw = quat.about_axis(ax, ay, az, angle)
    sx, sy, sz, sw = quat.multiplied(qx, qy, qz, qw, -tx, -ty, -tz, tw)
    return sx, sy, sz, sw, angle


@_inline
def _clamp(value, low, high):  # noqa: ANN001, ANN202
    return min(max(value, low), high)


@_inline
def _from_matrix(m00, m01, m02, m10, m11, m12, m20, m21, m22):  # noqa: ANN001, ANN202
    """:func:`motor.quaternion.from_matrix` of one matrix: the candidate of the largest
    of the diagonal and the trace (the first on a tie), normalized."""
    trace = m00 + m11 + m22
    best, largest = 0, m00
    if m11 > largest:
        best, largest = 1, m11
    if m22 > largest:
        best, largest = 2, m22
    if trace > largest:
        best = 3
    if best == 0:
        x, y, z, w = 1.0 + m00 - m11 - m22, m01 + m10, m02 + m20, m21 - m12
    elif best == 1:
        x, y, z, w = m01 + m10, 1.0 - m00 + m11 - m22, m12 + m21, m02 - m20
    elif best == 2:
        x, y, z, w = m02 + m20, m12 + m21, 1.0 - m00 - m11 + m22, m10 - m01
    else:
        x, y, z, w = m21 - m12, m02 - m20, m10 - m01, 1.0 + m00 + m11 + m22
    return quat.normalized4(x, y, z, w)


@numba.njit([numba.void(READ2, READ2, READ1, READ2, READ2, READ2, READ1, WRITE3)], cache=True, error_model="numpy")
def _posed_rows(targets, hands, swivel, swivel_from, reference, vectors, scalars, out):  # noqa: ANN001, ANN202, PLR0915
    side_sign, upper = scalars[_SIDE_SIGN], scalars[_UPPER]
    low_reach, high_reach = CLAVICLE_REACH
    knee = scalars[_FARTHEST] - 2.0 * REACH_EASE
    cx, cy, cz = vectors[_CLAVICLE, 0], vectors[_CLAVICLE, 1], vectors[_CLAVICLE, 2]
    px, py, pz = vectors[_PRONATION, 0], vectors[_PRONATION, 1], vectors[_PRONATION, 2]
    for i in range(targets.shape[0]):
        tx, ty, tz = targets[i, 0], targets[i, 1], targets[i, 2]
        hx, hy, hz, hw = quat.normalized4(hands[i, 0], hands[i, 1], hands[i, 2], hands[i, 3])
        # the clavicle turns the shoulder toward a far reach (chain.clavicle_rotation)
        rx = tx - (vectors[_SC_POSITION, 0] + cx)
        ry = ty - (vectors[_SC_POSITION, 1] + cy)
        rz = tz - (vectors[_SC_POSITION, 2] + cz)
        distance = np.sqrt(rx * rx + ry * ry + rz * rz)
        t = _clamp((distance / scalars[_ARM_LENGTH] - low_reach) / (high_reach - low_reach), 0.0, 1.0)
        amount = t * t * (3.0 - 2.0 * t)
        ax, ay, az = quat.crossed(cx, cy, cz, rx, ry, rz)
        axis_norm = np.sqrt(ax * ax + ay * ay + az * az)
        across = _clamp(axis_norm / max(scalars[_CLAVICLE_LENGTH] * distance, 1e-12) / 0.3, 0.0, 1.0)
        scale = max(axis_norm, 1e-12)
        kx, ky, kz, kw = quat.about_axis(ax / scale, ay / scale, az / scale, scalars[_CLAVICLE_MAX] * amount * across)
        ox, oy, oz = quat.rotated(kx, ky, kz, kw, cx, cy, cz)
        sx, sy, sz = vectors[_SC_POSITION, 0] + ox, vectors[_SC_POSITION, 1] + oy, vectors[_SC_POSITION, 2] + oz
        # the elbow circle (chain.ElbowCircle.of)
        rx, ry, rz = tx - sx, ty - sy, tz - sz
        distance = np.sqrt(rx * rx + ry * ry + rz * rz)
        if distance > 1e-9:
            scale = max(distance, 1e-12)
            ax, ay, az = rx / scale, ry / scale, rz / scale
        else:
            ax, ay, az = 0.0, -1.0, 0.0
        reached = distance
        if distance > knee:
            reached = knee + REACH_EASE * math.tanh(max(distance - knee, 0.0) / REACH_EASE)
        reached = max(reached, scalars[_NEAREST])
        squared = reached * reached
        flexion = math.acos(_clamp((squared - scalars[_UPPER_SQUARED] - scalars[_FORE_SQUARED]) / scalars[_BOTH_TWICE], -1.0, 1.0))
        cos_shoulder = _clamp((scalars[_UPPER_SQUARED] + squared - scalars[_FORE_SQUARED]) / (scalars[_TWICE_UPPER] * reached), -1.0, 1.0)
        raised = _clamp((ay - RAISED[0]) / (RAISED[1] - RAISED[0]), 0.0, 1.0)
        raised = raised * raised * (3.0 - 2.0 * raised)
        ex = (1.0 - raised) * DOWN_BACK[0] + raised * 0.0
        ey = (1.0 - raised) * DOWN_BACK[1] + raised * 0.0
        ez = (1.0 - raised) * DOWN_BACK[2] + raised * 1.0
        along = ex * ax + ey * ay + ez * az
        dx, dy, dz = ex - along * ax, ey - along * ay, ez - along * az
        down_norm = np.sqrt(dx * dx + dy * dy + dz * dz)
        if down_norm > 1e-6:
            scale = max(down_norm, 1e-12)
            dx, dy, dz = dx / scale, dy / scale, dz / scale
        else:
            dx, dy, dz = quat.crossed(ax, ay, az, side_sign, 0.0, 0.0)
        ux, uy, uz = quat.crossed(ax, ay, az, dx, dy, dz)
        ux, uy, uz = side_sign * ux, side_sign * uy, side_sign * uz
        along = upper * cos_shoulder
        mx, my, mz = sx + ax * along, sy + ay * along, sz + az * along
        radius = upper * np.sqrt(1.0 - cos_shoulder * cos_shoulder)
        # the swivel, counted from swivel_from (ik.swivel_of)
        fx, fy, fz = swivel_from[i, 0], swivel_from[i, 1], swivel_from[i, 2]
        psi = swivel[i] + math.atan2(fx * ux + fy * uy + fz * uz, fx * dx + fy * dy + fz * dz)
        # the joint rotations at that swivel (ik._arm_at)
        cos, sin = math.cos(psi), math.sin(psi)
        gx, gy, gz = dx * cos + ux * sin, dy * cos + uy * sin, dz * cos + uz * sin
        bx, by, bz = quat.normalized3(mx + gx * radius - sx, my + gy * radius - sy, mz + gz * radius - sz)
        nx, ny, nz = quat.crossed(gx, gy, gz, ax, ay, az)
        nx, ny, nz = quat.normalized3(nx, ny, nz)
        wx, wy, wz = quat.crossed(bx, by, bz, nx, ny, nz)
        rest = vectors[_UPPER_REST], vectors[_HINGE_REST], vectors[_REST_NORMAL]
        # target @ rest^T, both with the frames' axes as columns
        m00 = bx * rest[0][0] + nx * rest[1][0] + wx * rest[2][0]
        m01 = bx * rest[0][1] + nx * rest[1][1] + wx * rest[2][1]
        m02 = bx * rest[0][2] + nx * rest[1][2] + wx * rest[2][2]
        m10 = by * rest[0][0] + ny * rest[1][0] + wy * rest[2][0]
        m11 = by * rest[0][1] + ny * rest[1][1] + wy * rest[2][1]
        m12 = by * rest[0][2] + ny * rest[1][2] + wy * rest[2][2]
        m20 = bz * rest[0][0] + nz * rest[1][0] + wz * rest[2][0]
        m21 = bz * rest[0][1] + nz * rest[1][1] + wz * rest[2][1]
        m22 = bz * rest[0][2] + nz * rest[1][2] + wz * rest[2][2]
        qx, qy, qz, qw = _from_matrix(m00, m01, m02, m10, m11, m12, m20, m21, m22)
        out[i, 0, 0], out[i, 0, 1], out[i, 0, 2], out[i, 0, 3] = kx, ky, kz, kw
        out[i, 1, 0], out[i, 1, 1], out[i, 1, 2], out[i, 1, 3] = quat.multiplied(-kx, -ky, -kz, kw, qx, qy, qz, qw)
        hinge = vectors[_HINGE_REST]
        ex, ey, ez, ew = quat.about_axis(hinge[0], hinge[1], hinge[2], flexion)
        fx, fy, fz, fw = quat.multiplied(qx, qy, qz, qw, ex, ey, ez, ew)
        # the forearm's twist: the change the hand asks for since the reference
        lx, ly, lz, lw = quat.multiplied(-fx, -fy, -fz, fw, hx, hy, hz, hw)
        gx, gy, gz, gw, angle = _swing(-lx, -ly, -lz, lw, px, py, pz)
        certainty = _clamp(2.0 - 2.0 * math.acos(_clamp(abs(gw), 0.0, 1.0)) / SURE_SWING, 0.0, 1.0)
        more = _wrapped(-angle - reference[i, 1])
        twist = _clamp(reference[i, 0] + certainty * more, scalars[_TWIST_LOW], scalars[_TWIST_HIGH])
        tx, ty, tz, tw = quat.about_axis(px, py, pz, twist)
        lx, ly, lz, lw = quat.multiplied(ex, ey, ez, ew, tx, ty, tz, tw)
        out[i, 2, 0], out[i, 2, 1], out[i, 2, 2], out[i, 2, 3] = lx, ly, lz, lw
        # the wrist: the rest of the hand's turn, within the wrist's limits
        ux, uy, uz, uw = quat.multiplied(qx, qy, qz, qw, lx, ly, lz, lw)
        ux, uy, uz, uw = quat.multiplied(-ux, -uy, -uz, uw, hx, hy, hz, hw)
        gx, gy, gz, gw, _ = _swing(ux, uy, uz, uw, px, py, pz)
        if gw < 0.0:
            gx, gy, gz, gw = -gx, -gy, -gz, -gw
        sin_half = np.sqrt(gx * gx + gy * gy + gz * gz)
        scale = 2.0 * math.atan2(sin_half, gw) / sin_half if sin_half > 1e-12 else 2.0
        vx, vy, vz = gx * scale, gy * scale, gz * scale
        axis = vectors[_FLEXION]
        bend = _clamp(vx * axis[0] + vy * axis[1] + vz * axis[2], scalars[_WRIST_FLEXION_LOW], scalars[_WRIST_FLEXION_HIGH])
        bend = reference[i, 2] + certainty * (bend - reference[i, 2])
        other = vectors[_DEVIATION]
        deviation = _clamp(vx * other[0] + vy * other[1] + vz * other[2], scalars[_DEVIATION_LOW], scalars[_DEVIATION_HIGH])
        deviation = reference[i, 3] + certainty * (deviation - reference[i, 3])
        vx, vy, vz = bend * axis[0] + deviation * other[0], bend * axis[1] + deviation * other[1], bend * axis[2] + deviation * other[2]
        out[i, 3, 0], out[i, 3, 1], out[i, 3, 2], out[i, 3, 3] = quat.of_rotation_vector(vx, vy, vz)


def load_kernels() -> None:
    """Run this module's compiled loop once (it loads when the module is imported):
    :func:`motor.compiled.warm_up`."""
    vectors, scalars = np.eye(8, 3), np.ones(17)
    row = np.array([[0.0, 0.0, 0.0, 1.0]])
    _posed_rows(np.zeros((1, 3)), row, np.zeros(1), np.ones((1, 3)), row, vectors, scalars, np.empty((1, 4, 4)))
