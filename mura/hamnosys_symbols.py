"""The HamNoSys 4 vocabulary: symbol names, Unicode codepoints and grammatical categories.

HamNoSys writes a sign as a string of glyphs; SiGML writes the same glyphs as empty tags
named after them (``<hamflathand/>``), and HamNoSys 4 fonts place them in the Unicode
private-use area (U+E000 …). Every reader of signs — the tag stream of ``<hns_sign>``, a
Unicode string, the gestural SiGML that names the same features — shares this table. It is
loaded from ``specs/hamnosys/symbols.tsv`` (name, codepoint, category).

Categories group symbols by the part of the grammar that reads them: ``handshape``,
``thumbmod``, ``bending``, ``extfinger``, ``palm``, ``location-head``, ``location-body``,
``location-arm``, ``location-hand``, ``finger``, ``side``, ``contact``, ``move-straight``,
``move-circle``, ``move-arc`` (path shapes that modify a straight movement, including
wavy and zigzag), ``clock``, ``ellipse``, ``local-move``, ``size``, ``manner``, ``repeat``,
``bracket``, ``symmetry``, ``punctuation`` and ``misc``.
"""

from __future__ import annotations

import csv
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from mura.resources import SPECS_DIR

SYMBOLS_FILE: Path = SPECS_DIR / "hamnosys" / "symbols.tsv"

#: Spellings met in real SiGML corpora for symbols that have another canonical name.
#: Looked up after lower-casing (``hamUpperarm`` is simply ``hamupperarm``).
#:
#: - ``hampalmud``: HamNoSys has no up-down palm (the eight palm orientations go round the
#:   extended-finger axis: u, ur, r, dr, d, dl, l, ul, and "up" and "down" cancel). The
#:   corpora's own notes read it as ``hampalmd``; the spurious ``u`` is dropped.
#: - ``hammoveudl``: likewise no such direction; read with the same rule as ``hammovedl``.
#: - ``hampinchopen`` / ``hamcee12open``: the open pinch and the open cee of the basic
#:   shapes, written without (or with) the digits the font names carry.
#: - ``hamfingerhookedmod``, ``hamdoublebend``, ``hamdoublehook``: bending modifiers spelled
#:   after the adjective.
#: - ``hamnbs``: the font's non-breaking space, punctuation like ``hamspace``; likewise
#:   the font's layout characters ``hamtab``, ``hamlinefeed``, ``hampagebreak`` and
#:   ``hamreturn``.
#: - ``hamperiod``, ``hamclockplus``, ``hamsympar``, ``hamsymlr``, ``hamthumbout``,
#:   ``hamthumbacross``, ``hamthumbopen``: older names of ``hamfullstop``,
#:   ``hamclockfull``, ``hamsymmpar``, ``hamsymmlr`` and the thumb modifiers, which the
#:   HamNoSys 4 font's conversion tables still accept.
ALIASES: Mapping[str, str] = {
    "hampalmud": "hampalmd",
    "hammoveudl": "hammovedl",
    "hampinchopen": "hampinch12open",
    "hamcee12open": "hamceeopen",
    "hamfingerhookedmod": "hamfingerhookmod",
    "hamdoublebend": "hamdoublebent",
    "hamdoublehook": "hamdoublehooked",
    "hamnbs": "hamspace",
    "hamtab": "hamspace",
    "hamlinefeed": "hamspace",
    "hampagebreak": "hamspace",
    "hamreturn": "hamspace",
    "hamperiod": "hamfullstop",
    "hamclockplus": "hamclockfull",
    "hamsympar": "hamsymmpar",
    "hamsymlr": "hamsymmlr",
    "hamthumbout": "hamthumboutmod",
    "hamthumbacross": "hamthumbacrossmod",
    "hamthumbopen": "hamthumbopenmod",
}


@dataclass(frozen=True)
class Symbol:
    """One HamNoSys symbol: its canonical name, Unicode codepoint and category."""

    name: str
    codepoint: int
    category: str

    @property
    def char(self) -> str:
        """The symbol as a character of a HamNoSys 4 Unicode string."""
        return chr(self.codepoint)


@dataclass(frozen=True)
class Vocabulary:
    """The symbol table with its look-ups by (case-folded) name and by codepoint."""

    symbols: tuple[Symbol, ...]
    by_name: Mapping[str, Symbol]
    by_codepoint: Mapping[int, Symbol]

    def lookup(self, name: str) -> Symbol | None:
        """The symbol a tag name stands for, through aliases and case-insensitively."""
        key = name.lower()
        key = ALIASES.get(key, key)
        return self.by_name.get(key)

    def of_char(self, char: str) -> Symbol | None:
        """The symbol a character of a HamNoSys 4 Unicode string stands for."""
        return self.by_codepoint.get(ord(char))

    def in_category(self, category: str) -> tuple[Symbol, ...]:
        """Every symbol of one category, in table order."""
        return tuple(s for s in self.symbols if s.category == category)


@cache
def vocabulary() -> Vocabulary:
    """The HamNoSys vocabulary, read once from :data:`SYMBOLS_FILE`."""
    return load_vocabulary(SYMBOLS_FILE)


def load_vocabulary(path: Path) -> Vocabulary:
    """Read a symbol table (tab-separated ``name``, ``codepoint`` hex, ``category``)."""
    symbols: list[Symbol] = []
    with path.open(encoding="utf-8", newline="") as handle:
        for row in csv.DictReader(handle, delimiter="\t"):
            symbols.append(Symbol(row["name"], int(row["codepoint"], 16), row["category"]))
    by_name = {s.name.lower(): s for s in symbols}
    by_codepoint = {s.codepoint: s for s in symbols}
    if len(by_name) != len(symbols) or len(by_codepoint) != len(symbols):
        raise ValueError(f"{path}: duplicate symbol names or codepoints")
    return Vocabulary(tuple(symbols), by_name, by_codepoint)


def lookup(name: str) -> Symbol | None:
    """Shorthand for ``vocabulary().lookup(name)``."""
    return vocabulary().lookup(name)
