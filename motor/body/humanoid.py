"""Users' own avatars: VRM 0.x / 1.0 and glTF humanoids read into mura avatars.

A file is a usable humanoid when its skeleton names the bones mura drives: through VRM's
humanoid bone map (``extensions.VRM.humanoid.humanBones`` in VRM 0.x,
``extensions.VRMC_vrm.humanoid.humanBones`` in VRM 1.0), or, in a plain glTF, by node name —
mura's H-Anim names (``l_shoulder``, ``l_index1`` …) or Mixamo's (``mixamorig:LeftArm``,
``LeftHandIndex1`` …; the ``mixamorig`` prefix is optional). See :data:`VRM_TO_HANIM` and
:data:`MIXAMO_TO_VRM` for the tables.

mura reads the rest pose (each node's rest translation and rotation), takes the bones'
positions, and normalises the rest pose to mura's (straight arms hanging at the sides,
palms facing the thighs, thumbs forward, fingers straight and parallel), rotating each
bone as :mod:`motor.body.rest_pose` does. The motion is computed for this body's own
proportions; ``rest_corrections`` are the rotations that carry mura's rest frames onto the
file's, which the viewer and the glTF exporter use to pose the file's own bones. When
the file has a skinned mesh it is re-posed with its weights and measured for body
locations and collision volumes (:mod:`motor.body.definition`); what could not be
measured is said in ``Definition.guessed``.

Refused, with what is missing: a file without a humanoid map or recognisable bone names,
without arms or hands or fingers. Warned: proportions far from human.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from motor.body.conventions import AvatarError
from motor.body.definition import Body, Definition, Skin, derive_definition
from motor.body.rest_pose import normalised_rest

#: VRM humanoid bone -> H-Anim joint (VRM 1.0 names; VRM 0.x thumbs are translated first).
VRM_TO_HANIM: dict[str, str] = {
    "hips": "humanoid_root", "spine": "vl5", "chest": "vl1", "upperChest": "vt6", "neck": "vc7", "head": "skullbase",
}  # fmt: skip
for _side, _prefix in (("left", "l"), ("right", "r")):
    VRM_TO_HANIM.update({
        f"{_side}Shoulder": f"{_prefix}_sternoclavicular", f"{_side}UpperArm": f"{_prefix}_shoulder",
        f"{_side}LowerArm": f"{_prefix}_elbow", f"{_side}Hand": f"{_prefix}_wrist",
        f"{_side}ThumbMetacarpal": f"{_prefix}_thumb1", f"{_side}ThumbProximal": f"{_prefix}_thumb2", f"{_side}ThumbDistal": f"{_prefix}_thumb3",
        f"{_side}UpperLeg": f"{_prefix}_hip", f"{_side}LowerLeg": f"{_prefix}_knee", f"{_side}Foot": f"{_prefix}_ankle",
        f"{_side}Toes": f"{_prefix}_metatarsal", f"{_side}Eye": f"{_prefix}_eyeball_joint",
    })  # fmt: skip
    for _finger, _name in (("Index", "index"), ("Middle", "middle"), ("Ring", "ring"), ("Little", "pinky")):
        VRM_TO_HANIM.update({f"{_side}{_finger}Proximal": f"{_prefix}_{_name}1", f"{_side}{_finger}Intermediate": f"{_prefix}_{_name}2",
                             f"{_side}{_finger}Distal": f"{_prefix}_{_name}3"})  # fmt: skip
#: VRM 0.x thumb names -> VRM 1.0.
VRM0_THUMBS = {f"{s}Thumb{a}": f"{s}Thumb{b}" for s in ("left", "right")
               for a, b in (("Proximal", "Metacarpal"), ("Intermediate", "Proximal"))}  # fmt: skip
#: Mixamo node names (without ``mixamorig:``) -> VRM 1.0 bone names.
MIXAMO_TO_VRM: dict[str, str] = {"Hips": "hips", "Spine": "spine", "Spine1": "chest", "Spine2": "upperChest", "Neck": "neck", "Head": "head"}
for _side, _mixamo in (("left", "Left"), ("right", "Right")):
    MIXAMO_TO_VRM.update({
        f"{_mixamo}Shoulder": f"{_side}Shoulder", f"{_mixamo}Arm": f"{_side}UpperArm", f"{_mixamo}ForeArm": f"{_side}LowerArm",
        f"{_mixamo}Hand": f"{_side}Hand", f"{_mixamo}UpLeg": f"{_side}UpperLeg", f"{_mixamo}Leg": f"{_side}LowerLeg",
        f"{_mixamo}Foot": f"{_side}Foot", f"{_mixamo}ToeBase": f"{_side}Toes", f"{_mixamo}Eye": f"{_side}Eye",
        f"{_mixamo}HandThumb1": f"{_side}ThumbMetacarpal", f"{_mixamo}HandThumb2": f"{_side}ThumbProximal",
        f"{_mixamo}HandThumb3": f"{_side}ThumbDistal",
    })  # fmt: skip
    for _finger, _vrm in (("Index", "Index"), ("Middle", "Middle"), ("Ring", "Ring"), ("Pinky", "Little")):
        MIXAMO_TO_VRM.update({f"{_mixamo}Hand{_finger}{k}": f"{_side}{_vrm}{seg}" for k, seg in ((1, "Proximal"), (2, "Intermediate"), (3, "Distal"))})

#: Bones a humanoid must have (VRM names).
REQUIRED: tuple[str, ...] = ("hips", "spine", "head") + tuple(
    f"{side}{bone}" for side in ("left", "right")
    for bone in ("UpperArm", "LowerArm", "Hand", "ThumbMetacarpal", "ThumbProximal", "ThumbDistal",
                 *(f"{f}{s}" for f in ("Index", "Middle", "Ring", "Little") for s in ("Proximal", "Intermediate", "Distal")))
)  # fmt: skip


class HumanoidError(AvatarError):
    """A file that is not a usable humanoid; the message names the file and what is missing."""


@dataclass(frozen=True, eq=False)
class Humanoid:
    """A humanoid read from a file.

    Attributes:
        path: the file.
        kind: ``"vrm0"``, ``"vrm1"``, ``"hanim"`` or ``"mixamo"``.
        vrm_bones: H-Anim joint -> VRM bone name of every mapped joint.
        nodes: H-Anim joint -> node index of every mapped joint.
        definition: the mura avatar definition derived from it.
        rotations: H-Anim joint -> the rotation R taking the file's rest frame to mura's
            (``rest_corrections`` are their inverses).
        node_rest: ``(N, 4)`` rest local rotation of every node; ``node_parents (N,)``.
        node_world: ``(N, 4)`` rest global rotation of every node.
        scale: metres per file unit of the root's translation (1 for glTF).
    """

    path: Path
    kind: str
    vrm_bones: dict[str, str]
    nodes: dict[str, int]
    definition: Definition
    rotations: dict[str, Rotation]
    node_rest: np.ndarray
    node_parents: np.ndarray
    node_world: np.ndarray
    joint_names: tuple[str, ...]

    def rest_corrections(self) -> dict[str, list[float]]:
        """H-Anim joint -> C = R⁻¹ (x, y, z, w) of every mapped joint."""
        return {joint: [round(float(v), 7) for v in self.rotations[joint].inv().as_quat()] for joint in self.vrm_bones}

    def mapped_parents(self) -> dict[str, str | None]:
        """Mapped joint -> its nearest mapped ancestor in mura's skeleton (None for the root)."""
        parents = {j["name"]: j["parent"] for j in self.definition.document["joints"]}
        out: dict[str, str | None] = {}
        for joint in self.vrm_bones:
            parent = parents[joint]
            while parent is not None and parent not in self.vrm_bones:
                parent = parents[parent]
            out[joint] = parent
        return out


