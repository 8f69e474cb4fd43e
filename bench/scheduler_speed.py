"""Scheduler speed: planning latency per chunk (fake and espeak speech, the real motor
control on avatar ``max`` at 60 fps), time to first frame, and the real-time factor of
rendering a whole utterance offline.

Not a test: prints figures. ``run(quick)`` returns ``{backend: {...}}`` plus
``time_to_first_frame_ms``. Planning latency is the wall time between a chunk's InPrep and
Pending events (speech synthesis with audio, timing, motor planning); time to first frame
is the wall time from ``Scheduler.run`` to the first ``FramesReady`` event (fake speech,
median over the example utterances); the real-time factor is utterance duration over the
wall time of ``Scheduler.run`` on a virtual clock (frames included).
"""

from __future__ import annotations

import statistics
import time
from pathlib import Path

from blackboard import (
    ChunkState,
    ChunkStateChanged,
    FramesReady,
    Scheduler,
    VirtualClock,
)
from motor.body.avatar import load_avatar
from motor.control import MotorControl
from mura.murml import load_utterance
from tts import BACKENDS

REPO = Path(__file__).resolve().parents[1]
UTTERANCES = sorted((REPO / "specs" / "utterances").glob("*.xml"))
_AVATAR = load_avatar("max")


def _render(synthesizer, path: Path) -> tuple[list[float], float, float, float]:
    """Planning latencies (s) of every chunk, the utterance duration, the wall time of the
    run and the wall time to its first frame (s)."""
    started: dict[int, float] = {}
    latencies: list[float] = []
    first_frame: list[float] = []

    def observe(event):
        if isinstance(event, ChunkStateChanged) and event.state is ChunkState.IN_PREP:
            started[event.chunk] = time.perf_counter()
        elif isinstance(event, ChunkStateChanged) and event.state is ChunkState.PENDING:
            latencies.append(time.perf_counter() - started[event.chunk])
        elif isinstance(event, FramesReady) and not first_frame:
            first_frame.append(time.perf_counter())

    utterance = load_utterance(path)
    scheduler = Scheduler(synthesizer, MotorControl(_AVATAR, fps=60), VirtualClock())
    scheduler.subscribe(observe)
    t0 = time.perf_counter()
    result = scheduler.run(utterance, name=path.stem)
    wall = time.perf_counter() - t0
    if result.failed_chunk is not None:
        raise RuntimeError(f"{path.name}: chunk {result.failed_chunk} failed: {result.error}")
    return latencies, result.timeline.duration, wall, first_frame[0] - t0


def run(quick: bool) -> dict:
    """Per speech backend: median and max planning latency per chunk, and the real-time factor;
    the median time to first frame with fake speech."""
    paths = UTTERANCES[:2] if quick else UTTERANCES
    repeats = 1 if quick else 5
    results: dict[str, dict | float] = {}
    first_frames: list[float] = []
    for name in ("fake", "espeak"):
        synthesizer = BACKENDS[name]()
        reason = getattr(synthesizer, "unavailable_reason", lambda: None)()
        if reason is not None:
            results[name] = {"unavailable": reason}
            continue
        _render(synthesizer, paths[0])  # warm up: load libraries, fill caches
        latencies, duration, wall = [], 0.0, 0.0
        for _ in range(repeats):
            for path in paths:
                chunk_latencies, seconds, spent, first = _render(synthesizer, path)
                if name == "fake":
                    first_frames.append(first)
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
    results["time_to_first_frame_ms"] = 1000 * statistics.median(first_frames)
    return results


if __name__ == "__main__":
    figures_by_backend = run(quick=False)
    print(f"time to first frame: {figures_by_backend.pop('time_to_first_frame_ms'):.1f} ms (median, fake speech)")
    for backend_name, figures in figures_by_backend.items():
        if "unavailable" in figures:
            print(f"{backend_name:7s} unavailable: {figures['unavailable']}")
            continue
        print(
            f"{backend_name:7s} planning per chunk: median {figures['planning_ms_median']:.2f} ms, "
            f"max {figures['planning_ms_max']:.2f} ms over {figures['chunks']} chunks; "
            f"whole utterances {figures['realtime_factor']:.0f}x real time ({figures['utterance_seconds']:.1f} s rendered)"
        )
