"""``mura plot`` writes the Fig. 5 and Fig. 6 pictures."""

from pathlib import Path

from agent.cli import main

REPO = Path(__file__).resolve().parents[2]
PNG = b"\x89PNG\r\n\x1a\n"


def test_plot_writes_both_figures(tmp_path, capsys):
    utterance = REPO / "specs" / "utterances" / "fig2_take_this_bar.xml"
    assert main(["plot", str(utterance), "-o", str(tmp_path), "--fps", "30"]) == 0
    out = capsys.readouterr().out
    for suffix in ("timeline.png", "wrist.png"):
        path = tmp_path / f"fig2_take_this_bar.{suffix}"
        assert path.read_bytes()[:8] == PNG
        assert str(path) in out


def test_plot_of_a_bad_spec_is_one_line(tmp_path, capsys):
    bad = REPO / "tests" / "mura" / "malformed" / "unknown_handshape.xml"
    assert main(["plot", str(bad), "-o", str(tmp_path)]) == 1
    assert capsys.readouterr().err.strip() == f"{bad}:7:34: HandShape: unknown hand shape 'BSclaw'"
