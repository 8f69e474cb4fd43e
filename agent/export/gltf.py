"""glTF 2.0 binary (GLB) export: avatars and their animation, for Blender, three.js and the page.

Two files are made here:

* :func:`write_avatar_glb` — a skinned avatar at rest (``build/avatars/NAME.glb``): joint
  nodes named with H-Anim names, identity rest rotations and translations equal to the
  bone offsets (so a mura local rotation *is* the node rotation), the mesh bound to them
  (inverse bind matrices are pure translations), and face units as morph targets named as
  ARKit blendshapes (``mesh.extras.targetNames``, which three.js reads).
* :class:`GlbAnimation` / :func:`write_motion_glb` — ``NAME.glb`` beside ``NAME.bvh``: the
  performance's avatar with one animation: a rotation channel per joint (linear, the
  Motion's frames), the root's translation (the Motion's: the root stands at its height
  above the floor, y = 0), and a ``weights`` channel for the face when the Motion carries face weights.
  Without a model (the light test avatars ``max`` and ``kim``) the file holds the
  skeleton alone; with a user's VRM/glTF the rotations are retargeted onto its own nodes
  (:mod:`motor.body.humanoid`).

Frames are collected in a scratch file as they come (``add``), and each channel is copied
from it when the file is written, so memory does not grow with the length.
"""

from __future__ import annotations

import functools
import io
import json
import os
import struct
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from agent.export.staging import ScratchRows, staged_binary
from motor.body.avatar import Avatar
from motor.body.skinned import SkinnedBody
from motor.motion import Motion

GLB_MAGIC = 0x46546C67
JSON_CHUNK = 0x4E4F534A
BIN_CHUNK = 0x004E4942
FLOAT, UNSIGNED_INT, UNSIGNED_SHORT, UNSIGNED_BYTE = 5126, 5125, 5123, 5121
ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963
COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}
DTYPES = {FLOAT: "<f4", UNSIGNED_INT: "<u4", UNSIGNED_SHORT: "<u2", UNSIGNED_BYTE: "u1"}
#: Frames converted at a time when writing channels.
FRAMES_PER_BLOCK = 4096


class GltfError(ValueError):
    """A model or motion that cannot be written as glTF; the message says what and where."""


