"""Wrist positions placed so that the whole hand, not only the wrist, stays out of the torso.

Sign planning keeps every wrist position a margin in front of the torso
(:func:`motor.body.collision.outside_torso`), but the hand reaches a palm's length beyond
the wrist: a hand whose fingers point back at the chest (``hamextfingeri`` at the neck,
or the fingers sweeping down past the chest while the hand turns on its way up from rest)
sinks its palm into the body although the wrist is clear. :func:`hands_clear_of_torso`
moves such wrist positions forward — as :func:`outside_torso` moves wrists — by the least
amount that puts the avatar's hand capsule (wrist to the middle finger's knuckle, as
thick as the palm; :mod:`motor.body.volumes`) in front of the torso's elliptic cylinder
with :data:`HAND_CLEARANCE` to spare. A hand that touches the chest with its palm, as
the sign says, keeps its place: its capsule lies in front of the surface already.

The torso is the avatar's trunk at rest — its ``torso`` collision volume and its
``chest`` where it has one (the signs are planned on the body at rest). Points of the capsule are checked at :data:`CAPSULE_SAMPLES` along
its axis, each as a sphere of the capsule's radius: a sphere lies clear of the vertical
cylinder when its centre lies outside the cylinder grown by the radius (and the
clearance), or above or below it by more than that. Pushing along +z keeps each point's
height and side, so the push that clears the deepest sample clears them all.
"""

from __future__ import annotations

import numpy as np

from motor.body.avatar import Avatar
from motor.body.collision import hand_segments
from motor.body.torso_push import LANDED
from motor.body.volumes import EllipticCylinder

#: Space (m) left between the hand's capsule and the torso's surface.
HAND_CLEARANCE = 0.008
#: Fractions of the hand capsule's axis (wrist 0, knuckles 1) checked against the torso.
CAPSULE_SAMPLES = np.linspace(0.0, 1.0, 5)


def trunk_cylinders(avatar: Avatar) -> tuple[EllipticCylinder, ...]:
    """The avatar's trunk collision volumes (elliptic cylinders: the torso, and the chest where there is one)."""
    trunk = avatar.collision.trunk()
    for volume in trunk:
        if not isinstance(volume, EllipticCylinder):
            raise TypeError(f"avatar {avatar.name!r}: the {volume.name} collision volume must be an elliptic cylinder to plan hands against it")
    return trunk  # type: ignore[return-value]


def hand_torso_push(avatar: Avatar, side: str, wrists: np.ndarray, rotations: np.ndarray, clearance: float = HAND_CLEARANCE) -> np.ndarray:
    """How far (m, ``(n,)``, ≥ 0) each wrist position ``(n, 3)`` must move forward (+z) for
    the hand on ``side`` in global rotation ``(n, 4)`` to lie ``clearance`` in front of the
    torso (module docstring); 0 where it does already."""
    wrists = np.asarray(wrists, dtype=float).reshape(-1, 3)
    if wrists.shape[0] == 0:
        return np.zeros(0)
    capsule = avatar.collision.arm(side, "hand")
    grow = capsule.radius + clearance
    push = np.zeros(wrists.shape[0])
    # only wrists within the hand's reach of the grown torso can have a hand in it
    rest = avatar.rest_positions[avatar.joint_index(f"{side}_wrist")]
    reach = grow + max(float(np.linalg.norm(capsule.a - rest)), float(np.linalg.norm(capsule.b - rest)))
    trunk = trunk_cylinders(avatar)
    near = np.logical_or.reduce([_within_box(cylinder, wrists, reach) for cylinder in trunk])
    if not np.any(near):
        return push
    start, end = hand_segments(avatar, side, wrists[near], np.asarray(rotations, dtype=float).reshape(-1, 4)[near])
    points = start[:, None, :] + CAPSULE_SAMPLES[None, :, None] * (end - start)[:, None, :]
    for cylinder in trunk:
        push[near] = np.maximum(push[near], _push_out(cylinder, points, grow))
    return push


def _push_out(torso: EllipticCylinder, points: np.ndarray, grow: float) -> np.ndarray:
    """How far (m, ``(n,)``, ≥ 0) points ``(n, k, 3)`` must move forward (+z) for every
    point of each row to lie ``grow`` in front of the cylinder (or beside, above or below it)."""
    width, depth = torso.half_width + grow, torso.half_depth + grow
    across = (points[..., 0] - torso.center[0]) / width
    front = torso.center[2] + depth * np.sqrt(np.maximum(1.0 - across * across, 0.0))
    level = (points[..., 1] > torso.bottom - grow) & (points[..., 1] < torso.top + grow)
    needed = np.where(level & (np.abs(across) < 1.0), front - points[..., 2], 0.0)
    return np.maximum(needed.max(axis=1), 0.0)


def _within_box(torso: EllipticCylinder, points: np.ndarray, reach: float) -> np.ndarray:
    """Which points ``(n, 3)`` lie within ``reach`` (m) of the torso's bounding box (or
    behind it): the only wrists whose hand can touch it."""
    return (
        (np.abs(points[:, 0] - torso.center[0]) < torso.half_width + reach)
        & (points[:, 1] > torso.bottom - reach)
        & (points[:, 1] < torso.top + reach)
        & (points[:, 2] < torso.center[2] + torso.half_depth + reach)
    )


def hands_clear_of_torso(avatar: Avatar, side: str, wrists: np.ndarray, rotations: np.ndarray, clearance: float = HAND_CLEARANCE) -> np.ndarray:
    """Wrist positions ``(n, 3)`` moved forward where the hand on ``side`` (global rotations
    ``(n, 4)``) would enter the torso (:func:`hand_torso_push`); the others unchanged (the
    same array when none moves). Idempotent."""
    push = hand_torso_push(avatar, side, wrists, rotations, clearance)
    if not np.any(push > 0.0):
        return wrists
    out = np.array(wrists, dtype=float).reshape(-1, 3)
    out[:, 2] += np.where(push > 0.0, push + LANDED, 0.0)
    return out
