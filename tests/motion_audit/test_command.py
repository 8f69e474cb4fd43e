"""``python -m bench.motion_audit DIR``: a folder of synthetic renders, broken ones named;
the corpus sample; the audit's rows in the bench targets."""

import json

import pytest

from bench import runner
from bench.motion_audit.__main__ import main
from bench.motion_audit.corpus import SIGML, sample_signs

from .synthetic import SyntheticMotion, raise_arm
from .test_planted_faults import FAULT_FRAME, FRAMES, step_profile, swivel


def timeline(stroke_start: float) -> dict:
    phases = {"start": 0.0, "ready": stroke_start, "stroke_start": stroke_start, "stroke": stroke_start + 0.2, "stroke_end": stroke_start + 0.5, "relax": stroke_start + 0.5, "end": 2.0}
    return {"behaviors": [{"id": "raise", "kind": "gesture", "arms": ["right"], "phases": phases, "affiliate": {"onset": stroke_start + 0.2, "end": 1.5}}], "words": [], "motion_start_time": 0.0}


@pytest.fixture
def renders(tmp_path):
    """A folder of synthetic renders: a clean one, one with an elbow pop, and two broken files."""
    folder = tmp_path / "renders"
    (folder / "clean").mkdir(parents=True)
    SyntheticMotion(FRAMES).set("r_shoulder", raise_arm(FRAMES)).write(folder / "clean", "synthetic_raise", timeline(1.0))
    (folder / "faulty").mkdir()
    swivel(FRAMES, step_profile(FRAMES, FAULT_FRAME), 90.0).write(folder / "faulty", "synthetic_pop")
    (folder / "faulty" / "truncated.bvh").write_text(SyntheticMotion(5).bvh()[:-40])
    stretched = SyntheticMotion(5)
    stretched.offsets = stretched.offsets * 1.2  # no known avatar has these bones
    (folder / "faulty" / "stretched.bvh").write_text(stretched.bvh())
    (folder / "faulty" / "stranger.bvh").write_text("HIERARCHY\nROOT hips\n{\n OFFSET 0 0 0\n CHANNELS 3 Zrotation Xrotation Yrotation\n End Site\n {\n  OFFSET 0 1 0\n }\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n0 0 0\n")
    return folder


def test_folder_audit_names_faults_and_failures(renders, tmp_path, capsys):
    out = tmp_path / "audit.json"
    assert main([str(renders), "--json", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "faulty/synthetic_pop.bvh @ 1.00 s: r_elbow" in printed
    data = json.loads(out.read_text())
    summary = data["summary"]
    reasons = {failure["file"]: failure["reason"] for failure in summary["failed"]}
    assert "expected 5 frames" in reasons["faulty/truncated.bvh"]
    assert "matches no avatar" in reasons["faulty/stretched.bvh"]
    assert "no joint l_shoulder" in reasons["faulty/stranger.bvh"]
    assert all(f"failed: {name}: " in printed for name in reasons)
    assert summary["files"] == 2 and len(reasons) == 3
    assert summary["elbow_pop_events"] == 1 and summary["elbow_pop_worst"]["file"] == "faulty/synthetic_pop.bvh"
    assert data["groups"]["clean"]["elbow_pop_events"] == 0
    assert {f["file"] for f in data["files"]} == {"clean/synthetic_raise.bvh", "faulty/synthetic_pop.bvh"}
    assert summary["strokes"] == 1  # the raise, whose arm moves


@pytest.mark.parametrize("arguments", [["/nonexistent/folder"], [], ["somewhere", "--corpus"]])
def test_bad_invocations_exit_2(arguments, capsys):
    assert main(arguments) == 2
    assert "motion audit:" in capsys.readouterr().err


def test_a_folder_without_renders_exits_2(tmp_path, capsys):
    assert main([str(tmp_path)]) == 2
    assert "no *.bvh files" in capsys.readouterr().err


def test_unknown_avatar_is_named(renders, capsys):
    assert main([str(renders), "--avatar", "nobody"]) == 2
    assert "nobody.json: no such avatar file" in capsys.readouterr().err


@pytest.mark.skipif(not SIGML.is_dir(), reason="../shared/corpora/sigml is not beside the checkout")
@pytest.mark.parametrize("count", [10, 200])
def test_sign_sample_is_deterministic_and_spans_both_corpora(tmp_path, count):
    runs = []
    for name in ("a", "b"):
        (tmp_path / name).mkdir()
        runs.append([path.read_bytes() for path in sample_signs(tmp_path / name, count)])
    assert runs[0] == runs[1]
    assert sum(text.count(b"<hns_sign") + text.count(b"<hamgestural_sign") for text in runs[0]) == count
    if count == 200:
        assert len(runs[0]) == 2  # drawn from both corpora


def test_audit_rows_are_judged_by_the_bench():
    section = {"elbow_pop_events": 3, "wrist_step_events": 0, "largest_joint_turn_deg": 20.0, "torso_penetration_cm": 0.5,
               "power_law_beta_median": 0.19, "stroke_onset_error_max_frames": 0.8, "stroke_landmark_percent": 100.0}  # fmt: skip
    rows = {row["what"]: row["status"] for row in runner.judge({"bench.motion_audit": section})}
    audit_rows = {what: status for what, status in rows.items() if what.startswith("motion audit")}
    assert audit_rows["motion audit: elbow pops (events)"] == "missed"
    assert audit_rows["motion audit: wrist speed steps (events)"] == "met"
    assert audit_rows["motion audit: largest joint rotation per frame"] == "met"
    assert audit_rows["motion audit: power-law β, rendered curved strokes (median)"] == "missed"
    assert audit_rows["motion audit: stroke onset lead vs acoustic onset (max error, espeak)"] == "met"
    assert audit_rows["motion audit: peak wrist speed"] == "not measured"
