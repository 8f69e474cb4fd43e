"""``mura batch`` on a LocalCluster of two worker processes: a collection renders, a killed
run resumes without redoing what was done, poisoned items fail alone, and the outputs equal
a one-worker run byte for byte."""

from __future__ import annotations

import hashlib
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from batch_helpers import POISONS, SIGNS, poisoned_renderer, sigml

from agent.batch.items import read_corpus
from agent.batch.manifest import JOURNAL, MANIFEST
from agent.batch.render import RenderOptions
from agent.batch.run import run_batch
from agent.cli import main

OPTIONS = RenderOptions(avatar="max")
REPO = Path(__file__).resolve().parents[2]


def _manifest(folder: Path) -> dict:
    return json.loads((folder / MANIFEST).read_text(encoding="utf-8"))


def _files(folder: Path) -> dict[str, bytes]:
    return {path.name: path.read_bytes() for path in sorted(folder.iterdir()) if path.is_file()}


def test_collection_renders_on_two_workers(cluster: str, corpus_file: Path, tmp_path: Path) -> None:
    summary = run_batch(read_corpus([corpus_file]), tmp_path, OPTIONS, scheduler=cluster, progress=False)
    assert (summary.items, summary.rendered, summary.failed, summary.workers) == (7, 6, 1, 2)
    manifest = _manifest(tmp_path)
    items = {entry["label"]: entry for entry in manifest["items"]}
    assert [entry["label"] for entry in manifest["items"]] == list(SIGNS)  # corpus order
    assert items["broken"]["status"] == "failed" and "hamnosuch" in items["broken"]["reason"]
    assert items["नमस्ते"]["name"] == "नमस्ते" and items["a b/c"]["name"] == "a_b_c"
    for entry in manifest["items"]:
        for name, record in entry["files"].items():
            data = (tmp_path / name).read_bytes()
            assert hashlib.sha256(data).hexdigest() == record["sha256"] and len(data) == record["size"]
    assert {name for entry in manifest["items"] for name in entry["files"]} >= {"नमस्ते.bvh", "नमस्ते.motion.js", "中文.bvh"}
    report = json.loads((tmp_path / "report.json").read_text(encoding="utf-8"))
    (kind,) = report["failures_by_kind"]
    assert "unknown HamNoSys symbol" in kind and report["failures_by_kind"][kind]["examples"][0]["item"] == "broken"
    assert not (tmp_path / JOURNAL).exists() and not list(tmp_path.glob(".*.part"))
    assert "नमस्ते.motion.js" in (tmp_path / "index.html").read_text(encoding="utf-8")


def test_outputs_equal_a_one_worker_run(cluster: str, corpus_file: Path, tmp_path: Path) -> None:
    two, one = tmp_path / "two", tmp_path / "one"
    run_batch(read_corpus([corpus_file]), two, OPTIONS, scheduler=cluster, progress=False)
    summary = run_batch(read_corpus([corpus_file]), one, OPTIONS, workers=1, progress=False)
    assert summary.workers == 1
    first, second = _files(two), _files(one)
    assert sorted(first) == sorted(second)
    assert [name for name in first if first[name] != second[name]] == []


def test_a_rerun_skips_what_is_done_and_redoes_what_changed(cluster: str, corpus_file: Path, tmp_path: Path) -> None:
    run_batch(read_corpus([corpus_file]), tmp_path, OPTIONS, scheduler=cluster, progress=False)
    stamps = {path.name: path.stat().st_mtime_ns for path in tmp_path.glob("*.bvh")}
    (tmp_path / "HOUSE.motion.js").write_text("damaged")
    summary = run_batch(read_corpus([corpus_file]), tmp_path, OPTIONS, scheduler=cluster, progress=False)
    assert (summary.skipped, summary.rendered, summary.failed) == (5, 1, 1)  # HOUSE again, and the broken sign
    assert {name: (tmp_path / name).stat().st_mtime_ns for name in stamps if name != "HOUSE.bvh"} == {
        name: stamp for name, stamp in stamps.items() if name != "HOUSE.bvh"
    }
    assert _manifest(tmp_path)["summary"] == {"items": 7, "rendered": 6, "failed": 1}


