"""The body's collision volumes in a pose: placement, clear wrist targets, hands apart.

* :func:`joint_placement` / :func:`to_rest` carry points between the avatar frame and a
  volume's rest frame (a volume moves rigidly with its joint; :mod:`motor.body.volumes`),
  where :mod:`motor.body.distance` measures signed distances from it;
* :func:`outside_torso` places wrist targets out of the torso (what the planners place
  their targets and paths with); :func:`kept_out_of_torso` keeps every frame's wrist
  targets out of it, smoothly (what the motor control does to whatever it is given): a
  path that crosses the torso's front, top or bottom bends around it;
* :func:`hand_separation` (and :func:`separate_hands`, which applies it) keeps the two
  hands a palm thickness apart, smoothly in their gap: hands placed in contact stay as
  placed, hands asked to overlap are bent apart (to within :data:`motor.body.hands_parting.HAND_BAND`); hands
  whose paths cross pass one over the other. Frame by frame: over time the motor control
  eases the separation in and out (:mod:`motor.body.hands_apart`).

Both eases are C²: a distance past a limit is kept positive, unchanged from the band's
width ``band`` on and ``band (1 + tanh(gap / band − 1))`` below it — equal in value, slope
and curvature at ``band``, rising monotonically from 0 however deep the point was — so a
path that enters their band changes neither speed nor acceleration with a step. The torso's band lies in front of its margin (a clearance:
nothing is left inside it), the hands' band below the palm thickness (a contact: the
planners place hands that touch exactly there, and a movement that starts from the
contact keeps its planned minimum-jerk profile).
"""

from __future__ import annotations

import functools

import numba
import numpy as np

from motor import quaternion as quat
from motor.body.avatar import Avatar
from motor.body.distance import closest_parameters
from motor.body.hands_parting import EASE_ARGUMENT, GAP_COLUMNS, gaps, pushes
from motor.body.torso_push import EDGE_BAND, HAND_COLUMNS, SOFT_BAND, eased_gap, hand_depths, hand_moved, hand_pushes, hand_rays, landed, near_rows, ray, reach_box, reachable
from motor.body.volumes import Capsule
from motor.kernel_types import READ1, READ2, READ_INTS1, WRITE1, WRITE2

#: Clearance of the wrist from the torso surface, metres.
TORSO_MARGIN = 0.04
#: Fractions of the hand capsule's axis (wrist 0, knuckles 1) kept out of the torso by
#: :func:`hand_push_out_of_torso`, the rounds it takes, and how much farther than a hand's
#: length (m) from the torso's box it looks.
HAND_AXIS_SAMPLES = np.linspace(0.0, 1.0, 5)
_HAND_ROUNDS = 2
_HAND_REACH_SLACK = 0.02


def joint_placement(avatar: Avatar, positions: np.ndarray, orientations: np.ndarray, joint: str) -> tuple[np.ndarray, np.ndarray]:
    """Rotation ``(n, 4)`` and translation ``(n, 3)`` carrying a joint's rest geometry to
    its pose: ``posed = rotate(rotation, rest) + translation``. ``positions (n, J, 3)`` and
    ``orientations (n, J, 4)`` are forward kinematics' global joint poses."""
    index = avatar.joint_index(joint)
    rotation = orientations[:, index]
    return rotation, positions[:, index] - quat.rotate(rotation, avatar.rest_positions[index])


