"""A small synthetic humanoid performance (motion, speech WAV, timeline) for exporter tests.

The real skeleton lives in ``motor/``; these tests must not depend on it, so the fixture
builds its own H-Anim-named body: spine, head, arms, five-fingered hands and legs, 57 joints.
"""

from __future__ import annotations

import wave
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from headless_chromium import Browser, find_chromium
from scipy.spatial.transform import Rotation

from motor.motion import Motion

FPS = 60.0
DURATION = 2.0
SAMPLE_RATE = 16000

# (name, parent, offset in metres); "S" in a name is replaced by l/r and x offsets by side.
SPINE = [
    ("humanoid_root", None, (0.0, 0.0, 0.0)),
    ("sacroiliac", "humanoid_root", (0.0, -0.08, 0.0)),
    ("vl5", "humanoid_root", (0.0, 0.10, 0.0)),
    ("vt10", "vl5", (0.0, 0.18, 0.0)),
    ("vt6", "vt10", (0.0, 0.12, -0.01)),
    ("vc4", "vt6", (0.0, 0.16, 0.0)),
    ("skullbase", "vc4", (0.0, 0.09, 0.01)),
]
SIDE = [
    ("S_hip", "sacroiliac", (0.09, -0.02, 0.0)),
    ("S_knee", "S_hip", (0.0, -0.42, 0.0)),
    ("S_ankle", "S_knee", (0.0, -0.42, 0.0)),
    ("S_sternoclavicular", "vt6", (0.03, 0.12, 0.04)),
    ("S_shoulder", "S_sternoclavicular", (0.15, 0.0, -0.03)),
    ("S_elbow", "S_shoulder", (0.0, -0.28, 0.0)),
    ("S_wrist", "S_elbow", (0.0, -0.25, 0.0)),
    ("S_thumb1", "S_wrist", (0.025, -0.02, 0.02)),
    ("S_thumb2", "S_thumb1", (0.01, -0.035, 0.01)),
    ("S_thumb3", "S_thumb2", (0.0, -0.03, 0.0)),
    ("S_index0", "S_wrist", (0.02, -0.02, 0.0)),
    ("S_index1", "S_index0", (0.005, -0.06, 0.0)),
    ("S_index2", "S_index1", (0.0, -0.04, 0.0)),
    ("S_index3", "S_index2", (0.0, -0.025, 0.0)),
    ("S_middle1", "S_wrist", (0.002, -0.085, 0.0)),
    ("S_middle2", "S_middle1", (0.0, -0.045, 0.0)),
    ("S_middle3", "S_middle2", (0.0, -0.028, 0.0)),
    ("S_ring0", "S_wrist", (-0.012, -0.02, 0.0)),
    ("S_ring1", "S_ring0", (-0.005, -0.06, 0.0)),
    ("S_ring2", "S_ring1", (0.0, -0.042, 0.0)),
    ("S_ring3", "S_ring2", (0.0, -0.026, 0.0)),
    ("S_pinky0", "S_wrist", (-0.025, -0.02, 0.0)),
    ("S_pinky1", "S_pinky0", (-0.005, -0.055, 0.0)),
    ("S_pinky2", "S_pinky1", (0.0, -0.032, 0.0)),
    ("S_pinky3", "S_pinky2", (0.0, -0.022, 0.0)),
]
FINGER_JOINTS = ("thumb2", "thumb3", "index1", "index2", "index3", "middle1", "middle2", "middle3",
                 "ring1", "ring2", "ring3", "pinky1", "pinky2", "pinky3")


def _skeleton() -> tuple[tuple[str, ...], tuple[int, ...], np.ndarray]:
    rows = list(SPINE)
    for prefix, sign in (("l", 1.0), ("r", -1.0)):
        for name, parent, (x, y, z) in SIDE:
            rows.append((name.replace("S_", f"{prefix}_"), parent.replace("S_", f"{prefix}_"), (sign * x, y, z)))
    names = tuple(row[0] for row in rows)
    parents = tuple(-1 if row[1] is None else names.index(row[1]) for row in rows)
    return names, parents, np.array([row[2] for row in rows])


def _ramp(times: np.ndarray, start: float, end: float) -> np.ndarray:
    """0 before ``start``, 1 after ``end``, smoothstep between."""
    u = np.clip((times - start) / (end - start), 0.0, 1.0)
    return u * u * (3.0 - 2.0 * u)


