"""The numpy steps of :func:`motor.body.collision.kept_out_of_torso`,
:func:`motor.body.collision.hand_separation` and
:func:`motor.body.collision.hand_push_out_of_torso` as they stood before they were
compiled (issue 19): the plain paths the compiled loops are held to, bit for bit, by
``test_compiled_torso.py``, ``test_compiled_hands_parting.py`` and
``test_compiled_hand_torso.py``. Not used by mura itself."""

from __future__ import annotations

import numpy as np

from motor import quaternion as quat
from motor.body.avatar import Avatar
from motor.body.collision import _HAND_REACH_SLACK, _HAND_ROUNDS, HAND_AXIS_SAMPLES, TORSO_MARGIN, hands_may_meet
from motor.body.distance import closest_parameters
from motor.body.hands_parting import _CROSSED_WAY, _PREFERRED, CROSSING_SINE, END_SHARE, HAND_BAND
from motor.body.torso_push import EDGE_BAND, LANDED as _LANDED, RAY_DEPTH, SOFT_BAND, TINY as _TINY


def kept_out_of_torso(avatar: Avatar, points: np.ndarray, margin: float = TORSO_MARGIN) -> np.ndarray:
    torso = avatar.torso
    a, b = torso.half_width + margin, torso.half_depth + margin
    u = (points[:, 0] - torso.center[0]) / a
    w = (points[:, 2] - torso.center[2]) / b + RAY_DEPTH
    square = u * u + w * w
    disc = (RAY_DEPTH * w) ** 2 - square * (RAY_DEPTH**2 - 1.0)
    exit_ = (RAY_DEPTH * w + np.sqrt(np.maximum(disc, 0.0))) / np.maximum(square, _TINY)
    length = np.sqrt((u * a) ** 2 + (w * b) ** 2)
    gap = np.where((disc > 0.0) & (w > 0.0), (1.0 - exit_) * length, np.inf)
    fade = _fade(torso.bottom - points[:, 1]) * _fade(points[:, 1] - torso.top)
    near = np.minimum(gap, SOFT_BAND)
    eased = np.maximum(_eased(near, SOFT_BAND), _LANDED)
    moved = (eased > near) & (fade > 0.0)
    if not np.any(moved):
        return points
    beyond = fade * eased + (1.0 - fade) * near
    out = np.array(points, dtype=float)
    out[:, 0] = np.where(moved, torso.center[0] + (u * exit_ * a) + beyond * u * a / np.maximum(length, _TINY), out[:, 0])
    out[:, 2] = np.where(moved, torso.center[2] + (w * exit_ - RAY_DEPTH) * b + beyond * w * b / np.maximum(length, _TINY), out[:, 2])
    return out


def hand_push_out_of_torso(avatar: Avatar, side: str, wrists: np.ndarray, hands: np.ndarray) -> np.ndarray:
    """The numpy steps."""
    push = np.zeros((len(wrists), 3))
    near = _near_torso(avatar, side, wrists, TORSO_MARGIN + SOFT_BAND)
    if near.size == 0:
        return push
    kept = kept_out_of_torso(avatar, wrists[near])
    cleared = hand_out_of_torso(avatar, side, kept, hands[near])
    if cleared is not None:
        push[near] = cleared - kept
    return push


def _near_torso(avatar: Avatar, side: str, wrists: np.ndarray, slack: float = 0.0) -> np.ndarray:
    """The numpy steps."""
    capsule = avatar.collision.arm(side, "hand")
    torso = avatar.torso
    reach = float(np.linalg.norm(capsule.b - capsule.a)) + 2.0 * capsule.radius + SOFT_BAND + _HAND_REACH_SLACK + slack
    return np.flatnonzero(
        (np.abs(wrists[:, 0] - torso.center[0]) < torso.half_width + reach)
        & (wrists[:, 1] > torso.bottom - reach - EDGE_BAND)
        & (wrists[:, 1] < torso.top + reach + EDGE_BAND)
        & (wrists[:, 2] < torso.center[2] + torso.half_depth + reach)
    )


def hand_out_of_torso(avatar: Avatar, side: str, kept: np.ndarray, turns: np.ndarray) -> np.ndarray | None:
    """The numpy steps."""
    radius = avatar.collision.arm(side, "hand").radius
    rows = np.arange(len(kept))
    kept = np.array(kept, dtype=float)
    moved = False
    for _ in range(_HAND_ROUNDS):
        start, end = hand_segments(avatar, side, kept[rows], turns[rows])
        points = start[:, None, :] + HAND_AXIS_SAMPLES[None, :, None] * (end - start)[:, None, :]
        flat = points.reshape(-1, 3)
        push = (kept_out_of_torso(avatar, flat, radius) - flat).reshape(points.shape)
        depth = np.linalg.norm(push, axis=2)
        deepest = depth.max(axis=1)
        pushed = deepest > 0.0
        if not np.any(pushed):
            break
        weight = (depth[pushed] / deepest[pushed, None]) ** 8
        rows = rows[pushed]
        kept[rows] += np.einsum("nk,nkd->nd", weight, push[pushed]) / np.maximum(weight.sum(axis=1), 1.0)[:, None]
        moved = True
    return kept if moved else None


