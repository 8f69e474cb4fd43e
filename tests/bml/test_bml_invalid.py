"""Invalid BML blocks are refused with FILE:LINE:COL and what is wrong; ``mura check`` and
``mura render`` take ``.bml`` files (OK with warnings, or the located errors)."""

from __future__ import annotations

import json

import pytest

from agent.cli import main
from mura.bml import load_bml
from mura.errors import SpecError

NS = 'xmlns="http://www.bml-initiative.org/bml/bml-1.0"'
SPEECH = '<speech id="s1"><text>Take <sync id="tm1"/> this bar.</text></speech>'

#: name → (block body, where the error is (the first occurrence of this text), words of the message)
INVALID: dict[str, tuple[str, str, str]] = {
    "unknown_behaviour_reference": (SPEECH + '\n<gesture id="g1" lexeme="BEAT" stroke="s9:tm1"/>', 'stroke="s9', "names unknown behaviour 's9'"),
    "unknown_sync_point": (SPEECH + '\n<gesture id="g1" lexeme="BEAT" stroke="s1:tm7"/>', 'stroke="s1', "has no sync point 'tm7'"),
    "sync_point_the_type_lacks": (SPEECH + '\n<gaze id="z1" target="Loc-User" start="s1:tm1"/>\n<gesture id="g1" lexeme="BEAT" stroke="z1:stroke"/>',
                                  'stroke="z1', "gaze 'z1' has no sync point 'stroke'"),
    "negative_time": (SPEECH + '\n<gesture id="g1" lexeme="BEAT" start="-0.5"/>', 'start="-0.5', "lies before the block starts"),
    "not_a_time": (SPEECH + '\n<gesture id="g1" lexeme="BEAT" start="soon"/>', 'start="soon', "neither a time in seconds nor a reference"),
    "bad_offset": (SPEECH + '\n<gesture id="g1" lexeme="BEAT" stroke="s1:tm1+x"/>', 'stroke="s1', "has no sync point 'tm1+x'"),
    "infinite_time": (SPEECH + '\n<gesture id="g1" lexeme="BEAT" start="inf"/>', 'start="inf', "neither a time in seconds nor a reference"),
    "duplicate_id": (SPEECH + '\n<gesture id="s1" lexeme="BEAT"/>', 'id="s1" lexeme', "behaviour id 's1' is used twice"),
    "missing_id": (SPEECH + '\n<gesture lexeme="BEAT"/>', "<gesture", "<gesture> needs an id"),
    "missing_lexeme": (SPEECH + '\n<gesture id="g1" stroke="s1:tm1"/>', "<gesture", "needs a lexeme attribute"),
    "bad_mode": (SPEECH + '\n<gesture id="g1" lexeme="BEAT" mode="THREE_HANDS"/>', 'mode="', "mode 'THREE_HANDS' is not one of"),
    "sync_inside_word": ('<speech id="s1"><text>Ta<sync id="tm1"/>ke this.</text></speech>', "<sync", "stands inside a word"),
    "speech_without_text": ('<speech id="s1"/>', "<speech", "needs exactly one <text>"),
    "reference_to_another_block": (SPEECH + '\n<gesture id="g1" lexeme="BEAT" stroke="other:s1:tm1"/>', 'stroke="other', "refers to block 'other'"),
    "time_in_a_sync": (SPEECH + '\n<gesture id="g1" lexeme="BEAT"/>\n<constraint id="c"><synchronize ref="g1:stroke"><sync ref="1.0"/></synchronize></constraint>',
                       'ref="1.0"', "names a sync point, not a time"),
    "before_without_ref": (SPEECH + '\n<gesture id="g1" lexeme="BEAT"/>\n<constraint id="c"><before><sync ref="g1:end"/></before></constraint>',
                           "<before>", "<before> needs a ref attribute"),
    "required_unknown_behaviour": ('<required>\n<juggle id="j1"/></required>' + SPEECH, '<juggle', "unknown behaviour <juggle>, and it is required"),
    "required_locomotion": (SPEECH + '<required>\n<locomotion id="l1" target="door"/></required>', "<locomotion", "not supported by mura, and it is required"),
    "required_unknown_lexeme": (SPEECH + '<required>\n<gesture id="g1" lexeme="MOONWALK"/></required>', 'lexeme="MOONWALK', "unknown lexeme 'MOONWALK'"),
    "required_constraint_on_left_out": (SPEECH + '\n<locomotion id="l1" target="door"/>\n<required><constraint id="c"><after ref="l1:end"><sync ref="s1:start"/></after></constraint></required>',
                                        'ref="s1:start"', "required constraint s1:start >= l1:end"),
    "head_lexeme": (SPEECH + '\n<head id="h1" lexeme="SPIN"/>', 'lexeme="SPIN', "lexeme 'SPIN' is not one of NOD, SHAKE"),
    "head_repetition": (SPEECH + '\n<head id="h1" lexeme="NOD" repetition="-2"/>', 'repetition="', "is not a positive whole number"),
    "gaze_influence": (SPEECH + '\n<gaze id="z1" target="Loc-User" influence="KNEES"/>', 'influence="', "influence 'KNEES' is not one of"),
    "composition": (SPEECH, 'composition="', "composition 'SOMETIMES' is not one of MERGE, APPEND, REPLACE"),
    "empty_block": ("", "<bml", "holds no behaviour"),
    "malformed_xml": (SPEECH + '\n<gesture id="g1" lexeme="BEAT">', "</bml>", "malformed XML"),
    "murml_content": (SPEECH + '\n<murmlgesture xmlns="http://www.techfak.uni-bielefeld.de/ags/soa/murml" id="m1">'
                      '<murml-description><static slot="ElbowColour" value="red"/></murml-description></murmlgesture>',
                      'slot="ElbowColour', "unknown slot 'ElbowColour'"),
}