def to_rest(rotation: np.ndarray, translation: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Posed points ``(n, ..., 3)`` expressed in the rest frame of a placement ``(n, 4)``, ``(n, 3)``."""
    extra = (slice(None),) + (None,) * (points.ndim - 2)
    return quat.rotate(quat.conjugate(rotation)[extra], points - translation[extra])


def posed_capsule(capsule: Capsule, rotation: np.ndarray, translation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A capsule's end points ``(n, 3)`` in a placement."""
    return quat.rotate(rotation, capsule.a) + translation, quat.rotate(rotation, capsule.b) + translation


def _clip01(value: np.ndarray) -> np.ndarray:
    return np.minimum(np.maximum(value, 0.0), 1.0)


def outside_torso(avatar: Avatar, points: np.ndarray) -> np.ndarray:
    """Wrist positions ``(n, 3)`` (avatar frame at rest, metres) placed out of the torso:
    a point inside its elliptic cylinder grown by :data:`TORSO_MARGIN`, or behind it
    within its width, moved forward onto the grown cylinder's front surface; the others
    unchanged. What planners place their targets and path samples with (gestures
    :mod:`motor.arm.wrist_path`, signs, verbs): idempotent, and :func:`kept_out_of_torso`
    leaves what it returns where it is."""
    torso = avatar.torso
    a, b = torso.half_width + TORSO_MARGIN, torso.half_depth + TORSO_MARGIN
    dx = (points[:, 0] - torso.center[0]) / a
    front = torso.center[2] + b * np.sqrt(_clip01(1.0 - dx * dx))
    inside = inside_torso(avatar, points)
    if not np.any(inside):
        return points
    out = np.array(points, dtype=float)
    out[:, 2] = np.where(inside, front, out[:, 2])
    return out


def kept_out_of_torso(avatar: Avatar, points: np.ndarray, margin: float = TORSO_MARGIN) -> np.ndarray:
    """Wrist positions ``(n, 3)`` (avatar frame at rest, metres) kept out of the torso,
    smoothly (C¹): what the motor control does to every frame's wrist targets, whoever
    made them.

    The torso's elliptic cylinder grown by ``margin`` (m; :data:`TORSO_MARGIN` for a
    wrist): a point inside it, or in
    its shadow behind it, is moved out along the horizontal ray from a point
    :data:`motor.body.torso_push.RAY_DEPTH` half depths behind the torso's axis (forward
    in front of the chest, forward and outward at its sides, where moving straight
    forward would jump as the front turns back); a point outside by less than :data:`SOFT_BAND` along that ray is
    eased out with a C² curve (module docstring: a path meeting the surface bends instead
    of stopping dead); beyond the torso's top and bottom the push fades out over
    :data:`EDGE_BAND`. Points farther away are unchanged; no moved point is left inside."""
    rows = np.ascontiguousarray(points, dtype=float)
    out = np.empty(rows.shape)
    return out if _kept_out(rows, np.arange(len(rows)), _torso_shape(avatar, margin), out) else points


def _kept_out(points: np.ndarray, rows: np.ndarray, shape: np.ndarray, out: np.ndarray) -> bool:
    """Into ``out`` ``(m, 3)``: the ``rows`` of ``points`` ``(n, 3)`` kept out of the torso
    ``shape`` (:func:`_torso_shape`) as :func:`kept_out_of_torso` keeps them; whether any
    moved."""
    rays, arguments = np.empty((rows.size, _RAY_COLUMNS)), np.empty(rows.size)
    eased = _torso_rays(points, rows, shape, out, rays, arguments)
    # numpy's exp between the two loops: the compiled one rounds some last bits otherwise
    return eased > 0 and _pushed_out(shape, rays, np.exp(arguments[:eased]), out)


@functools.lru_cache(maxsize=32)
def _torso_shape(avatar: Avatar, margin: float) -> np.ndarray:
    """The torso grown by ``margin`` (m) as :mod:`motor.body.torso_push` takes it: centre x
    and z, half width and half depth, bottom and top."""
    torso = avatar.torso
    shape = np.array([torso.center[0], torso.center[2], torso.half_width + margin, torso.half_depth + margin, torso.bottom, torso.top])
    shape.flags.writeable = False
    return shape


#: The columns :func:`_torso_rays` keeps per point: :func:`motor.body.torso_push.ray`'s
#: but the argument of easing's exponential.
_RAY_COLUMNS = 6


@numba.njit([numba.int64(READ2, READ_INTS1, READ1, WRITE2, WRITE2, WRITE1)], cache=True, error_model="numpy")
def _torso_rays(points, rows, shape, out, rays, arguments):  # noqa: ANN001, ANN202
    """Into ``out`` the ``rows`` of ``points``, into ``rays`` their rays out of the torso
    ``shape`` (:func:`motor.body.torso_push.ray`; a point
    :func:`motor.body.torso_push.reachable` rejects as no nearer than the soft band,
    unfaded) and into ``arguments``, one after another, the exponentials' arguments of
    the points :func:`motor.body.torso_push.eased_gap` eases; returns how many those are."""
    cx, cz, a, b, bottom, top = shape[0], shape[1], shape[2], shape[3], shape[4], shape[5]
    box = reach_box(cz, a, b, bottom, top)
    eased = 0
    for i in range(rows.shape[0]):
        x, y, z = points[rows[i], 0], points[rows[i], 1], points[rows[i], 2]
        out[i, 0], out[i, 1], out[i, 2] = x, y, z
        if not reachable(x, y, z, cx, cz, box):
            rays[i, 4], rays[i, 5] = SOFT_BAND, 0.0
            continue
        u, w, exit_, length, near, fade, argument = ray(x, y, z, cx, cz, a, b, bottom, top)
        rays[i, 0], rays[i, 1], rays[i, 2], rays[i, 3], rays[i, 4], rays[i, 5] = u, w, exit_, length, near, fade
        if not near >= SOFT_BAND:
            arguments[eased] = argument
            eased += 1
    return eased


@numba.njit([numba.boolean(READ1, READ2, READ1, WRITE2)], cache=True, error_model="numpy")
def _pushed_out(shape, rays, rise, out):  # noqa: ANN001, ANN202
    """Into ``out`` (the points): :func:`kept_out_of_torso`'s last steps from
    :func:`_torso_rays` and numpy's exponentials ``rise`` of its arguments; whether any
    point moved."""
    cx, cz, a, b = shape[0], shape[1], shape[2], shape[3]
    moved = False
    used = 0
    for i in range(rays.shape[0]):
        u, w, exit_, length, near, fade = rays[i, 0], rays[i, 1], rays[i, 2], rays[i, 3], rays[i, 4], rays[i, 5]
        if near >= SOFT_BAND:
            continue
        eased = eased_gap(near, rise[used])
        used += 1
        if not (eased > near and fade > 0.0):
            continue
        moved = True
        out[i, 0], out[i, 2] = landed(u, w, exit_, length, near, fade, eased, cx, cz, a, b)
    return moved


def hand_push_out_of_torso(avatar: Avatar, side: str, wrists: np.ndarray, hands: np.ndarray) -> np.ndarray:
    """How far ``(n, 3)`` (m) each wrist ``(n, 3)`` (trunk frame), once
    :func:`kept_out_of_torso` has kept it out, must move further for the whole hand on
    ``side``, turned by global rotations ``hands`` ``(n, 4)``, to stay out too; zeros where
    it need not. A wrist clear of the torso may still carry the palm into it (fingers
    pointing back at the body as the hand turns on its way down to rest:
    ``41_tanedila_welle``'s left hand went 2.9 cm into the hip).

    Points along the hand capsule's axis (:data:`HAND_AXIS_SAMPLES`) are kept out of the
    torso grown by the capsule's radius (:func:`kept_out_of_torso`, continuous in
    position); the wrist moves by their pushes averaged with weights growing as the
    push's eighth power (the deepest point's push, blended continuously where two points
    are as deep, so that the wrist does not jump as the deepest point changes), twice.
    Only the wrists within a hand's length of the torso's box are kept out and looked at."""
    ends, shape, bounds = _hand_torso(avatar, side)
    rows = np.ascontiguousarray(wrists, dtype=float)
    push = np.zeros((len(rows), 3))
    near = np.empty(len(rows), dtype=np.int64)
    near = near[: near_rows(rows, bounds, near)]
    if near.size == 0:
        return push
    kept = np.empty((near.size, 3))
    _kept_out(rows, near, _torso_shape(avatar, TORSO_MARGIN), kept)
    cleared = _hand_out_of_torso(ends, shape, kept, np.ascontiguousarray(hands, dtype=float), near)
    if cleared is not None:
        hand_pushes(near, cleared, kept, push)
    return push


@functools.lru_cache(maxsize=32)
def _hand_torso(avatar: Avatar, side: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """What :mod:`motor.body.torso_push` takes of the hand on ``side`` and the torso: the
    hand capsule's end points less the wrist at rest ``(2, 3)``; the torso grown by the
    capsule's radius (centre x and z, half width and half depth, bottom and top); and
    the bounds of the wrists whose hand can come near the torso (within a hand's length
    and a slack of its box, or behind it: :func:`motor.body.torso_push.near_rows`)."""
    capsule = avatar.collision.arm(side, "hand")
    torso = avatar.torso
    wrist_rest = avatar.rest_positions[avatar.joint_index(f"{side}_wrist")]
    ends = np.stack((capsule.a - wrist_rest, capsule.b - wrist_rest))
    shape = np.array([torso.center[0], torso.center[2], torso.half_width + capsule.radius, torso.half_depth + capsule.radius, torso.bottom, torso.top])
    slack = TORSO_MARGIN + SOFT_BAND
    reach = float(np.linalg.norm(capsule.b - capsule.a)) + 2.0 * capsule.radius + SOFT_BAND + _HAND_REACH_SLACK + slack
    bounds = np.array([torso.center[0], torso.half_width + reach, torso.bottom - reach - EDGE_BAND, torso.top + reach + EDGE_BAND, torso.center[2] + torso.half_depth + reach])
    for frozen in (ends, shape, bounds):
        frozen.flags.writeable = False
    return ends, shape, bounds


def _hand_out_of_torso(ends: np.ndarray, shape: np.ndarray, kept: np.ndarray, hands: np.ndarray, hand_rows: np.ndarray) -> np.ndarray | None:
    """The rounds of :func:`hand_push_out_of_torso` on wrists ``kept`` ``(m, 3)`` already
    kept out of the torso, turned by the rows ``hand_rows`` of global hand rotations
    ``hands``, for a hand and the torso as :func:`_hand_torso` gives them (compiled:
    :mod:`motor.body.torso_push`): where they move; None when none moves."""
    kept = kept.copy()
    samples = HAND_AXIS_SAMPLES.size
    rows = np.arange(len(kept))
    reached, pushed = np.empty(rows.size, dtype=np.int64), np.empty(rows.size, dtype=np.int64)
    table, arguments = np.empty((rows.size * samples, HAND_COLUMNS)), np.empty(rows.size * samples)
    pushes, ratios = np.empty((rows.size * samples, 3)), np.empty(rows.size * samples)
    moved = False
    for _ in range(_HAND_ROUNDS):
        near, eased = hand_rays(kept, hands, rows, hand_rows, ends, HAND_AXIS_SAMPLES, shape, reached, table, arguments)
        if eased == 0:  # no point within the soft band: none moves
            break
        # numpy's exp and power between the loops: the compiled ones round some last bits otherwise
        moving = hand_depths(table[: near * samples], np.exp(arguments[:eased]), reached[:near], shape, pushes, ratios, pushed)
        if moving == 0:
            break
        rows = pushed[:moving].copy()
        hand_moved(rows, pushes, ratios[: moving * samples] ** 8, kept)
        moved = True
    return kept if moved else None


def inside_torso(avatar: Avatar, points: np.ndarray, margin: float = TORSO_MARGIN) -> np.ndarray:
    """Which wrist positions ``(n, 3)`` lie inside the torso grown by ``margin`` (m), or
    behind it within its width: with :data:`TORSO_MARGIN`, those :func:`outside_torso`
    places (and :func:`kept_out_of_torso` moves out: neither leaves one there)."""
    torso = avatar.torso
    a, b = torso.half_width + margin, torso.half_depth + margin
    dx = (points[:, 0] - torso.center[0]) / a
    front = torso.center[2] + b * np.sqrt(_clip01(1.0 - dx * dx))
    return (np.abs(dx) < 1.0) & (points[:, 2] < front) & (points[:, 1] > torso.bottom) & (points[:, 1] < torso.top)


def hand_segments(avatar: Avatar, side: str, wrists: np.ndarray, hands: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """End points ``(n, 3)`` of a hand's capsule for wrist positions and global hand
    rotations ``(n, 4)``."""
    ends = _hand_torso(avatar, side)[0]
    return wrists + quat.rotate(hands, ends[0]), wrists + quat.rotate(hands, ends[1])


def separate_hands(
    avatar: Avatar, left: np.ndarray, right: np.ndarray, left_hands: np.ndarray, right_hands: np.ndarray, allowance: float = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """Wrist positions ``(n, 3)`` of both arms moved apart where their hands would come
    closer than the palm thickness: the left wrist by :func:`hand_separation`, the right
    one as far the other way. Frame by frame: what the motor control does over time is
    :mod:`motor.body.hands_apart`."""
    half = hand_separation(avatar, left, right, left_hands, right_hands, allowance)
    if not np.any(half):
        return left, right
    return left + half, right - half


def hand_separation(
    avatar: Avatar, left: np.ndarray, right: np.ndarray, left_hands: np.ndarray, right_hands: np.ndarray, allowance: float = 0.0
) -> np.ndarray:
    """How far ``(n, 3)`` (m) the left wrist moves, and the right one the other way, where
    the hands of wrists ``left``, ``right`` ``(n, 3)`` turned by global rotations
    ``(n, 4)`` would come closer than the palm thickness (the distance of the hands'
    midlines when palm meets palm): half the deficit each, along the line between the
    hands' nearest points. Where the hands cross or coincide that line is tilted toward
    :func:`motor.body.hands_parting._parting`, which it becomes where they meet. Hands at least the thickness
    apart are not moved (a contact placed at the thickness stays as placed); nearer ones
    are eased apart in C² (module docstring, shifted) into :data:`motor.body.hands_parting.HAND_BAND` below it, so
    hands asked through each other bend apart without a speed or acceleration step as
    their gap changes and overlap at most that much. With an ``allowance`` (m) the
    thickness is taken that much smaller (a second look at hands already eased apart as
    asked)."""
    palm = avatar.collision.palm_thickness
    thickness = palm - allowance
    out = np.zeros((len(left), 3))
    near = np.flatnonzero(hands_may_meet(avatar, left, right))
    if near.size == 0:
        return out
    left, right = np.ascontiguousarray(left[near], dtype=float), np.ascontiguousarray(right[near], dtype=float)
    left_hands, right_hands = np.ascontiguousarray(left_hands[near], dtype=float), np.ascontiguousarray(right_hands[near], dtype=float)
    l0, l1 = hand_segments(avatar, "l", left, left_hands)
    r0, r1 = hand_segments(avatar, "r", right, right_hands)
    s, t = closest_parameters(l0, l1, r0, r1)
    table = np.empty((near.size, GAP_COLUMNS))
    if not gaps(l0, l1, r0, r1, s, t, thickness, table):
        return out
    rise = np.exp(table[:, EASE_ARGUMENT])
    capsule = avatar.collision.arm("r", "hand")
    constants = np.array([palm, thickness, float(np.linalg.norm(capsule.b - capsule.a)), *avatar.hand_frames["l"].palm_normal, *avatar.hand_frames["r"].palm_normal])
    parted = np.empty((near.size, 3))
    pushes(l0, l1, r0, r1, s, t, left, right, left_hands, right_hands, table, rise, constants, parted)
    out[near] = parted
    return out


def hands_may_meet(avatar: Avatar, left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """Which wrist positions ``(n, 3)`` are near enough for the hands to come within the
    palm thickness, whichever way the hands turn."""
    reach = max(float(np.linalg.norm(avatar.collision.arm(side, "hand").b - avatar.collision.arm(side, "hand").a)) for side in "lr")
    return quat.norm(left - right) < 2.0 * reach + avatar.collision.palm_thickness



def load_kernels() -> None:
    """Run this module's compiled loops once (they load when it is imported):
    :func:`motor.compiled.warm_up`."""
    shape, rays, out = np.array([0.0, 0.0, 0.2, 0.1, 0.0, 1.0]), np.zeros((1, _RAY_COLUMNS)), np.zeros((1, 3))
    eased = _torso_rays(np.zeros((1, 3)), np.zeros(1, dtype=np.int64), shape, out, rays, np.empty(1))
    _pushed_out(shape, rays, np.ones(eased), out)