class _Document:
    """A glTF JSON document and its one binary buffer, built by appending."""

    def __init__(self, gltf: dict | None = None, blob: bytes = b"") -> None:
        self.gltf = gltf if gltf is not None else {"asset": {"version": "2.0", "generator": "mura"}}
        self.pieces: list[bytes | tuple[int, Callable[[io.RawIOBase], None]]] = []
        self.length = 0
        if blob:
            self._append(blob)

    def _append(self, data: bytes) -> int:
        padding = (-self.length) % 4
        if padding:
            self.pieces.append(b"\0" * padding)
            self.length += padding
        offset = self.length
        self.pieces.append(data)
        self.length += len(data)
        return offset

    def _view(self, offset: int, length: int, target: int | None) -> int:
        views = self.gltf.setdefault("bufferViews", [])
        view = {"buffer": 0, "byteOffset": offset, "byteLength": length}
        if target is not None:
            view["target"] = target
        views.append(view)
        return len(views) - 1

    def view(self, data: bytes, target: int | None = None) -> int:
        return self._view(self._append(data), len(data), target)

    def deferred_view(self, length: int, write: Callable[[io.RawIOBase], None]) -> int:
        """A view whose ``length`` bytes ``write`` produces when the file is written."""
        padding = (-self.length) % 4
        if padding:
            self.pieces.append(b"\0" * padding)
            self.length += padding
        offset = self.length
        self.pieces.append((length, write))
        self.length += length
        return self._view(offset, length, None)

    def accessor(self, array: np.ndarray, kind: str, component: int, target: int | None = None,
                 bounds: bool = False, normalized: bool = False) -> int:  # fmt: skip
        data = np.ascontiguousarray(array, dtype=DTYPES[component])
        entry = {"bufferView": self.view(data.tobytes(), target), "componentType": component,
                 "count": int(data.shape[0]), "type": kind}  # fmt: skip
        if normalized:
            entry["normalized"] = True
        if bounds:
            flat = data.reshape(data.shape[0], -1)
            entry["min"] = [float(v) for v in flat.min(axis=0)]
            entry["max"] = [float(v) for v in flat.max(axis=0)]
        return self._add_accessor(entry)

    def sparse_accessor(self, count: int, indices: np.ndarray, values: np.ndarray) -> int:
        """A VEC3 float accessor of ``count`` zeros except ``values`` at ``indices``."""
        index_view = self.view(np.ascontiguousarray(indices, dtype="<u4").tobytes())
        value_view = self.view(np.ascontiguousarray(values, dtype="<f4").tobytes())
        entry = {
            "componentType": FLOAT, "count": count, "type": "VEC3",
            "min": [float(v) for v in np.minimum(values.min(axis=0), 0.0)],
            "max": [float(v) for v in np.maximum(values.max(axis=0), 0.0)],
            "sparse": {"count": int(len(indices)), "indices": {"bufferView": index_view, "componentType": UNSIGNED_INT},
                       "values": {"bufferView": value_view}},
        }  # fmt: skip
        return self._add_accessor(entry)

    def _add_accessor(self, entry: dict) -> int:
        accessors = self.gltf.setdefault("accessors", [])
        accessors.append(entry)
        return len(accessors) - 1

    def write(self, stream: io.RawIOBase) -> None:
        """The GLB container: header, JSON chunk, binary chunk."""
        self.length += (-self.length) % 4
        self.gltf["buffers"] = [{"byteLength": self.length}]
        text = json.dumps(self.gltf, separators=(",", ":"), allow_nan=False).encode("utf-8")
        text += b" " * ((-len(text)) % 4)
        total = 12 + 8 + len(text) + 8 + self.length
        stream.write(struct.pack("<III", GLB_MAGIC, 2, total))
        stream.write(struct.pack("<II", len(text), JSON_CHUNK) + text)
        stream.write(struct.pack("<II", self.length, BIN_CHUNK))
        written = 0
        for piece in self.pieces:
            if isinstance(piece, bytes):
                stream.write(piece)
                written += len(piece)
            else:
                length, produce = piece
                produce(stream)
                written += length
        stream.write(b"\0" * (self.length - written))


def read_glb(data: bytes, where: str) -> tuple[dict, bytes]:
    """The JSON document and binary chunk of a GLB file (``where`` names it in errors)."""
    if len(data) < 20:
        raise GltfError(f"{where}: too short to be a GLB file")
    magic, version, total = struct.unpack_from("<III", data, 0)
    if magic != GLB_MAGIC or version != 2:
        raise GltfError(f"{where}: not a glTF 2.0 binary file (magic {magic:#x}, version {version})")
    length, kind = struct.unpack_from("<II", data, 12)
    if kind != JSON_CHUNK or 20 + length > len(data):
        raise GltfError(f"{where}: the first chunk is not the JSON chunk")
    document = json.loads(data[20 : 20 + length])
    blob = b""
    offset = 20 + length
    if offset + 8 <= min(total, len(data)):
        blob_length, blob_kind = struct.unpack_from("<II", data, offset)
        if blob_kind == BIN_CHUNK:
            blob = data[offset + 8 : offset + 8 + blob_length]
    return document, blob


