"""The avatar's collision volumes: the body's own shape as a few simple solids.

An avatar file may state them (``"collision"``, read by :mod:`motor.body.avatar`); when it
does not, :func:`derived_volumes` builds them from the skeleton, the legacy ``torso``
cylinder and the named body locations. Every volume moves rigidly with its ``joint``;
its geometry is given in the avatar frame **at rest** (root at the origin, metres), so
its place in a pose follows from the joint's global transform relative to rest
(:mod:`motor.body.collision` poses them and measures distances).

Shapes:

* :class:`Capsule` — the points within ``radius`` of the segment ``a``–``b``;
* :class:`Ellipsoid` — semi-axes ``radii`` along the avatar's x, y, z at rest;
* :class:`EllipticCylinder` — a vertical cylinder with half width (x) and half depth
  (z) about ``center``'s x and z, from height ``bottom`` to ``top``.

The standard names are :data:`BODY_NAMES` and :data:`ARM_NAMES` per side; the arm
segments and hands must be capsules (the arm IK moves them with the bones). The trunk may
be one ``torso`` or a ``torso`` (abdomen, with the lumbar spine) under a ``chest`` (with
the thoracic spine, :data:`CHEST_JOINT`): a trunk turning toward a reach turns the chest
with it — on a skinned body the flesh beside the shoulders turns by about two thirds of
the thoracic spine's turn, the belly not at all — so one volume on the lumbar spine would
leave the chest behind while the shoulders come forward.
``palm_thickness`` is the distance between the two hands' midlines when palm touches
palm: hands in contact keep it (targets such as ``join_hands`` can use it too).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

#: Volumes of the trunk and head every avatar has.
BODY_NAMES: tuple[str, ...] = ("torso", "pelvis", "neck", "head")
#: The trunk's volumes, lumbar then thoracic: the ``chest`` is optional.
TRUNK_NAMES: tuple[str, ...] = ("torso", "chest")
#: The joint that carries the derived chest, and the joint at whose rest height the
#: derived torso ends and the chest begins (the lowest joint of the thoracic spine).
CHEST_JOINT = "vt6"
CHEST_FROM = "vt10"
#: Volumes of one arm (with an ``l_``/``r_`` prefix), all capsules, and the joint each
#: moves with.
ARM_NAMES: dict[str, str] = {"upper_arm": "shoulder", "forearm": "elbow", "hand": "wrist"}
#: Share of the upper arm next to the shoulder that is the shoulder's own flesh (it meets
#: the torso by construction), left out of the upper-arm capsule derived by default.
SHOULDER_SHARE = 0.25
#: Default radii as fractions of the bone's length (an adult's upper arm is about 8 cm
#: thick for 31 cm, the forearm about 6.5 cm for 27 cm).
UPPER_ARM_RADIUS = 0.13
FOREARM_RADIUS = 0.12
#: Share of the forearm, from the elbow, that its default capsule covers: toward the
#: wrist the forearm narrows to the hand's thickness, and the hand's capsule takes over
#: (so two hands can touch palm to palm without their forearms overlapping).
FOREARM_SHARE = 0.85
#: Default palm thickness as a fraction of the hand's length (wrist to middle knuckle)
#: when the avatar has no palm and back-of-hand locations to measure it from.
PALM_THICKNESS = 0.31


@dataclass(frozen=True, eq=False)
class Capsule:
    """Points within ``radius`` (m) of the segment ``a``–``b`` ``(3,)`` (rest, metres)."""

    name: str
    joint: str
    a: np.ndarray
    b: np.ndarray
    radius: float


@dataclass(frozen=True, eq=False)
class Ellipsoid:
    """Semi-axes ``radii (3,)`` along x, y, z at rest about ``center (3,)``, metres."""

    name: str
    joint: str
    center: np.ndarray
    radii: np.ndarray


@dataclass(frozen=True, eq=False)
class EllipticCylinder:
    """Vertical elliptic cylinder: ``center``'s x and z, half width (x), half depth (z),
    from ``bottom`` to ``top`` (heights), metres at rest."""

    name: str
    joint: str
    center: np.ndarray
    half_width: float
    half_depth: float
    bottom: float
    top: float


Volume = Capsule | Ellipsoid | EllipticCylinder


@dataclass(frozen=True, eq=False)
class CollisionVolumes:
    """An avatar's collision volumes by name, and its palm thickness (metres)."""

    volumes: tuple[Volume, ...]
    palm_thickness: float

    def __getitem__(self, name: str) -> Volume:
        for volume in self.volumes:
            if volume.name == name:
                return volume
        raise KeyError(f"no collision volume {name!r}")

    def __contains__(self, name: str) -> bool:
        return any(volume.name == name for volume in self.volumes)

    def arm(self, side: str, part: str) -> Capsule:
        """The capsule of one arm's ``upper_arm``, ``forearm`` or ``hand`` (capsules by
        validation)."""
        return self[f"{side}_{part}"]  # type: ignore[return-value]

    def trunk(self) -> tuple[Volume, ...]:
        """The trunk's volumes present (:data:`TRUNK_NAMES`), lumbar first."""
        return tuple(self[name] for name in TRUNK_NAMES if name in self)

    def body(self, limb_joints: frozenset[str]) -> tuple[Volume, ...]:
        """Every volume moving with none of ``limb_joints`` (the arms' and hands'
        joints): the obstacles of both arms."""
        return tuple(v for v in self.volumes if v.joint not in limb_joints)


