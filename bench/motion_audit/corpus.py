"""The audit's corpus: render the visible inputs through the public command line, then audit.

The inputs (:func:`corpus_items`):

* every example utterance ``specs/utterances/*.xml``, rendered with espeak-ng and with
  the fake speech (groups ``examples_espeak``, ``examples_fake``);
* every published MURML file ``../shared/corpora/murml/*.us``, with both as well
  (``murml_espeak``, ``murml_fake``);
* :data:`SIGN_SAMPLE` signs drawn with seed :data:`SIGN_SEED` from all the entries of
  ``../shared/corpora/sigml/*.sigml`` pooled (group ``signs``), written into one SiGML
  file per source corpus and rendered with ``mura sign --fps 60``.

Rendering goes through ``python -m agent.cli`` (the ``mura`` command) into a temporary
folder, one group per subfolder; an item that does not render is a
:class:`~bench.motion_audit.findings.Failure` with the command's reason, never the end
of the run. ``quick`` takes a small subset (:data:`QUICK`).
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from lxml import etree

from bench.motion_audit.audit import FileAudit, audit_folder
from bench.motion_audit.avatar_file import known_avatars
from bench.motion_audit.findings import Failure
from bench.motion_audit.report import summarize

REPO = Path(__file__).resolve().parents[2]
SHARED = REPO.parent / "shared"
EXAMPLES = REPO / "specs" / "utterances"
MURML = SHARED / "corpora" / "murml"
SIGML = SHARED / "corpora" / "sigml"
SIGN_SAMPLE = 200
SIGN_SEED = 12
FPS = 60
#: Seconds one render command may take before its items count as failed.
RENDER_TIMEOUT = 900
#: The quick subset: example utterances, MURML files (first in name order) and signs.
QUICK = {"examples": ("circle_wheel", "fig2_take_this_bar", "assembly_two_bars"), "murml": 2, "signs": 10}
#: Groups whose speech is espeak-ng: their strokes give the synchrony figures.
SPEECH_GROUPS = ("examples_espeak", "murml_espeak")


@dataclass(frozen=True)
class RenderJob:
    """One command: the ``mura`` arguments, the group folder it writes, and per expected
    output stem the item's name."""

    group: str
    arguments: tuple[str, ...]
    expected: dict[str, str]


def _utterance_jobs(quick: bool, avatar: tuple[str, ...]) -> list[RenderJob]:
    examples = sorted(EXAMPLES.glob("*.xml"))
    if quick:
        examples = [path for path in examples if path.stem in QUICK["examples"]]
    murml = sorted(MURML.glob("*.us"))[: QUICK["murml"] if quick else None]
    jobs = []
    for kind, files in (("examples", examples), ("murml", murml)):
        for tts in ("espeak", "fake"):
            if files:
                jobs.append(RenderJob(f"{kind}_{tts}", ("render", *map(str, files), "--tts", tts, "--fps", str(FPS), *avatar), {p.stem: str(p) for p in files}))
    return jobs


def _sign_entries(path: Path) -> tuple[etree._Element, list[etree._Element]]:
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False, huge_tree=False)
    root = etree.parse(str(path), parser).getroot()
    return root, [child for child in root if isinstance(child.tag, str)]


def sample_signs(folder: Path, count: int, seed: int = SIGN_SEED) -> list[Path]:
    """Draw ``count`` sign entries with ``seed`` from every ``*.sigml`` of the corpus
    pooled; write those of each corpus into ``folder/<corpus>_sample.sigml`` (in corpus
    order); return the files written."""
    corpora = [(path, *_sign_entries(path)) for path in sorted(SIGML.glob("*.sigml"))]
    pool = [(number, index) for number, (_, _, entries) in enumerate(corpora) for index in range(len(entries))]
    chosen = sorted(np.random.default_rng(seed).choice(len(pool), size=min(count, len(pool)), replace=False))
    written = []
    for number, (path, root, entries) in enumerate(corpora):
        picked = [entries[index] for n, index in (pool[k] for k in chosen) if n == number]
        if not picked:
            continue
        sample = etree.Element(root.tag)
        sample.extend(picked)
        target = folder / f"{path.stem}_sample.sigml"
        target.write_bytes(etree.tostring(sample, xml_declaration=True, encoding="utf-8", pretty_print=True))
        written.append(target)
    return written


