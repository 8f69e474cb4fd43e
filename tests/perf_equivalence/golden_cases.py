"""The utterances whose rendering is pinned, and how a rendering is reduced to a golden record.

Run as a script (``python tests/perf_equivalence/golden_cases.py``) only to regenerate the
golden files, which must be done from code whose output is known good: the files pin the
motion and timeline that optimizations of motion synthesis must not change.

A record keeps, per utterance: the frame count and start time, three fixed random
projections of every frame's rotations (so that any change to any frame shows), every
tenth frame's rotations in full, the root translation of those frames, and the timeline
JSON.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
SHARED = REPO.parent / "shared"
GOLDEN = Path(__file__).resolve().parent / "golden"
FPS = 60.0
#: Every how many frames the rotations are kept in full.
STRIDE = 10
#: Published MURML files rendered besides the examples (gesture-only, one or both arms,
#: static and dynamic), with a delay (s) added to their absolute timings: 0 renders them
#: as published (most ask for a stroke at 1.0 s, sooner than the preparation from rest
#: takes, which the scheduler resolves by delaying the absolute clock); 1 s renders them
#: with room to prepare.
CORPUS = {
    "01_fo_reissverschluss.us": 0.0,
    "04_lefu_petersilie.us": 0.0,
    "08_pewo_foehn.us": 1.0,
    "21_loeke_blume.us": 0.0,
    "41_tanedila_welle.us": 1.0,
}
_TIMING = re.compile(r'<timing onset="([0-9.]+)" end="([0-9.]+)"')


def sources() -> dict[str, tuple[Path, float]]:
    """Name → (file, delay in seconds) of every pinned utterance (corpus files only when
    ``../shared`` exists)."""
    cases = {f"example_{p.stem}": (p, 0.0) for p in sorted((REPO / "specs" / "utterances").glob("*.xml"))}
    corpus = SHARED / "corpora" / "murml"
    cases.update({f"murml_{Path(n).stem}": (corpus / n, d) for n, d in CORPUS.items() if (corpus / n).is_file()})
    return cases


def portable_timeline(timeline: dict) -> dict:
    """The timeline as JSON data with the checkout's own folders written as ``<repo>``
    and ``<shared>``, so that a golden record compares equal from any clone."""
    text = json.dumps(timeline).replace(str(SHARED), "<shared>").replace(str(REPO), "<repo>")
    return json.loads(text)


def projections(joints: int) -> np.ndarray:
    """Three fixed random weightings ``(J * 4, 3)`` of a frame's rotations."""
    return np.random.default_rng(20240611).standard_normal((joints * 4, 3))


def record(performance) -> dict[str, np.ndarray]:
    """The arrays kept of a rendering (see the module docstring)."""
    motion = performance.motion
    rotations = np.asarray(motion.rotations, dtype=float)
    flat = rotations.reshape(rotations.shape[0], -1)
    return {
        "frame_count": np.array(motion.frame_count),
        "start_time": np.array(motion.start_time),
        "projected": flat @ projections(rotations.shape[1]),
        "sampled": rotations[::STRIDE],
        "root": np.asarray(motion.root_translation, dtype=float)[::STRIDE],
    }


def utterance(path: Path, delay: float) -> Path | bytes:
    """The file itself, or its text with ``delay`` added to every absolute timing."""
    if delay == 0.0:
        return path
    shift = lambda m: f'<timing onset="{float(m[1]) + delay:g}" end="{float(m[2]) + delay:g}"'
    return _TIMING.sub(shift, path.read_text()).encode()


def render(case: tuple[Path, float], **config):
    """Offline rendering of a case at :data:`FPS` with fake speech; ``config`` replaces
    scheduler settings."""
    from dataclasses import replace

    from agent.agent import Agent

    agent = Agent(avatar="max", tts="fake", fps=FPS)
    agent.config = replace(agent.config, **config)
    return agent.render(utterance(*case), name=case[0].stem)


def main() -> None:
    GOLDEN.mkdir(exist_ok=True)
    for name, case in sources().items():
        performance = render(case)
        np.savez_compressed(GOLDEN / f"{name}.npz", **record(performance))
        (GOLDEN / f"{name}.timeline.json").write_text(json.dumps(portable_timeline(performance.timeline), indent=1, sort_keys=True))
        print(name, performance.motion.frame_count)


if __name__ == "__main__":
    main()
