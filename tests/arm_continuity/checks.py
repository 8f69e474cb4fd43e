"""Simple checks of rendered arm motion, written apart from the synthesis.

Every figure comes from the rendered local joint rotations through forward kinematics
(``motor.body.kinematics``) and plain geometry written here: joint positions sampled
along the segments, the torso as the avatar's elliptic cylinder, arm segments as
segments with a radius. Nothing here calls the IK, the swivel search or the collision
module, so the checks can catch what those get wrong.

Figures per motion (60 fps unless the motion says otherwise):

* ``pop_frames``: frames whose elbow moves faster than :data:`POP_SPEED` relative to its
  shoulder while more than twice as fast as the wrist (relative to the same shoulder);
* ``max_turn_deg``: the largest rotation of any arm joint (sternoclavicular, shoulder,
  elbow, wrist) between two frames, degrees; ``turns_over_limit``: frames above
  :data:`TURN_LIMIT_DEG`;
* ``torso_depth``: deepest point of an arm segment's surface (upper arm past its first
  quarter, forearm) inside the torso cylinder, carried with the chest (``vt6``), metres;
* ``arm_depth``: deepest overlap of one arm's segments (upper arm, forearm) with the
  other's, metres;
* ``palm_gap``: smallest distance between the two palms' midlines (wrist → middle
  knuckle) minus the palm thickness, metres (negative: the hands overlap);
* ``twist_wraps``: frames where the forearm's twist about its own axis changes by more
  than :data:`WRAP_DEG` degrees.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from motor.body.avatar import Avatar
from motor.body.kinematics import forward_kinematics
from motor.motion import Motion

#: Elbow speed (m/s, relative to the shoulder) above which a frame pops (with twice the wrist's).
POP_SPEED = 3.0
#: Largest rotation of a joint between two frames at 60 fps, degrees.
TURN_LIMIT_DEG = 25.0
#: A change of the forearm twist above this in one frame is a wrap, degrees.
WRAP_DEG = 90.0
#: Skin radius of the upper arm and forearm of a 1.80 m avatar (arm 0.58 m), metres;
#: scaled by arm length for other avatars.
UPPER_ARM_RADIUS = 0.04
FOREARM_RADIUS = 0.032
#: Fraction of the upper arm next to the shoulder that belongs to the shoulder's flesh,
#: and of the forearm from the elbow that is as thick as the forearm (toward the wrist it
#: narrows to the hand's thickness: hands touching palm to palm bring the wrists closer
#: than two forearm radii).
SHOULDER_PART = 0.25
FOREARM_PART = 0.85
#: Palm thickness of a 1.80 m avatar, metres (scaled like the radii).
PALM_THICKNESS = 0.03
_SAMPLES = np.linspace(0.0, 1.0, 9)
_ARM = ("sternoclavicular", "shoulder", "elbow", "wrist")


@dataclass(frozen=True)
class ArmFigures:
    frames: int
    pop_frames: int
    max_elbow_speed: float
    max_turn_deg: float
    turns_over_limit: int
    torso_depth: float
    arm_depth: float
    palm_gap: float
    twist_wraps: int


def figures(avatar: Avatar, motion: Motion) -> ArmFigures:
    """All figures of one motion (module docstring)."""
    pose = forward_kinematics(avatar, motion.rotations)
    scale = _arm_length(avatar) / 0.58
    joints = {side: {name: avatar.joint_index(f"{side}_{name}") for name in _ARM + ("middle1",)} for side in "lr"}
    at = {side: {name: pose.positions[:, index] for name, index in joints[side].items()} for side in "lr"}
    pops, elbow_speed = _pops(at, motion.fps)
    # the torso turns with the chest (the trunk may turn where a hand reaches across)
    chest = avatar.joint_index("vt6")
    rotation, position = pose.orientations[:, chest], pose.positions[:, chest]
    inverse = rotation * np.array([-1.0, -1.0, -1.0, 1.0])
    in_chest = {side: {name: _rotate(inverse, p - position) + avatar.rest_positions[chest] for name, p in at[side].items()} for side in "lr"}
    turns = _turns(avatar, motion)
    wraps = sum(int(np.sum(np.abs(np.diff(_twist(avatar, motion, side))) > np.radians(WRAP_DEG))) for side in "lr")
    return ArmFigures(
        frames=motion.frame_count,
        pop_frames=pops,
        max_elbow_speed=elbow_speed,
        max_turn_deg=float(np.degrees(turns.max(initial=0.0))),
        turns_over_limit=int(np.sum(turns.max(axis=1, initial=0.0) > np.radians(TURN_LIMIT_DEG))) if turns.size else 0,
        torso_depth=_torso_depth(avatar, in_chest, scale),
        arm_depth=_arm_depth(at, scale),
        palm_gap=_palm_gap(at, scale),
        twist_wraps=wraps,
    )


def _rotate(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Vectors ``(n, 3)`` rotated by unit quaternions ``(n, 4)`` (scalar last)."""
    u, w = q[:, :3], q[:, 3:4]
    t = 2.0 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


def _arm_length(avatar: Avatar) -> float:
    _, shoulder, elbow, wrist = (avatar.joint_index(f"r_{name}") for name in _ARM)
    return float(np.linalg.norm(avatar.offsets[elbow]) + np.linalg.norm(avatar.offsets[wrist]))


