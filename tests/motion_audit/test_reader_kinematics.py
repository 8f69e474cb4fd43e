"""The audit's BVH reader and forward kinematics against hand-computed positions, against
rotation matrices composed here, and against the ``bvh`` package's reading of the file."""

import numpy as np
import pytest
from bvh import Bvh

from bench.motion_audit.bvh_reader import BvhError, parse_bvh, read_bvh
from bench.motion_audit.kinematics import forward_kinematics

from .synthetic import SyntheticMotion, bvh_text

ROOT6 = ["Xposition", "Yposition", "Zposition", "Zrotation", "Xrotation", "Yrotation"]
ZXY = ["Zrotation", "Xrotation", "Yrotation"]
XZY = ["Xrotation", "Zrotation", "Yrotation"]


def chain(values, channels, offsets=((0, 0, 0), (0, 10, 0), (0, 10, 0))):
    """A three-joint chain root → j1 → j2 (offsets in cm) with one frame of ``values``."""
    return bvh_text(["root", "j1", "j2"], [-1, 0, 1], np.array(offsets, float), np.array([values], float), channels)


# (case, BVH text, expected positions of root, j1, j2 in metres) — worked out by hand with
# Rx(90): (x, y, z) → (x, −z, y); Ry(90): → (z, y, −x); Rz(90): → (−y, x, z).
CASES = [
    ("rest", chain([0, 0, 0, 0, 0, 0] + [0, 0, 0] * 2, [ROOT6, ZXY, ZXY]), [(0, 0, 0), (0, 0.1, 0), (0, 0.2, 0)]),
    ("root moved", chain([5, 100, -3, 0, 0, 0] + [0, 0, 0] * 2, [ROOT6, ZXY, ZXY]), [(0.05, 1, -0.03), (0.05, 1.1, -0.03), (0.05, 1.2, -0.03)]),
    ("root turned about z", chain([0, 0, 0, 90, 0, 0] + [0, 0, 0] * 2, [ROOT6, ZXY, ZXY]), [(0, 0, 0), (-0.1, 0, 0), (-0.2, 0, 0)]),
    ("j1 turned about x", chain([0] * 6 + [0, 90, 0] + [0, 0, 0], [ROOT6, ZXY, ZXY]), [(0, 0, 0), (0, 0.1, 0), (0, 0.1, 0.1)]),
    ("intrinsic Z then X", chain([0] * 6 + [90, 90, 0] + [0, 0, 0], [ROOT6, ZXY, ZXY]), [(0, 0, 0), (0, 0.1, 0), (0, 0.1, 0.1)]),
    ("intrinsic X then Z", chain([0] * 6 + [90, 90, 0] + [0, 0, 0], [ROOT6, XZY, ZXY]), [(0, 0, 0), (0, 0.1, 0), (-0.1, 0.1, 0)]),
    ("parent and child turned", chain([0] * 3 + [0, 0, 90] + [0, 90, 0] + [0, 0, 0], [ROOT6, ZXY, ZXY], ((0, 0, 0), (10, 0, 0), (0, 10, 0))), [(0, 0, 0), (0, 0, -0.1), (0.1, 0, -0.1)]),
    ("child with position channels", chain([0] * 6 + [0, 0, 0] + [20, 0, 0], [ROOT6, ZXY, ["Xposition", "Yposition", "Zposition"]]), [(0, 0, 0), (0, 0.1, 0), (0.2, 0.1, 0)]),
]


@pytest.mark.parametrize("name, text, expected", CASES, ids=[case[0] for case in CASES])
def test_positions_match_hand_computed(name, text, expected):
    kinematics = forward_kinematics(parse_bvh(text), scale=0.01)
    np.testing.assert_allclose(kinematics.positions[0], expected, atol=1e-9)


