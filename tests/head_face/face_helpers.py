"""Renderings shared by the head and face tests (cached per process) and small readers.

Measurements use :mod:`bench.head_face` (a scipy forward kinematics and the WAV's energy
envelope), never the motor side's own kinematics.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

import numpy as np

from agent.agent import Agent

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = REPO / "specs" / "utterances"


@cache
def rendered(utterance: str, avatar: str = "max", tts: str = "fake"):
    """An example utterance (stem) rendered offline at 60 fps."""
    return Agent(avatar=avatar, tts=tts, fps=60).render(EXAMPLES / f"{utterance}.xml")


def weight(motion, name: str) -> np.ndarray:
    """One morph weight of every frame."""
    return np.asarray(motion.face_weights)[:, list(motion.face_names).index(name)]


def frame_at(motion, time: float) -> int:
    return int(round((time - motion.start_time) * motion.fps))


def phases(performance, behavior: str) -> dict[str, float]:
    return next(b for b in performance.timeline["behaviors"] if b["id"] == behavior)["phases"]