def required_volumes() -> dict[str, tuple[type, ...]]:
    """Standard volume name → shapes allowed for it."""
    shapes: dict[str, tuple[type, ...]] = {name: (Capsule, Ellipsoid, EllipticCylinder) for name in BODY_NAMES}
    shapes.update({f"{side}_{part}": (Capsule,) for side in "lr" for part in ARM_NAMES})
    return shapes


def derived_volumes(
    joint_names: tuple[str, ...],
    rest_positions: np.ndarray,
    torso: object,
    sites: Mapping[str, tuple[int, np.ndarray]],
) -> CollisionVolumes:
    """Default volumes from the skeleton at rest, the legacy torso cylinder (an object with
    ``center``, ``half_width``, ``half_depth``, ``bottom``, ``top``) and the named body
    locations (name → (bone index, offset in the bone's rest frame)).

    The torso is the legacy cylinder, cut at the rest height of :data:`CHEST_FROM` into a
    torso on ``vl5`` and a chest on :data:`CHEST_JOINT` where the skeleton has both
    joints and the cut lies inside it; the pelvis an ellipsoid under it as wide and deep;
    the neck a capsule from ``vc7`` to ``skullbase`` as thick as the ``neck`` location lies
    in front of its bone; the head an ellipsoid through the ears, the top of the head, the
    chin and the nose; the arms capsules along their bones (the upper arm from a quarter
    of the way down, kept clear of the torso at rest; the forearm to :data:`FOREARM_SHARE`
    of the way to the wrist); the hands capsules from the wrist to the middle finger's
    base, as thick as the palm (the distance between the ``palm`` and ``handback``
    locations).
    """
    at = {name: rest_positions[i] for i, name in enumerate(joint_names)}
    site = lambda name: rest_positions[sites[name][0]] + sites[name][1]
    center = np.asarray(torso.center, dtype=float)
    height = torso.top - torso.bottom
    volumes: list[Volume] = [
        *_trunk(at, center, torso),
        Ellipsoid("pelvis", "sacroiliac", np.array([center[0], torso.bottom, center[2]]), np.array([torso.half_width, 0.2 * height, torso.half_depth])),
    ]
    neck_radius = float(site("neck")[2] - at["vc4"][2]) if "neck" in sites else 0.4 * torso.half_depth
    volumes.append(Capsule("neck", "vc4", at["vc7"].copy(), at["skullbase"].copy(), neck_radius))
    volumes.append(_head(at["skullbase"], site, sites))
    if "r_palm" in sites and "r_handback" in sites:
        palm = float(np.linalg.norm(site("r_palm") - site("r_handback")))
    else:
        palm = PALM_THICKNESS * float(np.linalg.norm(at["r_middle1"] - at["r_wrist"]))
    for side in "lr":
        shoulder, elbow, wrist, knuckle = (at[f"{side}_{j}"] for j in ("shoulder", "elbow", "wrist", "middle1"))
        upper = float(np.linalg.norm(elbow - shoulder))
        clear = abs(shoulder[0] - center[0]) - torso.half_width
        radius = min(UPPER_ARM_RADIUS * upper, clear) if clear > 0 else UPPER_ARM_RADIUS * upper
        volumes.append(Capsule(f"{side}_upper_arm", f"{side}_shoulder", shoulder + SHOULDER_SHARE * (elbow - shoulder), elbow.copy(), radius))
        fore = FOREARM_RADIUS * float(np.linalg.norm(wrist - elbow))
        volumes.append(Capsule(f"{side}_forearm", f"{side}_elbow", elbow.copy(), elbow + FOREARM_SHARE * (wrist - elbow), fore))
        volumes.append(Capsule(f"{side}_hand", f"{side}_wrist", wrist.copy(), knuckle.copy(), 0.5 * palm))
    return CollisionVolumes(tuple(volumes), palm)


def _trunk(at: Mapping[str, np.ndarray], center: np.ndarray, torso) -> list[EllipticCylinder]:
    """The legacy torso cylinder as a torso and, above the thoracic spine's first joint, a chest."""
    cylinder = lambda name, joint, bottom, top: EllipticCylinder(name, joint, center.copy(), torso.half_width, torso.half_depth, bottom, top)
    cut = float(at[CHEST_FROM][1]) if CHEST_FROM in at and CHEST_JOINT in at else None
    if cut is None or not torso.bottom < cut < torso.top:
        return [cylinder("torso", "vl5", torso.bottom, torso.top)]
    return [cylinder("torso", "vl5", torso.bottom, cut), cylinder("chest", CHEST_JOINT, cut, torso.top)]


def _head(skullbase: np.ndarray, site, sites: Mapping[str, tuple[int, np.ndarray]]) -> Ellipsoid:
    """The head's ellipsoid through the ears (width), the top of the head and the chin
    (height) and the nose (depth, about the ears' plane); proportions of an adult head
    where a location is missing."""
    top = site("headtop") if "headtop" in sites else skullbase + [0.0, 0.2, 0.0]
    chin = site("chin") if "chin" in sites else skullbase + [0.0, -0.015, 0.095]
    half_height = 0.5 * float(top[1] - chin[1])
    ears = [site(n) for n in ("l_ear", "r_ear") if n in sites]
    width = 0.5 * float(abs(ears[0][0] - ears[1][0])) if len(ears) == 2 else 0.7 * half_height
    depth_center = float(np.mean([e[2] for e in ears])) if ears else float(skullbase[2])
    depth = float(site("nose")[2]) - depth_center if "nose" in sites else 1.1 * half_height
    center = np.array([skullbase[0], 0.5 * float(top[1] + chin[1]), depth_center])
    return Ellipsoid("head", "skullbase", center, np.array([width, half_height, depth]))
