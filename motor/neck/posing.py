"""The head, the neck joints and the eyes of every frame in compiled passes
(:meth:`motor.neck.control.NeckControl.pose`, module docstring there).

In numpy each step was a dozen calls over all frames — the torso's pose down the chain,
the head's orientation, the neck's shares of it, each eye's aim — most of the time in
the calls and their temporaries. The loops here do the same operations in the same
order per frame, so the same numbers bit for bit
(``tests/perf_equivalence/test_compiled_neck.py`` pins them to the numpy code kept in
``tests/perf_equivalence/plain_neck.py``). ``sin`` and ``cos`` are the C library's, which
round as numpy's do here (:func:`motor.quaternion.about_axis`); the ``arctan2`` of the
neck's rotation vector and the ``arccos`` of the eyes' turn are numpy's, computed between
the loops, as numba's round differently.
"""

from __future__ import annotations


import numba
import numpy as np

from motor import quaternion as quat
from motor.kernel_types import READ1, READ2, READ3, READ_INTS1, WRITE1, WRITE2, WRITE3, maximum, minimum

#: Share of the neck's rotation at ``vc7`` and ``vc4``; the skull base takes the rest.
NECK_SHARES: tuple[float, float] = (0.25, 0.3)
#: Largest eye rotation from straight ahead in the head, radians (the oculomotor range).
EYE_RANGE = float(np.radians(45.0))


def pose_head_and_eyes(
    rotations: np.ndarray,
    path: np.ndarray,
    neck: np.ndarray,
    eyes: np.ndarray,
    joint_offsets: np.ndarray,
    eye_offsets: np.ndarray,
    gaze: np.ndarray,
    head_turns: np.ndarray,
) -> None:
    """Set the neck joints ``neck`` (vc7, vc4, skull base) and the eyes ``eyes`` of
    ``rotations`` ``(n, J, 4)`` (C-contiguous, changed in place): the head faces the
    gaze channel's head direction ``gaze[:, 3:6]`` turned by the head lexemes' rotation
    vectors ``head_turns[:, :3]``, relative to the torso at the end of ``path`` (the
    joints from the root to vc7's parent, bone offsets ``joint_offsets (J, 3)``, m), shared
    by the neck joints with ``head_turns[:, 3]`` flexing vc7; each eye, ``eye_offsets
    (E, 3)`` from the skull base at rest, looks at ``gaze[:, :3]``, at most
    :data:`EYE_RANGE` from straight ahead."""
    count = rotations.shape[0]
    head, torso, torso_at = np.empty((count, 4)), np.empty((count, 4)), np.empty((count, 3))
    relative, sin_half, cos_half = np.empty((count, 3)), np.empty(count), np.empty(count)
    _head_rows(rotations, path, joint_offsets, gaze, head_turns, head, torso, torso_at, relative, sin_half, cos_half)
    half_angle = np.arctan2(sin_half, cos_half)
    turns, dots = np.empty((count, eyes.size, 4)), np.empty((count, eyes.size))
    _neck_rows(rotations, neck, joint_offsets, eye_offsets, gaze, head_turns, head, torso, torso_at, relative, sin_half, half_angle, turns, dots)
    if eyes.size:
        _eye_rows(rotations, eyes, turns, dots, np.arccos(np.clip(np.abs(dots), 0.0, 1.0)))


@numba.njit(
    [numba.void(READ3, READ_INTS1, READ2, READ2, READ2, WRITE2, WRITE2, WRITE2, WRITE2, WRITE1, WRITE1)],
    cache=True,
    error_model="numpy",
)
def _head_rows(rotations, path, joint_offsets, gaze, head_turns, head, torso, torso_at, relative, sin_half, cos_half):  # noqa: ANN001, ANN202
    """Per frame: the head's orientation, the torso's orientation and position, and the
    head relative to the torso as :func:`motor.quaternion.to_rotation_vector` takes it
    (the quaternion's sign made ``w ≥ 0``, the sine and cosine of its half angle)."""
    for i in range(rotations.shape[0]):
        fx, fy, fz = quat.normalized3(gaze[i, 3], gaze[i, 4], gaze[i, 5])
        facing = quat.turn_between(0.0, 0.0, 1.0, fx, fy, fz)
        nod = quat.of_rotation_vector(head_turns[i, 0], head_turns[i, 1], head_turns[i, 2])
        hx, hy, hz, hw = quat.multiplied(facing[0], facing[1], facing[2], facing[3], nod[0], nod[1], nod[2], nod[3])
        head[i, 0], head[i, 1], head[i, 2], head[i, 3] = hx, hy, hz, hw
        ox, oy, oz, ow = 0.0, 0.0, 0.0, 1.0
        px, py, pz = 0.0, 0.0, 0.0
        for joint in path:
            rx, ry, rz = quat.rotated(ox, oy, oz, ow, joint_offsets[joint, 0], joint_offsets[joint, 1], joint_offsets[joint, 2])
            px, py, pz = px + rx, py + ry, pz + rz
            ox, oy, oz, ow = quat.multiplied(ox, oy, oz, ow, rotations[i, joint, 0], rotations[i, joint, 1], rotations[i, joint, 2], rotations[i, joint, 3])
        torso[i, 0], torso[i, 1], torso[i, 2], torso[i, 3] = ox, oy, oz, ow
        torso_at[i, 0], torso_at[i, 1], torso_at[i, 2] = px, py, pz
        qx, qy, qz, qw = quat.multiplied(ox * -1.0, oy * -1.0, oz * -1.0, ow * 1.0, hx, hy, hz, hw)
        if qw < 0.0:
            qx, qy, qz, qw = -qx, -qy, -qz, -qw
        relative[i, 0], relative[i, 1], relative[i, 2] = qx, qy, qz
        sin_half[i], cos_half[i] = quat.length3(qx, qy, qz), qw


