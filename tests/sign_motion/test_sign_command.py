"""``mura sign``: files per sign, a sequence, the report, HamNoSys strings and failures."""

from __future__ import annotations

import json

import pytest

from agent.cli import main
from agent.commands.sign import safe_stem
from mura.hamnosys import hamnosys_string

GOOD = "<hamflathand/><hamextfingero/><hampalmd/><hamchest/><hammoveo/>"
DOCUMENT = (
    '<sigml><hns_sign gloss="one/two"><hamnosys_manual>' + GOOD + "</hamnosys_manual></hns_sign>"
    '<hns_sign gloss="broken"><hamnosys_manual><hamfist/><hamnosuch/></hamnosys_manual></hns_sign>'
    '<hns_sign gloss="three"><hamnosys_manual><hamfist/><hamextfingeru/><hampalml/><hamchin/></hamnosys_manual></hns_sign>'
    "</sigml>"
)


@pytest.fixture()
def sigml(tmp_path):
    path = tmp_path / "signs.sigml"
    path.write_text(DOCUMENT)
    return path


def test_each_sign_renders_alone_and_the_broken_one_is_reported(tmp_path, sigml, capsys):
    out, report = tmp_path / "out", tmp_path / "report.json"
    status = main(["sign", str(sigml), "-o", str(out), "--report", str(report)])
    assert status == 1
    assert sorted(p.name for p in out.iterdir() if p.suffix == ".bvh") == ["one_two.bvh", "three.bvh"]
    data = json.loads(report.read_text())
    assert (data["total"], data["rendered"]) == (3, 2)
    by_gloss = {record["gloss"]: record for record in data["signs"]}
    assert not by_gloss["broken"]["rendered"] and "hamnosuch" in by_gloss["broken"]["reason"]
    assert by_gloss["three"]["rendered"] and by_gloss["three"]["duration"] > 0
    assert not list(out.glob("*.part"))
    assert "broken" in capsys.readouterr().out


def test_sequence_is_one_performance(tmp_path, sigml):
    out, report = tmp_path / "out", tmp_path / "report.json"
    main(["sign", str(sigml), "-o", str(out), "--sequence", "--report", str(report), "--fps", "30"])
    assert (out / "sequence.bvh").is_file()
    text = (out / "sequence.bvh").read_text()
    assert "Frame Time: 0.0333" in text
    data = json.loads(report.read_text())
    assert [r["gloss"] for r in data["signs"] if r["rendered"]] == ["one/two", "three"]


def test_hamnosys_string(tmp_path):
    out = tmp_path / "out"
    text = hamnosys_string(["hamflathand", "hamextfingero", "hampalmd", "hamchest", "hamcircleo"])
    assert main(["sign", "--hamnosys", text, "--gloss", "circle", "-o", str(out)]) == 0
    assert (out / "circle.bvh").is_file()


@pytest.mark.parametrize(
    ("arguments", "message"),
    [([], "give SiGML files or --hamnosys"), (["--hamnosys", "x", "--fps", "0"], "frame rate (--fps) 0 is outside 1..240")],
)
def test_bad_arguments(tmp_path, capsys, arguments, message):
    assert main(["sign", *arguments, "-o", str(tmp_path)]) == 2
    assert message in capsys.readouterr().err


def test_unreadable_document_is_a_failure_not_a_crash(tmp_path):
    bad = tmp_path / "bad.sigml"
    bad.write_text("<nope/>")
    report = tmp_path / "r.json"
    assert main(["sign", str(bad), "-o", str(tmp_path / "o"), "--report", str(report)]) == 1
    (record,) = json.loads(report.read_text())["signs"]
    assert "cannot read" in record["reason"]


@pytest.mark.parametrize(("gloss", "stem"), [("HOUSE1A^", "HOUSE1A"), ("a b/c", "a_b_c"), ("^^^", "sign"), ("../x", "x")])
def test_safe_stem(gloss, stem):
    assert safe_stem(gloss, set()) == stem


def test_safe_stem_is_unique():
    taken: set[str] = set()
    assert [safe_stem("a", taken) for _ in range(3)] == ["a", "a_2", "a_3"]


@pytest.mark.parametrize(("glosses", "stems"), [(["three"], ["three"]), (["one*", "thr?e"], ["one_two", "three"]), (["nothing"], [])])
def test_gloss_picks_signs(tmp_path, sigml, capsys, glosses, stems):
    out = tmp_path / "out"
    options = [option for gloss in glosses for option in ("--gloss", gloss)]
    status = main(["sign", str(sigml), "-o", str(out), "--no-glb", *options])
    assert sorted(p.stem for p in out.glob("*.bvh")) == stems
    assert status == (0 if stems else 1)
    if not stems:
        assert "no sign with gloss nothing" in capsys.readouterr().err


def test_unicode_glosses_name_files(tmp_path):
    document = "<sigml>" + "".join(
        f'<hns_sign gloss="{gloss}"><hamnosys_manual>{GOOD}</hamnosys_manual></hns_sign>' for gloss in ("नमस्ते", "Straße", "STRASSE", "straße")
    ) + "</sigml>"
    path = tmp_path / "signs.sigml"
    path.write_text(document, encoding="utf-8")
    out = tmp_path / "out"
    assert main(["sign", str(path), "-o", str(out), "--no-glb"]) == 0
    assert sorted(p.stem for p in out.glob("*.bvh")) == sorted(["नमस्ते", "Straße", "STRASSE_2", "straße_3"])  # full case folding: ß is ss
    assert (out / "index.html").is_file()
