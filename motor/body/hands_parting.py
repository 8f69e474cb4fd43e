"""Which way and how far two hands part, row by row, compiled: the arithmetic of
:func:`motor.body.collision.hand_separation` for the rows whose hands may meet.

The hands' capsules (:func:`motor.body.collision.hand_segments`) and their nearest points
(:func:`motor.body.distance.closest_parameters`) come in as arrays; :func:`gaps` measures
how near the hands' midlines come, numpy's ``exp`` eases the gaps (a compiled ``exp``
rounds some last bits otherwise), and :func:`pushes` finds the way the left hand leaves
the right one (:func:`_parting`, :func:`_crossed`) and how far along it. Each step is
numpy's, element by element in its order (``tests/perf_equivalence/plain_collision.py``
keeps the numpy version), ``np.einsum``'s sum of three products too (the first and the
last, then the middle one); the one exception is the sign of the crossing axis's
component along :data:`_PREFERRED` (a matrix product there, summed first to last here),
which could differ only for an axis within rounding of perpendicular to it.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from motor import quaternion as quat
from motor.kernel_types import READ1, READ2, WRITE2, clip, maximum, minimum

#: Depth (m) of the band below the palm thickness into which hands asked to come nearer
#: are eased (:func:`motor.body.collision.separate_hands`): they overlap at most that
#: much, while a contact placed at the palm thickness (:mod:`motor.program.fragment`)
#: stays exactly as placed.
HAND_BAND = 0.002
#: Fractions of a hand's midline (from the wrist to the knuckles) over which hands whose
#: nearest points both lie past them, and whose wrists lie as far apart, count as meeting
#: fingers into fingers (:func:`_parting`).
END_SHARE = (0.6, 0.8)
#: Sine of the angle between the hands' long axes from which they count as crossing.
CROSSING_SINE = 0.3
#: Side the left hand takes where the hands cross: up, a little to the left and forward.
_PREFERRED = np.array([0.1, 1.0, 0.01])
#: Way the left hand takes from the right where the wrists are crossed over (the left one
#: right of the right one): down, below the right hand, as the mirror image of a right-handed
#: gesture whose arms cross is placed (:meth:`motor.program.fragment.Compiler.stacked`).
_CROSSED_WAY = np.array([0.0, -1.0, 0.0])
_TINY = 1e-12
#: The columns :func:`gaps` keeps per row: the line between the hands' nearest points
#: (3), its length, the gap below the palm thickness (m), that gap shifted by
#: :data:`HAND_BAND`, and the argument of its easing's exponential.
GAP_COLUMNS = 7
EASE_ARGUMENT = 6
#: The constants :func:`pushes` takes, in order: the palm thickness and the thickness kept
#: (m), a hand's midline length (m), the left and right palm normals in the hand frames.
CONSTANTS = ("palm", "thickness", "length", "left_normal_x", "left_normal_y", "left_normal_z", "right_normal_x", "right_normal_y", "right_normal_z")


@numba.njit([numba.boolean(READ2, READ2, READ2, READ2, READ1, READ1, numba.float64, WRITE2)], cache=True, error_model="numpy")
def gaps(l0, l1, r0, r1, s, t, thickness, table):  # noqa: ANN001, ANN201
    """Into ``table`` (columns :data:`GAP_COLUMNS`): per row, the line between the hands'
    nearest points (at the fractions ``s``, ``t`` of the capsules ``l0``–``l1`` and
    ``r0``–``r1``), how far the hands are nearer than ``thickness`` (m), and the
    argument of the easing of that gap; whether any hands are nearer."""
    nearer = False
    for i in range(table.shape[0]):
        for j in range(3):
            table[i, j] = (l0[i, j] + s[i] * (l1[i, j] - l0[i, j])) - (r0[i, j] + t[i] * (r1[i, j] - r0[i, j]))
        apart = quat.length3(table[i, 0], table[i, 1], table[i, 2])
        gap = apart - thickness
        shifted = gap + HAND_BAND
        table[i, 3], table[i, 4], table[i, 5] = apart, gap, shifted
        table[i, EASE_ARGUMENT] = 2.0 * (minimum(shifted, HAND_BAND) / HAND_BAND - 1.0)
        nearer |= gap < 0.0
    return nearer


@numba.njit(cache=True, error_model="numpy", inline="always")
def _ramp(value, low, high):  # noqa: ANN001, ANN202
    """0 below ``low``, 1 above ``high``, smoothstep between."""
    u = clip((value - low) / (high - low), 0.0, 1.0)
    return u * u * (3.0 - 2.0 * u)


@numba.njit(cache=True, error_model="numpy", inline="always")
def _parting(left, right, apart, s, t, length):  # noqa: ANN001, ANN202
    """The way (a unit 3-tuple) the left hand leaves the right where they touch, for hands
    with long axes ``left``, ``right``, wrists ``apart`` (left less right; 3-tuples),
    nearest points at the fractions ``s``, ``t`` of their midlines and midlines
    ``length`` (m) long: where the fingers of hands whose wrists are most of a hand
    apart run into each other, they are drawn apart along the line between the wrists
    (mirrored hands stay mirrored); where they cross otherwise (one hand over the other,
    wrists near), across both hands (perpendicular to their long axes) — the side toward
    the avatar's top and left — and toward the avatar's left where they lie side by side
    (palm against palm); blended between."""
    ax, ay, az = quat.crossed(left[0], left[1], left[2], right[0], right[1], right[2])
    sine = quat.length3(ax, ay, az) / maximum(quat.length3(left[0], left[1], left[2]) * quat.length3(right[0], right[1], right[2]), _TINY)
    side = 1.0 if (ax * _PREFERRED[0] + ay * _PREFERRED[1]) + az * _PREFERRED[2] >= 0.0 else -1.0
    ax, ay, az = ax * side, ay * side, az * side
    size = maximum(quat.length3(ax, ay, az), _TINY)
    ax, ay, az = ax / size, ay / size, az / size
    weight = clip(sine / CROSSING_SINE, 0.0, 1.0)
    px, py, pz = weight * ax + (1.0 - weight) * 1.0, weight * ay + (1.0 - weight) * 0.0, weight * az + (1.0 - weight) * 0.0
    spread = quat.length3(apart[0], apart[1], apart[2])
    drawn = _ramp(minimum(s, t), END_SHARE[0], END_SHARE[1]) * _ramp(spread / length, END_SHARE[0], END_SHARE[1])
    wide = maximum(spread, _TINY)
    px = drawn * apart[0] / wide + (1.0 - drawn) * px
    py = drawn * apart[1] / wide + (1.0 - drawn) * py
    pz = drawn * apart[2] / wide + (1.0 - drawn) * pz
    size = maximum(quat.length3(px, py, pz), _TINY)
    return px / size, py / size, pz / size


@numba.njit(cache=True, error_model="numpy", inline="always")
def _crossed(spread, left_hand, right_hand, constants):  # noqa: ANN001, ANN202
    """How far (0 … 1) hands whose wrists lie ``spread`` apart along x (left less right,
    m), turned by global rotations ``left_hand``, ``right_hand`` (rows of 4), are crossed
    over: they then pass one over the other, never through each other sideways (which
    would flip the way they part as they pass). Wholly so where the left wrist lies right
    of the right one; hands whose palms face each other across x only once they are a
    palm thickness past each other (at one point they meet side by side, palm to palm),
    other hands already half where their wrists are level."""
    palm = constants[0]
    left_x, _, _ = quat.rotated(left_hand[0], left_hand[1], left_hand[2], left_hand[3], constants[3], constants[4], constants[5])
    right_x, _, _ = quat.rotated(right_hand[0], right_hand[1], right_hand[2], right_hand[3], constants[6], constants[7], constants[8])
    facing = 0.5 * (abs(left_x) + abs(right_x))
    u = clip((spread + palm * (0.5 + 0.5 * facing)) / (palm * (2.0 - facing)), 0.0, 1.0)
    return 1.0 - u * u * (3.0 - 2.0 * u)


@numba.njit([numba.void(*(READ2,) * 4, READ1, READ1, *(READ2,) * 4, READ2, READ1, READ1, WRITE2)], cache=True, error_model="numpy")
def pushes(l0, l1, r0, r1, s, t, left, right, left_hands, right_hands, table, rise, constants, out):  # noqa: ANN001, ANN201
    """Into ``out``: how far the left wrist moves per row (the right one the other way),
    from :func:`gaps`'s ``table``, numpy's exponential of its easing arguments ``rise``,
    the wrists ``left``, ``right`` and hand rotations; ``constants``: :data:`CONSTANTS`.
    The line between the hands, tilted toward :func:`_parting` where they (nearly) pass
    through each other, where the line means little, and toward :data:`_CROSSED_WAY` where
    their wrists are crossed over (:func:`_crossed`); then how far along that way the
    hands part to be eased beyond the thickness."""
    palm, thickness, length = constants[0], constants[1], constants[2]
    for i in range(out.shape[0]):
        bx, by, bz, apart, shifted = table[i, 0], table[i, 1], table[i, 2], table[i, 3], table[i, 5]
        eased = (shifted if shifted >= HAND_BAND else 2.0 * HAND_BAND * rise[i] / (1.0 + rise[i])) - HAND_BAND
        meeting = maximum(1.0 - apart / (0.5 * palm), 0.0)
        axis_l = (l1[i, 0] - l0[i, 0], l1[i, 1] - l0[i, 1], l1[i, 2] - l0[i, 2])
        axis_r = (r1[i, 0] - r0[i, 0], r1[i, 1] - r0[i, 1], r1[i, 2] - r0[i, 2])
        wrists = (left[i, 0] - right[i, 0], left[i, 1] - right[i, 1], left[i, 2] - right[i, 2])
        px, py, pz = _parting(axis_l, axis_r, wrists, s[i], t[i], length)
        tilt = 0.25 * palm * meeting
        dx, dy, dz = bx + tilt * px, by + tilt * py, bz + tilt * pz
        crossed = _crossed(wrists[0], left_hands[i], right_hands[i], constants)
        dx *= 1.0 - crossed
        # the side the hands are on already, else (where they are level) the left one below
        level = maximum(1.0 - abs(dy) / (0.25 * palm), 0.0)
        way = 0.25 * palm * crossed * level
        dx, dy, dz = dx + way * _CROSSED_WAY[0], dy + way * _CROSSED_WAY[1], dz + way * _CROSSED_WAY[2]
        size = maximum(quat.length3(dx, dy, dz), _TINY)
        dx, dy, dz = dx / size, dy / size, dz / size
        along = (bx * dx + bz * dz) + by * dy  # np.einsum's pairing of three products
        wanted = eased + thickness
        push = math.sqrt(maximum(along * along - apart * apart + wanted * wanted, 0.0)) - along
        half = 0.5 * push
        out[i, 0], out[i, 1], out[i, 2] = half * dx, half * dy, half * dz


def load_kernels() -> None:
    """Run this module's compiled loops once (they load when it is imported):
    :func:`motor.compiled.warm_up`."""
    rows, one = np.zeros((1, 3)), np.zeros(1)
    table = np.zeros((1, GAP_COLUMNS))
    gaps(rows, rows + 1.0, rows, rows, one, one, 0.01, table)
    hands = np.array([[0.0, 0.0, 0.0, 1.0]])
    pushes(rows, rows + 1.0, rows, rows, one, one, rows, rows, hands, hands, table, np.ones(1), np.ones(len(CONSTANTS)), np.zeros((1, 3)))
