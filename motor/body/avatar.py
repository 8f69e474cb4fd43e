"""Avatar definitions: skeleton, joint limits, hand calibration and named body locations.

Specs are avatar-independent; an avatar file (JSON in ``specs/avatars/``) supplies the
geometry that gives them numbers. Conventions of every avatar file:

* metres; y up, the avatar faces +z, +x is the avatar's left (H-Anim);
* the root joint ``humanoid_root`` sits at the origin at hip level, so every position in
  the file (grid, torso, postures) is relative to it; ``root_height`` places it above the
  floor for exporters;
* rest pose = identity local rotations: standing, arms hanging down at the sides, palms
  facing the thighs, thumbs forward, fingers straight and parallel. Joint offsets are in
  the parent's frame at rest, which at rest is the avatar frame.

:func:`load_avatar` validates a file completely and raises :class:`AvatarError` naming the
field at fault (``kim.json: locations.nose.bone: unknown bone 'skul'``).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

from motor.body.conventions import (
    ARM_JOINTS,
    ARM_LIMITS,
    AVATAR_DIR,
    BUILT_AVATAR_DIR,
    DEFAULT_AVATAR,
    HAND_JOINTS,
    LONG_FINGERS,
    MODEL_SUFFIXES,
    POSTURES,
    SIDES,
    THUMB_POSTURES,
    AvatarError,
    required_joints,
)
from motor.body.volumes import (
    Capsule,
    CollisionVolumes,
    Ellipsoid,
    EllipticCylinder,
    Volume,
    derived_volumes,
    required_volumes,
)
from mura.murml_vocabulary import GRID_DISTANCES, GRID_HEIGHTS, GRID_LATERALS

@dataclass(frozen=True, eq=False)
class Site:
    """A named body or hand location: a point fixed to a bone.

    ``offset`` is in the bone's frame (metres), ``normal`` the outward surface direction
    there (unit, bone frame); proximities are measured along it.
    """

    bone: int
    offset: np.ndarray
    normal: np.ndarray


@dataclass(frozen=True, eq=False)
class Grid:
    """The MURML/ACE signing-space grid scaled to this avatar, metres.

    Heights are above the root (hip level), laterals from the mid-sagittal plane (positive
    to the avatar's left), distances in front of the plane ``z = front`` through the chest
    surface.
    """

    heights: dict[str, float]
    laterals: dict[str, float]
    distances: dict[str, float]
    front: float


@dataclass(frozen=True, eq=False)
class Torso:
    """The torso as an elliptic cylinder for collision checks: centre ``(3,)`` in the
    avatar frame, half width (x) and half depth (z), bottom and top heights, metres."""

    center: np.ndarray
    half_width: float
    half_depth: float
    bottom: float
    top: float


@dataclass(frozen=True, eq=False)
class Posture:
    """A named arm posture: the wrist position ``(3,)`` (avatar frame, metres) and the
    global hand rotation ``(4,)``."""

    wrist: np.ndarray
    hand_rotation: np.ndarray


@dataclass(frozen=True, eq=False)
class FingerCalibration:
    """Per-finger constants of the seed-000 base-joint formula, long fingers in
    :data:`LONG_FINGERS` order: ``theta_flat``, ``theta_fist1``, ``theta_fist2`` (4,)
    radians, positive away from the middle finger (the θ twist positive toward the
    thumb); ``max_bend`` (4, 3) maximum flexion of base, middle, end joints;
    ``max_splay`` (4,). Thumb: ``thumb_max_bend`` (2,) for its two hinges and
    ``thumb_postures`` name -> (5,) parameters (see :data:`THUMB_POSTURES`)."""

    theta_flat: np.ndarray
    theta_fist1: np.ndarray
    theta_fist2: np.ndarray
    max_bend: np.ndarray
    max_splay: np.ndarray
    thumb_max_bend: np.ndarray
    thumb_postures: dict[str, np.ndarray]


@dataclass(frozen=True, eq=False)
class HandFrame:
    """Axes of one hand in the avatar frame at rest (unit vectors).

    ``finger_axis`` λ runs from the wrist to the middle finger's base; ``thumb_side``
    points across the hand toward the thumb; ``palm_normal`` σ leaves the palm;
    ``bend_axis`` β flexes fingers toward the palm for positive angles;
    ``splay_axis`` turns fingers toward the thumb for positive angles; ``twist_axis`` is
    λ signed so that mirrored hands get mirrored rotations; ``thumb_axis`` is the thumb's
    metacarpal direction.
    """

    finger_axis: np.ndarray
    thumb_side: np.ndarray
    palm_normal: np.ndarray
    bend_axis: np.ndarray
    splay_axis: np.ndarray
    twist_axis: np.ndarray
    thumb_axis: np.ndarray


@dataclass(frozen=True, eq=False)
class Avatar:
    """A loaded, validated avatar. Arrays are read-only; joints are parents-first.

    Attributes:
        name, source: the avatar's name and the file it came from.
        stature, root_height: metres.
        joint_names: H-Anim names, parents before children.
        parents: ``(J,)`` parent index, -1 for the root.
        offsets: ``(J, 3)`` bone offsets in the parent frame at rest, metres.
        rest_positions: ``(J, 3)`` joint positions at rest, avatar frame.
        levels: joint indices grouped by depth in the tree, for vectorized FK.
        limits: joint name -> limit name -> (min, max) radians.
        sites: location name -> :class:`Site` (paired sites carry an ``l_``/``r_`` prefix).
        grid, torso, postures, calibration, hand_frames: see their classes.
        collision: the body's collision volumes and palm thickness (the file's
            ``collision`` entry, else derived from the skeleton: :mod:`motor.body.volumes`).
    """

    name: str
    source: str
    stature: float
    root_height: float
    joint_names: tuple[str, ...]
    parents: np.ndarray
    offsets: np.ndarray
    rest_positions: np.ndarray
    levels: tuple[np.ndarray, ...]
    limits: dict[str, dict[str, tuple[float, float]]]
    sites: dict[str, Site]
    grid: Grid
    torso: Torso
    postures: dict[str, dict[str, Posture]]
    calibration: FingerCalibration
    hand_frames: dict[str, HandFrame]
    collision: CollisionVolumes

    @property
    def joint_count(self) -> int:
        return len(self.joint_names)

    def joint_index(self, name: str) -> int:
        """Index of a joint by H-Anim name; KeyError naming the joint if absent."""
        try:
            return self.joint_names.index(name)
        except ValueError:
            raise KeyError(f"avatar {self.name!r} has no joint {name!r}") from None

    def arm_joints(self, side: str) -> np.ndarray:
        """Indices of sternoclavicular, shoulder, elbow, wrist of one side (``l``/``r``)."""
        return np.array([self.joint_index(f"{check_side(side)}_{joint}") for joint in ARM_JOINTS])

    def hand_joints(self, side: str) -> np.ndarray:
        """Indices of the 17 hand joints of one side, in :data:`HAND_JOINTS` order."""
        return np.array([self.joint_index(f"{check_side(side)}_{joint}") for joint in HAND_JOINTS])

    def limit(self, joint: str, kind: str) -> tuple[float, float]:
        """A joint limit ``(min, max)`` in radians."""
        return self.limits[joint][kind]

    def arm_lengths(self, side: str) -> tuple[float, float]:
        """Upper-arm and forearm lengths of one side, metres (measured once: every body
        site placed at a proximity asks for them)."""
        measured = self._measured_arms
        if side not in measured:
            _, _, elbow, wrist = self.arm_joints(side)
            measured[side] = float(np.linalg.norm(self.offsets[elbow])), float(np.linalg.norm(self.offsets[wrist]))
        return measured[side]

    @cached_property
    def _measured_arms(self) -> dict[str, tuple[float, float]]:
        """:meth:`arm_lengths` by side, as measured so far (the offsets are read-only)."""
        return {}

    def arm_length(self, side: str = "r") -> float:
        """Shoulder-to-wrist length of the straight arm, metres: the unit of proximities."""
        upper, fore = self.arm_lengths(side)
        return upper + fore


def check_side(side: str) -> str:
    """The side itself if it is "l" or "r"; ValueError otherwise."""
    if side not in SIDES:
        raise ValueError(f"side must be 'l' or 'r', got {side!r}")
    return side


def load_avatar(name_or_path: str | Path) -> Avatar:
    """Load and validate an avatar: a name in ``specs/avatars/`` (``"max"``) or
    ``build/avatars/`` (``"makehuman"``), a path to an avatar file, or a user's VRM/glTF
    humanoid (``.vrm``, ``.glb``, ``.gltf``; see :mod:`motor.body.humanoid`).

    Raises AvatarError naming the file and the offending field.
    """
    path = Path(name_or_path)
    if path.suffix.lower() in MODEL_SUFFIXES:
        from motor.body.humanoid import humanoid_definition  # reads glTF only when asked to

        return _Reader(path.name).avatar(humanoid_definition(path).document, str(path))
    if path.suffix != ".json":
        path = AVATAR_DIR / f"{name_or_path}.json"
        if not path.is_file() and (BUILT_AVATAR_DIR / f"{name_or_path}.json").is_file():
            path = BUILT_AVATAR_DIR / f"{name_or_path}.json"
    if not path.is_file():
        known = ", ".join(sorted({p.stem for folder in (AVATAR_DIR, BUILT_AVATAR_DIR) for p in folder.glob("*.json")}))
        hint = " (built avatars appear after `make setup`)" if str(name_or_path) == DEFAULT_AVATAR else ""
        raise AvatarError(f"{path.name}: no such avatar file (known avatars: {known}){hint}")
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as error:
        raise AvatarError(f"{path.name}:{error.lineno}:{error.colno}: not valid JSON: {error.msg}") from None
    return _Reader(path.name).avatar(data, str(path))


class _Reader:
    """Validating reader of one avatar document; every error names file and field."""

    def __init__(self, file: str) -> None:
        self.file = file

    def fail(self, field: str, message: str) -> AvatarError:
        return AvatarError(f"{self.file}: {field}: {message}")

    def field(self, data: dict[str, Any], key: str, where: str = "") -> Any:
        if not isinstance(data, dict):
            raise self.fail(where or "<top>", "expected an object")
        if key not in data:
            raise self.fail(f"{where}.{key}" if where else key, "missing required field")
        return data[key]

    def number(self, value: Any, where: str) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value):
            raise self.fail(where, f"expected a finite number, got {value!r}")
        return float(value)

    def vector(self, value: Any, size: int, where: str) -> np.ndarray:
        if not isinstance(value, list) or len(value) != size:
            raise self.fail(where, f"expected a list of {size} numbers, got {value!r}")
        return np.array([self.number(v, f"{where}[{i}]") for i, v in enumerate(value)])

    def unit(self, value: Any, size: int, where: str, what: str) -> np.ndarray:
        vector = self.vector(value, size, where)
        norm = float(np.linalg.norm(vector))
        if abs(norm - 1.0) > 1e-3:
            raise self.fail(where, f"{what} must have unit length, has length {norm:.4f}")
        return vector / norm

    def avatar(self, data: Any, source: str) -> Avatar:
        if not isinstance(data, dict):
            raise self.fail("<top>", "expected a JSON object")
        name = self.field(data, "name")
        if not isinstance(name, str) or not name:
            raise self.fail("name", "expected a non-empty string")
        names, parents, offsets = self.skeleton(self.field(data, "joints"))
        rest = _rest_positions(parents, offsets)
        sites = self.sites(self.field(data, "locations"), names)
        frames = {side: _hand_frame(side, names, offsets, rest) for side in SIDES}
        torso = self.torso(self.field(data, "torso"))
        if "collision" in data:
            collision = self.collision(data["collision"], names)
        else:
            collision = derived_volumes(names, rest, torso, {name: (site.bone, site.offset) for name, site in sites.items()})
        return Avatar(
            name=name,
            source=source,
            stature=self.number(self.field(data, "stature"), "stature"),
            root_height=self.number(self.field(data, "root_height"), "root_height"),
            joint_names=names,
            parents=_frozen(parents),
            offsets=_frozen(offsets),
            rest_positions=_frozen(rest),
            levels=_levels(parents),
            limits=self.limits(self.field(data, "limits"), names),
            sites=sites,
            grid=self.grid(self.field(data, "grid")),
            torso=torso,
            postures=self.postures(self.field(data, "postures")),
            calibration=self.calibration(self.field(data, "fingers"), self.field(data, "thumb")),
            hand_frames=frames,
            collision=collision,
        )

    def skeleton(self, joints: Any) -> tuple[tuple[str, ...], np.ndarray, np.ndarray]:
        if not isinstance(joints, list) or not joints:
            raise self.fail("joints", "expected a non-empty list of joints")
        declared: dict[str, tuple[str | None, np.ndarray]] = {}
        for i, joint in enumerate(joints):
            where = f"joints[{i}]"
            name = self.field(joint, "name", where)
            if not isinstance(name, str) or not name:
                raise self.fail(f"{where}.name", "expected a non-empty string")
            if name in declared:
                raise self.fail(f"{where}.name", f"joint {name!r} declared twice")
            parent = self.field(joint, "parent", where)
            if parent is not None and not isinstance(parent, str):
                raise self.fail(f"{where}.parent", f"expected a joint name or null, got {parent!r}")
            declared[name] = (parent, self.vector(self.field(joint, "offset", where), 3, f"{where}.offset"))
        for i, (name, (parent, _)) in enumerate(declared.items()):
            if parent is not None and parent not in declared:
                raise self.fail(f"joints[{i}].parent", f"joint {name!r} has unknown parent {parent!r}")
        roots = [name for name, (parent, _) in declared.items() if parent is None]
        if len(roots) != 1:
            raise self.fail("joints", f"expected exactly one root joint (parent null), found {roots}")
        missing = [name for name in required_joints() if name not in declared]
        if missing:
            raise self.fail("joints", f"missing joint {missing[0]!r}" + (f" (and {len(missing) - 1} more)" if len(missing) > 1 else ""))
        order = self.topological(declared, roots[0])
        index = {name: i for i, name in enumerate(order)}
        parents = np.array([-1 if declared[n][0] is None else index[declared[n][0]] for n in order])
        offsets = np.array([declared[n][1] for n in order])
        return tuple(order), parents, offsets

    def topological(self, declared: dict[str, tuple[str | None, np.ndarray]], root: str) -> list[str]:
        children: dict[str, list[str]] = {name: [] for name in declared}
        for name, (parent, _) in declared.items():
            if parent is not None:
                children[parent].append(name)
        order = [root]
        for name in order:
            order.extend(children[name])
        if len(order) != len(declared):
            stuck = next(name for name in declared if name not in set(order))
            raise self.fail("joints", f"cycle in the joint hierarchy through {stuck!r} (it never reaches the root {root!r})")
        return order

    def limits(self, data: Any, names: tuple[str, ...]) -> dict[str, dict[str, tuple[float, float]]]:
        if not isinstance(data, dict):
            raise self.fail("limits", "expected an object of joint -> {limit: [min, max]}")
        limits: dict[str, dict[str, tuple[float, float]]] = {}
        for joint, ranges in data.items():
            if joint not in names:
                raise self.fail(f"limits.{joint}", f"unknown joint {joint!r}")
            if not isinstance(ranges, dict):
                raise self.fail(f"limits.{joint}", "expected an object of limit -> [min, max]")
            limits[joint] = {}
            for kind, pair in ranges.items():
                low, high = self.vector(pair, 2, f"limits.{joint}.{kind}")
                if low > high:
                    raise self.fail(f"limits.{joint}.{kind}", f"min {low} exceeds max {high}")
                limits[joint][kind] = (float(low), float(high))
        for side in SIDES:
            for joint, kinds in ARM_LIMITS.items():
                for kind in kinds:
                    if kind not in limits.get(f"{side}_{joint}", {}):
                        raise self.fail(f"limits.{side}_{joint}.{kind}", "missing required field")
        return limits

    def sites(self, data: Any, names: tuple[str, ...]) -> dict[str, Site]:
        if not isinstance(data, dict):
            raise self.fail("locations", "expected an object of name -> {bone, offset, normal}")
        sites: dict[str, Site] = {}
        for name, entry in data.items():
            where = f"locations.{name}"
            bone = self.field(entry, "bone", where)
            if bone not in names:
                raise self.fail(f"{where}.bone", f"unknown bone {bone!r}")
            offset = self.vector(self.field(entry, "offset", where), 3, f"{where}.offset")
            normal = self.unit(self.field(entry, "normal", where), 3, f"{where}.normal", "a normal")
            sites[name] = Site(names.index(bone), _frozen(offset), _frozen(normal))
        return sites

    def table(self, data: Any, where: str, required: dict[str, float]) -> dict[str, float]:
        if not isinstance(data, dict):
            raise self.fail(where, "expected an object of name -> metres")
        for name in required:
            if name not in data:
                raise self.fail(f"{where}.{name}", "missing required field")
        for name in data:
            if name not in required:
                raise self.fail(f"{where}.{name}", "not a grid name of the MURML symbol table")
        return {name: self.number(data[name], f"{where}.{name}") for name in required}

    def grid(self, data: Any) -> Grid:
        return Grid(
            heights=self.table(self.field(data, "heights", "grid"), "grid.heights", GRID_HEIGHTS),
            laterals=self.table(self.field(data, "laterals", "grid"), "grid.laterals", GRID_LATERALS),
            distances=self.table(self.field(data, "distances", "grid"), "grid.distances", GRID_DISTANCES),
            front=self.number(self.field(data, "front", "grid"), "grid.front"),
        )

    def torso(self, data: Any) -> Torso:
        values = {
            key: self.number(self.field(data, key, "torso"), f"torso.{key}")
            for key in ("half_width", "half_depth", "bottom", "top")
        }
        for key in ("half_width", "half_depth"):
            if values[key] <= 0:
                raise self.fail(f"torso.{key}", f"must be positive, got {values[key]}")
        center = self.vector(self.field(data, "center", "torso"), 3, "torso.center")
        return Torso(_frozen(center), **values)

    def collision(self, data: Any, names: tuple[str, ...]) -> CollisionVolumes:
        """The ``collision`` entry: a list of volumes (format in :mod:`motor.body.volumes`),
        every standard name present with an allowed shape, and optionally
        ``palm_thickness`` (else the hands' capsules' thickness)."""
        entries = self.field(data, "volumes", "collision")
        if not isinstance(entries, list):
            raise self.fail("collision.volumes", "expected a list of volumes")
        volumes: list[Volume] = []
        for i, entry in enumerate(entries):
            volume = self.volume(entry, f"collision.volumes[{i}]", names)
            if any(v.name == volume.name for v in volumes):
                raise self.fail(f"collision.volumes[{i}].name", f"volume {volume.name!r} declared twice")
            volumes.append(volume)
        for name, shapes in required_volumes().items():
            found = next((v for v in volumes if v.name == name), None)
            if found is None:
                raise self.fail("collision.volumes", f"missing volume {name!r}")
            if not isinstance(found, shapes):
                allowed = " or ".join(_SHAPE_NAMES[s] for s in shapes)
                raise self.fail(f"collision.volumes[{volumes.index(found)}].shape", f"volume {name!r} must be a {allowed}")
        if "palm_thickness" in data:
            thickness = self.positive(data["palm_thickness"], "collision.palm_thickness")
        else:  # as thick as the hands' capsules
            thickness = sum(v.radius for v in volumes if v.name in ("l_hand", "r_hand"))
        return CollisionVolumes(tuple(volumes), thickness)

    def volume(self, data: Any, where: str, names: tuple[str, ...]) -> Volume:
        name = self.field(data, "name", where)
        if not isinstance(name, str) or not name:
            raise self.fail(f"{where}.name", "expected a non-empty string")
        joint = self.field(data, "joint", where)
        if joint not in names:
            raise self.fail(f"{where}.joint", f"unknown joint {joint!r}")
        shape = self.field(data, "shape", where)
        if shape == "capsule":
            a, b = (_frozen(self.vector(self.field(data, k, where), 3, f"{where}.{k}")) for k in ("a", "b"))
            return Capsule(name, joint, a, b, self.positive(self.field(data, "radius", where), f"{where}.radius"))
        if shape == "ellipsoid":
            center = _frozen(self.vector(self.field(data, "center", where), 3, f"{where}.center"))
            radii = self.vector(self.field(data, "radii", where), 3, f"{where}.radii")
            for k, r in enumerate(radii):
                self.positive(float(r), f"{where}.radii[{k}]")
            return Ellipsoid(name, joint, center, _frozen(radii))
        if shape == "elliptic_cylinder":
            center = _frozen(self.vector(self.field(data, "center", where), 3, f"{where}.center"))
            width, depth = (self.positive(self.field(data, k, where), f"{where}.{k}") for k in ("half_width", "half_depth"))
            bottom, top = (self.number(self.field(data, k, where), f"{where}.{k}") for k in ("bottom", "top"))
            if bottom >= top:
                raise self.fail(f"{where}.top", f"top {top} must be above bottom {bottom}")
            return EllipticCylinder(name, joint, center, width, depth, bottom, top)
        raise self.fail(f"{where}.shape", f"unknown shape {shape!r} (expected {', '.join(_SHAPE_NAMES.values())})")

    def positive(self, value: Any, where: str) -> float:
        number = self.number(value, where)
        if number <= 0:
            raise self.fail(where, f"must be positive, got {number}")
        return number

    def postures(self, data: Any) -> dict[str, dict[str, Posture]]:
        postures: dict[str, dict[str, Posture]] = {}
        for name in POSTURES:
            entry = self.field(data, name, "postures")
            postures[name] = {}
            for side in SIDES:
                where = f"postures.{name}.{side}"
                arm = self.field(entry, side, f"postures.{name}")
                wrist = self.vector(self.field(arm, "wrist", where), 3, f"{where}.wrist")
                rotation = self.unit(self.field(arm, "hand_rotation", where), 4, f"{where}.hand_rotation", "a quaternion")
                postures[name][side] = Posture(_frozen(wrist), _frozen(rotation))
        return postures

    def calibration(self, fingers: Any, thumb: Any) -> FingerCalibration:
        columns: dict[str, list[Any]] = {k: [] for k in ("theta_flat", "theta_fist1", "theta_fist2", "max_bend", "max_splay")}
        for finger in LONG_FINGERS:
            entry = self.field(fingers, finger, "fingers")
            for key in ("theta_flat", "theta_fist1", "theta_fist2", "max_splay"):
                columns[key].append(self.number(self.field(entry, key, f"fingers.{finger}"), f"fingers.{finger}.{key}"))
            columns["max_bend"].append(self.vector(self.field(entry, "max_bend", f"fingers.{finger}"), 3, f"fingers.{finger}.max_bend"))
        table = self.field(thumb, "positions", "thumb")
        postures = {
            name: _frozen(self.vector(self.field(table, name, "thumb.positions"), 5, f"thumb.positions.{name}"))
            for name in THUMB_POSTURES
        }
        return FingerCalibration(
            theta_flat=_frozen(np.array(columns["theta_flat"])),
            theta_fist1=_frozen(np.array(columns["theta_fist1"])),
            theta_fist2=_frozen(np.array(columns["theta_fist2"])),
            max_bend=_frozen(np.array(columns["max_bend"])),
            max_splay=_frozen(np.array(columns["max_splay"])),
            thumb_max_bend=_frozen(self.vector(self.field(thumb, "max_bend", "thumb"), 2, "thumb.max_bend")),
            thumb_postures=postures,
        )


_SHAPE_NAMES = {Capsule: "capsule", Ellipsoid: "ellipsoid", EllipticCylinder: "elliptic_cylinder"}


def _frozen(array: np.ndarray) -> np.ndarray:
    array = np.array(array)
    array.flags.writeable = False
    return array


def _rest_positions(parents: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    positions = np.zeros_like(offsets)
    for joint, parent in enumerate(parents):
        positions[joint] = offsets[joint] + (positions[parent] if parent >= 0 else 0.0)
    return positions


def _levels(parents: np.ndarray) -> tuple[np.ndarray, ...]:
    depth = np.zeros(len(parents), dtype=int)
    for joint, parent in enumerate(parents):
        depth[joint] = depth[parent] + 1 if parent >= 0 else 0
    return tuple(_frozen(np.flatnonzero(depth == d)) for d in range(int(depth.max()) + 1))


def _unit(vector: np.ndarray) -> np.ndarray:
    return vector / np.linalg.norm(vector)


def _hand_frame(side: str, names: tuple[str, ...], offsets: np.ndarray, rest: np.ndarray) -> HandFrame:
    """Hand axes from the rest geometry: λ toward the middle finger's base, the thumb side
    from the little finger's base toward the index's, the palm normal by handedness."""
    at = {name: rest[i] for i, name in enumerate(names)}
    wrist = at[f"{side}_wrist"]
    finger_axis = _unit(at[f"{side}_middle1"] - wrist)
    across = at[f"{side}_index1"] - at[f"{side}_pinky1"]
    thumb_side = _unit(across - finger_axis * float(across @ finger_axis))
    handedness = 1.0 if side == "l" else -1.0
    palm_normal = handedness * np.cross(finger_axis, thumb_side)
    return HandFrame(
        finger_axis=_frozen(finger_axis),
        thumb_side=_frozen(thumb_side),
        palm_normal=_frozen(palm_normal),
        bend_axis=_frozen(np.cross(finger_axis, palm_normal)),
        splay_axis=_frozen(np.cross(finger_axis, thumb_side)),
        twist_axis=_frozen(handedness * finger_axis),
        thumb_axis=_frozen(_unit(offsets[names.index(f"{side}_thumb2")])),
    )
