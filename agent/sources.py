"""Where an utterance comes from: XML text (MURML or a BML block), a file path or an already parsed model."""

from __future__ import annotations

import os
from pathlib import Path

from mura.bml import BmlBlock, is_bml, read_bml
from mura.errors import SourceLocation, SpecError
from mura.expansion import check_utterance
from mura.lexicon import GestureLexicon
from mura.limits import DEFAULT_LIMITS, Limits
from mura.model import Utterance
from mura.murml import read_utterances
from mura.xml_source import XmlSource

UtteranceSource = str | bytes | os.PathLike[str] | Utterance | BmlBlock


def read_utterance(
    source: UtteranceSource, limits: Limits = DEFAULT_LIMITS, lexicon: GestureLexicon | None = None
) -> tuple[Utterance, str]:
    """An utterance and a name for it, from XML text, a file path or a parsed model,
    checked against ``limits`` (a model built in Python too); gesture functions are
    looked up in ``lexicon`` (the bundled one when None)."""
    utterance, name, _ = read_spec(source, limits, lexicon)
    return utterance, name


def read_spec(
    source: UtteranceSource, limits: Limits = DEFAULT_LIMITS, lexicon: GestureLexicon | None = None
) -> tuple[Utterance, str, BmlBlock | None]:
    """The utterance, a name for it and, for BML, its block (``<bml>`` root; MURML otherwise),
    checked against ``limits``; functions and lexemes resolve through ``lexicon``.

    A BML block read from text is named by its id, from a file by the file's stem."""
    if isinstance(source, BmlBlock):
        return check_utterance(source.utterance, limits), source.id, source
    if isinstance(source, Utterance):
        return check_utterance(source, limits), Path(source.source).stem or "utterance", None
    if isinstance(source, bytes) or (isinstance(source, str) and source.lstrip().startswith("<")):
        raw = source.encode("utf-8") if isinstance(source, str) else source
        xml, name = XmlSource.from_bytes(raw, "<utterance>", limits=limits), None
    else:
        path = Path(source)
        xml, name = XmlSource.from_path(path, limits=limits), path.stem
    if is_bml(xml.root):
        block = read_bml(xml, lexicon)
        return check_utterance(block.utterance, limits), name or block.id, block
    utterances = read_utterances(xml, lexicon, limits)
    if len(utterances) != 1:
        raise SpecError(f"expected one utterance, found {len(utterances)}", SourceLocation(xml.file, 1, 1))
    return utterances[0], name or "utterance", None
