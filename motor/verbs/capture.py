"""Keyframes of indicating verbs from motion-capture clips: BVH kinematics on the clip's
own skeleton, normalised to the signer's body.

For each performance of a clip (:mod:`mura.capture`), the hands are located at its
keyframe times by forward kinematics of the BVH itself — its offsets and Euler channels
(intrinsic rotations in the listed order), frames interpolated linearly (positions) and by
slerp (rotations) between the two nearest — and expressed in the signer frame of
:mod:`mura.recordings`:

- everything is taken in the frame of the clip's root joint, so walking or turning does
  not move the hands (a bending spine does: that is signing);
- the origin is the midpoint of the shoulder joints at rest, the unit the distance
  between them at rest (the signer's shoulder width), y the clip's ``up`` axis, x from
  the right shoulder to the left one (made level), z = x × y (forward);
- orientation is the rotation from the canonical rest hand (fingers down, palm to the
  thigh) to the recorded hand. The clip's rest hand frame is the sidecar's ``hand_rest``,
  or else: the finger axis from the wrist to its child named ``middle…`` (else the mean of
  its children, else along the forearm); the palm normal toward the body's midline when
  the fingers hang (arms-down rest) and down otherwise (T-pose).

This kinematics shares no code with the avatar's (:mod:`motor.body.kinematics`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation, Slerp

from motor.verbs.arc import hand_orientation
from mura.bvh import BvhClip
from mura.capture import CaptureSession, read_capture_session
from mura.errors import SpecError
from mura.recordings import HandKeyframes, Performance, RecordingSession

_AXIS = {"X": 0, "Y": 1, "Z": 2}


def read_capture(bvh: str | Path) -> RecordingSession:
    """The performances of a clip and its sidecar as a recording session."""
    session = read_capture_session(bvh)
    performances, refused = [], list(session.refused)
    for captured in session.performances:
        try:
            performances.append(_performance(session, captured))
        except SpecError as error:
            refused.append(error)
    return RecordingSession(tuple(performances), tuple(refused), session.synthetic, f"{session.clip.file} (BVH capture, signer {session.signer or 'unnamed'})")


def local_transforms(clip: BvhClip, frames: np.ndarray) -> tuple[Rotation, np.ndarray]:
    """Each joint's local rotation ``(F·J)`` and translation ``(F, J, 3)`` at ``frames``."""
    values = clip.frames[frames]
    count, joints = values.shape[0], len(clip.names)
    translation = np.broadcast_to(clip.offsets, (count, joints, 3)).copy()
    rotations = []
    for joint, channels in enumerate(clip.channels):
        column = clip.first_column[joint]
        turns = [(name[0], column + i) for i, name in enumerate(channels) if name.endswith("rotation")]
        for i, name in enumerate(channels):
            if name.endswith("position"):
                translation[:, joint, _AXIS[name[0]]] += values[:, column + i]
        if turns:
            order = "".join(axis for axis, _ in turns)
            rotations.append(Rotation.from_euler(order, values[:, [c for _, c in turns]], degrees=True))
        else:
            rotations.append(Rotation.identity(count))
    return rotations, translation


def global_transforms(clip: BvhClip, frames: np.ndarray, root_fixed: bool = True) -> tuple[list[Rotation], np.ndarray]:
    """Each joint's global rotation and position ``(F, J, 3)``; with ``root_fixed`` the
    root's own motion is left out (the root's frame)."""
    local, translation = local_transforms(clip, frames)
    positions = np.zeros_like(translation)
    rotations: list[Rotation] = []
    for joint, parent in enumerate(clip.parents):
        if parent < 0:
            rotations.append(Rotation.identity(len(frames)) if root_fixed else local[joint])
            positions[:, joint] = 0.0 if root_fixed else translation[:, joint]
            continue
        rotations.append(rotations[parent] * local[joint])
        positions[:, joint] = positions[:, parent] + rotations[parent].apply(translation[:, joint])
    return rotations, positions


def _rest(clip: BvhClip) -> np.ndarray:
    """Joint positions at rest (all channels zero), in the root's frame."""
    positions = np.zeros((len(clip.names), 3))
    for joint, parent in enumerate(clip.parents):
        if parent >= 0:
            positions[joint] = positions[parent] + clip.offsets[joint]
    return positions


def _body_axes(session: CaptureSession, rest: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Columns (left, up, forward) in clip coordinates, the shoulder midpoint, the width."""
    right, left = rest[session.shoulders[0]], rest[session.shoulders[1]]
    width = float(np.linalg.norm(left - right))
    if width < 1e-9:
        raise SpecError("the shoulder joints coincide at rest; the clip cannot be normalised", session.performances[0].where)
    lateral = left - right
    lateral = lateral - (lateral @ session.up) * session.up
    lateral /= np.linalg.norm(lateral)
    return np.stack([lateral, session.up, np.cross(lateral, session.up)], axis=1), 0.5 * (left + right), width


def _rest_hand(session: CaptureSession, hand: str, rest: np.ndarray, axes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The hand's finger axis and palm normal at rest (clip coordinates)."""
    if hand in session.hand_rest:
        finger, palm = session.hand_rest[hand]
        return finger / np.linalg.norm(finger), palm / np.linalg.norm(palm)
    clip, joint = session.clip, session.hands[hand]
    children = clip.children(joint)
    middle = [c for c in children if "middle" in clip.names[c].lower()]
    if middle:
        finger = rest[middle[0]] - rest[joint]
    elif children:
        finger = np.mean([rest[c] for c in children], axis=0) - rest[joint]
    else:
        finger = rest[joint] - rest[clip.parents[joint]]
    finger = finger / np.linalg.norm(finger)
    hanging = abs(finger @ session.up) > 0.7
    inward = axes[:, 0] if hand == "right" else -axes[:, 0]
    return finger, inward if hanging else -session.up


def _performance(session: CaptureSession, captured) -> Performance:
    clip = session.clip
    missing = [h for h in ("right",) if h not in session.hands]
    if missing:
        raise SpecError(f"performance {captured.id!r}: the clip has no right hand", captured.where)
    rest = _rest(clip)
    axes, centre, width = _body_axes(session, rest)
    times = np.asarray(captured.keyframes)
    position = times / clip.frame_time
    low = np.clip(np.floor(position).astype(int), 0, clip.frames.shape[0] - 1)
    high = np.minimum(low + 1, clip.frames.shape[0] - 1)
    fraction = position - low
    rotations, positions = global_transforms(clip, np.concatenate([low, high]))
    count = times.shape[0]
    hands = {}
    for hand, joint in session.hands.items():
        lerped = positions[:count, joint] * (1.0 - fraction[:, None]) + positions[count:, joint] * fraction[:, None]
        pairs = rotations[joint]
        turns = Rotation.concatenate([Slerp([0.0, 1.0], Rotation.concatenate([pairs[k], pairs[count + k]]))([fraction[k]]) for k in range(count)])
        finger, palm = _rest_hand(session, hand, rest, axes)
        location = (lerped - centre) @ axes / width
        orientation = hand_orientation(turns.apply(finger) @ axes, turns.apply(palm) @ axes, hand)
        if not (np.all(np.isfinite(location)) and np.all(np.isfinite(orientation))):
            raise SpecError(f"performance {captured.id!r}: the {hand} hand's kinematics are not finite", captured.where)
        hands[hand] = HandKeyframes(location, orientation)
    return Performance(captured.id, captured.verb, session.signer, captured.subject, captured.object, times - times[0], hands, captured.where)
