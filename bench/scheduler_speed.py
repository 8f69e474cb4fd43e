"""Scheduler speed: planning latency per chunk (fake and espeak speech, the tests' fake
motor) and the real-time factor of rendering a whole utterance offline.

Not a test: prints figures. ``run(quick)`` returns ``{backend: {...}}``. Planning
latency is the wall time between a chunk's InPrep and Pending events (speech synthesis
with audio, timing, motor planning); the real-time factor is utterance duration over the
wall time of ``Scheduler.run`` on a virtual clock (frames included).
"""

from __future__ import annotations

import importlib.util
import statistics
import sys
import time
from pathlib import Path

from blackboard import ChunkState, ChunkStateChanged, Scheduler, VirtualClock
from mura.murml import load_utterance
from tts import BACKENDS

REPO = Path(__file__).resolve().parents[1]
UTTERANCES = sorted((REPO / "specs" / "utterances").glob("*.xml"))


def _fakes():
    """The fake motor control of tests/blackboard (the real composition is not wired in yet)."""
    path = REPO / "tests" / "blackboard" / "blackboard_fakes.py"
    spec = importlib.util.spec_from_file_location("blackboard_fakes", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def _render(synthesizer, motor_class, path: Path) -> tuple[list[float], float, float]:
    """Planning latencies (s) of every chunk, the utterance duration and the wall time of the run."""
    started: dict[int, float] = {}
    latencies: list[float] = []

    def observe(event):
        if isinstance(event, ChunkStateChanged) and event.state is ChunkState.IN_PREP:
            started[event.chunk] = time.perf_counter()
        elif isinstance(event, ChunkStateChanged) and event.state is ChunkState.PENDING:
            latencies.append(time.perf_counter() - started[event.chunk])

    scheduler = Scheduler(synthesizer, motor_class(), VirtualClock())
    scheduler.subscribe(observe)
    t0 = time.perf_counter()
    result = scheduler.run(load_utterance(path), name=path.stem)
    wall = time.perf_counter() - t0
    if result.failed_chunk is not None:
        raise RuntimeError(f"{path.name}: chunk {result.failed_chunk} failed: {result.error}")
    return latencies, result.timeline.duration, wall


def run(quick: bool) -> dict:
    """Per speech backend: median and max planning latency per chunk, and the real-time factor."""
    motor_class = _fakes().FakeMotor
    paths = UTTERANCES[:2] if quick else UTTERANCES
    repeats = 1 if quick else 5
    results: dict[str, dict] = {}
    for name in ("fake", "espeak"):
        synthesizer = BACKENDS[name]()
        reason = getattr(synthesizer, "unavailable_reason", lambda: None)()
        if reason is not None:
            results[name] = {"unavailable": reason}
            continue
        _render(synthesizer, motor_class, paths[0])  # warm up: load libraries, fill caches
        latencies, duration, wall = [], 0.0, 0.0
        for _ in range(repeats):
            for path in paths:
                chunk_latencies, seconds, spent = _render(synthesizer, motor_class, path)
                latencies += chunk_latencies
                duration += seconds
                wall += spent
        results[name] = {
            "chunks": len(latencies),
            "planning_ms_median": 1000 * statistics.median(latencies),
            "planning_ms_max": 1000 * max(latencies),
            "utterance_seconds": duration,
            "realtime_factor": duration / wall,
        }
    return results


if __name__ == "__main__":
    for backend_name, figures in run(quick=False).items():
        if "unavailable" in figures:
            print(f"{backend_name:7s} unavailable: {figures['unavailable']}")
            continue
        print(
            f"{backend_name:7s} planning per chunk: median {figures['planning_ms_median']:.2f} ms, "
            f"max {figures['planning_ms_max']:.2f} ms over {figures['chunks']} chunks; "
            f"whole utterances {figures['realtime_factor']:.0f}x real time ({figures['utterance_seconds']:.1f} s rendered)"
        )
