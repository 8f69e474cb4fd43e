"""The articulated hand: HamNoSys hand shapes to joint parameters to joint rotations.

Seed 000, section 4.3. A hand shape becomes a vector of joint *parameters* that is
independent of the avatar (bends as proportions of each joint's maximum, splay as a
proportion of the finger's maximum splay, the thumb as weights over the avatar's
calibrated thumb postures); transitions between shapes interpolate these vectors
linearly; :func:`hand_rotations` turns them into the 17 local joint rotations with the
avatar's constants, the finger base joint by the seed's formula

    (σ, mid(s, 0, b′)) · (β, b) · (σ, mid(θflat, θfist1, b′)) · (λ, θfist2 · b′),  b′ = 2b/π

with σ the splay axis (normal to the palm), β the bend axis, λ the hand's long axis.

Parameter layout (:data:`PARAMETER_COUNT` = 26):

* ``[0:7]`` weights of the thumb postures of :data:`motor.body.conventions.THUMB_POSTURES` (sum 1);
* ``[7]`` how much an explicit thumb bending overrides the posture's hinges, ``[8:10]`` that
  bending (middle, end) as proportions of the thumb's maximum bend;
* ``[10 + 4k : 14 + 4k]`` for long finger k (index, middle, ring, pinky): base bend,
  splay (positive away from the middle finger; the middle finger's own toward the ring
  finger), middle bend, end bend — bends as proportions of ``max_bend``, splay of ``max_splay``.
"""

from __future__ import annotations

import functools
from dataclasses import replace

import numba
import numpy as np

from motor import quaternion as quat
from motor.body.avatar import Avatar
from motor.body.conventions import LONG_FINGERS, THUMB_POSTURES
from motor.kernel_types import READ2, WRITE3
from mura.errors import SpecError
from mura.values import (
    BASIC_HANDSHAPES,
    FINGER_BENDINGS,
    FINGERS,
    OPENINGS,
    THUMB_POSITIONS,
    HandShape,
)

THUMB_WEIGHTS = slice(0, len(THUMB_POSTURES))
THUMB_OVERRIDE = len(THUMB_POSTURES)
THUMB_BENDING = slice(THUMB_OVERRIDE + 1, THUMB_OVERRIDE + 3)
FINGER_START = THUMB_OVERRIDE + 3
PARAMETER_COUNT = FINGER_START + 4 * len(LONG_FINGERS)

#: Sign that turns "away from the middle finger" into "toward the thumb", per long finger.
_TOWARD_THUMB = np.array([1.0, -1.0, -1.0, -1.0])

#: Maximum carpometacarpal flexion of the ring and little fingers (radians), reached with
#: full bend and full splay (the tennis-ball grasp).
_CMC_MAX = {"ring": 0.15, "pinky": 0.3}

#: Finger poses as proportions (base bend, splay, middle bend, end bend).
_STRAIGHT = (0.0, 0.0, 0.0, 0.0)
_FOLDED = (1.0, 0.0, 1.0, 0.8)
_PINCH = (0.62, 0.0, 0.62, 0.35)
_CEE_OPEN = (0.2, 0.0, 0.2, 0.1)

#: Splay (proportion of max) of fingers in the spread shapes.
_SPREAD = {"index": 0.8, "middle": 0.3, "ring": 0.6, "pinky": 0.8}
_CONVERGE = {"index": -0.3, "middle": 0.0, "ring": -0.3, "pinky": -0.5}

#: How far cee (and opened pinch) shapes open, from the pinch (0) toward the open hand (1).
_OPENING = {"narrow": 0.3, "normal": 0.45, "wide": 0.75}


def _shape_table() -> dict[str, tuple[tuple[str, ...], str, str, str]]:
    """Basic shape -> (active fingers, active pose, others' pose, thumb posture)."""
    four = LONG_FINGERS
    return {
        "fist": ((), "straight", "folded", "fist"),
        "flathand": (four, "straight", "folded", "alongside"),
        "finger2": (("index",), "straight", "folded", "fist"),
        "finger23": (("index", "middle"), "straight", "folded", "fist"),
        "finger23spread": (("index", "middle"), "spread", "folded", "fist"),
        "finger2345": (four, "spread", "folded", "across"),
        "pinch12": (("index",), "pinch", "folded", "pinch"),
        "pinchall": (four, "pinchall", "folded", "pinchall"),
        "pinch12open": (("index",), "pinch", "spread", "pinch"),
        "cee12": (("index",), "cee", "folded", "pinch"),
        "ceeall": (four, "ceeall", "folded", "pinchall"),
        "ceeopen": (("index",), "cee", "spread", "pinch"),
    }