def _sign_job(inputs: Path, quick: bool, avatar: tuple[str, ...]) -> RenderJob | None:
    if not SIGML.is_dir():
        return None
    files = sample_signs(inputs, QUICK["signs"] if quick else SIGN_SAMPLE)
    return RenderJob("signs", ("sign", *map(str, files), "--fps", str(FPS), "--pages", "--report", str(inputs / "signs_report.json"), *avatar), {})


def _run(job: RenderJob, output: Path) -> tuple[list[str], str]:
    """Run one render command into ``output``; its stderr lines and a reason if it died."""
    command = [sys.executable, "-m", "agent.cli", *job.arguments, "-o", str(output)]
    try:
        done = subprocess.run(command, cwd=REPO, capture_output=True, text=True, timeout=RENDER_TIMEOUT, check=False)
    except subprocess.TimeoutExpired:
        return [], f"the render command took more than {RENDER_TIMEOUT} s"
    return done.stderr.splitlines(), "" if done.returncode in (0, 1) else f"the render command exited with status {done.returncode}"


def _utterance_failures(job: RenderJob, output: Path, stderr: list[str], died: str) -> list[Failure]:
    failures = []
    for stem, source in job.expected.items():
        if (output / f"{stem}.bvh").is_file():
            continue
        reasons = [line for line in stderr if source in line and ": warning:" not in line]
        failures.append(Failure(f"{job.group}/{stem}", died or (reasons[-1] if reasons else "no BVH was written")))
    return failures


def _sign_failures(report_path: Path, died: str) -> list[Failure]:
    if died or not report_path.is_file():
        return [Failure("signs", died or "mura sign wrote no report")]
    report = json.loads(report_path.read_text(encoding="utf-8"))
    return [Failure(f"signs/{Path(r['source']).stem}:{r['gloss']}", str(r.get("reason"))) for r in report["signs"] if not r["rendered"]]


def render_corpus(
    folder: Path, quick: bool, progress: Callable[[str], None] | None = None, avatar: str | None = None
) -> tuple[int, list[Failure]]:
    """Render every item into ``folder/<group>/`` on ``avatar`` (None: mura's default); the
    number of items and those that failed."""
    inputs = folder / "inputs"
    inputs.mkdir(parents=True, exist_ok=True)
    chosen = () if avatar is None else ("--avatar", avatar)
    jobs = _utterance_jobs(quick, chosen)
    sign_job = _sign_job(inputs, quick, chosen)
    items, failures = sum(len(job.expected) for job in jobs), []
    for job in jobs + ([sign_job] if sign_job else []):
        if progress is not None:
            progress(f"rendering {job.group}")
        output = folder / job.group
        stderr, died = _run(job, output)
        if job.group == "signs":
            report_path = inputs / "signs_report.json"
            failures += _sign_failures(report_path, died)
            items += json.loads(report_path.read_text(encoding="utf-8"))["total"] if report_path.is_file() else 0
        else:
            failures += _utterance_failures(job, output, stderr, died)
    shutil.rmtree(inputs)
    return items, failures


def _group_of(audit: FileAudit) -> str:
    return audit.file.split("/", 1)[0]


def audit_corpus(
    quick: bool, keep: Path | None = None, progress: Callable[[str], None] | None = None, avatar: str | None = None
) -> dict:
    """Render the corpus on ``avatar`` (None: mura's default), audit every render; figures
    overall, per group and for speech.

    With ``keep``, the renders are left in that folder (which must not exist yet; it
    appears only when complete) so that the worst offenders can be looked at.
    """
    started = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="motion_audit_", dir=None if keep is None else keep.parent) as temporary:
        folder = Path(temporary) / "renders"
        items, render_failures = render_corpus(folder, quick, progress, avatar)
        rendered_at = time.perf_counter()
        audits, audit_failures = audit_folder(folder, known_avatars(), None if progress is None else (lambda name: progress(f"auditing {name}")))
        if keep is not None:
            folder.rename(keep)
    groups = sorted({_group_of(audit) for audit in audits})
    speech = [audit for audit in audits if _group_of(audit) in SPEECH_GROUPS]
    return {
        "items": items,
        "rendered": items - len(render_failures),
        "render_failures": [failure.as_json() for failure in render_failures],
        "render_seconds": rendered_at - started,
        "audit_seconds": time.perf_counter() - rendered_at,
        "overall": summarize(audits, audit_failures),
        "speech": summarize(speech),
        "groups": {group: summarize([a for a in audits if _group_of(a) == group]) for group in groups},
    }
