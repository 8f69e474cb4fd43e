"""The parts of a corpus run, without a cluster: names, items, reasons by kind, warnings
said once, the manifest's record of what is done, and the motion files of the index."""

from __future__ import annotations

import base64
import json
import unicodedata
from pathlib import Path

import numpy as np
import pytest
from batch_helpers import SIGNS, sigml

from agent.batch.items import SIGN, UTTERANCE, read_corpus
from agent.batch.manifest import Journal, entry_of, is_done, read_manifest, write_manifest
from agent.batch.naming import MAX_STEM_BYTES, safe_stem, unique_stems
from agent.batch.render import FAILED, RenderOptions, render_item
from agent.batch.report import EXAMPLES_PER_KIND, Example, group_by_kind, reason_kind, summarize_warnings
from agent.batch.items import CHUNK_ITEMS, chunks_of
from agent.cli import main
from agent.export.corpus_index import QUATERNION_SCALE, motion_payload
from motor.motion import Motion

REPO = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize(
    ("gloss", "stem"),
    [
        ("HOUSE1A^", "HOUSE1A"), ("नमस्ते", "नमस्ते"), ("Düren", "Düren"), ("中文?", "中文"), ("نعم", "نعم"),
        ("a b/c", "a_b_c"), ("../x", "x"), ("^^^", "sign"), ("..", "sign"), ("CON", "CON_"), ("nul.txt", "nul.txt_"),
        ("e\u0301t\u00e9", "\u00e9t\u00e9"),  # decomposed accents become the composed letters (NFC)
    ],
)
def test_stems_keep_letters_of_every_script(gloss: str, stem: str) -> None:
    assert safe_stem(gloss) == stem


@pytest.mark.parametrize("gloss", ["x" * 400, "ना" * 200, "é" * 300, "a/" * 500])
def test_long_glosses_are_cut_on_a_character_boundary(gloss: str) -> None:
    stem = safe_stem(gloss)
    data = stem.encode("utf-8")
    assert 0 < len(data) <= MAX_STEM_BYTES and data.decode("utf-8") == stem == unicodedata.normalize("NFC", stem)
    assert not stem.endswith((".", " ", "_"))


def test_unique_stems_ignore_case_and_keep_input_order() -> None:
    assert unique_stems(["a", "A", "a", "नमस्ते", "नमस्ते", "x" * 400, "x" * 400]) == [
        "a", "A_2", "a_3", "नमस्ते", "नमस्ते_2", "x" * MAX_STEM_BYTES, "x" * (MAX_STEM_BYTES - 2) + "_2",
    ]  # fmt: skip


def test_items_of_collections_and_folders(tmp_path: Path) -> None:
    (tmp_path / "signs.sigml").write_text(sigml(SIGNS), encoding="utf-8")
    (tmp_path / "talk").mkdir()
    (tmp_path / "talk" / "here.xml").write_bytes((REPO / "specs" / "utterances" / "sign_here.xml").read_bytes())
    (tmp_path / "talk" / "notes.txt").write_text("not a corpus file")
    (tmp_path / "bad.sigml").write_text("<sigml><hns_sign")
    corpus = read_corpus([tmp_path / "signs.sigml", tmp_path / "talk", tmp_path / "bad.sigml"])
    assert [item.kind for item in corpus.items] == [SIGN] * len(SIGNS) + [UTTERANCE]
    assert [item.index for item in corpus.items] == list(range(len(SIGNS) + 1))
    (broken,) = [item for item in corpus.items if item.error]
    assert broken.label == "broken" and "signs.sigml:1:" in broken.error and "hamnosuch" in broken.error
    ((source, reason),) = corpus.unreadable
    assert source.endswith("bad.sigml") and "malformed XML" in reason


def test_choosing_by_gloss_keeps_the_names_of_the_whole_corpus(tmp_path: Path) -> None:
    path = tmp_path / "signs.sigml"
    path.write_text(sigml({"a": SIGNS["HOUSE"], "A": SIGNS["HOUSE"], "b": SIGNS["HOUSE"]}), encoding="utf-8")
    assert [(item.label, item.name) for item in read_corpus([path], ["A", "b*"]).items] == [("A", "A_2"), ("b", "b")]
    assert read_corpus([path], ["nothing*"]).items == ()


