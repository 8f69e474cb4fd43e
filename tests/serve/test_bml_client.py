"""The example client sends its blocks to a running ``mura serve`` and prints their feedback."""

from __future__ import annotations

from agent.examples import bml_client


def test_example_client_follows_its_blocks_to_the_end(server, capsys):
    assert bml_client.main([server[0]]) == 0
    lines = capsys.readouterr().out.splitlines()
    greet_spoken = next(i for i, line in enumerate(lines) if line.startswith("greet: s1:end at "))
    offer_start = next(i for i, line in enumerate(lines) if line.startswith("offer: block start"))
    assert greet_spoken < offer_start  # APPEND joins once the speech and strokes are over
    assert any(line.startswith("greet: block end") and line.endswith("(DONE)") for line in lines)
    assert any(line.startswith("greet: predicted strokes: point ") for line in lines)
    assert any(line.startswith("offer: offer:stroke at ") for line in lines)
    assert lines[-1].startswith("offer: block end") and lines[-1].endswith("(DONE)")


def test_example_client_sends_files_and_reports_refusals(server, tmp_path, capsys):
    bad = tmp_path / "bad.bml"
    bad.write_text('<bml xmlns="http://www.bml-initiative.org/bml/bml-1.0" id="bad"><gesture id="g" lexeme="BEAT" start="-1"/></bml>')
    assert bml_client.main([server[0], str(bad)]) == 1
    assert "error: <message" in capsys.readouterr().out


def test_example_client_without_a_server_says_so(capsys):
    assert bml_client.main(["ws://127.0.0.1:9"]) == 2
    assert "bml_client: ws://127.0.0.1:9" in capsys.readouterr().err