def _gltf(path: Path):
    from pygltflib import GLTF2  # read-only use; only user avatars need it

    try:
        if path.suffix.lower() == ".gltf":
            return GLTF2().load_json(str(path))
        if path.read_bytes()[:4] != b"glTF":
            raise ValueError("no GLB header (a .vrm/.glb file starts with 'glTF')")
        return GLTF2().load_binary(str(path))
    except Exception as error:  # noqa: BLE001 - any failure to parse is "not a glTF file"
        raise HumanoidError(f"{path.name}: not a readable glTF/VRM file ({type(error).__name__}: {error})") from None


def _bone_map(gltf, path: Path) -> tuple[str, dict[str, int]]:
    """Which naming the file uses, and VRM bone name -> node index."""
    extensions = gltf.extensions or {}
    if "VRMC_vrm" in extensions:
        bones = extensions["VRMC_vrm"].get("humanoid", {}).get("humanBones", {})
        return "vrm1", {name: int(entry["node"]) for name, entry in bones.items() if isinstance(entry, dict) and "node" in entry}
    if "VRM" in extensions:
        bones = extensions["VRM"].get("humanoid", {}).get("humanBones", [])
        mapping = {VRM0_THUMBS.get(b.get("bone"), b.get("bone")): int(b["node"]) for b in bones if isinstance(b, dict) and b.get("node", -1) >= 0}
        if not mapping:
            raise HumanoidError(f"{path.name}: a VRM without humanoid bones (extensions.VRM.humanoid.humanBones is empty)")
        return "vrm0", mapping
    names = {node.name: index for index, node in enumerate(gltf.nodes) if node.name}
    hanim = {vrm: names[joint] for vrm, joint in VRM_TO_HANIM.items() if joint in names}
    stripped = {name.split(":")[-1]: index for name, index in names.items()}
    mixamo = {vrm: stripped[m] for m, vrm in MIXAMO_TO_VRM.items() if m in stripped}
    if not hanim and not mixamo:
        raise HumanoidError(f"{path.name}: no humanoid bones: neither a VRM humanoid map nor H-Anim or Mixamo node names "
                            "(see `mura avatar check` and the README)")  # fmt: skip
    return ("hanim", hanim) if len(hanim) >= len(mixamo) else ("mixamo", mixamo)