def write_avatar_glb(body: SkinnedBody, path: str | os.PathLike[str]) -> None:
    """Write a skinned avatar at rest as GLB (see the module docstring)."""
    document = _Document()
    gltf = document.gltf
    gltf["asset"]["copyright"] = "; ".join(body.credits) if body.credits else "mura"
    lift = np.array([0.0, body.root_height, 0.0])
    rest = body.rest_positions
    joints = len(body.joint_names)
    nodes = []
    for index, name in enumerate(body.joint_names):
        translation = lift if index == 0 else body.offsets[index]
        node = {"name": name, "translation": [float(v) for v in translation]}
        children = [child for child, parent in enumerate(body.parents) if parent == index]
        if children:
            node["children"] = children
        nodes.append(node)
    nodes.append({"name": body.name, "mesh": 0, "skin": 0})
    gltf["nodes"] = nodes
    gltf["scenes"] = [{"name": body.name, "nodes": [0, joints]}]
    gltf["scene"] = 0
    inverse_bind = np.tile(np.eye(4), (joints, 1, 1))
    inverse_bind[:, 3, :3] = -(rest + lift)  # column-major: translation in the last column
    gltf["skins"] = [{"name": body.name, "joints": list(range(joints)), "skeleton": 0,
                      "inverseBindMatrices": document.accessor(inverse_bind.reshape(joints, 16), "MAT4", FLOAT)}]  # fmt: skip
    attributes = {
        "POSITION": document.accessor(body.positions + lift, "VEC3", FLOAT, ARRAY_BUFFER, bounds=True),
        "NORMAL": document.accessor(body.normals, "VEC3", FLOAT, ARRAY_BUFFER),
        "COLOR_0": document.accessor(np.round(np.clip(body.colors, 0.0, 1.0) * 255), "VEC4", UNSIGNED_BYTE, ARRAY_BUFFER, normalized=True),
        "JOINTS_0": document.accessor(body.joints, "VEC4", UNSIGNED_BYTE if joints < 256 else UNSIGNED_SHORT, ARRAY_BUFFER),
        "WEIGHTS_0": document.accessor(body.weights, "VEC4", FLOAT, ARRAY_BUFFER),
    }
    targets = [{"POSITION": document.sparse_accessor(len(body.positions), t.indices, t.offsets)} for t in body.morph_targets]
    index_type = UNSIGNED_SHORT if len(body.positions) < 65536 else UNSIGNED_INT
    primitives, materials = [], []
    for part in body.parts:
        primitive = {"attributes": attributes, "indices": document.accessor(part.triangles.ravel(), "SCALAR", index_type, ELEMENT_ARRAY_BUFFER),
                     "material": len(materials), "mode": 4}  # fmt: skip
        if targets:
            primitive["targets"] = targets
        primitives.append(primitive)
        materials.append({"name": part.name, "doubleSided": part.name in ("eyelashes", "hair"),
                          "pbrMetallicRoughness": {"baseColorFactor": list(part.color), "metallicFactor": 0.0, "roughnessFactor": part.roughness}})  # fmt: skip
    mesh = {"name": body.name, "primitives": primitives}
    if targets:
        mesh["weights"] = [0.0] * len(targets)
        mesh["extras"] = {"targetNames": [t.name for t in body.morph_targets]}
    gltf["meshes"] = [mesh]
    gltf["materials"] = materials
    gltf["extras"] = {"mura": {"avatar": body.name, "root_height": body.root_height, "joints": list(body.joint_names)}}
    with staged_binary(path) as stream:
        document.write(stream)


@dataclass(frozen=True, eq=False)
class Binding:
    """How a Motion's joints drive a model's nodes.

    ``nodes (J,)`` the node each motion joint drives (-1: none); ``root_node`` takes the
    root translation (times ``root_scale``); ``root_height`` is the model's own root
    height at rest; ``retarget`` (optional) turns a block of local
    rotations ``(n, J, 4)`` into node rotations ``(n, len(track_nodes), 4)`` for models whose
    rest pose differs from mura's, ``track_nodes`` then naming the nodes it drives; the
    mesh node with face morph targets and their names, if any.
    """

    nodes: np.ndarray
    root_node: int
    root_height: float
    retarget: Callable[[np.ndarray], np.ndarray] | None = None
    track_nodes: tuple[int, ...] = ()
    morph_node: int | None = None
    morph_names: tuple[str, ...] = ()
    root_scale: float = 1.0


@dataclass(frozen=True, eq=False)
class AvatarModel:
    """A model file's document and binary, with the binding of a Motion onto it."""

    gltf: dict
    blob: bytes
    binding: Binding


@functools.lru_cache(maxsize=8)
def hanim_model(path: Path, joint_names: tuple[str, ...]) -> AvatarModel:
    """A GLB whose nodes carry mura's H-Anim names with identity rest rotations (what
    :func:`write_avatar_glb` makes): joints bind to nodes by name."""
    gltf, blob = read_glb(path.read_bytes(), str(path))
    by_name = {node.get("name"): i for i, node in enumerate(gltf.get("nodes", []))}
    nodes = np.array([by_name.get(name, -1) for name in joint_names])
    if nodes[0] < 0:
        raise GltfError(f"{path.name}: no node named {joint_names[0]!r} for the root joint")
    morph_node, names = None, ()
    for index, node in enumerate(gltf["nodes"]):
        mesh = gltf.get("meshes", [])[node["mesh"]] if "mesh" in node else None
        if mesh and mesh.get("extras", {}).get("targetNames"):
            morph_node, names = index, tuple(mesh["extras"]["targetNames"])
    height = float(gltf.get("extras", {}).get("mura", {}).get("root_height", 0.0))
    return AvatarModel(gltf, blob, Binding(nodes, int(nodes[0]), height, morph_node=morph_node, morph_names=names))