def _write(tmp_path, name: str, body: str):
    composition = ' composition="SOMETIMES"' if name == "composition" else ""
    text = f'<bml {NS} id="bad"{composition}>\n{body}\n</bml>\n'
    path = tmp_path / f"{name}.bml"
    path.write_text(text, encoding="utf-8")
    return path, text


def _position(text: str, needle: str) -> tuple[int, int]:
    offset = text.index(needle)
    return text.count("\n", 0, offset) + 1, offset - (text.rfind("\n", 0, offset) + 1) + 1


def _first(error: SpecError) -> SpecError:
    return error.errors[0] if hasattr(error, "errors") else error


@pytest.mark.parametrize("name", sorted(INVALID))
def test_invalid_block_is_refused_with_its_place(tmp_path, name):
    body, at, words = INVALID[name]
    path, text = _write(tmp_path, name, body)
    with pytest.raises(SpecError) as caught:
        load_bml(path)
    error = _first(caught.value)
    assert words in error.message, error.message
    if name != "malformed_xml":
        assert (error.line, error.column) == _position(text, at), str(error)
    else:
        assert error.line == _position(text, at)[0]
    assert str(error).startswith(f"{path}:{error.line}:{error.column}: ")


def test_check_prints_ok_with_warnings_and_exit_zero(tmp_path, capsys):
    path = tmp_path / "ok.bml"
    path.write_text(f'<bml {NS} id="ok">{SPEECH}<locomotion id="l1" target="door"/><gesture id="g1" lexeme="BEAT" stroke="s1:tm1" colour="red"/></bml>')
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith(f"{path}: OK (BML block 'ok'")
    assert any(line.startswith(f"{path}:1:") and "warning:" in line and "locomotion" in line for line in out[1:])
    assert any("unknown attribute 'colour'" in line for line in out[1:])


@pytest.mark.parametrize("name", ["unknown_behaviour_reference", "negative_time", "required_locomotion"])
def test_check_and_render_refuse_invalid_blocks_with_file_line_col(tmp_path, capsys, name):
    body, at, words = INVALID[name]
    path, text = _write(tmp_path, name, body)
    line, column = _position(text, at)
    assert main(["check", str(path)]) == 1
    assert f"{path}:{line}:{column}: " in capsys.readouterr().out
    assert main(["render", str(path), "-o", str(tmp_path / "out"), "--tts", "fake"]) == 1
    assert f"{path}:{line}:{column}: " in capsys.readouterr().err
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_render_writes_the_files_of_a_block(tmp_path, capsys, repo):
    out = tmp_path / "out"
    assert main(["render", str(repo / "specs" / "bml" / "take_this_bar.bml"), "-o", str(out), "--tts", "fake"]) == 0
    assert {f"take_this_bar.{ext}" for ext in ("bvh", "html", "timeline.json", "wav")} <= {p.name for p in out.iterdir()}
    timeline = json.loads((out / "take_this_bar.timeline.json").read_text(encoding="utf-8"))
    assert all(behavior["performed"] for behavior in timeline["behaviors"])  # the nod too
    assert "not performed" not in capsys.readouterr().err


def test_unnamespaced_bml_is_read_with_a_warning(tmp_path):
    path = tmp_path / "plain.bml"
    path.write_text(f'<bml id="plain">{SPEECH}</bml>')
    block = load_bml(path)
    assert block.utterance.chunks[0].speech == "s1"
    assert any("namespace" in w.message for w in block.warnings)