def _node_rest(gltf) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Per node: parent, local translation, local rotation; global position and rotation at rest."""
    count = len(gltf.nodes)
    parents = np.full(count, -1)
    for index, node in enumerate(gltf.nodes):
        for child in node.children or []:
            parents[child] = index
    translation = np.zeros((count, 3))
    rotation = np.tile([0.0, 0.0, 0.0, 1.0], (count, 1))
    scale = np.ones((count, 3))
    for index, node in enumerate(gltf.nodes):
        if node.matrix:
            matrix = np.array(node.matrix, dtype=float).reshape(4, 4).T
            translation[index] = matrix[:3, 3]
            scale[index] = np.linalg.norm(matrix[:3, :3], axis=0)
            rotation[index] = Rotation.from_matrix(matrix[:3, :3] / scale[index]).as_quat()
        else:
            translation[index] = node.translation or (0.0, 0.0, 0.0)
            rotation[index] = node.rotation or (0.0, 0.0, 0.0, 1.0)
            scale[index] = node.scale or (1.0, 1.0, 1.0)
    world_p = np.zeros((count, 3))
    world_r = [Rotation.identity()] * count
    world_s = np.ones((count, 3))
    for index in _parents_first(parents):
        parent = parents[index]
        local = Rotation.from_quat(rotation[index])
        if parent < 0:
            world_p[index], world_r[index], world_s[index] = translation[index], local, scale[index]
        else:
            world_p[index] = world_p[parent] + world_r[parent].apply(world_s[parent] * translation[index])
            world_r[index] = world_r[parent] * local
            world_s[index] = world_s[parent] * scale[index]
    return parents, translation, rotation, world_p, Rotation.concatenate(world_r).as_quat()


def _parents_first(parents: np.ndarray) -> list[int]:
    order = [i for i in range(len(parents)) if parents[i] < 0]
    for index in order:
        order.extend(int(c) for c in np.flatnonzero(parents == index))
    return order


@functools.lru_cache(maxsize=8)
def read_humanoid(path: str | Path) -> Humanoid:
    """Read and normalise a humanoid (cached per path; the file is not expected to change
    while mura runs)."""
    path = Path(path)
    if not path.is_file():
        raise HumanoidError(f"{path}: no such file")
    gltf = _gltf(path)
    kind, bones = _bone_map(gltf, path)
    missing = [bone for bone in REQUIRED if bone not in bones]
    if missing:
        arms = [b for b in missing if "Arm" in b or b.endswith("Hand")]
        what = "no arms or hands" if arms else "bones missing"
        raise HumanoidError(f"{path.name}: not a usable humanoid ({what}): missing {', '.join(missing[:8])}"
                            + (f" and {len(missing) - 8} more" if len(missing) > 8 else ""))  # fmt: skip
    parents, _, node_rest, node_p, node_r = _node_rest(gltf)
    if kind == "vrm0":  # VRM 0.x faces -z: turn it to face +z like mura (and VRM 1.0)
        turn = Rotation.from_euler("y", np.pi)
        node_p = turn.apply(node_p)
        node_r = (turn * Rotation.from_quat(node_r)).as_quat()
    positions = {VRM_TO_HANIM[bone]: node_p[node] for bone, node in bones.items() if bone in VRM_TO_HANIM}
    floor = float(-node_p[:, 1].min()) if node_p[:, 1].min() < 0 else 0.0
    skeleton = _skeleton(positions, path)
    rest = normalised_rest(skeleton.names, skeleton.parents, skeleton.positions, {})
    root = rest.positions[0]
    skin, crown, warnings = _skin(gltf, path, bones, kind, skeleton, rest)
    floor = float(root[1] - (skin.floor if skin is not None else 0.0))
    body = Body(
        name=path.stem, joint_names=skeleton.names, parents=tuple(int(p) for p in skeleton.parents),
        positions=rest.positions - root, floor=floor, tips={k: v - root for k, v in rest.tips.items()},
        crown=None if crown is None else crown - root[1],
        skin=None if skin is None else Skin(skin.vertices - root, skin.owner),
        description=f"User avatar read from {path.name} ({kind}).",
    )  # fmt: skip
    definition = derive_definition(body)
    guessed = list(definition.guessed) + skeleton.guessed + warnings
    definition = Definition(definition.document, tuple(dict.fromkeys(guessed)), definition.warnings)
    mapped = {VRM_TO_HANIM[b]: b for b in bones if b in VRM_TO_HANIM and VRM_TO_HANIM[b] in skeleton.names}
    return Humanoid(
        path=path, kind=kind, vrm_bones=mapped, nodes={VRM_TO_HANIM[b]: n for b, n in bones.items() if b in VRM_TO_HANIM},
        definition=definition, rotations={name: rest.rotations[i] for i, name in enumerate(skeleton.names)},
        node_rest=node_rest, node_parents=parents, node_world=node_r, joint_names=skeleton.names,
    )  # fmt: skip


def humanoid_definition(path: str | Path) -> Definition:
    """The mura avatar definition of a VRM/glTF humanoid; raises :class:`HumanoidError`."""
    return read_humanoid(Path(path).resolve()).definition


@dataclass(frozen=True, eq=False)
class _Skeleton:
    names: tuple[str, ...]
    parents: np.ndarray
    positions: np.ndarray
    guessed: list[str]


def _skeleton(found: dict[str, np.ndarray], path: Path) -> _Skeleton:
    """mura's joints from the mapped bones: the spine filled in between hips, spine, chest,
    upper chest, neck and head; ring and little-finger metacarpals (which VRM lacks)
    placed on the way to their knuckles."""
    guessed: list[str] = []
    at = dict(found)
    hips, head = at["humanoid_root"], at["skullbase"]
    if "vl1" not in at:
        at["vl1"] = at["vl5"] + 0.45 * (head - at["vl5"])
        guessed.append("chest: between spine and head")
    if "vc7" not in at:
        at["vc7"] = at["vl1"] + 0.75 * (head - at["vl1"])
        guessed.append("neck: between chest and head")
    upper = at.get("vt6", at["vl1"] + 0.5 * (at["vc7"] - at["vl1"]))
    at.setdefault("vt6", upper)
    at["sacroiliac"] = hips + 0.35 * (at["vl5"] - hips)
    at["vl3"] = at["vl5"] + 0.5 * (at["vl1"] - at["vl5"])
    at["vt10"] = at["vl1"] + 0.5 * (at["vt6"] - at["vl1"])
    at["vt1"] = at["vt6"] + 0.6 * (at["vc7"] - at["vt6"])
    at["vc4"] = at["vc7"] + 0.5 * (head - at["vc7"])
    for side in ("l", "r"):
        if f"{side}_sternoclavicular" not in at:
            at[f"{side}_sternoclavicular"] = at["vt1"] + 0.25 * (at[f"{side}_shoulder"] - at["vt1"])
            guessed.append(f"{side}_sternoclavicular: a quarter of the way from the upper spine to the shoulder")
        for finger in ("ring", "pinky"):
            at[f"{side}_{finger}0"] = at[f"{side}_wrist"] + 0.3 * (at[f"{side}_{finger}1"] - at[f"{side}_wrist"])
        guessed.append(f"{side} ring and little-finger metacarpal joints: 0.3 of the way from wrist to knuckle")
    names, parents = [], []
    for name, parent in _TREE:
        if name in at:
            names.append(name)
            parents.append(-1 if parent is None else names.index(parent))
    return _Skeleton(tuple(names), np.array(parents), np.array([at[n] for n in names]), guessed)


def _tree() -> tuple[tuple[str, str | None], ...]:
    spine = ("humanoid_root", "sacroiliac", "vl5", "vl3", "vl1", "vt10", "vt6", "vt1", "vc7", "vc4", "skullbase")
    tree: list[tuple[str, str | None]] = [(name, None if i == 0 else spine[i - 1]) for i, name in enumerate(spine)]
    for s in ("l", "r"):
        tree += [(f"{s}_sternoclavicular", "vt1"), (f"{s}_shoulder", f"{s}_sternoclavicular"), (f"{s}_elbow", f"{s}_shoulder"),
                 (f"{s}_wrist", f"{s}_elbow"), (f"{s}_thumb1", f"{s}_wrist"), (f"{s}_thumb2", f"{s}_thumb1"), (f"{s}_thumb3", f"{s}_thumb2")]  # fmt: skip
        for finger, base in (("index", f"{s}_wrist"), ("middle", f"{s}_wrist"), ("ring", f"{s}_ring0"), ("pinky", f"{s}_pinky0")):
            if finger in ("ring", "pinky"):
                tree.append((f"{s}_{finger}0", f"{s}_wrist"))
            tree += [(f"{s}_{finger}1", base), (f"{s}_{finger}2", f"{s}_{finger}1"), (f"{s}_{finger}3", f"{s}_{finger}2")]
        tree += [(f"{s}_hip", "humanoid_root"), (f"{s}_knee", f"{s}_hip"), (f"{s}_ankle", f"{s}_knee"),
                 (f"{s}_metatarsal", f"{s}_ankle"), (f"{s}_eyeball_joint", "skullbase")]  # fmt: skip
    return tuple(tree)


_TREE = _tree()


@dataclass(frozen=True, eq=False)
class _PosedSkin:
    vertices: np.ndarray
    owner: np.ndarray
    floor: float


def _skin(gltf, path: Path, bones: dict[str, int], kind: str, skeleton: _Skeleton, rest) -> tuple[_PosedSkin | None, float | None, list[str]]:
    """The file's skinned mesh at rest, re-posed into mura's rest pose; its crown height."""
    notes: list[str] = []
    skinned = [(node, gltf.skins[node.skin]) for node in gltf.nodes if node.mesh is not None and node.skin is not None]
    if not skinned:
        has_mesh = any(node.mesh is not None for node in gltf.nodes)
        notes.append(f"{path.name}: {'a mesh without a skin' if has_mesh else 'no mesh'}: locations and volumes by proportions")
        return None, None, notes
    parents, _, _, node_p, node_r = _node_rest(gltf)
    node_of_joint = {node: VRM_TO_HANIM[bone] for bone, node in bones.items() if bone in VRM_TO_HANIM and VRM_TO_HANIM[bone] in skeleton.names}
    index = {name: i for i, name in enumerate(skeleton.names)}
    all_vertices, all_owner = [], []
    world = np.zeros((len(gltf.nodes), 4, 4))
    for i in range(len(gltf.nodes)):
        world[i] = np.eye(4)
        world[i][:3, :3] = Rotation.from_quat(node_r[i]).as_matrix()
        world[i][:3, 3] = node_p[i]
    for node, skin in skinned:
        inverse = _accessor(gltf, skin.inverseBindMatrices).reshape(-1, 4, 4).transpose(0, 2, 1) if skin.inverseBindMatrices is not None else np.tile(np.eye(4), (len(skin.joints), 1, 1))
        mats = world[np.array(skin.joints)] @ inverse
        owners = np.array([_mapped_ancestor(j, parents, node_of_joint, index) for j in skin.joints])
        for primitive in gltf.meshes[node.mesh].primitives:
            attributes = primitive.attributes
            if attributes.POSITION is None or attributes.JOINTS_0 is None or attributes.WEIGHTS_0 is None:
                continue
            position = _accessor(gltf, attributes.POSITION)
            joints = _accessor(gltf, attributes.JOINTS_0).astype(int)
            weights = _accessor(gltf, attributes.WEIGHTS_0)
            homogeneous = np.concatenate([position, np.ones((len(position), 1))], axis=1)
            placed = np.einsum("vk,vkab,vb->va", weights, mats[joints], homogeneous)[:, :3]
            strongest = owners[joints[np.arange(len(joints)), np.argmax(weights, axis=1)]]
            all_vertices.append(placed)
            all_owner.append(strongest)
    if not all_vertices:
        notes.append(f"{path.name}: the skinned mesh has no joints or weights: locations and volumes by proportions")
        return None, None, notes
    vertices = np.concatenate(all_vertices)
    owner = np.concatenate(all_owner)
    if kind == "vrm0":
        vertices = Rotation.from_euler("y", np.pi).apply(vertices)
    floor = float(vertices[:, 1].min())
    matrices = rest.rotations.as_matrix()
    valid = owner >= 0
    moved = vertices.copy()
    moved[valid] = np.einsum("vab,vb->va", matrices[owner[valid]], vertices[valid] - skeleton.positions[owner[valid]]) + rest.positions[owner[valid]]
    crown = float(moved[owner == index["skullbase"], 1].max()) if np.any(owner == index["skullbase"]) else None
    return _PosedSkin(moved[valid], owner[valid], floor), crown, notes


def _mapped_ancestor(node: int, parents: np.ndarray, mapped: dict[int, str], index: dict[str, int]) -> int:
    while node >= 0:
        if node in mapped:
            return index[mapped[node]]
        node = int(parents[node])
    return -1


def _accessor(gltf, accessor_index: int) -> np.ndarray:
    """An accessor's data as a float or int array ``(count, components)`` (sparse not supported here)."""
    accessor = gltf.accessors[accessor_index]
    view = gltf.bufferViews[accessor.bufferView]
    data = gltf.get_data_from_buffer_uri(gltf.buffers[view.buffer].uri) if gltf.buffers[view.buffer].uri else gltf.binary_blob()
    dtype = {5126: "<f4", 5125: "<u4", 5123: "<u2", 5121: "u1", 5122: "<i2", 5120: "i1"}[accessor.componentType]
    width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}[accessor.type]
    itemsize = np.dtype(dtype).itemsize
    stride = view.byteStride or itemsize * width
    start = (view.byteOffset or 0) + (accessor.byteOffset or 0)
    raw = np.frombuffer(data, dtype=np.uint8, count=stride * (accessor.count - 1) + itemsize * width, offset=start)
    rows = np.lib.stride_tricks.as_strided(raw, shape=(accessor.count, itemsize * width), strides=(stride, 1))
    values = np.frombuffer(np.ascontiguousarray(rows).tobytes(), dtype=dtype).reshape(accessor.count, width).astype(float)
    if accessor.normalized:
        values = values / float(np.iinfo(np.dtype(dtype)).max)
    return values


