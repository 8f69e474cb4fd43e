"""The arm placed for wrist targets of the body upright at rest, in compiled passes.

A reach check (:func:`motor.arm.ik.arm_reach`) places the arm for a quarter of a million
wrist targets of a corpus: :func:`motor.arm.chain.place_arm` and
:func:`motor.arm.chain.natural_swivel` compose about a hundred numpy operations on arrays
of a few thousand rows. Here the elementwise arithmetic runs in three compiled loops (the
clavicle and shoulder, the elbow circle, the natural swivel's upper-arm direction), each
with numpy's operations in numpy's order (a sum over three coordinates adds them first to
last), and the functions numba computes differently from numpy in the last bit (``tanh``,
``arccos``, ``arctan2``, ``hypot``) are numpy's, over whole arrays between the loops. The
placement and the natural swivels are those of the numpy composition bit for bit
(``tests/perf_equivalence/test_upright_placement.py``); a call with a target or hand
rotation that is not finite takes that composition (its clamps pass NaN, the loops'
would not).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from motor import quaternion as quat
from motor.arm.chain import (
    CLAVICLE_REACH,
    DOWN_BACK,
    ELEVATION_MODEL,
    MODEL_ARM_CM,
    RAISED,
    YAW_MODEL,
    ArmPlacement,
    ElbowCircle,
    arm_chain,
    farthest_reach,
    natural_swivel,
    nearest_reach,
    place_arm,
    short_of,
)
from motor.body.avatar import Avatar
from motor.kernel_types import READ1, READ2, WRITE2, WRITE3


def upright_placement(avatar: Avatar, side: str, wrist_targets: np.ndarray, hand_rotations: np.ndarray | None = None) -> tuple[ArmPlacement, np.ndarray]:
    """:func:`motor.arm.chain.place_arm` of wrist targets ``(n, 3)`` (and hand rotations
    ``(n, 4)``) with the body upright at rest, and the natural swivels there ``(n,)``
    (radians): the same numbers."""
    targets = np.ascontiguousarray(np.asarray(wrist_targets, dtype=float).reshape(-1, 3))
    hands = None if hand_rotations is None else np.asarray(hand_rotations, dtype=float).reshape(-1, 4)
    if not np.isfinite(targets).all() or (hands is not None and not np.isfinite(hands).all()):
        placement = place_arm(avatar, side, targets, hands)
        return placement, natural_swivel(placement.chain, placement.circle, placement.targets, None)
    chain = arm_chain(avatar, side)
    frames = targets.shape[0]
    sc_position = chain.torso_joint_rest + chain.sc_offset
    clavicle_local, shoulder = np.empty((frames, 4)), np.empty((frames, 3))
    arm = chain.upper + chain.fore
    clavicle = np.asarray(chain.clavicle, dtype=float)
    _clavicle_rows(targets, sc_position, sc_position + clavicle, clavicle, float(quat.norm(clavicle)), arm, chain.clavicle_max, clavicle_local, shoulder)
    reach = targets - shoulder
    distance = quat.norm(reach)
    reached = np.maximum(short_of(distance, farthest_reach(chain)), nearest_reach(chain))
    columns = np.empty((6, frames))
    vectors = np.empty((6, frames, 3))
    lengths = np.array([chain.upper, chain.upper**2, chain.fore**2, 2.0 * chain.upper * chain.fore, 2.0 * chain.upper, arm])
    _circle_rows(reach, distance, reached, shoulder, lengths, chain.side_sign, columns, vectors)
    axis, center, down, out, wrist, local = vectors
    cos_flexion, cos_shoulder, radius, shortfall, lateral, distance_cm = columns
    circle = ElbowCircle(
        shoulder=shoulder, axis=axis, center=center, radius=radius, down=down, out=out, wrist=wrist,
        shortfall=shortfall, flexion=np.arccos(np.minimum(np.maximum(cos_flexion, -1.0), 1.0)),
    )  # fmt: skip
    placement = ArmPlacement(chain, None, clavicle_local, clavicle_local, circle, targets, None if hands is None else quat.normalize(hands), None)
    target_elevation = np.degrees(np.arctan2(local[:, 1], np.hypot(lateral, local[:, 2])))
    azimuth = np.degrees(np.arctan2(lateral, local[:, 2]))
    elevation = np.radians(np.minimum(np.maximum(ELEVATION_MODEL[0] + ELEVATION_MODEL[1] * distance_cm + ELEVATION_MODEL[2] * target_elevation, 0.0), 170.0))
    yaw = np.radians(YAW_MODEL[0] + YAW_MODEL[1] * azimuth + YAW_MODEL[2] * target_elevation)
    along = np.empty((2, frames))
    _swivel_sides(np.sin(elevation), np.cos(elevation), np.sin(yaw), np.cos(yaw), shoulder, center, down, out, chain.upper, chain.side_sign, along)
    return placement, np.arctan2(along[0], along[1])


@numba.njit([numba.void(READ2, READ1, READ1, READ1, numba.float64, numba.float64, numba.float64, WRITE2, WRITE2)], cache=True, error_model="numpy")
def _clavicle_rows(targets, sc_position, base, clavicle, clavicle_length, arm, clavicle_max, clavicle_local, shoulder):  # noqa: ANN001, ANN202
    """:func:`motor.arm.chain.clavicle_rotation` (upright) per row into ``clavicle_local
    (n, 4)``, and the shoulder it places ``(n, 3)``; ``base``: the sternoclavicular joint
    plus the clavicle at rest."""
    low, high = CLAVICLE_REACH
    cx, cy, cz = clavicle[0], clavicle[1], clavicle[2]
    for i in range(targets.shape[0]):
        rx, ry, rz = targets[i, 0] - base[0], targets[i, 1] - base[1], targets[i, 2] - base[2]
        distance = quat.length3(rx, ry, rz)
        t = min(max((distance / arm - low) / (high - low), 0.0), 1.0)
        amount = t * t * (3.0 - 2.0 * t)
        ax, ay, az = quat.crossed(cx, cy, cz, rx, ry, rz)
        axis_length = quat.length3(ax, ay, az)
        across = min(max(axis_length / max(clavicle_length * distance, 1e-12) / 0.3, 0.0), 1.0)
        scale = max(axis_length, 1e-12)
        half = 0.5 * (clavicle_max * amount * across)
        sine = math.sin(half)
        q = (ax / scale * sine, ay / scale * sine, az / scale * sine, math.cos(half))
        clavicle_local[i, 0], clavicle_local[i, 1], clavicle_local[i, 2], clavicle_local[i, 3] = q
        px, py, pz = quat.rotated(q[0], q[1], q[2], q[3], cx, cy, cz)
        shoulder[i, 0], shoulder[i, 1], shoulder[i, 2] = sc_position[0] + px, sc_position[1] + py, sc_position[2] + pz


@numba.njit([numba.void(READ2, READ1, READ1, READ2, READ1, numba.float64, WRITE2, WRITE3)], cache=True, error_model="numpy")
def _circle_rows(reach, distance, reached, shoulder, lengths, side_sign, columns, vectors):  # noqa: ANN001, ANN202
    """:class:`motor.arm.chain.ElbowCircle` ``of`` (upright) per row, from the reach from
    the shoulder, its length and the length reached: into ``columns`` the cosines of the
    elbow's flexion and of the shoulder's angle, the radius, the shortfall, and for the
    natural swivel the reach's lateral part and length in the model's centimetres; into
    ``vectors`` the axis, centre, swivel zero (down), out, wrist and the reach.
    ``lengths``: the upper arm, its square, the forearm's square, twice their product,
    twice the upper arm, the arm."""
    upper, upper2, fore2, twice_product, twice_upper, arm = lengths[0], lengths[1], lengths[2], lengths[3], lengths[4], lengths[5]
    b0, b1, b2 = DOWN_BACK[0], DOWN_BACK[1], DOWN_BACK[2]
    for i in range(reach.shape[0]):
        r = (reach[i, 0], reach[i, 1], reach[i, 2])
        d, rd = distance[i], reached[i]
        if d > 1e-9:
            scale = max(d, 1e-12)
            a = (r[0] / scale, r[1] / scale, r[2] / scale)
        else:
            a = (0.0, -1.0, 0.0)
        columns[0, i] = (rd * rd - upper2 - fore2) / twice_product
        cos_shoulder = min(max((upper2 + rd * rd - fore2) / (twice_upper * rd), -1.0), 1.0)
        raised = min(max(((a[0] * 0.0 + a[1] * 1.0) + a[2] * 0.0 - RAISED[0]) / (RAISED[1] - RAISED[0]), 0.0), 1.0)
        raised = raised * raised * (3.0 - 2.0 * raised)
        e = (
            (1.0 - raised) * b0 + raised * 0.0,
            (1.0 - raised) * b1 + raised * 0.0,
            (1.0 - raised) * b2 + raised * 1.0,
        )
        along = (e[0] * a[0] + e[1] * a[1]) + e[2] * a[2]
        dx, dy, dz = e[0] - along * a[0], e[1] - along * a[1], e[2] - along * a[2]
        down_length = quat.length3(dx, dy, dz)
        if down_length > 1e-6:
            scale = max(down_length, 1e-12)
            dx, dy, dz = dx / scale, dy / scale, dz / scale
        else:
            dx, dy, dz = quat.crossed(a[0], a[1], a[2], side_sign, 0.0, 0.0)
        ox, oy, oz = quat.crossed(a[0], a[1], a[2], dx, dy, dz)
        to_center = upper * cos_shoulder
        for c in range(3):
            vectors[0, i, c] = a[c]
            vectors[1, i, c] = shoulder[i, c] + a[c] * to_center
            vectors[4, i, c] = shoulder[i, c] + a[c] * rd
            vectors[5, i, c] = r[c]
        vectors[2, i, 0], vectors[2, i, 1], vectors[2, i, 2] = dx, dy, dz
        vectors[3, i, 0], vectors[3, i, 1], vectors[3, i, 2] = side_sign * ox, side_sign * oy, side_sign * oz
        columns[1, i] = cos_shoulder
        columns[2, i] = upper * math.sqrt(1.0 - cos_shoulder * cos_shoulder)
        columns[3, i] = abs(d - rd)
        columns[4, i] = side_sign * r[0]
        columns[5, i] = d / arm * MODEL_ARM_CM


@numba.njit([numba.void(READ1, READ1, READ1, READ1, READ2, READ2, READ2, READ2, numba.float64, numba.float64, WRITE2)], cache=True, error_model="numpy")
def _swivel_sides(sin_elevation, cos_elevation, sin_yaw, cos_yaw, shoulder, center, down, out, upper, side_sign, along):  # noqa: ANN001, ANN202
    """Into ``along (2, n)``: how far the elbow the model predicts (the upper arm at its
    elevation and yaw, :func:`motor.arm.chain.natural_swivel`) lies from the circle's
    centre along its out and its down direction (the natural swivel's sine and cosine
    sides)."""
    for i in range(shoulder.shape[0]):
        u = (side_sign * sin_elevation[i] * sin_yaw[i], -cos_elevation[i], sin_elevation[i] * cos_yaw[i])
        o = (shoulder[i, 0] + upper * u[0] - center[i, 0], shoulder[i, 1] + upper * u[1] - center[i, 1], shoulder[i, 2] + upper * u[2] - center[i, 2])
        along[0, i] = (o[0] * out[i, 0] + o[1] * out[i, 1]) + o[2] * out[i, 2]
        along[1, i] = (o[0] * down[i, 0] + o[1] * down[i, 1]) + o[2] * down[i, 2]


def load_kernels() -> None:
    """Run this module's compiled loops once (they load when it is imported):
    :func:`motor.compiled.warm_up`."""
    one, row = np.zeros(1), np.array([[0.1, -0.2, 0.3]])
    placement = np.empty((1, 4)), np.empty((1, 3))
    _clavicle_rows(row, np.zeros(3), np.ones(3), np.ones(3), 1.0, 0.6, 0.2, *placement)
    _circle_rows(row, np.ones(1), np.ones(1), row, np.ones(6), 1.0, np.empty((6, 1)), np.empty((6, 1, 3)))
    _swivel_sides(one, one, one, one, row, row, row, row, 0.3, 1.0, np.empty((2, 1)))