def skeleton_model(motion: Motion, root_height: float) -> AvatarModel:
    """A model of the Motion's skeleton alone: one node per joint at its rest offset."""
    nodes = []
    for index, name in enumerate(motion.joint_names):
        translation = [0.0, root_height, 0.0] if index == 0 else [float(v) for v in motion.offsets[index]]
        node = {"name": name, "translation": translation}
        children = [child for child, parent in enumerate(motion.parents) if parent == index]
        if children:
            node["children"] = children
        nodes.append(node)
    gltf = {"asset": {"version": "2.0", "generator": "mura"}, "nodes": nodes, "scenes": [{"nodes": [0]}], "scene": 0}
    return AvatarModel(gltf, b"", Binding(np.arange(len(nodes)), 0, root_height))


class GlbAnimation:
    """``NAME.glb`` of a performance, written from windows of frames (see the module docstring).

    ``add(window)`` appends a window's rotations, root positions and face weights to
    ``scratch`` (a file the caller owns, removed by the caller); ``write(stream)`` writes
    the model with the animation, reading each channel back from the scratch file.
    """

    def __init__(self, scratch: str | os.PathLike[str], model: AvatarModel | None = None, root_height: float = 0.0) -> None:
        self.scratch = Path(scratch)
        self.model = model
        self.root_height = root_height
        self.frame_count = 0
        self._first: Motion | None = None
        self._out = open(self.scratch, "wb")

    def add(self, window: Motion) -> None:
        if self._first is None:
            self._first = window
        elif window.joint_names != self._first.joint_names or window.fps != self._first.fps or window.face_names != self._first.face_names:
            raise GltfError(f"glTF export: the frames from frame {self.frame_count} on have another skeleton, frame rate or face")
        if not (np.all(np.isfinite(window.rotations)) and np.all(np.isfinite(window.root_translation))):
            raise GltfError(f"glTF export: non-finite rotation or root position in frames {self.frame_count}–{self.frame_count + window.frame_count}")
        faces = window.face_weights if window.face_weights is not None else np.zeros((window.frame_count, 0))
        row = np.concatenate([window.rotations.reshape(window.frame_count, -1), window.root_translation, faces], axis=1)
        self._out.write(np.ascontiguousarray(row, dtype="<f8").tobytes())
        self.frame_count += window.frame_count

    def close(self) -> None:
        if not self._out.closed:
            self._out.close()

    def write(self, stream: io.RawIOBase) -> None:
        self.close()
        if self._first is None:
            raise GltfError("glTF export: no frames were added")
        first = self._first
        joints, faces = len(first.joint_names), len(first.face_names)
        frames = ScratchRows(self.scratch, self.frame_count, 4 * joints + 3 + faces, "<f8")
        model = self.model or skeleton_model(first, self.root_height)
        document = _Document(json.loads(json.dumps(model.gltf)), model.blob)
        _add_animation(document, model.binding, first, frames, joints, faces)
        document.write(stream)


def write_motion_glb(motion: Motion, path: str | os.PathLike[str], model: AvatarModel | None = None, root_height: float = 0.0) -> None:
    """Write ``motion`` on ``model`` (or on its bare skeleton) as ``path``; the file
    appears only when complete."""
    path = Path(path)
    scratch = path.with_name(f".{path.name}.frames.part")
    try:
        animation = GlbAnimation(scratch, model, root_height)
        animation.add(motion)
        with staged_binary(path) as stream:
            animation.write(stream)
    finally:
        scratch.unlink(missing_ok=True)