_SHAPES = _shape_table()
assert set(_SHAPES) == set(BASIC_HANDSHAPES)
_THUMB_MODIFIER_POSTURE = {"out": "out", "across": "across", "open": "open"}
assert set(_THUMB_MODIFIER_POSTURE) == set(THUMB_POSITIONS)


def handshape_params(shape: HandShape) -> np.ndarray:
    """The avatar-independent joint parameters ``(PARAMETER_COUNT,)`` of a hand shape.

    Raises SpecError naming the symbol for an unknown basic shape, bending, finger,
    thumb position or opening.
    """
    if shape.between is not None:
        return 0.5 * (handshape_params(replace(shape, between=None)) + handshape_params(shape.between))
    symbol = shape.name or shape.basic
    if shape.basic not in _SHAPES:
        raise SpecError(f"unknown hand shape {symbol!r} (basic shape {shape.basic!r} is not one of {', '.join(BASIC_HANDSHAPES)})")
    active, active_pose, other_pose, thumb = _SHAPES[shape.basic]
    opening = _opening(shape, symbol, active_pose)
    if shape.extended is not None:
        _check_fingers(shape.extended, symbol)
        active = tuple(f for f in shape.extended if f != "thumb")
    params = np.zeros(PARAMETER_COUNT)
    for k, finger in enumerate(LONG_FINGERS):
        pose = _finger_pose(finger, active_pose if finger in active else other_pose, opening)
        params[FINGER_START + 4 * k : FINGER_START + 4 * k + 4] = pose
    weights = dict.fromkeys(THUMB_POSTURES, 0.0)
    if shape.thumb is not None and active_pose not in ("pinch", "pinchall", "cee", "ceeall"):
        if shape.thumb not in _THUMB_MODIFIER_POSTURE:
            raise SpecError(f"unknown thumb position {shape.thumb!r} in hand shape {symbol!r}")
        thumb = _THUMB_MODIFIER_POSTURE[shape.thumb]
    weights[thumb] += 1.0 - opening
    weights["open"] += opening
    params[THUMB_WEIGHTS] = [weights[name] for name in THUMB_POSTURES]
    bendings = ([(active, shape.bending)] if shape.bending is not None else []) + [(fb.fingers, fb.bending) for fb in shape.finger_bends]
    for fingers, bending in bendings:
        _apply_bending(params, fingers, bending, symbol)
    return params


def _opening(shape: HandShape, symbol: str, active_pose: str) -> float:
    if shape.opening is not None and shape.opening not in OPENINGS:
        raise SpecError(f"unknown opening {shape.opening!r} in hand shape {symbol!r} (expected {', '.join(OPENINGS)})")
    if active_pose in ("cee", "ceeall"):
        return _OPENING[shape.opening or "normal"]
    if active_pose in ("pinch", "pinchall") and shape.opening is not None:
        return _OPENING[shape.opening] - _OPENING["narrow"]
    return 0.0


def _finger_pose(finger: str, pose: str, opening: float) -> tuple[float, float, float, float]:
    if pose == "straight":
        return _STRAIGHT
    if pose == "folded":
        return _FOLDED
    if pose == "spread":
        return (0.0, _SPREAD[finger], 0.0, 0.0)
    converge = _CONVERGE[finger] if pose in ("pinchall", "ceeall") else 0.0
    closed = np.array(_PINCH) + np.array([0.0, converge, 0.0, 0.0])
    closed = (1.0 - opening) * closed + opening * np.array(_CEE_OPEN)
    return tuple(float(v) for v in closed)  # type: ignore[return-value]


def _check_fingers(fingers: tuple[str, ...], symbol: str) -> None:
    for finger in fingers:
        if finger not in FINGERS:
            raise SpecError(f"unknown finger {finger!r} in hand shape {symbol!r} (expected {', '.join(FINGERS)})")


def _apply_bending(params: np.ndarray, fingers: tuple[str, ...], bending: str, symbol: str) -> None:
    if bending not in FINGER_BENDINGS:
        raise SpecError(f"unknown finger bending {bending!r} in hand shape {symbol!r} (expected {', '.join(FINGER_BENDINGS)})")
    _check_fingers(fingers, symbol)
    base, middle, end = FINGER_BENDINGS[bending]
    for finger in fingers:
        if finger == "thumb":
            params[THUMB_OVERRIDE] = 1.0
            params[THUMB_BENDING] = (middle, end)
            continue
        start = FINGER_START + 4 * LONG_FINGERS.index(finger)
        params[start], params[start + 2], params[start + 3] = base, middle, end


