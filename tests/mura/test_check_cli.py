"""``mura check`` prints one line per valid file, each error as FILE:LINE:COL, and exits 0 only if all are valid."""

from pathlib import Path

from agent.cli import main

HERE = Path(__file__).parent


def test_all_examples_check_ok(repo, capsys):
    files = sorted(str(p) for p in (repo / "specs" / "utterances").glob("*.xml"))
    assert len(files) >= 6
    assert main(["check", *files, str(repo / "specs" / "lexicon" / "gestures.xml")]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == len(files) + 1
    assert all(": OK (" in line for line in lines)


def test_invalid_file_makes_exit_one(repo, capsys):
    good = str(repo / "specs" / "utterances" / "fig2_take_this_bar.xml")
    bad = str(HERE / "malformed" / "unknown_time_tag.xml")
    assert main(["check", good, bad]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith(good + ": OK")
    assert out[1] == f"{bad}:5:29: behaviour 'g1': end names unknown time tag 't9' (known: t1, t2)"


def test_unknown_document_type(tmp_path, capsys):
    path = tmp_path / "song.xml"
    path.write_text("<song/>")
    assert main(["check", str(path)]) == 1
    assert capsys.readouterr().out.strip() == f"{path}:1:1: unknown document type <song> (expected <definition>, <utterance>, <bml>, <lexicon>, <gestures>, <hns>, <sigml> or <sigml_collection>)"


def test_sigml_lists_each_broken_sign(tmp_path, capsys):
    path = tmp_path / "signs.sigml"
    path.write_text(
        "<sigml>\n<hns_sign gloss='GOOD'><hamnosys_manual><hamfist/><hamextfingeru/><hampalmd/><hamchest/></hamnosys_manual></hns_sign>\n"
        "<hns_sign gloss='EMPTY'><hamnosys_manual></hamnosys_manual></hns_sign>\n</sigml>\n"
    )
    assert main(["check", str(path)]) == 1
    (line,) = capsys.readouterr().out.splitlines()
    assert line.startswith(f"{path}:3:1: ") and "EMPTY" in line and "empty manual stream" in line