def _add_animation(document: _Document, binding: Binding, first: Motion, frames: ScratchRows, joints: int, faces: int) -> None:
    count = frames.shape[0]
    if count == 0:
        return
    times = np.arange(count, dtype=np.float64) / first.fps
    time_accessor = document.accessor(times, "SCALAR", FLOAT, bounds=True)
    channels, samplers = [], []

    def channel(node: int, path: str, kind: str, width: int, produce: Callable[[np.ndarray], np.ndarray]) -> None:
        def write(stream: io.RawIOBase) -> None:
            for start in range(0, count, FRAMES_PER_BLOCK):
                block = np.asarray(frames[start : start + FRAMES_PER_BLOCK])
                stream.write(np.ascontiguousarray(produce(block), dtype="<f4").tobytes())

        view = document.deferred_view(4 * width * count, write)
        elements = count * width // COMPONENTS[kind]  # weights: one scalar per target per frame
        accessor = document._add_accessor({"bufferView": view, "componentType": FLOAT, "count": elements, "type": kind})
        samplers.append({"input": time_accessor, "output": accessor, "interpolation": "LINEAR"})
        channels.append({"sampler": len(samplers) - 1, "target": {"node": int(node), "path": path}})

    if binding.retarget is None:
        for joint in range(joints):
            node = int(binding.nodes[joint])
            if node >= 0:
                channel(node, "rotation", "VEC4", 4, lambda block, j=joint: _hemisphere(block[:, 4 * j : 4 * j + 4]))
    else:
        for k, node in enumerate(binding.track_nodes):
            channel(node, "rotation", "VEC4", 4,
                    lambda block, k=k: _hemisphere(binding.retarget(block[:, : 4 * joints].reshape(-1, joints, 4))[:, k]))  # fmt: skip
    if binding.root_node >= 0:
        channel(binding.root_node, "translation", "VEC3", 3, lambda block: block[:, 4 * joints : 4 * joints + 3] * binding.root_scale)
    if binding.morph_node is not None and faces and binding.morph_names:
        columns = [first.face_names.index(name) if name in first.face_names else -1 for name in binding.morph_names]
        picks = np.array(columns)

        def weights(block: np.ndarray) -> np.ndarray:
            face = block[:, 4 * joints + 3 :]
            values = np.where(picks >= 0, face[:, np.maximum(picks, 0)], 0.0)
            return np.clip(values, 0.0, 1.0).ravel()

        channel(binding.morph_node, "weights", "SCALAR", len(picks), weights)
    animations = document.gltf.setdefault("animations", [])
    animations.append({"name": "mura", "channels": channels, "samplers": samplers})


def _hemisphere(quaternions: np.ndarray) -> np.ndarray:
    """Unit quaternions (normalized), their sign unchanged (glTF slerps the shorter way)."""
    norms = np.linalg.norm(quaternions, axis=-1, keepdims=True)
    return quaternions / np.maximum(norms, 1e-12)


def motion_model(avatar: Avatar) -> AvatarModel | None:
    """The model a performance on ``avatar`` is exported on: the built skinned GLB beside
    its definition, the user's VRM/glTF (retargeted), or None for skeleton-only avatars."""
    source = Path(avatar.source)
    suffix = source.suffix.lower()
    if suffix == ".json":
        glb = source.with_suffix(".glb")
        return hanim_model(glb, avatar.joint_names) if glb.is_file() else None
    if suffix not in (".vrm", ".glb", ".gltf"):
        return None
    from pygltflib import GLTF2, BufferFormat

    from motor.body.humanoid import read_humanoid, retarget

    humanoid = read_humanoid(source.resolve())
    if suffix == ".gltf":
        loaded = GLTF2().load(str(source))
        loaded.convert_buffers(BufferFormat.BINARYBLOB)
        blob = loaded.binary_blob() or b""
        gltf = json.loads(loaded.to_json())
        for buffer in gltf.get("buffers", []):
            buffer.pop("uri", None)
    else:
        gltf, blob = read_glb(source.read_bytes(), source.name)
    parents = np.asarray(avatar.parents)
    names = avatar.joint_names
    nodes, _ = retarget(humanoid, names, parents, np.tile([0.0, 0.0, 0.0, 1.0], (1, avatar.joint_count, 1)))
    binding = Binding(
        nodes=np.full(avatar.joint_count, -1), root_node=-1, root_height=avatar.root_height,
        retarget=lambda block: retarget(humanoid, names, parents, block)[1], track_nodes=nodes,
    )  # fmt: skip
    return AvatarModel(gltf, blob, binding)
