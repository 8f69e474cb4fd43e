"""The collision volumes the audit checks, from the avatar file or derived from the skeleton.

An avatar file's ``collision.volumes`` (the one definition agreed for mura: every volume
moves rigidly with its ``joint``; ``center``, ``a``, ``b`` in the avatar frame at rest) is
used as written. Any of the volumes the audit needs — :data:`TORSO` and, per side,
:data:`ARM_SEGMENTS` — that the file does not give is derived here, conservatively (on
the small side, so that what the audit reports as penetration is penetration):

* ``chest``: only where the file gives one; the trunk is then its ``torso`` (the abdomen)
  and its ``chest``, each carried by its own joint, and the torso group measures both.
* ``torso``: the legacy ``torso`` entry (an elliptic cylinder), carried by the joint the
  clavicles hang from (``vt1`` in H-Anim); without one, an elliptic cylinder as wide as
  :data:`TORSO_WIDTH_OF_SHOULDERS` of the shoulders' spread, :data:`TORSO_DEPTH_OF_WIDTH`
  as deep, from the root to the shoulders.
* ``{side}_upper_arm``: a capsule from :data:`UPPER_ARM_START` of the way down the bone
  (the flesh at the shoulder joint overlaps the chest in any body) to the elbow, radius
  :data:`UPPER_ARM_RADIUS` of the bone's length (3.4 cm on a 31 cm upper arm).
* ``{side}_forearm``: elbow to wrist, radius :data:`FOREARM_RADIUS` of its length.
* ``{side}_hand``: wrist to the middle finger's base joint, radius
  :data:`HAND_RADIUS` of that length — half the palm's thickness (1.3 cm on a 9.7 cm
  palm), so two hands touching palm to palm are 2.5 cm apart, not on one point.

Volumes of other shapes than capsules for the arm segments are replaced by the capsule
inscribed in them (axis along the longest semi-axis), so depths stay conservative.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bench.motion_audit.avatar_file import AvatarError, AvatarFile
from bench.motion_audit.distance import Capsule, Ellipsoid, EllipticCylinder, Shape
from bench.motion_audit.kinematics import Kinematics

TORSO = "torso"
CHEST = "chest"
ARM_SEGMENTS = ("upper_arm", "forearm", "hand")
SIDES = ("l", "r")
UPPER_ARM_START = 0.2
UPPER_ARM_RADIUS = 0.11
FOREARM_RADIUS = 0.09
HAND_RADIUS = 0.13
TORSO_WIDTH_OF_SHOULDERS = 0.75
TORSO_DEPTH_OF_WIDTH = 0.75


@dataclass(frozen=True)
class Volume:
    """A named shape (in the avatar frame at rest, metres) that moves with ``joint``;
    ``derived`` when the audit made it rather than the avatar file."""

    name: str
    joint: str
    shape: Shape
    derived: bool


def _vector(value: object, where: str) -> np.ndarray:
    array = np.asarray(value, dtype=float) if isinstance(value, list) else np.array([])
    if array.shape != (3,) or not np.all(np.isfinite(array)):
        raise AvatarError(f"{where}: expected three numbers, got {value!r}")
    return array


def _number(value: object, where: str, positive: bool = True) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value) or (positive and value <= 0):
        raise AvatarError(f"{where}: expected a {'positive ' if positive else ''}number, got {value!r}")
    return float(value)


def volume_from_entry(entry: object, where: str) -> Volume:
    """One entry of an avatar file's ``collision.volumes``; AvatarError naming the field."""
    if not isinstance(entry, dict):
        raise AvatarError(f"{where}: expected an object")
    name, joint, kind = entry.get("name"), entry.get("joint"), entry.get("shape")
    if not isinstance(name, str) or not isinstance(joint, str):
        raise AvatarError(f"{where}: 'name' and 'joint' must be strings")
    where = f"{where} ({name})"
    if kind == "capsule":
        shape: Shape = Capsule(_vector(entry.get("a"), f"{where}.a"), _vector(entry.get("b"), f"{where}.b"), _number(entry.get("radius"), f"{where}.radius"))
    elif kind == "ellipsoid":
        radii = _vector(entry.get("radii"), f"{where}.radii")
        if np.any(radii <= 0):
            raise AvatarError(f"{where}.radii: every semi-axis must be positive")
        shape = Ellipsoid(_vector(entry.get("center"), f"{where}.center"), radii)
    elif kind == "elliptic_cylinder":
        bottom = _number(entry.get("bottom"), f"{where}.bottom", positive=False)
        top = _number(entry.get("top"), f"{where}.top", positive=False)
        if top <= bottom:
            raise AvatarError(f"{where}: 'top' ({top}) must be above 'bottom' ({bottom})")
        shape = EllipticCylinder(
            _vector(entry.get("center"), f"{where}.center"),
            _number(entry.get("half_width"), f"{where}.half_width"),
            _number(entry.get("half_depth"), f"{where}.half_depth"),
            bottom,
            top,
        )
    else:
        raise AvatarError(f"{where}: unknown shape {kind!r} (expected capsule, ellipsoid or elliptic_cylinder)")
    return Volume(name=name, joint=joint, shape=shape, derived=False)