def _elementary(axis: str, degrees: float) -> np.ndarray:
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    return {"X": np.array([[1, 0, 0], [0, c, -s], [0, s, c]]), "Y": np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]), "Z": np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])}[axis]


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("orders", [("ZXY", "ZXY", "ZXY"), ("XYZ", "YZX", "ZYX"), ("YXZ", "XZY", "ZXY")])
def test_positions_match_matrices_composed_in_the_channel_order(seed, orders):
    rng = np.random.default_rng(seed)
    frames = 4
    offsets = rng.uniform(-20, 20, (3, 3)).round(6)  # as written in the file
    angles = rng.uniform(-180, 180, (frames, 3, 3)).round(6)
    root = rng.uniform(-50, 50, (frames, 3)).round(6)
    channels = [["Xposition", "Yposition", "Zposition", *(f"{a}rotation" for a in orders[0])]] + [[f"{a}rotation" for a in order] for order in orders[1:]]
    values = np.concatenate([root, angles[:, 0], angles[:, 1], angles[:, 2]], axis=1)
    text = bvh_text(["root", "a", "b"], [-1, 0, 1], offsets, values, channels)
    kinematics = forward_kinematics(parse_bvh(text), scale=0.01)
    for frame in range(frames):
        rotations = [np.linalg.multi_dot([_elementary(axis, angles[frame, j, k]) for k, axis in enumerate(orders[j])]) for j in range(3)]
        global_root = rotations[0]
        a = root[frame] / 100 + global_root @ offsets[1] / 100
        b = a + global_root @ rotations[1] @ offsets[2] / 100
        np.testing.assert_allclose(kinematics.positions[frame], [root[frame] / 100, a, b], atol=1e-9)


def test_reader_agrees_with_the_bvh_package(tmp_path):
    motion = SyntheticMotion(5)
    path = tmp_path / "synthetic_rest.bvh"
    path.write_text(motion.bvh())
    ours, theirs = read_bvh(path), Bvh(path.read_text())
    assert list(ours.joint_names) == theirs.get_joints_names()
    for joint in ours.joints:
        assert joint.offset == pytest.approx(theirs.joint_offset(joint.name))
        assert list(joint.channels) == theirs.joint_channels(joint.name)
    assert ours.frame_count == theirs.nframes and ours.frame_time == pytest.approx(theirs.frame_time)
    np.testing.assert_allclose(ours.values, np.array(theirs.frames, dtype=float))


GOOD = chain([0] * 6 + [0, 0, 0] * 2, [ROOT6, ZXY, ZXY])
BROKEN = [
    ("no MOTION", GOOD.replace("MOTION", "MOTON"), "no MOTION line"),
    ("unknown channel", GOOD.replace("CHANNELS 3 Zrotation", "CHANNELS 3 Wrotation", 1), "unknown channel 'Wrotation'"),
    ("offset not a number", GOOD.replace("OFFSET 0.000000 10.000000", "OFFSET zero 10.000000", 1), "expected the OFFSET of 'j1' (a number)"),
    ("too few values", GOOD.replace("Frames: 1", "Frames: 2"), "expected 2 frames of 12 channel values"),
    ("not a number in a frame", GOOD.rstrip("\n")[:-8] + "nope\n", "not a number"),
    ("NaN in a frame", GOOD.rstrip("\n")[:-8] + "nan\n", "not finite"),
    ("zero frame time", GOOD.replace("Frame Time: 0.01666667", "Frame Time: 0"), "positive time"),
    ("extra brace", GOOD.replace("MOTION", "}\nMOTION"), "unexpected '}' after the root joint's closing brace"),
    ("unclosed root", GOOD.replace("}\nMOTION", "MOTION"), "the file ends where JOINT, End Site or '}' closing 'root' was expected"),
]


@pytest.mark.parametrize("name, text, message", BROKEN, ids=[case[0] for case in BROKEN])
def test_broken_files_are_named_errors(name, text, message):
    with pytest.raises(BvhError) as raised:
        parse_bvh(text, "broken.bvh")
    assert str(raised.value).startswith("broken.bvh")
    assert message in str(raised.value)


def test_line_numbers_point_at_the_fault():
    text = GOOD.replace("CHANNELS 3 Zrotation", "CHANNELS 3 Wrotation", 1)
    line = next(number for number, row in enumerate(text.splitlines(), 1) if "Wrotation" in row)
    with pytest.raises(BvhError, match=rf"^broken.bvh:{line}:"):
        parse_bvh(text, "broken.bvh")