def _pops(at: dict, fps: float) -> tuple[int, float]:
    frames, fastest = 0, 0.0
    for side in "lr":
        shoulder = at[side]["shoulder"]
        elbow = np.linalg.norm(np.diff(at[side]["elbow"] - shoulder, axis=0), axis=1) * fps
        wrist = np.linalg.norm(np.diff(at[side]["wrist"] - shoulder, axis=0), axis=1) * fps
        frames += int(np.sum((elbow > POP_SPEED) & (elbow > 2.0 * wrist)))
        fastest = max(fastest, float(elbow.max(initial=0.0)))
    return frames, fastest


def _turns(avatar: Avatar, motion: Motion) -> np.ndarray:
    """Rotation angle (rad) of every arm joint between consecutive frames ``(n - 1, 8)``."""
    indices = [avatar.joint_index(f"{side}_{name}") for side in "lr" for name in _ARM]
    q = motion.rotations[:, indices]
    dot = np.abs(np.sum(q[1:] * q[:-1], axis=-1))
    return 2.0 * np.arccos(np.clip(dot, 0.0, 1.0))


def _twist(avatar: Avatar, motion: Motion, side: str) -> np.ndarray:
    """The elbow's rotation about the forearm's own axis, radians in (-π, π]."""
    elbow = motion.rotations[:, avatar.joint_index(f"{side}_elbow")]
    axis = avatar.offsets[avatar.joint_index(f"{side}_wrist")]
    axis = axis / np.linalg.norm(axis)
    projected = elbow[:, :3] @ axis
    return 2.0 * np.arctan2(projected, elbow[:, 3])


def _cylinder_depth(avatar: Avatar, points: np.ndarray) -> np.ndarray:
    """Radial depth (m) of points inside the torso's elliptic cylinder, 0 outside."""
    torso = avatar.torso
    offset = points - torso.center
    scaled = np.hypot(offset[..., 0] / torso.half_width, offset[..., 2] / torso.half_depth)
    radial = np.hypot(offset[..., 0], offset[..., 2])
    depth = radial * (1.0 / np.maximum(scaled, 1e-9) - 1.0)
    within = (points[..., 1] > torso.bottom) & (points[..., 1] < torso.top)
    return np.where(within & (scaled < 1.0), depth, 0.0)


def _torso_depth(avatar: Avatar, at: dict, scale: float) -> float:
    deepest = 0.0
    for side in "lr":
        s, e, w = at[side]["shoulder"], at[side]["elbow"], at[side]["wrist"]
        upper = s[:, None] + (SHOULDER_PART + (1 - SHOULDER_PART) * _SAMPLES)[None, :, None] * (e - s)[:, None]
        fore = e[:, None] + (FOREARM_PART * _SAMPLES)[None, :, None] * (w - e)[:, None]
        # a point whose axis is outside but within a radius of the surface also counts
        for points, radius in ((upper, UPPER_ARM_RADIUS * scale), (fore, FOREARM_RADIUS * scale)):
            grown = _grown_cylinder_depth(avatar, points, radius)
            deepest = max(deepest, float(grown.max(initial=0.0)))
    return deepest


def _grown_cylinder_depth(avatar: Avatar, points: np.ndarray, radius: float) -> np.ndarray:
    """Depth (m) of a sphere of ``radius`` about each point inside the torso cylinder,
    measured along the cylinder's radial direction (0 when it does not reach in)."""
    torso = avatar.torso
    offset = points - torso.center
    scaled = np.hypot(offset[..., 0] / torso.half_width, offset[..., 2] / torso.half_depth)
    radial = np.hypot(offset[..., 0], offset[..., 2])
    surface = radial / np.maximum(scaled, 1e-9)
    depth = surface - radial + radius
    within = (points[..., 1] > torso.bottom) & (points[..., 1] < torso.top)
    return np.where(within, np.clip(depth, 0.0, None), 0.0)


def segment_distance(p0: np.ndarray, p1: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """Shortest distance between segments p0–p1 and q0–q1, each ``(n, 3)``, by dense
    sampling of one and exact projection onto the other."""
    samples = np.linspace(0.0, 1.0, 41)
    points = p0[:, None] + samples[None, :, None] * (p1 - p0)[:, None]
    d = q1 - q0
    length2 = np.maximum(np.sum(d * d, axis=1), 1e-12)
    t = np.clip(np.sum((points - q0[:, None]) * d[:, None], axis=2) / length2[:, None], 0.0, 1.0)
    nearest = q0[:, None] + t[..., None] * d[:, None]
    return np.linalg.norm(points - nearest, axis=2).min(axis=1)


def _arm_depth(at: dict, scale: float) -> float:
    deepest = 0.0
    segments = {
        side: (
            (at[side]["shoulder"] + SHOULDER_PART * (at[side]["elbow"] - at[side]["shoulder"]), at[side]["elbow"], UPPER_ARM_RADIUS * scale),
            (at[side]["elbow"], at[side]["elbow"] + FOREARM_PART * (at[side]["wrist"] - at[side]["elbow"]), FOREARM_RADIUS * scale),
        )
        for side in "lr"
    }
    for a0, a1, ra in segments["l"]:
        for b0, b1, rb in segments["r"]:
            gap = segment_distance(a0, a1, b0, b1) - ra - rb
            deepest = max(deepest, float(-gap.min(initial=0.0)))
    return max(deepest, 0.0)


def _palm_gap(at: dict, scale: float) -> float:
    gap = segment_distance(at["l"]["wrist"], at["l"]["middle1"], at["r"]["wrist"], at["r"]["middle1"])
    return float(gap.min(initial=np.inf)) - PALM_THICKNESS * scale
