"""What every avatar shares, stated once: where avatar files live, the sides and arms and
how they are named, the joints every skeleton has, the postures and limits every file
defines, and the error a file that breaks them raises (:mod:`motor.body.avatar` reads
the files; :mod:`motor.body.definition` and :mod:`motor.body.humanoid` make them)."""

from __future__ import annotations

from pathlib import Path

from mura.values import FINGERS

AVATAR_DIR = Path(__file__).resolve().parents[2] / "specs" / "avatars"
#: Avatars built at set-up (``make setup``: the skinned ``makehuman`` avatar), found by name too.
BUILT_AVATAR_DIR = Path(__file__).resolve().parents[2] / "build" / "avatars"
#: The avatar the page and the demo use by default (built at set-up).
DEFAULT_AVATAR = "makehuman"
#: Users' own avatar files, read as humanoids (:mod:`motor.body.humanoid`).
MODEL_SUFFIXES = (".vrm", ".glb", ".gltf")

SIDES: tuple[str, ...] = ("l", "r")
#: The arms as the scheduler and the specs name them, and their side prefixes.
ARMS: tuple[str, ...] = ("right", "left")
AVATAR_SIDE: dict[str, str] = {"right": "r", "left": "l"}

#: The trunk, neck and head joints every avatar has, root first.
SPINE_JOINTS: tuple[str, ...] = (
    "humanoid_root", "sacroiliac", "vl5", "vl3", "vl1", "vt10", "vt6", "vt1", "vc7", "vc4", "skullbase",
)  # fmt: skip

#: Arm chain, shoulder girdle to wrist, without the side prefix.
ARM_JOINTS: tuple[str, ...] = ("sternoclavicular", "shoulder", "elbow", "wrist")

#: The 17 hand joints, in the order of :func:`motor.hand.shape.hand_rotations`' output.
HAND_JOINTS: tuple[str, ...] = (
    "thumb1", "thumb2", "thumb3",
    "index1", "index2", "index3",
    "middle1", "middle2", "middle3",
    "ring0", "ring1", "ring2", "ring3",
    "pinky0", "pinky1", "pinky2", "pinky3",
)  # fmt: skip

#: Fingers other than the thumb, in hand-parameter order.
LONG_FINGERS: tuple[str, ...] = FINGERS[1:]

#: Named thumb postures every avatar calibrates: (abduction, palmar, twist, middle, end).
THUMB_POSTURES: tuple[str, ...] = ("alongside", "across", "fist", "out", "open", "pinch", "pinchall")

#: Joint limits the IK checks, per arm joint (radians): name -> required ranges.
ARM_LIMITS: dict[str, tuple[str, ...]] = {
    "sternoclavicular": ("swing",),
    "elbow": ("flexion", "twist"),
    "wrist": ("flexion", "deviation"),
}

#: Named arm postures (wrist positions and hand rotations) every avatar defines.
POSTURES: tuple[str, ...] = ("rest", "interim_rest")


def required_joints() -> tuple[str, ...]:
    """Every joint an avatar must have (53): spine, both arms, both fully articulated hands."""
    limbs = tuple(f"{side}_{joint}" for side in SIDES for joint in ARM_JOINTS + HAND_JOINTS)
    return SPINE_JOINTS + limbs


class AvatarError(ValueError):
    """An avatar file that cannot be used; the message names the file and the field."""
