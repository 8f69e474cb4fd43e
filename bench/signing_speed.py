"""Signing from the real SiGML corpora: render rate, frames per second, compression.

Not a test: prints figures. ``run(quick)`` reads both corpora (``../shared/corpora/sigml``;
``quick``: every 20th sign), plans every sign, realizes all planned signs in order as one
sequence at 25 fps, and checks every frame (NaN, wrist reach, upper arm in the torso).

* **render rate**: signs that parse, plan and render with every frame clean, over all
  signs of the documents; failures by reason (parse failures included), each listed.
* **frames per second**: frames of the sequence over the time to synthesize them
  (activation, sampling, IK and hands, the elbow check); planning is reported apart, per
  sign. The seed reports 15,000 frames/s for about 50 bone rotations per frame.
  Wall-clock (``synthesis_frames_per_second``) and process time
  (``synthesis_process_frames_per_second``); the bare floor
  (:func:`bench.motion_speed.compose_and_write`: forward kinematics of the same rotations
  and writing them as float32 bytes) in the same run, and the ratio
  ``synthesis_over_bare`` (process times). Pin to one core for the figures:
  ``taskset -c 0 .venv/bin/python -m bench.signing_speed``.
* **planning per sign**: one :func:`motor.signing.planning.plan_signs` call over all the
  parsed signs, divided by the signs it planned: wall-clock (``planning_ms_per_sign``) and
  this process's CPU time (``planning_process_ms_per_sign``, steadier on a shared machine).
* **compression**: bytes of SiGML per second of animation against raw motion data,
  50 rotations × 3 floats × 4 bytes per frame at 25 fps (the seed reports 37-fold).
"""

from __future__ import annotations

import json
import re
import sys
import time
from collections import Counter
from pathlib import Path

import numpy as np

from bench.motion_speed import CLOCK, compose_and_write
from bench.timing import median_seconds
from motor.body.avatar import load_avatar
from motor.signing.plan import SignPlanningError
from motor.compiled import warm_up
from motor.signing.planning import plan_signs
from motor.signing.sequence import frame_faults, realize_signs
from mura.sigml import parse_sigml

CORPORA = ("German_SL_DGS.sigml", "Indian_SL.sigml")
FOLDER = Path(__file__).resolve().parents[1].parent / "shared" / "corpora" / "sigml"
FPS = 25.0
#: Raw motion data of the seed's comparison: 50 rotations × 3 floats × 4 bytes per frame.
RAW_BYTES_PER_FRAME = 50 * 3 * 4
#: A frame counts as faulty above these (metres).
SHORTFALL_LIMIT = 1e-3
DEPTH_LIMIT = 0.01
_SIGN_ELEMENT = re.compile(rb"<(hns_sign|hamgestural_sign)\b.*?</\1>", re.DOTALL)


def run(quick: bool) -> dict:
    avatar = load_avatar("max")
    warm_up()
    stride = 20 if quick else 1
    failures: list[dict] = []
    signs, sizes, total = [], [], 0
    for name in CORPORA:
        data = (FOLDER / name).read_bytes()
        result = parse_sigml(data, file=name)
        failed = {failure.index for failure in result.failures}
        elements = [len(m.group(0)) for m in _SIGN_ELEMENT.finditer(data)]
        parsed_sizes = [size for index, size in enumerate(elements) if index not in failed]
        signs.extend(result.signs[::stride])
        sizes.extend(parsed_sizes[::stride])
        taken_failures = result.failures[::stride]
        total += len(result.signs[::stride]) + len(taken_failures)
        failures.extend({"sign": f.gloss, "reason": str(f.error)} for f in taken_failures)
    started, started_cpu = time.perf_counter(), time.process_time()
    results = plan_signs(avatar, signs)
    planning, planning_cpu = time.perf_counter() - started, time.process_time() - started_cpu
    plans = []
    for sign, result, size in zip(signs, results, sizes):
        if isinstance(result, SignPlanningError):
            failures.append({"sign": sign.gloss, "reason": str(result)})
        else:
            plans.append((result, size))

    started, started_cpu = time.perf_counter(), time.process_time()
    signed = realize_signs(avatar, [plan for plan, _ in plans], FPS)
    synthesis, synthesis_cpu = time.perf_counter() - started, time.process_time() - started_cpu
    bare = median_seconds(lambda: compose_and_write(avatar, signed.motion.rotations), 3, CLOCK)
    faults = frame_faults(avatar, signed)
    bad = faults["non_finite"] | (faults["shortfall"] > SHORTFALL_LIMIT) | (faults["upper_arm_depth"] > DEPTH_LIMIT)
    times = signed.motion.times
    clean_bytes, clean_seconds = 0, 0.0
    for (plan, size), timing in zip(plans, signed.timings):
        window = (times >= timing.start) & (times < timing.end)
        if np.any(bad & window):
            frames = bad & window
            failures.append({
                "sign": plan.gloss,
                "reason": "frames with "
                + ", ".join(k for k in ("non_finite", "shortfall", "upper_arm_depth") if np.any(_fault(faults, k)[frames])),
            })  # fmt: skip
            continue
        clean_bytes += size
        clean_seconds += timing.end - timing.start
    rendered = total - len(failures)
    raw_per_second = RAW_BYTES_PER_FRAME * FPS
    sigml_per_second = clean_bytes / clean_seconds if clean_seconds else float("nan")
    reasons = Counter(_reason(f["reason"]) for f in failures)
    return {
        "signs": total,
        "rendered": rendered,
        "render_rate": round(rendered / total, 4) if total else None,
        "rendered_percent": round(100.0 * rendered / total, 2) if total else None,
        "failures_by_reason": dict(reasons.most_common()),
        "failures": failures,
        "planning_ms_per_sign": round(1e3 * planning / max(len(plans), 1), 2),
        "planning_process_ms_per_sign": round(1e3 * planning_cpu / max(len(plans), 1), 3),
        "planned_signs": len(plans),
        "frames": signed.motion.frame_count,
        "animation_seconds": round(signed.duration, 1),
        "synthesis_frames_per_second": round(signed.motion.frame_count / synthesis),
        "synthesis_process_frames_per_second": round(signed.motion.frame_count / synthesis_cpu),
        "bare_compose_and_write_frames_per_second": round(signed.motion.frame_count / bare),
        "synthesis_over_bare": round(synthesis_cpu / bare, 1),
        "rotations_per_frame": len(signed.motion.joint_names),
        "max_shortfall_m": float(np.max(faults["shortfall"])),
        "max_upper_arm_depth_m": float(np.max(faults["upper_arm_depth"])),
        "sigml_bytes_per_second": round(sigml_per_second, 1),
        "raw_motion_bytes_per_second": raw_per_second,
        "compression_factor": round(raw_per_second / sigml_per_second, 1) if clean_seconds else None,
        "warnings": len(signed.warnings),
    }


def _fault(faults: dict[str, np.ndarray], key: str) -> np.ndarray:
    if key == "non_finite":
        return faults[key]
    return faults[key] > (SHORTFALL_LIMIT if key == "shortfall" else DEPTH_LIMIT)


def _reason(text: str) -> str:
    """A failure's reason without the place and the sign's name, for counting."""
    reason = text.split(": ")[-1]
    return re.sub(r"'[^']*'", "'…'", reason)[:90]


if __name__ == "__main__":
    print(json.dumps(run(quick="--quick" in sys.argv), indent=2, ensure_ascii=False))