#: How far a long finger bends or unbends at its base when it plays (finger play), as a
#: proportion of the base joint's maximum bend: a straight finger bends to half bent (the
#: halfbent bending), a bent one opens by as much.
PLAY_BEND = 0.5
#: A finger bent at least this much at its base and middle joints (a folded, unselected
#: finger: a fist's, a pinch's other fingers) does not play.
PLAY_FOLDED = 0.9


def played(params: np.ndarray, fingers: tuple[str, ...]) -> np.ndarray:
    """The hand parameters ``(PARAMETER_COUNT,)`` with each of the long ``fingers`` moved
    by :data:`PLAY_BEND` at its base joint — bent where it is straighter than half bent,
    opened where it is more bent — its other joints and splay as they are; folded fingers
    (:data:`PLAY_FOLDED`) stay. One step of finger play: a change *of* the hand's shape by
    a finger's small movement, so that a bent finger is not snapped open to half bent
    and back (a 100° turn of its middle joint every tenth of a second)."""
    out = np.array(params, dtype=float)
    for finger in fingers:
        base = FINGER_START + 4 * LONG_FINGERS.index(finger)
        if out[base] >= PLAY_FOLDED and out[base + 2] >= PLAY_FOLDED:
            continue
        out[base] += PLAY_BEND if out[base] < 0.5 else -PLAY_BEND
    return out


def hand_rotations(avatar: Avatar, side: str, params: np.ndarray) -> np.ndarray:
    """Local rotations ``(n, 17, 4)`` of one hand's joints (order of ``avatar.hand_joints``).

    ``params (n, PARAMETER_COUNT)`` as made by :func:`handshape_params` (or interpolated).
    The thumb's angles are numpy's (:func:`thumb_angles`); the rotations one compiled
    loop over the rows: the thumb's base joint turns about its abduction, palmar and twist
    axes in turn, its outer joints and the long fingers' middle and end joints about their
    hinges, the ring and little fingers' carpometacarpal joints about an oblique axis and
    the long fingers' base joints by the seed's formula (module docstring). The same
    numbers, bit for bit, as numpy's arithmetic on whole arrays
    (``tests/perf_equivalence/plain_hand.py``).
    """
    params = np.atleast_2d(np.asarray(params, dtype=float))
    if params.shape[-1] != PARAMETER_COUNT:
        raise ValueError(f"hand parameters have {params.shape[-1]} columns, expected {PARAMETER_COUNT}")
    axes, fingers = _hand_tables(avatar, side)
    rotations = np.empty((params.shape[0], 17, 4))
    _hand_rows(np.ascontiguousarray(params), np.ascontiguousarray(thumb_angles(avatar, params)), axes, fingers, rotations)
    return rotations


#: Rows of a hand's axis table (:func:`_hand_tables`).
_SPLAY, _BEND, _TWIST, _CMC_AXIS, _ABDUCTION, _PALMAR, _THUMB_TWIST = range(7)
#: Columns of a hand's finger table (:func:`_hand_tables`).
_TOWARD, _FLAT, _FIST1, _FIST2, _BEND_BASE, _BEND_MIDDLE, _BEND_END, _SPLAY_MAX, _CMC = range(9)


@functools.lru_cache(maxsize=32)
def _hand_tables(avatar: Avatar, side: str) -> tuple[np.ndarray, np.ndarray]:
    """The hand's constants as :func:`_hand_rows` reads them: axes ``(7, 3)`` and, per
    long finger, its constants ``(4, 9)`` (a carpometacarpal maximum of 0: no such joint)."""
    frame = avatar.hand_frames[side]
    calibration = avatar.calibration
    axes = np.stack([frame.splay_axis, frame.bend_axis, frame.twist_axis, quat.normalize(frame.bend_axis + 0.35 * frame.twist_axis), *thumb_axes(avatar, side)])
    fingers = np.column_stack([
        _TOWARD_THUMB, calibration.theta_flat, calibration.theta_fist1, calibration.theta_fist2, calibration.max_bend,
        calibration.max_splay, [_CMC_MAX.get(finger, 0.0) for finger in LONG_FINGERS],
    ]).astype(float)  # fmt: skip
    axes.flags.writeable = fingers.flags.writeable = False
    return axes, fingers


