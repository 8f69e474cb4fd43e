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


@dataclass(frozen=True, eq=False)
class Rendered:
    """One performance: its frame rate, the wrists ``{"right": (n, 3), "left": …}`` in the
    avatar frame, the frame times and the timeline JSON."""

    fps: float
    wrists: dict[str, np.ndarray]
    times: np.ndarray
    timeline: dict
    warnings: tuple[str, ...]

    def frame(self, time: float) -> int:
        return int(round((time - self.times[0]) * self.fps))

    def behaviors(self, kind: str | None = None) -> list[dict]:
        return [b for b in self.timeline["behaviors"] if kind is None or b["kind"] == kind]


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
        joints = joint_positions(motion, ("r_wrist", "l_wrist"))
        wrists = {"right": joints["r_wrist"] - motion.root_translation, "left": joints["l_wrist"] - motion.root_translation}
        _CACHE[key] = Rendered(fps, wrists, motion.times, performed.timeline.to_json(), tuple(performed.warnings))
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
