"""The numpy wrist state of the swivel search as it stood before it was compiled
(:func:`motor.arm.swivel_cost.wrist_state`, issue 19): the plain path the compiled loop is
held to by ``test_compiled_wrist.py`` (within a few units in the last place: numba's
``atan2`` and numpy's may round differently). Not used by mura itself."""

from __future__ import annotations

import numpy as np

from motor.arm.chain import ArmPlacement
from motor.body.distance import Components

_TINY = 1e-12


def wrist_state(placement: ArmPlacement, elbow: Components, radial: Components) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Wrist flexion and deviation, forearm twist (all radians, unclamped) and the swing
    between forearm and hand (radians) that the hand rotation ``placement.hands`` asks for
    with elbows at ``elbow`` (directions ``radial`` from the circle's centre).

    The same quantities :func:`motor.arm.ik.solve_arm` computes, from vectors alone: the
    wrist's swing is the rotation taking the forearm's axis, seen from the hand, onto the
    hand's long axis (its rotation vector gives flexion and deviation); the forearm twist
    is what turns the elbow's hinge onto where the hand, swung back, wants it (Rodrigues'
    formula for the swing of a fixed vector)."""
    chain, circle = placement.chain, placement.circle
    matrix = _matrices(placement.hands)
    column = lambda i, j: matrix[:, i, j][:, None]
    forearm = tuple((circle.wrist[:, i : i + 1] - elbow[i]) * (1.0 / chain.fore) for i in range(3))
    seen = tuple(column(0, i) * forearm[0] + column(1, i) * forearm[1] + column(2, i) * forearm[2] for i in range(3))
    a = chain.fore_rest
    axis = (seen[1] * a[2] - seen[2] * a[1], seen[2] * a[0] - seen[0] * a[2], seen[0] * a[1] - seen[1] * a[0])
    sine = np.sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2])
    cosine = seen[0] * a[0] + seen[1] * a[1] + seen[2] * a[2]
    angle = np.arctan2(sine, cosine)
    scale = angle / np.maximum(sine, _TINY)
    flex_across, dev_across = _cross(a, chain.flexion_axis), _cross(a, chain.deviation_axis)
    flexion = scale * (seen[0] * flex_across[0] + seen[1] * flex_across[1] + seen[2] * flex_across[2])
    deviation = scale * (seen[0] * dev_across[0] + seen[1] * dev_across[1] + seen[2] * dev_across[2])
    h = chain.hinge_rest
    along = (axis[0] * h[0] + axis[1] * h[1] + axis[2] * h[2]) / np.maximum(1.0 + cosine, _TINY)
    swung = (
        h[0] * cosine - (axis[1] * h[2] - axis[2] * h[1]) + axis[0] * along,
        h[1] * cosine - (axis[2] * h[0] - axis[0] * h[2]) + axis[1] * along,
        h[2] * cosine - (axis[0] * h[1] - axis[1] * h[0]) + axis[2] * along,
    )
    wanted = tuple(column(i, 0) * swung[0] + column(i, 1) * swung[1] + column(i, 2) * swung[2] for i in range(3))
    c = tuple(circle.axis[:, i : i + 1] for i in range(3))
    hinge = (radial[1] * c[2] - radial[2] * c[1], radial[2] * c[0] - radial[0] * c[2], radial[0] * c[1] - radial[1] * c[0])
    across = (hinge[1] * wanted[2] - hinge[2] * wanted[1], hinge[2] * wanted[0] - hinge[0] * wanted[2], hinge[0] * wanted[1] - hinge[1] * wanted[0])
    sign = float(chain.pronation_axis @ chain.fore_rest)
    twist = np.arctan2(sign * (across[0] * forearm[0] + across[1] * forearm[1] + across[2] * forearm[2]), hinge[0] * wanted[0] + hinge[1] * wanted[1] + hinge[2] * wanted[2])
    return flexion, deviation, twist, angle


def _cross(u: np.ndarray, v: np.ndarray) -> tuple[float, float, float]:
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def _matrices(q: np.ndarray) -> np.ndarray:
    """Rotation matrices ``(n, 3, 3)`` of unit quaternions ``(n, 4)`` (scalar last)."""
    x, y, z, w = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    return np.stack(
        (
            np.stack((1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)), axis=-1),
            np.stack((2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)), axis=-1),
            np.stack((2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)), axis=-1),
        ),
        axis=-2,
    )


