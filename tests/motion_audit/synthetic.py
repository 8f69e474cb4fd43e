"""Synthetic renders for the motion audit's tests: BVH text written here, on the ``max``
skeleton read from its avatar file as plain JSON (so the audit recognizes the avatar).

Every motion here is synthetic (made by the tests), labelled so in its name.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

REPO = Path(__file__).resolve().parents[2]
FPS = 60.0


def max_skeleton() -> tuple[list[str], list[int], np.ndarray]:
    """Names, parent indices and offsets (metres) of the ``max`` avatar, in file order."""
    joints = json.loads((REPO / "specs" / "avatars" / "max.json").read_text())["joints"]
    names = [joint["name"] for joint in joints]
    parents = [names.index(joint["parent"]) if joint["parent"] else -1 for joint in joints]
    return names, parents, np.array([joint["offset"] for joint in joints], dtype=float)


def bvh_text(names, parents, offsets_cm, values: np.ndarray, channels, fps: float = FPS) -> str:
    """A BVH file: joints in the given order (parents first, written depth first as listed),
    ``channels[j]`` the channel names of joint j, ``values`` ``(frames, channels)``."""
    children: dict[int, list[int]] = {j: [] for j in range(len(names))}
    for j, parent in enumerate(parents):
        if parent >= 0:
            children[parent].append(j)
    order: list[int] = []
    lines = ["HIERARCHY"]

    def write(joint: int, depth: int) -> None:
        order.append(joint)
        pad = "  " * depth
        lines.append(f"{pad}{'ROOT' if parents[joint] < 0 else 'JOINT'} {names[joint]}")
        lines.append(f"{pad}{{")
        lines.append(f"{pad}  OFFSET {' '.join(f'{v:.6f}' for v in offsets_cm[joint])}")
        lines.append(f"{pad}  CHANNELS {len(channels[joint])} {' '.join(channels[joint])}")
        for child in children[joint]:
            write(child, depth + 1)
        if not children[joint]:
            lines.extend([f"{pad}  End Site", f"{pad}  {{", f"{pad}    OFFSET 0.0 -1.0 0.0", f"{pad}  }}"])
        lines.append(f"{pad}}}")

    write(parents.index(-1), 0)
    if order != list(range(len(names))):
        raise ValueError("joints must be listed depth first")
    lines += ["MOTION", f"Frames: {values.shape[0]}", f"Frame Time: {1.0 / fps:.8f}"]
    lines += [" ".join(f"{v:.6f}" for v in row) for row in values]
    return "\n".join(lines) + "\n"


def depth_first(names, parents, offsets):
    """The skeleton re-ordered depth first (as BVH lists it)."""
    order: list[int] = []

    def visit(joint: int) -> None:
        order.append(joint)
        for child in [j for j, p in enumerate(parents) if p == joint]:
            visit(child)

    visit(parents.index(-1))
    new_index = {old: new for new, old in enumerate(order)}
    return [names[j] for j in order], [new_index[parents[j]] if parents[j] >= 0 else -1 for j in order], offsets[order]


class SyntheticMotion:
    """A synthetic performance on the ``max`` skeleton: per-joint local rotations over
    ``frames`` (identity unless set), the root 0.981 m up; ``bvh()`` writes it as mura does
    (root ``Xposition Yposition Zposition Zrotation Xrotation Yrotation``, joints ``ZXY``)."""

    def __init__(self, frames: int, fps: float = FPS) -> None:
        self.names, self.parents, self.offsets = depth_first(*max_skeleton())
        self.frames, self.fps = frames, fps
        self.rotations = {name: Rotation.identity(frames) for name in self.names}

    def set(self, joint: str, rotation: Rotation) -> SyntheticMotion:
        self.rotations[joint] = rotation
        return self

    def bvh(self) -> str:
        columns = []
        channels = []
        for j, name in enumerate(self.names):
            angles = self.rotations[name].as_euler("ZXY", degrees=True)
            if self.parents[j] < 0:
                columns.append(np.tile([0.0, 98.1, 0.0], (self.frames, 1)))
                channels.append(["Xposition", "Yposition", "Zposition", "Zrotation", "Xrotation", "Yrotation"])
            else:
                channels.append(["Zrotation", "Xrotation", "Yrotation"])
            columns.append(angles)
        return bvh_text(self.names, self.parents, self.offsets * 100.0, np.concatenate(columns, axis=1), channels, self.fps)

    def write(self, folder: Path, stem: str, timeline: dict | None = None) -> Path:
        path = folder / f"{stem}.bvh"
        path.write_text(self.bvh())
        if timeline is not None:
            (folder / f"{stem}.timeline.json").write_text(json.dumps(timeline))
        return path


def minimum_jerk(frames: int) -> np.ndarray:
    tau = np.linspace(0.0, 1.0, frames)
    return tau**3 * (10 - 15 * tau + 6 * tau**2)


def raise_arm(frames: int, side: str = "r", degrees: float = 70.0, start: int = 10, duration: int = 50) -> Rotation:
    """The shoulder flexing forward (about x) by ``degrees`` with a minimum-jerk profile
    over ``duration`` frames from ``start``, held before and after: smooth, clean motion."""
    profile = np.zeros(frames)
    profile[start : start + duration] = minimum_jerk(duration)
    profile[start + duration :] = 1.0
    return Rotation.from_rotvec(np.outer(-np.radians(degrees) * profile, [1.0, 0.0, 0.0]))
