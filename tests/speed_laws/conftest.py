"""Renders measured by the speed-law tests: every example utterance and published MURML file.

Each is performed once per session by the scheduler with the fake speech on the ``max``
avatar, at 60 fps (what a viewer sees: peak speeds) and at 240 fps (continuity: at 60 fps
a minimum-jerk start already reaches 40 % of its peak acceleration one frame after it
leaves rest, too coarse to tell it from a step). The wrists are found with the forward
kinematics of :mod:`bench.speed_laws`, which shares no code with the synthesis.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from bench.speed_laws import joint_positions, render
from motor.body.avatar import Avatar, load_avatar

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((REPO / "specs" / "utterances").glob("*.xml"))
PUBLISHED = sorted((REPO.parent / "shared" / "corpora" / "murml").glob("*.us"))
FILES = [*EXAMPLES, *PUBLISHED]


#: How near (m) beyond the palm thickness the palms count as touching.
CONTACT = 0.01


@dataclass(frozen=True, eq=False)
class Rendered:
    """One performance: its frame rate, the wrists ``{"right": (n, 3), "left": …}`` in the
    avatar frame, the frame times, the timeline JSON, the warnings and the middle
    knuckles (the far end of each palm) like the wrists."""

    fps: float
    wrists: dict[str, np.ndarray]
    times: np.ndarray
    timeline: dict
    warnings: tuple[str, ...]
    knuckles: dict[str, np.ndarray]

    def frame(self, time: float) -> int:
        return int(round((time - self.times[0]) * self.fps))

    def behaviors(self, kind: str | None = None) -> list[dict]:
        return [b for b in self.timeline["behaviors"] if kind is None or b["kind"] == kind]

    def hands_in_contact(self, palm_thickness: float) -> np.ndarray:
        """Frames where the two palms (wrist to middle knuckle) come within :data:`CONTACT`
        of ``palm_thickness`` (m) of each other, and the frames next to them (central
        differences): where the motor control keeps the hands apart as the arms turn them,
        whatever the planned paths do."""
        w, k = self.wrists, self.knuckles
        steps = np.linspace(0.0, 1.0, 11)[:, None, None]
        left = w["left"][None] + steps * (k["left"] - w["left"])[None]
        right = w["right"][None] + steps * (k["right"] - w["right"])[None]
        gap = np.linalg.norm(left[:, None] - right[None], axis=-1).min(axis=(0, 1))
        near = gap < palm_thickness + CONTACT
        return near | np.roll(near, 1) | np.roll(near, -1)


_CACHE: dict[tuple[str, float], Rendered] = {}


@pytest.fixture(scope="session")
def avatar() -> Avatar:
    return load_avatar("max")


def rendered(path: Path, fps: float) -> Rendered:
    """The performance of ``path`` at ``fps`` (rendered once per session)."""
    key = (str(path), fps)
    if key not in _CACHE:
        performed = render(path, fps)
        motion = performed.motion
        joints = joint_positions(motion, ("r_wrist", "l_wrist", "r_middle1", "l_middle1"))
        wrists = {"right": joints["r_wrist"] - motion.root_translation, "left": joints["l_wrist"] - motion.root_translation}
        knuckles = {"right": joints["r_middle1"] - motion.root_translation, "left": joints["l_middle1"] - motion.root_translation}
        _CACHE[key] = Rendered(fps, wrists, motion.times, performed.timeline.to_json(), tuple(performed.warnings), knuckles)
    return _CACHE[key]


def file_id(path: Path) -> str:
    return path.stem


@pytest.fixture(params=FILES, ids=file_id)
def fine(request) -> Rendered:
    """Each file rendered at 240 fps."""
    return rendered(request.param, 240.0)


@pytest.fixture(params=FILES, ids=file_id)
def viewed(request) -> Rendered:
    """Each file rendered at 60 fps."""
    return rendered(request.param, 60.0)
