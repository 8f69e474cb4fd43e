"""Which way a hand turns from one global rotation to another.

Two rotations are joined by two arcs about the same axis: the short one (angle θ ≤ π)
and the long one the other way round (2π − θ). A hand raised with the fingers up and
lowered to rest with the fingers down turns about half a turn either way; the short arc,
which a plain slerp takes, may sweep the fingers back toward the body, which no wrist
reaches: the arm then gives the hand another turn than the one asked, and
``ignore``'s right hand went 1.2 cm into the hip on its way to rest. A person lowering
the hand keeps the fingers ahead.

:func:`turn_way` takes the arc of least cost: its angle (radians) plus
:data:`BACKWARD_WEIGHT` times the mean square of how far the fingers point backward
(the negative part of the finger axis's forward component) at :data:`ARC_SAMPLES`
points along it. Short turns keep the short arc (the long one is longer by more than the
weight can pay for); near a half turn the fingers decide.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence

import numpy as np

from motor import quaternion as quat
from motor.body.avatar import Avatar, check_side

#: Radians of turn that fingers pointing straight back all along an arc cost.
BACKWARD_WEIGHT = 0.5 * np.pi
#: Points along each arc at which the fingers are looked at (ends included).
ARC_SAMPLES = 9
_FORWARD = 2  # the avatar frame's z axis points forward


def turn_way(avatar: Avatar, side: str, before: np.ndarray, after: np.ndarray, fractions: np.ndarray) -> np.ndarray:
    """Global hand rotations ``(k, 4)`` at ``fractions`` ``(k,)`` (0 at ``before``, 1 at
    ``after``) of the turn of the hand on ``side`` between two global rotations ``(4,)``,
    along the arc of least cost (module docstring). At fraction 1 the rotation is
    ``after`` up to sign."""
    return turn_ways(avatar, side, [before], [after], [fractions])


def turn_ways(avatar: Avatar, side: str, befores: Sequence[np.ndarray], afters: Sequence[np.ndarray], fractions: Sequence[np.ndarray]) -> np.ndarray:
    """:func:`turn_way` of many turns, their rotations one after another ``(Σk, 4)``: each
    arc found (and remembered) on its own, the rotations along all of them in one
    vectorized pass — the very numbers of turning one at a time (a sequence of signs turns
    its hands in every transition)."""
    counts = [len(part) for part in fractions]
    if not counts:
        return np.empty((0, 4))
    arcs = [_arc(avatar, side, before, after) for before, after in zip(befores, afters)]
    axes = np.repeat(np.array([axis for axis, _ in arcs]), counts, axis=0)
    angles = np.repeat(np.array([turn for _, turn in arcs]), counts) * np.concatenate([np.asarray(part, dtype=float) for part in fractions])
    return quat.multiply(quat.from_axis_angle(axes, angles), np.repeat(np.asarray(befores, dtype=float).reshape(-1, 4), counts, axis=0))


def turn_vector(avatar: Avatar, side: str, before: np.ndarray, after: np.ndarray) -> np.ndarray:
    """The turn of :func:`turn_way` as a rotation vector ``(3,)`` (radians) in the hand's
    own frame at ``before``: ``before · exp(s · vector)`` runs along the arc of least cost
    as ``s`` goes from 0 to 1."""
    axis, turn = _arc(avatar, side, before, after)
    return quat.rotate(quat.conjugate(np.asarray(before, dtype=float)), axis) * turn


def takes_long_way(avatar: Avatar, side: str, before: np.ndarray, after: np.ndarray) -> bool:
    """Whether :func:`turn_way` turns the hand the long way round (more than half a turn),
    which a slerp between the two rotations would not."""
    return abs(_arc(avatar, side, before, after)[1]) > np.pi


def _arc(avatar: Avatar, side: str, before: np.ndarray, after: np.ndarray) -> tuple[np.ndarray, float]:
    """The axis ``(3,)`` and signed angle (radians) of the arc of least cost."""
    before, after = np.asarray(before, dtype=float), np.asarray(after, dtype=float)
    axis, turn = _remembered_arc(avatar, side, before.tobytes(), after.tobytes())
    return axis.copy(), turn


@functools.lru_cache(maxsize=8192)
def _remembered_arc(avatar: Avatar, side: str, before_bytes: bytes, after_bytes: bytes) -> tuple[np.ndarray, float]:
    """:func:`_arc` of rotations given by their bytes: signs turn the hand between the same
    few orientations over and over (a corpus: about five times per pair), and the arc
    depends on the two rotations and the avatar's hand only."""
    before, after = np.frombuffer(before_bytes), np.frombuffer(after_bytes)
    axis, angle = _relative_axis_angle(before, after)
    if angle == 0.0:
        return axis, 0.0
    along = np.linspace(0.0, 1.0, ARC_SAMPLES)
    finger = avatar.hand_frames[check_side(side)].finger_axis
    costs = []
    for turn in (angle, angle - 2.0 * np.pi):
        fingers = quat.rotate(_along_arc(before, axis, turn, along), finger[None])
        backward = np.maximum(-fingers[:, _FORWARD], 0.0)
        costs.append(abs(turn) + BACKWARD_WEIGHT * float(np.mean(backward * backward)))
    return axis, (angle if costs[0] <= costs[1] else angle - 2.0 * np.pi)


def _relative_axis_angle(before: np.ndarray, after: np.ndarray) -> tuple[np.ndarray, float]:
    """Unit axis ``(3,)`` and angle (radians, within [0, π]) of the global turn
    ``after · before⁻¹``; an arbitrary axis for no turn."""
    relative = quat.multiply(np.asarray(after, dtype=float), quat.conjugate(np.asarray(before, dtype=float)))
    if relative[3] < 0.0:
        relative = -relative
    sine = float(np.linalg.norm(relative[:3]))
    angle = 2.0 * float(np.arctan2(sine, relative[3]))
    if sine < 1e-12:
        return np.array([1.0, 0.0, 0.0]), 0.0
    return relative[:3] / sine, angle


def _along_arc(before: np.ndarray, axis: np.ndarray, turn: float, fractions: np.ndarray) -> np.ndarray:
    """``before`` turned about ``axis`` (global) by ``turn · fractions`` radians ``(k, 4)``."""
    return quat.multiply(quat.from_axis_angle(axis, turn * fractions), np.asarray(before, dtype=float)[None])
