"""``mura say``: the text notation, the table, the WAV file, the errors."""

from __future__ import annotations

import argparse

import pytest

from agent.commands import say
from tts import TextMark, read_wav


def _run(*argv: str) -> int:
    parser = argparse.ArgumentParser(prog="mura")
    say.register(parser.add_subparsers(dest="command"))
    args = parser.parse_args(["say", *argv])
    return args.func(args)


@pytest.mark.parametrize(
    ("notation", "text", "marks", "emphasis"),
    [
        ("plain words", "plain words", (), ()),
        ("I saw [t1]*this* fish[end].", "I saw this fish.", (TextMark("t1", 6), TextMark("end", 15)), ((6, 10),)),
        ("*very big* [a]one", "very big one", (TextMark("a", 9),), ((0, 8),)),
    ],
)
def test_notation(notation, text, marks, emphasis):
    assert say.parse_marked_text(notation) == (text, marks, emphasis)


def test_timings_table_and_wav(tmp_path, capsys):
    out = tmp_path / "say.wav"
    assert _run("Hello [t1]*there*.", "--tts", "fake", "--timings", "-o", str(out)) == 0
    printed = capsys.readouterr().out
    assert "fake: 2 words" in printed and "mark       0.383           t1" in printed
    assert "word       0.383" in printed and "there [6:11]" in printed
    samples, rate = read_wav(out)
    assert rate == 22050 and len(samples) > 0


@pytest.mark.parametrize(("text", "message"), [("[bad name] hi", "not a valid XML name"), ("...", "no words"), ("he[t]llo", "inside the word")])
def test_bad_text_exits_2_with_message(capsys, text, message):
    assert _run(text, "--tts", "fake") == 2
    assert message in capsys.readouterr().err
