"""NAME.face.json and the page's copy: ARKit names, one row per frame, the motion's weights."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
from face_helpers import rendered

from motor.face.arkit import FACE_NAMES


def test_face_json_holds_every_frame_of_the_motion(tmp_path):
    performance = rendered("fig2_take_this_bar")
    saved = performance.save(tmp_path)
    data = json.loads(saved.face.read_text())
    assert data["fps"] == 60.0 and tuple(data["names"]) == FACE_NAMES
    weights = np.array(data["weights"])
    assert weights.shape == (performance.motion.frame_count, 52)
    assert np.all((weights >= 0.0) & (weights <= 1.0))
    assert np.allclose(weights, performance.motion.face_weights, atol=5e-5, rtol=1e-3)


def test_the_page_carries_the_moving_weights(tmp_path):
    performance = rendered("fig2_take_this_bar")
    page = performance.save(tmp_path).html.read_text()
    face = json.loads(re.search(r'<script type="application/json" id="mura-face">(.*?)</script>', page, re.S).group(1))
    moving = [name for name, column in zip(FACE_NAMES, performance.motion.face_weights.T) if column.max() > 0.0]
    assert face["names"] == moving and {"jawOpen", "eyeBlinkLeft", "browInnerUp"} <= set(moving)
    assert len(face["weights"]) == performance.motion.frame_count


def test_the_glb_animates_the_face_morphs(tmp_path):
    from agent.export.gltf import motion_model, read_glb, write_motion_glb
    from motor.body.avatar import BUILT_AVATAR_DIR

    if not (BUILT_AVATAR_DIR / "makehuman.glb").is_file():
        pytest.fail("the built avatar is missing: run `make setup`")
    performance = rendered("fig2_take_this_bar", "makehuman")
    path = tmp_path / "fig2.glb"
    write_motion_glb(performance.motion, path, motion_model(performance.avatar), performance.avatar.root_height)
    gltf, blob = read_glb(path.read_bytes(), path.name)
    (animation,) = gltf["animations"]
    (channel,) = [c for c in animation["channels"] if c["target"]["path"] == "weights"]
    accessor = gltf["accessors"][animation["samplers"][channel["sampler"]]["output"]]
    view = gltf["bufferViews"][accessor["bufferView"]]
    values = np.frombuffer(blob, dtype="<f4", count=accessor["count"], offset=view.get("byteOffset", 0) + accessor.get("byteOffset", 0))
    names = gltf["meshes"][gltf["nodes"][channel["target"]["node"]]["mesh"]]["extras"]["targetNames"]
    weights = values.reshape(performance.motion.frame_count, len(names))
    assert weights[:, names.index("jawOpen")] == pytest.approx(np.clip(performance.motion.face_weights[:, FACE_NAMES.index("jawOpen")], 0, 1), abs=1e-6)