def test_chunks_are_fixed_by_corpus_position(tmp_path: Path) -> None:
    path = tmp_path / "many.sigml"
    path.write_text(sigml({f"s{i}": SIGNS["HOUSE"] for i in range(40)}), encoding="utf-8")
    items = read_corpus([path]).items
    chunks = chunks_of([item for item in items if item.index % 3])
    assert [[item.index // CHUNK_ITEMS for item in chunk] for chunk in chunks] == [[0] * 10, [1] * 11, [2] * 5]


@pytest.mark.parametrize(
    ("first", "second"),
    [
        ("a.sigml:3:5: sign 'X': unexpected symbol hamnodding at position 7: expected a location",
         "b.sigml:90:13: sign 'Y Z': unexpected symbol hambetween at position 4: expected a location"),
        ("2 path(s) of the right hand moved within reach or out of the body, by up to 2.3 cm",
         "5 path(s) of the right hand moved within reach or out of the body, by up to 10.6 cm"),
        ("u.us:1:118: dynamic PalmOrientation has no segments", "v.us:12:4: dynamic PalmOrientation has no segments"),
    ],
)  # fmt: skip
def test_instances_of_one_reason_share_a_kind(first: str, second: str) -> None:
    kind = reason_kind(first)
    assert kind == reason_kind(second)
    assert "hamnodding" not in kind and "7" not in kind and "a.sigml" not in kind


def test_different_reasons_stay_apart() -> None:
    reasons = ["empty manual stream", "unexpected symbol hamx at position 1: expected a location", "unexpected symbol hamx at position 1: expected hamparend"]
    assert len({reason_kind(reason) for reason in reasons}) == 3


def test_groups_count_every_instance_and_keep_a_few_examples() -> None:
    examples = [Example(f"s{i}", "f", f"f:{i}:1: sign 's{i}': empty manual stream") for i in range(7)] + [Example("t", "f", "odd")]
    groups = group_by_kind(examples)
    assert list(groups) == ["empty manual stream", "odd"]
    assert groups["empty manual stream"]["count"] == 7 and len(groups["empty manual stream"]["examples"]) == EXAMPLES_PER_KIND


@pytest.mark.parametrize(
    ("warnings", "said"),
    [
        (["b1: slot GazeDirection is not realized", "b1: slot GazeDirection is not realized"], ["b1: slot GazeDirection is not realized (×2)"]),
        (["b1: slot X", "b2: slot X", "b3: other"], ["b1, b2: slot X", "b3: other"]),
        (["plain message", "plain message"], ["plain message (×2)"]),
        ([], []),
    ],
)
def test_warnings_are_said_once(warnings: list[str], said: list[str]) -> None:
    assert list(summarize_warnings(warnings)) == said


def test_manifest_knows_what_is_done(tmp_path: Path) -> None:
    path = tmp_path / "signs.sigml"
    path.write_text(sigml({"HOUSE": SIGNS["HOUSE"], "broken": SIGNS["broken"]}), encoding="utf-8")
    house, broken = read_corpus([path]).items
    options = RenderOptions(avatar="max")
    out = tmp_path / "out"
    results = [render_item(house, options, out), render_item(broken, options, out)]
    assert results[1].status == FAILED
    journal = Journal(out)
    for item, result in zip((house, broken), results):
        journal.append(entry_of(item, result, options.key()))
    journal.close()
    with (out / ".manifest.journal").open("a") as stream:
        stream.write('{"name": "half-writ')  # a run killed while writing its last line
    recorded = read_manifest(out)
    assert is_done(recorded["HOUSE"], house, options.key(), out)
    assert not is_done(recorded["broken"], broken, options.key(), out)
    assert not is_done(recorded["HOUSE"], house, RenderOptions(avatar="max", fps=30).key(), out)
    write_manifest(out, recorded.values(), {"avatar": "max"})
    assert read_manifest(out).keys() == {"HOUSE", "broken"} and not (out / ".manifest.journal").exists()
    (out / "HOUSE.bvh").write_text("shorter")
    assert not is_done(read_manifest(out)["HOUSE"], house, options.key(), out)
    data = json.loads((out / "manifest.json").read_text())
    assert data["summary"] == {"items": 2, "rendered": 1, "failed": 1}


def test_motion_file_payload_round_trips() -> None:
    rng = np.random.default_rng(3)
    quaternions = rng.normal(size=(5, 4, 4))
    quaternions /= np.linalg.norm(quaternions, axis=-1, keepdims=True)
    roots = rng.normal(size=(5, 3))
    motion = Motion(25.0, ("a", "b", "c", "d"), (-1, 0, 1, 2), np.zeros((4, 3)), quaternions, roots, start_time=0.5)
    payload = motion_payload(motion)
    decoded = np.frombuffer(base64.b64decode(payload["rotations"]), dtype="<i2").reshape(5, 4, 4) / QUATERNION_SCALE
    assert np.max(np.abs(decoded - quaternions)) <= 0.5 / QUATERNION_SCALE + 1e-12
    assert np.allclose(np.frombuffer(base64.b64decode(payload["root"]), dtype="<f4").reshape(5, 3), roots, atol=1e-6)
    assert (payload["frames"], payload["start"], payload["duration"]) == (5, 0.5, 0.2)
    assert motion_payload(motion) == payload  # the same motion, the same bytes


def test_render_says_each_warning_once(tmp_path: Path, capsys) -> None:
    frames = '<frame ftime="0.2"><posture>Humanoid (vc4 3 5 0 0)</posture></frame><frame ftime="0.5"><posture>Humanoid (vc4 3 0 0 0)</posture></frame>'
    nod = f'<dynamic slot="Neck" scope="neck"><keyframing mode="spline"><phase>{frames}</phase></keyframing></dynamic>'
    behaviours = "".join(
        f'<behaviorspec id="{gid}"><gesture><timing onset="{onset}" end="{onset + 1}"/><constraints><parallel>'
        f'<static slot="HandLocation" value="LocChest LocCenterRight LocNorm"/>{nod}{nod}</parallel></constraints></gesture></behaviorspec>'
        for gid, onset in (("g1", 1), ("g2", 4))
    )
    path = tmp_path / "nods.xml"
    path.write_text(f"<definition><utterance>{behaviours}</utterance></definition>")
    assert main(["render", str(path), "-o", str(tmp_path / "out"), "--no-glb", "--avatar", "max"]) == 0
    lines = [line for line in capsys.readouterr().err.splitlines() if "keyframed" in line]
    assert lines == [f"{path}: warning: g1, g2: keyframed Neck (2 frames of named joints) is not realized by the motor programs (×4)"]
