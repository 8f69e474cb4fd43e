"""``mura verbs``: evaluate prints the table and says the data are synthetic; fit, render
and synthesize write their files; bad input is reported without a traceback."""

import json

import pytest

from agent.cli import main
from motor.verbs.shipped import RECORDINGS_PATH
from motor.verbs.synthetic import synthetic_session
from mura.recordings import recordings_csv


def test_evaluate_prints_the_table(capsys, tmp_path):
    plot = tmp_path / "paths.png"
    assert main(["verbs", "evaluate", "--folds", "1", "--plot", str(plot)]) == 0
    out = capsys.readouterr().out
    assert "SYNTHETIC" in out
    assert "| verb | model | location (cm) | start (cm) | direction (°) | orientation (°) |" in out
    for verb in ("ASK", "GIVE", "MEET", "SCOLD", "TELL", "COPY", "EMAIL", "SEND"):
        for kind in ("point", "vector", "uninflected"):
            assert f"| {verb} | {kind} |" in out
    assert plot.is_file() and plot.read_bytes()[:4] == b"\x89PNG"


def test_synthesize_reproduces_the_shipped_session(tmp_path, capsys):
    target = tmp_path / "session.json"
    assert main(["verbs", "synthesize", "-o", str(target)]) == 0
    assert target.read_text() == RECORDINGS_PATH.read_text()
    assert json.loads(target.read_text())["synthetic"] is True


def test_fit_lists_refused_rows_and_fits_the_rest(tmp_path, capsys):
    performances = synthetic_session(verbs=("ASK",))
    lines = recordings_csv(performances).splitlines()
    lines[3] = lines[3].replace(",right,", ",thumb,")
    table = tmp_path / "ask.csv"
    table.write_text("\n".join(lines) + "\n")
    model = tmp_path / "models.json"
    assert main(["verbs", "fit", str(table), "-o", str(model)]) == 1
    captured = capsys.readouterr()
    assert f"refused: {table}:4:" in captured.err and "hand 'thumb'" in captured.err
    assert "fitted 1 verb(s) from 41 performance(s)" in captured.out
    assert set(json.loads(model.read_text())["verbs"]) == {"ASK"}


def test_fit_refuses_a_verb_with_too_few_arrangements(tmp_path, capsys):
    table = tmp_path / "few.csv"
    table.write_text(recordings_csv(synthetic_session(verbs=("GIVE",))[:6]))
    assert main(["verbs", "fit", str(table), "-o", str(tmp_path / "m.json")]) == 2
    err = capsys.readouterr().err
    assert "not fitted:" in err and "too few examples to fit" in err and f"{table}:2:" in err
    assert not (tmp_path / "m.json").exists()


@pytest.mark.parametrize("kind", ["point", "vector", "uninflected"])
def test_render_writes_bvh_and_page(tmp_path, capsys, kind):
    assert main(["verbs", "render", "EMAIL", "--subject", "-0.6", "--object", "0.9", "--model", kind, "-o", str(tmp_path)]) == 0
    names = sorted(p.suffix for p in tmp_path.iterdir())
    assert names == [".bvh", ".html"]
    assert "SYNTHETIC" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["verbs", "render", "HUG", "--object", "0.5"], "unknown indicating verb"),
        (["verbs", "render", "GIVE", "--subject", "2", "--object", "0.5"], "outside the arc"),
        (["verbs", "render", "GIVE", "--object", "0.5", "--models", "/nonexistent.json"], "cannot read"),
    ],
)
def test_render_bad_input_is_one_line(tmp_path, capsys, args, message):
    assert main([*args, "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0]


def test_sequence_performs_a_sigml_sequence_with_placed_entities(tmp_path, capsys):
    assert main(["verbs", "sequence", "specs/verbs/ask_sequence.sigml", "-o", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "4 of 4 signs performed" in out and "john at +0.90" in out and "mary at -0.60" in out
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ask_sequence.bvh", "ask_sequence.html"]


def test_sequence_item_that_fails_fails_alone(tmp_path, capsys):
    document = tmp_path / "bad.sigml"
    document.write_text(
        '<sigml><space><place entity="ann" arc="0.2"/></space>'
        '<sign point="ann"/><sign verb="ASK" subject="ann" object="bob"/><sign verb="TELL" object="-0.5"/></sigml>'
    )
    assert main(["verbs", "sequence", str(document), "-o", str(tmp_path / "out")]) == 1
    captured = capsys.readouterr()
    assert "2 of 3 signs performed" in captured.out
    assert "failed: ASK:" in captured.err and "'bob'" in captured.err