def retarget(humanoid: Humanoid, joint_names: tuple[str, ...], avatar_parents: np.ndarray, locals_: np.ndarray) -> tuple[tuple[int, ...], np.ndarray]:
    """Node rotations of the file's own nodes for mura local rotations ``(n, J, 4)`` of
    the avatar's joints ``joint_names`` (parents ``avatar_parents``).

    Each mapped node's posed global rotation is ``W · R · G0`` (W mura's global rotation of
    its joint, R the rest normalisation, G0 the node's rest global rotation); other nodes
    keep their rest local rotation. Returns the nodes driven and ``(n, len(nodes), 4)``.
    """
    frames, joints = locals_.shape[:2]
    world = np.empty_like(locals_)
    for joint in range(joints):  # over joints; each step is vectorized over frames
        parent = avatar_parents[joint]
        q = Rotation.from_quat(locals_[:, joint].reshape(-1, 4))
        world[:, joint] = q.as_quat() if parent < 0 else (Rotation.from_quat(world[:, parent]) * q).as_quat()
    joint_index = {name: i for i, name in enumerate(joint_names)}
    turn = Rotation.from_euler("y", np.pi) if humanoid.kind == "vrm0" else Rotation.identity()
    count = len(humanoid.node_parents)
    node_global: list[Rotation | None] = [None] * count
    driven = {node: joint for joint, node in humanoid.nodes.items() if joint in joint_index}
    out_nodes, out = [], []
    for node in _parents_first(humanoid.node_parents):
        parent = humanoid.node_parents[node]
        rest_world = turn * Rotation.from_quat(humanoid.node_world[node])
        if node in driven:
            joint = driven[node]
            posed = Rotation.from_quat(world[:, joint_index[joint]]) * humanoid.rotations[joint] * rest_world
        elif parent < 0:
            posed = Rotation.concatenate([rest_world] * frames) if frames else rest_world
        else:
            posed = node_global[parent] * Rotation.from_quat(humanoid.node_rest[node])
        node_global[node] = posed
        if node in driven:
            parent_global = node_global[parent] if parent >= 0 else Rotation.concatenate([turn] * frames)
            local = parent_global.inv() * posed if parent >= 0 else turn.inv() * posed
            out_nodes.append(node)
            out.append(local.as_quat())
    return tuple(out_nodes), np.stack(out, axis=1) if out else np.zeros((frames, 0, 4))
