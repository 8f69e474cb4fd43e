"""Rendering the real SiGML corpora with ``mura batch``: coverage, throughput, bytes.

Not a test: prints figures. ``run(quick)`` reads both corpora (``../shared/corpora/sigml``;
``quick``: every 10th sign) as ``mura batch`` does and renders them with the default
avatar and options, once on one worker and once on every core of the machine (a
``LocalCluster`` of processes each time, in a fresh folder).

* **rendered % of valid signs**: signs rendered over signs with a manual part (a sign
  whose ``<hamnosys_manual>`` is empty has nothing to render); failures grouped by kind.
* **throughput**: items per second from the first item sent to the last one back (the
  cluster's start and the index page apart, given separately), on one worker and on all;
  per-worker efficiency is the many-worker rate over the number of workers times the
  one-worker rate. On a machine shared with other work these rates fall with its load, so
  items per processor-second of the workers (their user and system time) is given too:
  the rate of one worker with a core to itself.
* **bytes per sign**: the per-sign files (BVH, face weights and the index's motion file) on average,
  and with the index page and the avatar model's sidecar shared out over the signs.
"""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path

from agent.batch.items import Corpus, read_corpus
from agent.batch.outputs import INDEX
from agent.batch.render import RenderOptions
from agent.batch.run import run_batch

CORPORA = ("German_SL_DGS.sigml", "Indian_SL.sigml")
FOLDER = Path(__file__).resolve().parents[1].parent / "shared" / "corpora" / "sigml"
EMPTY = "empty manual stream"


def run(quick: bool) -> dict:
    corpus = read_corpus([FOLDER / name for name in CORPORA])
    items = corpus.items[::10] if quick else corpus.items
    sample = Corpus(items, corpus.unreadable)
    valid = [item for item in items if not (item.error or "").endswith(EMPTY)]
    cores = os.cpu_count() or 1
    figures: dict = {"signs": len(items), "valid_signs": len(valid), "cores": cores}
    rates = {}
    for workers in sorted({1, cores}):
        with tempfile.TemporaryDirectory(prefix="mura-bench-batch-") as folder:
            summary = run_batch(sample, folder, RenderOptions(), workers=workers, progress=False)
            rates[workers] = summary.items_per_second
            done = summary.rendered + summary.failed
            figures[f"workers_{workers}"] = {
                "items_per_s": round(summary.items_per_second, 3),
                "items_per_cpu_s": round(done / summary.worker_cpu_seconds, 3) if summary.worker_cpu_seconds else 0.0,
                "render_seconds": round(summary.render_seconds, 2),
                "worker_cpu_seconds": round(summary.worker_cpu_seconds, 2),
                "startup_and_pages_seconds": round(summary.seconds - summary.render_seconds, 2),
            }
            if workers == 1:
                figures.update(_coverage_and_bytes(Path(folder), summary.rendered, len(valid)))
    figures["items_per_s_one_worker"] = rates[1]
    figures["items_per_s_all_workers"] = rates[cores]
    figures["per_worker_efficiency"] = round(rates[cores] / (cores * rates[1]), 3) if rates[1] else 0.0
    return figures


def _coverage_and_bytes(folder: Path, rendered: int, valid: int) -> dict:
    report = json.loads((folder / "report.json").read_text(encoding="utf-8"))
    per_sign = sum(p.stat().st_size for p in folder.iterdir()
                   if (p.suffix in (".bvh", ".js") or p.name.endswith(".face.json")) and not p.name.startswith("mura-avatar-"))
    face = sum(p.stat().st_size for p in folder.glob("*.face.json"))
    shared = sum(p.stat().st_size for p in folder.iterdir() if p.name == INDEX or p.name.startswith("mura-avatar-"))
    motion = sum(p.stat().st_size for p in folder.glob("*.motion.js"))
    return {
        "rendered": rendered,
        "rendered_percent_of_valid": round(100.0 * rendered / valid, 2) if valid else 0.0,
        "failures_by_kind": {kind: group["count"] for kind, group in report["failures_by_kind"].items()},
        "bytes_per_sign": round(per_sign / max(rendered, 1)),
        "motion_file_bytes_per_sign": round(motion / max(rendered, 1)),
        "face_file_bytes_per_sign": round(face / max(rendered, 1)),
        "bytes_per_sign_with_shared_pages": round((per_sign + shared) / max(rendered, 1)),
    }
