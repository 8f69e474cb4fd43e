"""Items 1, 6, 7: the XML prolog, non-files and encodings.

1. A 222-byte ``<!DOCTYPE x SYSTEM "[][]…[">`` made a backtracking pattern run for 2^70
   steps: every command hung. Reading is now linear, whatever the prolog holds.
6. ``/dev/zero`` (which reports size 0) was read until memory ran out, a FIFO without a
   writer hung, and ``mura sign`` read a whole file before checking its size.
7. An entity declaration was found only in UTF-8; in UTF-16 it was accepted.
"""

from __future__ import annotations

import os
import threading

import pytest
from hostile_helpers import all_files, run_mura, utterance

from agent.cli import main
from mura.errors import SpecError
from mura.limits import Limits
from mura.murml import parse_utterance
from mura.xml_source import XmlSource


def _doctype_bomb(root: str, size: int = 222) -> str:
    """``<!DOCTYPE x SYSTEM "[][]…[">`` then ``root``, ``size`` characters in all: the
    unclosed last bracket made the old pattern try every split of the pairs."""
    head, tail = '<!DOCTYPE x SYSTEM "', '[">\n' + root
    pairs, odd = divmod(size - len(head) - len(tail), 2)
    return head + "[]" * pairs + tail + " " * odd


SIGML = '<sigml><hns_sign gloss="A"><hamnosys_manual><hamflathand/><hamextfingeru/><hampalml/><hamchest/></hamnosys_manual></hns_sign></sigml>'


@pytest.mark.timeout(30)
@pytest.mark.parametrize(
    ("command", "root"),
    [
        (["check"], utterance()),
        (["render", "--tts", "fake"], utterance()),
        (["check"], SIGML),
        (["sign"], SIGML),
        (["play", "--tts", "fake", "--no-browser", "--linger", "0"], utterance("Hi.")),
    ],
    ids=["check", "render", "check-sigml", "sign", "play"],
)
def test_doctype_full_of_brackets_is_read_at_once(write, tmp_path, capsys, command, root):
    spec = write("bomb.xml", _doctype_bomb(root))
    assert spec.stat().st_size == 222 and spec.read_text().count("[]") >= 30
    output = ["-o", str(tmp_path / "out")] if command[0] in ("render", "sign") else []
    assert main([*command, str(spec), *output]) == 0
    assert "Traceback" not in capsys.readouterr().err


@pytest.mark.timeout(30)
@pytest.mark.parametrize("pairs", [1_000, 20_000])  # libxml2 caps a system literal at 50,000 characters
def test_start_tags_are_found_in_linear_time(pairs):
    """The same prolog at megabyte size, and the positions after it still exact."""
    text = '<!DOCTYPE x SYSTEM "' + "[]" * pairs + '[">\n<a>\n  <b x="1"/></a>'
    source = XmlSource.from_bytes(text.encode(), "big.xml")
    where = source.where(source.root[0], "x")
    assert (where.line, where.column) == (3, 6)


@pytest.mark.parametrize(
    "prolog",
    [
        '<!DOCTYPE a [ <!ELEMENT a ANY> <!ATTLIST a x CDATA "]>"> ]>',  # '>' and ']' inside a quoted default
        '<!DOCTYPE a SYSTEM "x>y" [ <!-- ]> --> ]>',  # '>' in the system literal, ']>' in a comment
        '<!-- <a x="1"> --><?pi <a x="1"?><!DOCTYPE a>',
    ],
)
def test_positions_skip_every_kind_of_markup(prolog):
    source = XmlSource.from_bytes(f'{prolog}\n<a>\n  <b x="1"/></a>'.encode(), "p.xml")
    assert (source.where(source.root).line, source.where(source.root).column) == (2, 1)
    assert (source.where(source.root[0], "x").line, source.where(source.root[0], "x").column) == (3, 6)


# -- item 6: non-files ---------------------------------------------------------------------


@pytest.mark.timeout(60)
def test_dev_zero_is_refused_by_the_bytes_read():
    """/dev/zero reports size 0; reading stops at the limit (under an address-space limit)."""
    checked = run_mura("check", "/dev/zero")
    assert checked.status == 1
    assert checked.out.startswith("/dev/zero:1:1: input is more than the limit of 33554432 bytes")


