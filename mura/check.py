"""Checking spec files of any of mura's languages, for ``mura check``.

The document's root element says which language a file is in: ``<definition>`` or
``<utterance>`` (MURML), ``<bml>`` (a BML 1.0 block), ``<lexicon>`` or ``<gestures>`` (a
gesture lexicon: mura's or the published format), ``<hns>`` (a published symbol table),
``<sigml>`` or ``<sigml_collection>`` (signs). Utterances and BML blocks are read with the
given lexicon (the bundled one with any ``--lexicon`` files layered over it). Every problem
found comes back as a :class:`SpecError` (for SiGML, one per broken sign); a file with none
is valid. What a valid BML block leaves out or does not perform comes back as warnings.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from mura.bml import BmlBlock, is_bml, read_bml
from mura.expansion import check_utterance
from mura.errors import SpecError, SpecErrors
from mura.gesture_functions import check_entry
from mura.lexicon import LEXICON_ROOTS, GestureLexicon, combine_lexicons, load_lexicon, read_lexicon
from mura.limits import DEFAULT_LIMITS, Limits
from mura.murml import read_utterances
from mura.sigml import ROOTS as SIGML_ROOTS
from mura.sigml import read_sigml
from mura.xml_source import XmlSource


@dataclass(frozen=True)
class CheckResult:
    """What checking one file found: a summary when valid, else its errors."""

    path: str
    summary: str
    errors: tuple[SpecError, ...] = ()
    warnings: tuple[str, ...] = ()

    @property
    def ok(self) -> bool:
        return not self.errors


def check_file(path: str | Path, limits: Limits = DEFAULT_LIMITS, lexicon: GestureLexicon | None = None) -> CheckResult:
    """Parse and validate one spec file, against ``limits`` too (utterances and BML blocks
    with ``lexicon``, else the bundled one)."""
    name = str(path)
    try:
        source = XmlSource.from_path(path, limits=limits)
        if is_bml(source.root):
            block = read_bml(source, lexicon)
            check_utterance(block.utterance, limits)
            return CheckResult(name, _bml_summary(block), warnings=tuple(str(w) for w in block.warnings))
        summary = _check_source(source, limits, lexicon)
    except SpecErrors as many:
        return CheckResult(name, "", many.errors)
    except SpecError as error:
        return CheckResult(name, "", (error,))
    return CheckResult(name, summary)


def _bml_summary(block: BmlBlock) -> str:
    utterance = block.utterance
    timed = len(block.kinds) - len(block.performed)
    return (f"BML block {block.id!r} ({block.composition}), {len(utterance.chunks)} speech(es), "
            f"{len(utterance.behaviors)} other behaviour(s) of which {timed} timed only, {len(utterance.constraints)} constraint(s)")


def _check_source(source: XmlSource, limits: Limits, lexicon: GestureLexicon | None) -> str:
    root = source.root.tag
    if root in ("definition", "utterance"):
        utterances = read_utterances(source, lexicon, limits)
        chunks = sum(len(u.chunks) for u in utterances)
        behaviors = sum(len(u.behaviors) for u in utterances)
        return f"{len(utterances)} utterance(s), {chunks} chunk(s), {behaviors} behaviour(s)"
    if root in SIGML_ROOTS:
        result = read_sigml(source, limits)
        if result.failures:
            raise SpecErrors([failure.error for failure in result.failures])
        return f"{len(result.signs)} sign(s)"
    if root in LEXICON_ROOTS:
        own = read_lexicon(source)
        combined = combine_lexicons([lexicon or load_lexicon(), own])
        errors = [error for entry in own.entries.values() for error in check_entry(combined, entry, limits)]
        if errors:
            raise SpecErrors(errors)
        symbols = own.symbols
        named = len(symbols.heights) + len(symbols.laterals) + len(symbols.distances) + len(symbols.movement_distances) + len(symbols.palm_angles)
        return f"lexicon of {len(own.entries)} function(s), {len(own.scene)} place(s), {named} symbol(s)"
    raise source.error(
        "unknown document type <" + root + "> (expected <definition>, <utterance>, <bml>, <lexicon>, <gestures>, <hns>, "
        "<sigml> or <sigml_collection>)",
        source.root,
    )