def test_killed_run_resumes_without_redoing_completed_items(cluster: str, tmp_path: Path) -> None:
    # Enough chunks of 16 that both workers cannot finish them all between two looks at the journal.
    signs = {f"{gloss} {copy}": symbols for copy in range(24) for gloss, symbols in SIGNS.items() if gloss != "broken"}
    corpus = tmp_path / "many.sigml"
    corpus.write_text(sigml(signs), encoding="utf-8")
    out = tmp_path / "out"
    command = [sys.executable, "-m", "agent.cli", "batch", str(corpus), "-o", str(out), "--workers", "2", "--avatar", "max", "--no-progress"]
    process = subprocess.Popen(command, cwd=REPO, start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    journal = out / JOURNAL
    deadline = time.monotonic() + 240
    try:
        while time.monotonic() < deadline and process.poll() is None:
            if journal.is_file() and len(journal.read_text(encoding="utf-8").splitlines()) >= 8:
                break
            time.sleep(0.05)
    finally:
        os.killpg(process.pid, signal.SIGKILL)
        process.wait()
    assert journal.is_file(), "the run never recorded an item"
    finished = [json.loads(line) for line in journal.read_text(encoding="utf-8").splitlines() if line.strip().endswith("}")]
    assert 8 <= len(finished) < len(signs), "the run was not killed half-way"
    stamps = {name: (out / name).stat().st_mtime_ns for entry in finished for name in entry["files"]}
    summary = run_batch(read_corpus([corpus]), out, OPTIONS, scheduler=cluster, progress=False)
    assert summary.skipped >= len(finished) and summary.skipped + summary.rendered == len(signs)
    assert {name: (out / name).stat().st_mtime_ns for name in stamps} == stamps  # not written again
    assert _manifest(out)["summary"] == {"items": len(signs), "rendered": len(signs), "failed": 0}
    assert not journal.exists() and not list(out.glob(".*.part"))


def test_poisoned_items_are_reported_while_the_rest_render(tmp_path: Path) -> None:
    signs = dict(list(SIGNS.items())[:4])
    signs.update({poison: "hamflathand hamextfingero hampalmd hamchest hammoveo" for poison in POISONS})
    path = tmp_path / "poisoned.sigml"
    path.write_text(sigml(signs), encoding="utf-8")
    options = RenderOptions(avatar="max", time_limit=3.0)
    summary = run_batch(read_corpus([path]), tmp_path / "out", options, workers=2, progress=False, renderer=poisoned_renderer)
    assert (summary.rendered, summary.failed) == (4, 3)
    reasons = {entry["label"]: entry.get("reason", "") for entry in _manifest(tmp_path / "out")["items"]}
    assert "the worker rendering it died" in reasons["POISON-EXIT"]
    assert "ran out of memory" in reasons["POISON-MEMORY"]
    assert "ran past the time limit of 3 s" in reasons["POISON-SLOW"]
    assert all(not reasons[gloss] for gloss in list(SIGNS)[:4])


@pytest.mark.parametrize(("arguments", "message"), [(["--workers", "0"], "--workers must be at least 1"), (["--avatar", "nobody"], "no such avatar")])
def test_bad_arguments_are_refused_before_any_work(corpus_file: Path, tmp_path: Path, capsys, arguments: list[str], message: str) -> None:
    assert main(["batch", str(corpus_file), "-o", str(tmp_path / "out"), *arguments]) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_folders_of_utterances_and_bml_blocks_render_with_their_speech(cluster: str, tmp_path: Path) -> None:
    talk = tmp_path / "talk"
    talk.mkdir()
    for name in ("sign_here.xml", "present_and_negate.xml"):
        (talk / name).write_bytes((REPO / "specs" / "utterances" / name).read_bytes())
    (talk / "take_this_bar.bml").write_bytes((REPO / "specs" / "bml" / "take_this_bar.bml").read_bytes())
    (talk / "broken.xml").write_text("<utterance><behaviorspec/></utterance>")
    summary = run_batch(read_corpus([talk]), tmp_path / "out", OPTIONS, scheduler=cluster, progress=False)
    assert (summary.rendered, summary.failed) == (3, 1)
    items = {entry["label"]: entry for entry in _manifest(tmp_path / "out")["items"]}
    assert set(items["sign_here"]["files"]) == {f"sign_here.{suffix}" for suffix in ("wav", "bvh", "timeline.json", "face.json", "motion.js")}
    assert items["take_this_bar"]["status"] == "rendered"  # a BML block is an item like an utterance
    assert "broken.xml:1:" in items["broken"]["reason"]
    index = (tmp_path / "out" / "index.html").read_text(encoding="utf-8")
    assert '"audio":"sign_here.wav"' in index


def test_interrupted_run_stops_its_workers_and_resumes(cluster: str, tmp_path: Path) -> None:
    # Enough chunks of 16 that both workers cannot finish them all between two looks at the journal.
    signs = {f"{gloss} {copy}": symbols for copy in range(24) for gloss, symbols in SIGNS.items() if gloss != "broken"}
    corpus = tmp_path / "many.sigml"
    corpus.write_text(sigml(signs), encoding="utf-8")
    out = tmp_path / "out"
    command = [sys.executable, "-m", "agent.cli", "batch", str(corpus), "-o", str(out), "--workers", "2", "--avatar", "max", "--no-progress"]
    process = subprocess.Popen(
        command, cwd=REPO, start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),  # as a terminal's Ctrl-C finds it
    )  # fmt: skip
    journal = out / JOURNAL
    deadline = time.monotonic() + 240
    while time.monotonic() < deadline and process.poll() is None:
        if journal.is_file() and len(journal.read_text(encoding="utf-8").splitlines()) >= 4:
            break
        time.sleep(0.05)
    os.killpg(process.pid, signal.SIGINT)
    try:
        _, err = process.communicate(timeout=120)
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
    assert process.returncode == 130 and "interrupted" in err
    ended = _group_ends(process.pid, within=20.0)
    if not ended:
        os.killpg(process.pid, signal.SIGKILL)
    assert ended, "worker processes outlived the interrupted driver"
    assert not (out / MANIFEST).exists() and not list(out.glob(".*.part"))
    summary = run_batch(read_corpus([corpus]), out, OPTIONS, scheduler=cluster, progress=False)
    assert summary.skipped >= 4 and summary.skipped + summary.rendered == len(signs)


def _group_ends(group: int, within: float) -> bool:
    """Whether every process of ``group`` has ended within ``within`` seconds."""
    deadline = time.monotonic() + within
    while time.monotonic() < deadline:
        try:
            os.killpg(group, 0)
        except ProcessLookupError:
            return True
        time.sleep(0.1)
    return False