@numba.njit([numba.void(READ2, READ2, READ2, READ2, WRITE3)], cache=True, error_model="numpy")
def _hand_rows(params, angles, axes, fingers, out):  # noqa: ANN001, ANN202
    about = quat.about_axis
    splay_x, splay_y, splay_z = axes[_SPLAY, 0], axes[_SPLAY, 1], axes[_SPLAY, 2]
    bend_x, bend_y, bend_z = axes[_BEND, 0], axes[_BEND, 1], axes[_BEND, 2]
    palmar = axes[_PALMAR]
    for i in range(params.shape[0]):
        a = about(axes[_ABDUCTION, 0], axes[_ABDUCTION, 1], axes[_ABDUCTION, 2], angles[i, 0])
        b = about(palmar[0], palmar[1], palmar[2], angles[i, 1])
        c = about(axes[_THUMB_TWIST, 0], axes[_THUMB_TWIST, 1], axes[_THUMB_TWIST, 2], angles[i, 2])
        ab = quat.multiplied(a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3])
        out[i, 0, 0], out[i, 0, 1], out[i, 0, 2], out[i, 0, 3] = quat.multiplied(ab[0], ab[1], ab[2], ab[3], c[0], c[1], c[2], c[3])
        out[i, 1, 0], out[i, 1, 1], out[i, 1, 2], out[i, 1, 3] = about(palmar[0], palmar[1], palmar[2], angles[i, 3])
        out[i, 2, 0], out[i, 2, 1], out[i, 2, 2], out[i, 2, 3] = about(palmar[0], palmar[1], palmar[2], angles[i, 4])
        slot = 3
        for k in range(fingers.shape[0]):
            f = fingers[k]
            column = FINGER_START + 4 * k
            bend = params[i, column] * f[_BEND_BASE]
            splay = params[i, column + 1] * f[_SPLAY_MAX]
            b_prime = min(max(2.0 * bend / np.pi, 0.0), 1.0)
            if f[_CMC] != 0.0:
                angle = f[_CMC] * b_prime * min(max(abs(params[i, column + 1]), 0.0), 1.0)
                out[i, slot, 0], out[i, slot, 1], out[i, slot, 2], out[i, slot, 3] = about(axes[_CMC_AXIS, 0], axes[_CMC_AXIS, 1], axes[_CMC_AXIS, 2], angle)
                slot += 1
            s = about(splay_x, splay_y, splay_z, f[_TOWARD] * splay * (1.0 - b_prime))
            b = about(bend_x, bend_y, bend_z, bend)
            t = about(splay_x, splay_y, splay_z, f[_TOWARD] * (f[_FLAT] * (1.0 - b_prime) + f[_FIST1] * b_prime))
            w = about(axes[_TWIST, 0], axes[_TWIST, 1], axes[_TWIST, 2], f[_FIST2] * b_prime)
            sb = quat.multiplied(s[0], s[1], s[2], s[3], b[0], b[1], b[2], b[3])
            tw = quat.multiplied(t[0], t[1], t[2], t[3], w[0], w[1], w[2], w[3])
            out[i, slot, 0], out[i, slot, 1], out[i, slot, 2], out[i, slot, 3] = quat.multiplied(sb[0], sb[1], sb[2], sb[3], tw[0], tw[1], tw[2], tw[3])
            middle = about(bend_x, bend_y, bend_z, params[i, column + 2] * f[_BEND_MIDDLE])
            out[i, slot + 1, 0], out[i, slot + 1, 1], out[i, slot + 1, 2], out[i, slot + 1, 3] = middle
            end = about(bend_x, bend_y, bend_z, params[i, column + 3] * f[_BEND_END])
            out[i, slot + 2, 0], out[i, slot + 2, 1], out[i, slot + 2, 2], out[i, slot + 2, 3] = end
            slot += 3


def load_kernels() -> None:
    """Run this module's compiled loop once (it loads when the module is imported):
    :func:`motor.compiled.warm_up`."""
    _hand_rows(np.zeros((1, PARAMETER_COUNT)), np.zeros((1, 5)), np.eye(7, 3), np.zeros((4, 9)), np.empty((1, 17, 4)))


def thumb_axes(avatar: Avatar, side: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Axes of the thumb's parameters: abduction (toward the thumb side of the hand),
    palmar flexion (toward the palm, also the hinge axis of its two outer joints) and
    twist about its metacarpal (opposition), unit vectors in the rest frame."""
    frame = avatar.hand_frames[side]
    palmar = quat.normalize(np.cross(frame.thumb_axis, frame.palm_normal))
    handedness = 1.0 if side == "l" else -1.0
    return frame.splay_axis, palmar, handedness * frame.thumb_axis


def thumb_angles(avatar: Avatar, params: np.ndarray) -> np.ndarray:
    """Thumb joint angles ``(n, 5)``: abduction, palmar, twist, middle, end (radians)."""
    table = np.array([avatar.calibration.thumb_postures[name] for name in THUMB_POSTURES])
    angles = params[:, THUMB_WEIGHTS] @ table
    override = params[:, THUMB_OVERRIDE : THUMB_OVERRIDE + 1]
    bent = params[:, THUMB_BENDING] * avatar.calibration.thumb_max_bend
    angles[:, 3:5] = (1.0 - override) * angles[:, 3:5] + override * bent
    return angles