def hand_segments(avatar: Avatar, side: str, wrists: np.ndarray, hands: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The numpy steps."""
    capsule = avatar.collision.arm(side, "hand")
    wrist_rest = avatar.rest_positions[avatar.joint_index(f"{side}_wrist")]
    return wrists + quat.rotate(hands, capsule.a - wrist_rest), wrists + quat.rotate(hands, capsule.b - wrist_rest)


def hand_separation(
    avatar: Avatar, left: np.ndarray, right: np.ndarray, left_hands: np.ndarray, right_hands: np.ndarray, allowance: float = 0.0
) -> np.ndarray:
    """The numpy steps."""
    palm = avatar.collision.palm_thickness
    thickness = palm - allowance
    out = np.zeros((len(left), 3))
    near = np.flatnonzero(hands_may_meet(avatar, left, right))
    if near.size == 0:
        return out
    l0, l1 = hand_segments(avatar, "l", left[near], left_hands[near])
    r0, r1 = hand_segments(avatar, "r", right[near], right_hands[near])
    s, t = closest_parameters(l0, l1, r0, r1)
    between = (l0 + s[:, None] * (l1 - l0)) - (r0 + t[:, None] * (r1 - r0))
    gap = quat.norm(between) - thickness
    if not np.any(gap < 0.0):
        return out
    eased = _eased(gap + HAND_BAND, HAND_BAND) - HAND_BAND
    # where the hands (nearly) pass through each other, the line between them means little:
    # tilt it toward the way they part
    meeting = np.maximum(1.0 - quat.norm(between) / (0.5 * palm), 0.0)[:, None]
    length = float(np.linalg.norm(avatar.collision.arm("r", "hand").b - avatar.collision.arm("r", "hand").a))
    direction = between + 0.25 * palm * meeting * _parting(l1 - l0, r1 - r0, left[near] - right[near], s, t, length)
    crossed = _crossed(avatar, left[near, 0] - right[near, 0], left_hands[near], right_hands[near])
    direction[:, 0] *= 1.0 - crossed
    # the side the hands are on already, else (where they are level) the left one below
    level = np.maximum(1.0 - np.abs(direction[:, 1]) / (0.25 * palm), 0.0)
    direction += (0.25 * palm * crossed * level)[:, None] * _CROSSED_WAY
    direction = direction / np.maximum(quat.norm(direction), _TINY)[:, None]
    # how far along that way the hands part to be ``eased`` beyond the thickness
    along = np.einsum("ij,ij->i", between, direction)
    wanted = eased + thickness
    push = np.sqrt(np.maximum(along * along - quat.norm(between) ** 2 + wanted * wanted, 0.0)) - along
    out[near] = (0.5 * push)[:, None] * direction
    return out

def _crossed(avatar: Avatar, spread: np.ndarray, left_hands: np.ndarray, right_hands: np.ndarray) -> np.ndarray:
    """The numpy steps."""
    palm = avatar.collision.palm_thickness
    normals = (quat.rotate(hands, avatar.hand_frames[side].palm_normal) for side, hands in (("l", left_hands), ("r", right_hands)))
    facing = 0.5 * sum(np.abs(normal[:, 0]) for normal in normals)
    u = np.clip((spread + palm * (0.5 + 0.5 * facing)) / (palm * (2.0 - facing)), 0.0, 1.0)
    return 1.0 - u * u * (3.0 - 2.0 * u)

def _parting(left: np.ndarray, right: np.ndarray, apart: np.ndarray, s: np.ndarray, t: np.ndarray, length: float) -> np.ndarray:
    """The numpy steps."""
    across = quat.cross(left, right)
    sine = quat.norm(across) / np.maximum(quat.norm(left) * quat.norm(right), _TINY)
    across = across * np.where(across @ _PREFERRED >= 0.0, 1.0, -1.0)[:, None]
    across = across / np.maximum(quat.norm(across), _TINY)[:, None]
    weight = np.minimum(np.maximum(sine / CROSSING_SINE, 0.0), 1.0)[:, None]
    parting = weight * across + (1.0 - weight) * np.array([1.0, 0.0, 0.0])
    spread = quat.norm(apart)
    drawn = (_smooth_ramp(np.minimum(s, t), END_SHARE) * _smooth_ramp(spread / length, END_SHARE))[:, None]
    parting = drawn * apart / np.maximum(spread, _TINY)[:, None] + (1.0 - drawn) * parting
    return parting / np.maximum(quat.norm(parting), _TINY)[:, None]

def _smooth_ramp(value: np.ndarray, edges: tuple[float, float]) -> np.ndarray:
    """The numpy steps."""
    u = np.minimum(np.maximum((value - edges[0]) / (edges[1] - edges[0]), 0.0), 1.0)
    return u * u * (3.0 - 2.0 * u)


def _eased(gap: np.ndarray, band: float) -> np.ndarray:
    """The numpy steps."""
    rise = np.exp(2.0 * (np.minimum(gap, band) / band - 1.0))  # 1 + tanh(x) = 2 e^2x / (1 + e^2x), > 0
    return np.where(gap >= band, gap, 2.0 * band * rise / (1.0 + rise))


def _fade(beyond: np.ndarray) -> np.ndarray:
    """The numpy steps."""
    u = np.minimum(np.maximum(beyond / EDGE_BAND, 0.0), 1.0)
    return 1.0 - u * u * (3.0 - 2.0 * u)
