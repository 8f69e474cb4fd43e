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

* ``[0:7]`` weights of the thumb postures of :data:`motor.body.avatar.THUMB_POSTURES` (sum 1);
* ``[7]`` how much an explicit thumb bending overrides the posture's hinges, ``[8:10]`` that
  bending (middle, end) as proportions of the thumb's maximum bend;
* ``[10 + 4k : 14 + 4k]`` for long finger k (index, middle, ring, pinky): base bend,
  splay (positive away from the middle finger; the middle finger's own toward the ring
  finger), middle bend, end bend — bends as proportions of ``max_bend``, splay of ``max_splay``.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from motor import quaternion as quat
from motor.body.avatar import (
    LONG_FINGERS,
    THUMB_POSTURES,
    Avatar,
    FingerCalibration,
    HandFrame,
)
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
    """
    params = np.atleast_2d(np.asarray(params, dtype=float))
    if params.shape[-1] != PARAMETER_COUNT:
        raise ValueError(f"hand parameters have {params.shape[-1]} columns, expected {PARAMETER_COUNT}")
    frame = avatar.hand_frames[side]
    calibration = avatar.calibration
    rotations = np.empty((params.shape[0], 17, 4))
    rotations[:, 0:3] = _thumb_rotations(avatar, side, params)
    slot = 3
    for k, finger in enumerate(LONG_FINGERS):
        columns = params[:, FINGER_START + 4 * k : FINGER_START + 4 * k + 4]
        bend, middle, end = (columns[:, (0, 2, 3)] * calibration.max_bend[k]).T
        splay = columns[:, 1] * calibration.max_splay[k]
        if finger in _CMC_MAX:
            rotations[:, slot] = _cmc_rotation(frame, finger, bend, columns[:, 1])
            slot += 1
        rotations[:, slot] = _base_rotation(frame, k, bend, splay, calibration)
        rotations[:, slot + 1] = quat.from_axis_angle(frame.bend_axis, middle)
        rotations[:, slot + 2] = quat.from_axis_angle(frame.bend_axis, end)
        slot += 3
    return rotations


def _base_rotation(frame: HandFrame, k: int, bend: np.ndarray, splay: np.ndarray, calibration: FingerCalibration) -> np.ndarray:
    """The seed-000 finger base joint from bend and splay (radians)."""
    toward_thumb = _TOWARD_THUMB[k]
    b_prime = np.clip(2.0 * bend / np.pi, 0.0, 1.0)
    splay_part = quat.from_axis_angle(frame.splay_axis, toward_thumb * splay * (1.0 - b_prime))
    bend_part = quat.from_axis_angle(frame.bend_axis, bend)
    taper = calibration.theta_flat[k] * (1.0 - b_prime) + calibration.theta_fist1[k] * b_prime
    taper_part = quat.from_axis_angle(frame.splay_axis, toward_thumb * taper)
    twist_part = quat.from_axis_angle(frame.twist_axis, calibration.theta_fist2[k] * b_prime)
    return quat.multiply(quat.multiply(splay_part, bend_part), quat.multiply(taper_part, twist_part))


def _cmc_rotation(frame: HandFrame, finger: str, bend: np.ndarray, splay_proportion: np.ndarray) -> np.ndarray:
    """Carpometacarpal hinge of the ring or little finger, its axis oblique across the palm."""
    axis = quat.normalize(frame.bend_axis + 0.35 * frame.twist_axis)
    b_prime = np.clip(2.0 * bend / np.pi, 0.0, 1.0)
    return quat.from_axis_angle(axis, _CMC_MAX[finger] * b_prime * np.clip(np.abs(splay_proportion), 0.0, 1.0))


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


def thumb_rotations_from_angles(avatar: Avatar, side: str, angles: np.ndarray) -> np.ndarray:
    """Local rotations ``(n, 3, 4)`` of thumb1..3 from angles ``(n, 5)`` (see :func:`thumb_angles`)."""
    abduction, palmar, twist = thumb_axes(avatar, side)
    base = quat.multiply(
        quat.multiply(quat.from_axis_angle(abduction, angles[:, 0]), quat.from_axis_angle(palmar, angles[:, 1])),
        quat.from_axis_angle(twist, angles[:, 2]),
    )
    return np.stack((base, quat.from_axis_angle(palmar, angles[:, 3]), quat.from_axis_angle(palmar, angles[:, 4])), axis=1)


def _thumb_rotations(avatar: Avatar, side: str, params: np.ndarray) -> np.ndarray:
    return thumb_rotations_from_angles(avatar, side, thumb_angles(avatar, params))
