"""The sidecar JSON of a motion-capture clip of indicating verbs.

A BVH clip ``NAME.bvh`` (:mod:`mura.bvh`) comes with ``NAME.json`` beside it, saying which
performances the clip holds and when their keyframes are::

    {"format": "mura verb capture", "version": 1,
     "signer": "S1", "synthetic": false, "up": "y",
     "joints": {"right_hand": "RightHand", "left_hand": "LeftHand",
                "right_shoulder": "RightArm", "left_shoulder": "LeftArm"},
     "hand_rest": {"right": {"finger": [0, -1, 0], "palm": [1, 0, 0]}},
     "performances": [
        {"id": "give-1", "verb": "GIVE", "subject": -0.6, "object": 0.9, "keyframes": [0.40, 0.92]}]}

``up`` is the clip's vertical axis (``x``, ``y``, ``z``, optionally signed: ``-z``);
``joints`` names the wrist ("hand") and shoulder joints (default: the first of
:data:`JOINT_CANDIDATES` the clip has; a one-handed recording may lack the left hand);
``hand_rest`` optionally gives each hand's finger axis and palm normal in the clip's rest
pose (default: see :mod:`motor.verbs.capture`); keyframe times are seconds on the clip's
clock. A performance whose arc positions are outside [−1, 1], whose keyframes do not
increase or fall outside the clip, or whose verb needs a hand the clip lacks is refused
with the sidecar's file and the line where the performance starts; the others are kept.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mura.bvh import BvhClip, read_bvh
from mura.errors import SourceLocation, SpecError
from mura.recordings import MAX_KEYFRAMES, performance_lines

#: The ``format`` of a sidecar.
SIDECAR_FORMAT = "mura verb capture"
#: Joint names tried, in order, when the sidecar names none.
JOINT_CANDIDATES: dict[str, tuple[str, ...]] = {
    "right_hand": ("r_wrist", "RightHand", "RightWrist", "R_Wrist", "rhand"),
    "left_hand": ("l_wrist", "LeftHand", "LeftWrist", "L_Wrist", "lhand"),
    "right_shoulder": ("r_shoulder", "RightArm", "RightUpArm", "R_Shoulder", "rshoulder"),
    "left_shoulder": ("l_shoulder", "LeftArm", "LeftUpArm", "L_Shoulder", "lshoulder"),
}
_AXES = {"x": 0, "y": 1, "z": 2}


@dataclass(frozen=True)
class CapturedPerformance:
    """One performance of a clip: its arrangement and keyframe times (seconds)."""

    id: str
    verb: str
    subject: float | None
    object: float
    keyframes: tuple[float, ...]
    where: SourceLocation


@dataclass(frozen=True, eq=False)
class CaptureSession:
    """A clip and its sidecar: joint indices, axes, rest hand frames, performances.

    ``up`` is a unit vector in the clip's coordinates; ``hands`` maps ``right``/``left``
    to joint indices (the left hand may be absent); ``hand_rest`` holds the sidecar's
    ``(finger, palm)`` rest vectors per hand, where given.
    """

    clip: BvhClip
    sidecar: str
    signer: str
    synthetic: bool
    up: np.ndarray
    hands: Mapping[str, int]
    shoulders: tuple[int, int]
    hand_rest: Mapping[str, tuple[np.ndarray, np.ndarray]]
    performances: tuple[CapturedPerformance, ...]
    refused: tuple[SpecError, ...]


def sidecar_path(bvh: str | Path) -> Path:
    """Where the sidecar of a clip is: the same name with ``.json``."""
    return Path(bvh).with_suffix(".json")


def read_capture_session(bvh: str | Path) -> CaptureSession:
    """A clip and its sidecar, checked (module docstring); raises :class:`SpecError` when
    either cannot be used at all."""
    clip = read_bvh(bvh)
    path = sidecar_path(bvh)
    where = SourceLocation(str(path), 1, 1)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as error:
        raise SpecError(f"cannot read the clip's sidecar: {error.strerror or error}", SourceLocation(str(path))) from None
    try:
        document = json.loads(text)
    except json.JSONDecodeError as error:
        raise SpecError(f"not JSON: {error.msg}", SourceLocation(str(path), error.lineno, error.colno)) from None
    if not isinstance(document, dict) or document.get("format") != SIDECAR_FORMAT:
        raise SpecError(f'not a capture sidecar (expected "format": "{SIDECAR_FORMAT}")', where)
    up = _up_axis(str(document.get("up", "y")), where)
    joints = _joints(clip, dict(document.get("joints", {})), where)
    hand_rest = _hand_rest(dict(document.get("hand_rest", {})), where)
    entries = document.get("performances")
    if not isinstance(entries, list) or not entries:
        raise SpecError('"performances" must be a non-empty list', where)
    lines = performance_lines(text, len(entries))
    performances, refused = [], []
    for index, (entry, line) in enumerate(zip(entries, lines)):
        try:
            performances.append(_performance(entry, index, clip, SourceLocation(str(path), line, 1)))
        except SpecError as error:
            refused.append(error)
    hands = {hand: joints[f"{hand}_hand"] for hand in ("right", "left") if f"{hand}_hand" in joints}
    return CaptureSession(
        clip, str(path), str(document.get("signer", "")), bool(document.get("synthetic", False)), up, hands,
        (joints["right_shoulder"], joints["left_shoulder"]), hand_rest, tuple(performances), tuple(refused),
    )  # fmt: skip


def _up_axis(text: str, where: SourceLocation) -> np.ndarray:
    sign = -1.0 if text.startswith("-") else 1.0
    axis = text.lstrip("+-").lower()
    if axis not in _AXES:
        raise SpecError(f"up axis {text!r} is not x, y or z (optionally signed)", where)
    vector = np.zeros(3)
    vector[_AXES[axis]] = sign
    return vector


def _joints(clip: BvhClip, named: dict, where: SourceLocation) -> dict[str, int]:
    joints = {}
    for role, candidates in JOINT_CANDIDATES.items():
        name = named.get(role)
        if name is not None:
            if name not in clip.names:
                raise SpecError(f"joint {name!r} ({role}) is not in the clip {clip.file}", where)
            joints[role] = clip.names.index(name)
            continue
        found = next((c for c in candidates if c in clip.names), None)
        if found is not None:
            joints[role] = clip.names.index(found)
        elif role != "left_hand":
            raise SpecError(f"the clip has no {role.replace('_', ' ')} joint (tried {', '.join(candidates)}); name it in \"joints\"", where)
    return joints


def _hand_rest(entries: dict, where: SourceLocation) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    rest = {}
    for hand, item in entries.items():
        if hand not in ("right", "left") or not isinstance(item, dict):
            raise SpecError(f"hand_rest: {hand!r} is not right or left with finger and palm", where)
        try:
            finger, palm = np.asarray(item["finger"], dtype=float), np.asarray(item["palm"], dtype=float)
        except (KeyError, TypeError, ValueError):
            raise SpecError(f"hand_rest.{hand} needs finger and palm vectors", where) from None
        if finger.shape != (3,) or palm.shape != (3,) or np.linalg.norm(np.cross(finger, palm)) < 1e-6:
            raise SpecError(f"hand_rest.{hand}: finger and palm must be two non-parallel 3-vectors", where)
        rest[hand] = (finger, palm)
    return rest


def _performance(entry: object, index: int, clip: BvhClip, where: SourceLocation) -> CapturedPerformance:
    if not isinstance(entry, dict) or not isinstance(entry.get("verb"), str):
        raise SpecError(f"performance {index + 1} needs a verb", where)
    name = str(entry.get("id", f"#{index + 1}"))
    label = f"performance {name!r} ({entry['verb'].upper()})"
    positions = {}
    for key in ("subject", "object"):
        value = entry.get(key)
        if value is None and key == "subject":
            positions[key] = None
            continue
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise SpecError(f"{label}: {key} {value!r} is not a number", where)
        if not -1.0 <= value <= 1.0:
            raise SpecError(f"{label}: {key} arc position {value} is outside [-1, 1]", where)
        positions[key] = float(value)
    keys = entry.get("keyframes")
    if not isinstance(keys, list) or not all(isinstance(k, (int, float)) and not isinstance(k, bool) for k in keys):
        raise SpecError(f"{label}: keyframes must be a list of times (s)", where)
    if not 2 <= len(keys) <= MAX_KEYFRAMES or any(b <= a for a, b in zip(keys, keys[1:])):
        raise SpecError(f"{label}: keyframes {keys} must be 2 to {MAX_KEYFRAMES} increasing times", where)
    if keys[0] < 0 or keys[-1] > clip.duration + 1e-9:
        raise SpecError(f"{label}: keyframes {keys} fall outside the clip (0 … {clip.duration:.3f} s)", where)
    return CapturedPerformance(name, entry["verb"].upper(), positions["subject"], positions["object"], tuple(float(k) for k in keys), where)
