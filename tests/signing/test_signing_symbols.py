"""The HamNoSys vocabulary: the shared reference facts, categories and aliases."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

from mura.hamnosys_symbols import ALIASES, load_vocabulary, lookup, vocabulary


def test_table_carries_the_reference_facts(shared: Path) -> None:
    with (shared / "reference" / "hamnosys-symbols.tsv").open(encoding="utf-8") as handle:
        reference = {row["name"]: int(row["codepoint"], 16) for row in csv.DictReader(handle, delimiter="\t")}
    ours = {s.name: s.codepoint for s in vocabulary().symbols}
    assert ours == reference


@pytest.mark.parametrize(
    ("name", "codepoint", "category"),
    [
        ("hamfist", 0xE000, "handshape"),
        ("hamthumbacrossmod", 0xE00D, "thumbmod"),
        ("hamfingerhookmod", 0xE012, "bending"),
        ("hamextfingero", 0xE029, "extfinger"),
        ("hampalmd", 0xE03C, "palm"),
        ("hamnose", 0xE045, "location-head"),
        ("hamstomach", 0xE053, "location-body"),
        ("hamupperarm", 0xE060, "location-arm"),
        ("hamfingertip", 0xE075, "location-hand"),
        ("hampinky", 0xE074, "finger"),
        ("hamlrat", 0xE059, "side"),
        ("hamtouch", 0xE0D1, "contact"),
        ("hammoved", 0xE084, "move-straight"),
        ("hamcircleo", 0xE092, "move-circle"),
        ("hamarcl", 0xE0B9, "move-arc"),
        ("hamclockfull", 0xE0B8, "clock"),
        ("hamellipseh", 0xE0C0, "ellipse"),
        ("hamswinging", 0xE0A6, "local-move"),
        ("hamsmallmod", 0xE0C6, "size"),
        ("hamhalt", 0xE0CC, "manner"),
        ("hamrepeatfromstart", 0xE0D8, "repeat"),
        ("hamparbegin", 0xE0E2, "bracket"),
        ("hamsymmlr", 0xE0E9, "symmetry"),
        ("hamcomma", 0x2C, "punctuation"),
        ("hamreplace", 0xE0AA, "misc"),
    ],
)
def test_symbol_codepoint_and_category(name: str, codepoint: int, category: str) -> None:
    symbol = lookup(name)
    assert symbol is not None
    assert (symbol.name, symbol.codepoint, symbol.category) == (name, codepoint, category)
    assert vocabulary().of_char(chr(codepoint)) == symbol


@pytest.mark.parametrize(
    ("written", "canonical"),
    [
        ("hamUpperarm", "hamupperarm"),
        ("HAMFIST", "hamfist"),
        ("hammoveX", "hammoveX"),
        ("hampalmud", "hampalmd"),
        ("hammoveudl", "hammovedl"),
        ("hampinchopen", "hampinch12open"),
        ("hamcee12open", "hamceeopen"),
        ("hamfingerhookedmod", "hamfingerhookmod"),
        ("hamsymlr", "hamsymmlr"),
        ("hamSymPar", "hamsymmpar"),
        ("hamclockplus", "hamclockfull"),
        ("hamthumbout", "hamthumboutmod"),
        ("hamperiod", "hamfullstop"),
        ("hamtab", "hamspace"),
    ],
)
def test_aliases_and_case(written: str, canonical: str) -> None:
    symbol = lookup(written)
    assert symbol is not None and symbol.name == canonical


def test_every_alias_names_a_real_symbol() -> None:
    for alias, target in ALIASES.items():
        assert lookup(target) is not None, alias
        assert lookup(alias) == lookup(target)


def test_unknown_name_is_none() -> None:
    assert lookup("hamnosuchthing") is None


def test_every_category_is_one_the_grammar_reads() -> None:
    categories = {s.category for s in vocabulary().symbols}
    assert categories == {
        "handshape", "thumbmod", "bending", "extfinger", "palm", "location-head", "location-body",
        "location-arm", "location-hand", "finger", "side", "contact", "move-straight", "move-circle",
        "move-arc", "clock", "ellipse", "local-move", "size", "manner", "repeat", "bracket", "symmetry",
        "punctuation", "misc",
    }


def test_duplicate_codepoints_are_refused(tmp_path: Path) -> None:
    table = tmp_path / "symbols.tsv"
    table.write_text("name\tcodepoint\tcategory\nhamfist\tE000\thandshape\nhamflat\tE000\thandshape\n", encoding="utf-8")
    with pytest.raises(ValueError, match="duplicate"):
        load_vocabulary(table)