def inscribed_capsule(shape: Shape) -> Capsule:
    """The shape itself if a capsule, else the capsule inside it along its longest axis."""
    if isinstance(shape, Capsule):
        return shape
    if isinstance(shape, Ellipsoid):
        longest = int(np.argmax(shape.radii))
        radius = float(np.min(np.delete(shape.radii, longest)))
        reach = np.zeros(3)
        reach[longest] = max(float(shape.radii[longest]) - radius, 0.0)
        return Capsule(shape.center - reach, shape.center + reach, radius)
    radius = min(shape.half_width, shape.half_depth)
    middle = np.array([shape.center[0], 0.5 * (shape.bottom + shape.top), shape.center[2]])
    reach = np.array([0.0, max(0.5 * (shape.top - shape.bottom) - radius, 0.0), 0.0])
    return Capsule(middle - reach, middle + reach, radius)


def _derived_torso(avatar: AvatarFile, kinematics: Kinematics) -> Volume:
    carrier = _torso_carrier(kinematics)
    legacy = avatar.torso
    if legacy is not None:
        entry = {"name": TORSO, "joint": carrier, "shape": "elliptic_cylinder", **legacy}
        volume = volume_from_entry(entry, f"{avatar.path}: torso")
        return Volume(TORSO, carrier, volume.shape, derived=True)
    rest = kinematics.rest_positions
    left, right = rest[kinematics.index("l_shoulder")], rest[kinematics.index("r_shoulder")]
    half_width = TORSO_WIDTH_OF_SHOULDERS * 0.5 * abs(left[0] - right[0])
    center = np.array([0.5 * (left[0] + right[0]), 0.0, 0.5 * (left[2] + right[2])])
    shape = EllipticCylinder(center, half_width, TORSO_DEPTH_OF_WIDTH * half_width, 0.0, 0.5 * (left[1] + right[1]))
    return Volume(TORSO, carrier, shape, derived=True)


def _torso_carrier(kinematics: Kinematics) -> str:
    """The joint the torso moves with: the parent of the clavicle (or of the shoulder)."""
    for child in ("r_sternoclavicular", "l_sternoclavicular", "r_shoulder", "l_shoulder"):
        if child in kinematics.names:
            parent = kinematics.parents[kinematics.index(child)]
            if parent >= 0:
                return kinematics.names[parent]
    raise AvatarError("the skeleton has no clavicle or shoulder joint to carry the torso")


def _hand_end(kinematics: Kinematics, side: str) -> np.ndarray:
    """The far end of the palm at rest: the middle finger's base joint, else the mean of
    the wrist's children."""
    rest = kinematics.rest_positions
    if f"{side}_middle1" in kinematics.names:
        return rest[kinematics.index(f"{side}_middle1")]
    wrist = kinematics.index(f"{side}_wrist")
    children = [index for index, parent in enumerate(kinematics.parents) if parent == wrist]
    if not children:
        raise AvatarError(f"the skeleton has no joint beyond {side}_wrist to size the hand")
    return rest[children].mean(axis=0)


def _derived_arm(kinematics: Kinematics, side: str, segment: str) -> Volume:
    rest = kinematics.rest_positions
    shoulder, elbow, wrist = (rest[kinematics.index(f"{side}_{joint}")] for joint in ("shoulder", "elbow", "wrist"))
    if segment == "upper_arm":
        start = shoulder + UPPER_ARM_START * (elbow - shoulder)
        shape = Capsule(start, elbow, UPPER_ARM_RADIUS * float(np.linalg.norm(elbow - shoulder)))
        return Volume(f"{side}_upper_arm", f"{side}_shoulder", shape, derived=True)
    if segment == "forearm":
        return Volume(f"{side}_forearm", f"{side}_elbow", Capsule(elbow, wrist, FOREARM_RADIUS * float(np.linalg.norm(wrist - elbow))), derived=True)
    end = _hand_end(kinematics, side)
    return Volume(f"{side}_hand", f"{side}_wrist", Capsule(wrist, end, HAND_RADIUS * float(np.linalg.norm(end - wrist))), derived=True)


def audit_volumes(avatar: AvatarFile, kinematics: Kinematics) -> dict[str, Volume]:
    """The torso and both arms' segments, from the avatar file where it has them (arm
    segments as capsules) and derived from the skeleton where it does not."""
    given: dict[str, Volume] = {}
    for number, entry in enumerate(avatar.collision or []):
        volume = volume_from_entry(entry, f"{avatar.path}: collision.volumes[{number}]")
        if volume.joint not in kinematics.names:
            raise AvatarError(f"{avatar.path}: collision volume {volume.name!r} moves with joint {volume.joint!r}, which the skeleton lacks")
        given[volume.name] = volume
    volumes = {TORSO: given.get(TORSO) or _derived_torso(avatar, kinematics)}
    if CHEST in given:
        volumes[CHEST] = given[CHEST]
    for side in SIDES:
        for segment in ARM_SEGMENTS:
            name = f"{side}_{segment}"
            if name in given:
                volume = given[name]
                volumes[name] = Volume(name, volume.joint, inscribed_capsule(volume.shape), derived=False)
            else:
                volumes[name] = _derived_arm(kinematics, side, segment)
    return volumes