@numba.njit(
    [numba.void(WRITE3, READ_INTS1, READ2, READ2, READ2, READ2, READ2, READ2, READ2, READ2, READ1, READ1, WRITE3, WRITE2)],
    cache=True,
    error_model="numpy",
)
def _neck_rows(rotations, neck, joint_offsets, eye_offsets, gaze, head_turns, head, torso, torso_at, relative, sin_half, half_angle, turns, dots):  # noqa: ANN001, ANN202, E501
    """Per frame: the neck joints' rotations (written), then each eye's turn from straight
    ahead toward the point looked at, and that turn's ``w`` as the eyes' slerp reads it
    (its dot product with the identity)."""
    vc7, vc4, skull = neck[0], neck[1], neck[2]
    for i in range(rotations.shape[0]):
        angle = 2.0 * half_angle[i]
        scale = angle / sin_half[i] if sin_half[i] > 1e-12 else 2.0
        rx, ry, rz = relative[i, 0] * scale, relative[i, 1] * scale, relative[i, 2] * scale
        protrusion = head_turns[i, 3]
        lower = quat.of_rotation_vector(NECK_SHARES[0] * rx + protrusion * 1.0, NECK_SHARES[0] * ry + protrusion * 0.0, NECK_SHARES[0] * rz + protrusion * 0.0)
        middle = quat.of_rotation_vector(NECK_SHARES[1] * rx, NECK_SHARES[1] * ry, NECK_SHARES[1] * rz)
        rotations[i, vc7, 0], rotations[i, vc7, 1], rotations[i, vc7, 2], rotations[i, vc7, 3] = lower
        rotations[i, vc4, 0], rotations[i, vc4, 1], rotations[i, vc4, 2], rotations[i, vc4, 3] = middle
        hx, hy, hz, hw = head[i, 0], head[i, 1], head[i, 2], head[i, 3]
        bx, by, bz, bw = quat.multiplied(torso[i, 0], torso[i, 1], torso[i, 2], torso[i, 3], lower[0], lower[1], lower[2], lower[3])
        ax, ay, az, aw = quat.multiplied(bx, by, bz, bw, middle[0], middle[1], middle[2], middle[3])
        sx, sy, sz, sw = quat.multiplied(ax * -1.0, ay * -1.0, az * -1.0, aw * 1.0, hx, hy, hz, hw)
        top = quat.normalized4(sx, sy, sz, sw)
        rotations[i, skull, 0], rotations[i, skull, 1], rotations[i, skull, 2], rotations[i, skull, 3] = top
        ox, oy, oz, ow = torso[i, 0], torso[i, 1], torso[i, 2], torso[i, 3]
        px, py, pz = torso_at[i, 0], torso_at[i, 1], torso_at[i, 2]
        for joint in neck:
            vx, vy, vz = quat.rotated(ox, oy, oz, ow, joint_offsets[joint, 0], joint_offsets[joint, 1], joint_offsets[joint, 2])
            px, py, pz = px + vx, py + vy, pz + vz
            ox, oy, oz, ow = quat.multiplied(ox, oy, oz, ow, rotations[i, joint, 0], rotations[i, joint, 1], rotations[i, joint, 2], rotations[i, joint, 3])
        for e in range(eye_offsets.shape[0]):
            cx, cy, cz = quat.rotated(ox, oy, oz, ow, eye_offsets[e, 0], eye_offsets[e, 1], eye_offsets[e, 2])
            sx, sy, sz = quat.rotated(hx * -1.0, hy * -1.0, hz * -1.0, hw * 1.0, gaze[i, 0] - (px + cx), gaze[i, 1] - (py + cy), gaze[i, 2] - (pz + cz))
            ux, uy, uz = quat.normalized3(sx, sy, sz)
            tx, ty, tz, tw = quat.turn_between(0.0, 0.0, 1.0, ux, uy, uz)
            turns[i, e, 0], turns[i, e, 1], turns[i, e, 2], turns[i, e, 3] = tx, ty, tz, tw
            dots[i, e] = quat.identity_dot(tx, ty, tz, tw)


@numba.njit([numba.void(WRITE3, READ_INTS1, READ3, READ2, READ2)], cache=True, error_model="numpy")
def _eye_rows(rotations, eyes, turns, dots, theta):  # noqa: ANN001, ANN202
    """Per frame and eye: the slerp from straight ahead toward its turn, as far as the
    eyes' range allows (:func:`motor.quaternion.slerp`'s arithmetic; ``theta`` is the
    turn's half angle, numpy's ``arccos``)."""
    for i in range(rotations.shape[0]):
        for e in range(eyes.size):
            half = theta[i, e]
            t = minimum(1.0, EYE_RANGE / maximum(2.0 * half, 1e-12))
            eye = eyes[e]
            out = quat.slerped_from_identity(turns[i, e, 0], turns[i, e, 1], turns[i, e, 2], turns[i, e, 3], dots[i, e], half, t)
            rotations[i, eye, 0], rotations[i, eye, 1], rotations[i, eye, 2], rotations[i, eye, 3] = out


def load_kernels() -> None:
    """Run this module's compiled loops once (they load when it is imported):
    :func:`motor.compiled.warm_up`."""
    rotations = np.zeros((1, 5, 4))
    rotations[..., 3] = 1.0
    gaze = np.array([[0.0, 1.6, 10.0, 0.0, 0.0, 1.0]])
    pose_head_and_eyes(rotations, np.array([0]), np.array([1, 2, 3]), np.array([4]), np.full((5, 3), 0.1), np.full((1, 3), 0.03), gaze, np.zeros((1, 4)))