def test_sign_reads_no_more_than_the_limit(tmp_path, capsys):
    assert main(["sign", "/dev/zero", "-o", str(tmp_path / "out"), "--limit", "max_input_bytes=1000000"]) == 1
    out = capsys.readouterr().out
    assert "/dev/zero: *: cannot read the document: /dev/zero:1:1: input is more than the limit of 1000000 bytes" in out
    assert all_files(tmp_path / "out") == []


def test_fifo_without_a_writer_is_refused_after_the_stream_timeout(tmp_path, capsys):
    fifo = tmp_path / "pipe.xml"
    os.mkfifo(fifo)
    assert main(["check", str(fifo), "--limit", "stream_timeout=0.2"]) == 1
    assert capsys.readouterr().out.strip() == f"{fifo}:0:0: no data arrived for 0.2 s from this pipe or device (raise with --limit stream_timeout=N)"


def test_fifo_with_a_writer_is_read(tmp_path, capsys):
    fifo = tmp_path / "pipe.xml"
    os.mkfifo(fifo)
    writer = threading.Thread(target=lambda: fifo.write_text(utterance(), encoding="utf-8"))
    writer.start()
    assert main(["check", str(fifo)]) == 0
    writer.join()
    assert capsys.readouterr().out.strip() == f"{fifo}: OK (1 utterance(s), 1 chunk(s), 0 behaviour(s))"


@pytest.mark.parametrize("command", ["check", "sign"])
def test_oversized_file_is_refused_by_its_size(write, tmp_path, capsys, command):
    spec = write("big.sigml", SIGML + " " * 5000)
    output = ["-o", str(tmp_path / "out")] if command == "sign" else []
    assert main([command, str(spec), *output, "--limit", "max_input_bytes=1000"]) == 1
    assert f"{spec}:1:1: file is {spec.stat().st_size} bytes, more than the limit of 1000" in capsys.readouterr().out


def test_a_folder_is_not_a_spec(tmp_path, capsys):
    assert main(["check", str(tmp_path)]) == 1
    assert capsys.readouterr().out.strip() == f"{tmp_path}:0:0: cannot read file: it is a folder"


# -- item 7: encodings ---------------------------------------------------------------------

ENTITY_DOCUMENT = (
    '<?xml version="1.0" encoding="{encoding}"?>\n'
    '<!DOCTYPE utterance [<!ENTITY a "ha"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;">]>\n'
    "<utterance><specification>&b; there.</specification></utterance>"
)


@pytest.mark.parametrize(
    ("codec", "declared"),
    [("utf-8", "UTF-8"), ("utf-16", "UTF-16"), ("utf-16-le", "UTF-16"), ("utf-16-be", "UTF-16"),
     ("utf-32", "UTF-32"), ("latin-1", "ISO-8859-1")],
)  # fmt: skip
def test_entity_declarations_are_refused_in_every_encoding(codec, declared):
    data = ENTITY_DOCUMENT.format(encoding=declared).encode(codec)
    with pytest.raises(SpecError) as caught:
        parse_utterance(data, file="e.xml")
    assert str(caught.value) == "e.xml:2:22: entity declarations are not allowed in specs"


@pytest.mark.parametrize("codec", ["utf-16", "utf-32", "utf-8-sig", "latin-1"])
def test_documents_in_other_encodings_read_with_exact_positions(codec):
    declared = {"utf-8-sig": "UTF-8", "latin-1": "ISO-8859-1"}.get(codec, codec.upper())
    text = f'<?xml version="1.0" encoding="{declared}"?>\n<utterance><specification>Grüße <time id="t1"/> dir.</specification></utterance>'
    parsed = parse_utterance(text.encode(codec), file="enc.xml")
    assert parsed.chunks[0].text == "Grüße dir."
    assert parsed.chunks[0].time_tags[0].where.line == 2


def test_undecodable_bytes_are_located():
    with pytest.raises(SpecError) as caught:
        parse_utterance(b"<utterance>\n<specification>Hi \xff there.</specification></utterance>", file="bad.xml")
    assert str(caught.value) == "bad.xml:2:19: not valid UTF-8: byte 0xff cannot be decoded"


def test_oversized_bytes_are_refused_before_decoding():
    with pytest.raises(SpecError, match="more than the limit of 100 "):
        XmlSource.from_bytes(b"<a>" + b"x" * 200 + b"</a>", "b.xml", limits=Limits(max_input_bytes=100))
