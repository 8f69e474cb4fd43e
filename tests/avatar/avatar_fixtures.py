"""User avatars the tests make from the built default one (VRM 1.0 / Mixamo-named glTF)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from agent.export.gltf import read_glb
from motor.body.conventions import BUILT_AVATAR_DIR
from motor.body.humanoid import VRM_TO_HANIM

BUILT_GLB = BUILT_AVATAR_DIR / "makehuman.glb"
BUILT_JSON = BUILT_AVATAR_DIR / "makehuman.json"
#: The fixture's forearms and hands are longer than the built avatar's by this factor.
FOREARM_SCALE = 1.15
#: The fixture stands in a T-pose: upper arms raised this far from the built avatar's rest.
T_POSE = np.radians(80.0)


def write_glb(path: Path, gltf: dict, blob: bytes) -> Path:
    import struct

    text = json.dumps(gltf).encode()
    text += b" " * ((-len(text)) % 4)
    blob += b"\0" * ((-len(blob)) % 4)
    total = 12 + 8 + len(text) + 8 + len(blob)
    path.write_bytes(struct.pack("<III", 0x46546C67, 2, total) + struct.pack("<II", len(text), 0x4E4F534A) + text
                     + struct.pack("<II", len(blob), 0x004E4942) + blob)  # fmt: skip
    return path


def make_vrm(built: tuple[dict, bytes], path: Path, naming: str = "vrm1", t_pose: bool = True, drop: tuple[str, ...] = ()) -> Path:
    """A user avatar made from the built one (same mesh and weights): bones renamed to VRM
    humanoid bones (``vrm1``) or Mixamo names (``mixamo``), forearms longer, arms raised
    into a T-pose at rest; ``drop`` removes humanoid bones from the map/names."""
    gltf, blob = json.loads(json.dumps(built[0])), built[1]
    by_name = {node["name"]: i for i, node in enumerate(gltf["nodes"])}
    human = {}
    for vrm, joint in VRM_TO_HANIM.items():
        if joint in by_name and vrm not in drop:
            human[vrm] = {"node": by_name[joint]}
    for side in ("l", "r"):
        for joint in (f"{side}_wrist",):
            node = gltf["nodes"][by_name[joint]]
            node["translation"] = [v * FOREARM_SCALE for v in node["translation"]]
        if t_pose:
            sign = 1.0 if side == "l" else -1.0
            node = gltf["nodes"][by_name[f"{side}_shoulder"]]
            node["rotation"] = [float(v) for v in Rotation.from_rotvec([0.0, 0.0, sign * T_POSE]).as_quat()]
    if naming == "mixamo":
        from motor.body.humanoid import MIXAMO_TO_VRM

        vrm_to_mixamo = {vrm: f"mixamorig:{m}" for m, vrm in MIXAMO_TO_VRM.items()}
        for vrm, entry in human.items():
            gltf["nodes"][entry["node"]]["name"] = vrm_to_mixamo[vrm]
        for vrm in drop:
            joint = VRM_TO_HANIM[vrm]
            gltf["nodes"][by_name[joint]]["name"] = "dropped_" + joint
    else:
        gltf["extensionsUsed"] = ["VRMC_vrm"]
        gltf["extensions"] = {"VRMC_vrm": {"specVersion": "1.0", "meta": {"name": "fixture", "authors": ["mura tests"],
                                                                        "licenseUrl": "https://vrm.dev/licenses/1.0/"},
                                           "humanoid": {"humanBones": human}}}  # fmt: skip
    return write_glb(path, gltf, blob)