def synthetic_motion(fps: float = FPS, duration: float = DURATION) -> Motion:
    """The right arm rises forward into a pointing-like stroke while its fingers curl, the
    left arm sways out, the head turns and the root sways: every joint kind moves."""
    names, parents, offsets = _skeleton()
    index = {name: i for i, name in enumerate(names)}
    times = np.arange(int(round(duration * fps))) / fps
    frames, joints = times.size, len(names)
    rotvecs = np.zeros((frames, joints, 3))
    rise = _ramp(times, 0.2, 0.8) - _ramp(times, 1.4, 1.9)
    rotvecs[:, index["r_shoulder"], 0] = -np.radians(80.0) * rise
    rotvecs[:, index["r_shoulder"], 2] = -np.radians(15.0) * rise
    rotvecs[:, index["r_elbow"], 0] = -np.radians(55.0) * rise
    rotvecs[:, index["r_wrist"], 1] = np.radians(30.0) * rise
    for finger in FINGER_JOINTS:
        rotvecs[:, index[f"r_{finger}"], 0] = -np.radians(70.0) * rise
        rotvecs[:, index[f"l_{finger}"], 0] = -np.radians(20.0) * np.sin(np.pi * times) ** 2
    rotvecs[:, index["l_shoulder"], 2] = np.radians(25.0) * np.sin(np.pi * times)
    rotvecs[:, index["l_elbow"], 0] = -np.radians(30.0) * np.sin(np.pi * times) ** 2
    rotvecs[:, index["skullbase"], 1] = np.radians(20.0) * np.sin(2 * np.pi * times / duration)
    rotvecs[:, index["vt10"], 2] = np.radians(4.0) * np.sin(np.pi * times)
    rotations = Rotation.from_rotvec(rotvecs.reshape(-1, 3)).as_quat().reshape(frames, joints, 4)
    root = np.column_stack([0.03 * np.sin(np.pi * times), np.full(frames, 0.95), np.zeros(frames)])
    return Motion(fps=fps, joint_names=names, parents=parents, offsets=offsets, rotations=rotations,
                  root_translation=root)


def synthetic_timeline() -> dict:
    """A timeline in the scheduler's shape: two chunks, one gesture, words and phonemes."""
    return {
        "version": 1,
        "name": "synthetic",
        "duration": DURATION,
        "fps": FPS,
        "chunks": [
            {"index": 0, "text": "And now take this bar", "speech_onset": 0.3, "speech_end": 1.3,
             "states": [{"state": "InPrep", "time": 0.0}, {"state": "Pending", "time": 0.01},
                        {"state": "Lurking", "time": 0.1}, {"state": "InExec", "time": 0.2},
                        {"state": "Subsiding", "time": 1.3}, {"state": "Completed", "time": 1.9}]},
            {"index": 1, "text": "and put it there", "speech_onset": 1.4, "speech_end": 1.95,
             "states": [{"state": "InPrep", "time": 0.3}, {"state": "Pending", "time": 0.35},
                        {"state": "InExec", "time": 1.4}]},
        ],
        "behaviors": [
            {"id": "gesture_1", "chunk": 0, "arms": ["right"],
             "phases": {"start": 0.2, "ready": 0.8, "stroke_start": 0.8, "stroke": 0.9,
                        "stroke_end": 1.4, "relax": 1.4, "end": 1.9},
             "affiliate": {"onset": 0.9, "end": 1.3}},
        ],
        "words": [{"text": word, "start": 0.3 + 0.2 * i, "end": 0.48 + 0.2 * i, "chunk": 0}
                  for i, word in enumerate("And now take this bar".split())],
        "phonemes": [{"symbol": "a", "start": 0.3, "end": 0.36, "chunk": 0}],
        "time_tags": {"t1": 0.9, "t2": 1.3},
    }


def write_tone(path: Path, duration: float = DURATION) -> None:
    """A quiet 220 Hz mono 16-bit tone standing in for speech."""
    samples = np.arange(int(duration * SAMPLE_RATE)) / SAMPLE_RATE
    pcm = (0.2 * 32767 * np.sin(2 * np.pi * 220.0 * samples)).astype("<i2")
    with wave.open(str(path), "wb") as stream:
        stream.setnchannels(1)
        stream.setsampwidth(2)
        stream.setframerate(SAMPLE_RATE)
        stream.writeframes(pcm.tobytes())


@pytest.fixture(scope="session")
def motion() -> Motion:
    return synthetic_motion()


@pytest.fixture(scope="session")
def timeline() -> dict:
    return synthetic_timeline()


@pytest.fixture(scope="session")
def performance_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """An output folder holding the speech WAV, as the exporters find it."""
    folder = tmp_path_factory.mktemp("performance")
    write_tone(folder / "synthetic.wav")
    return folder


@pytest.fixture(scope="session")
def browser() -> Iterator[Browser]:
    """One headless Chromium shared by the page tests (starting it is the slow part)."""
    executable = find_chromium()
    if executable is None:
        pytest.skip("Chromium is not installed (apt-get install -y chromium); the page tests need it")
    with Browser(executable) as running:
        yield running
