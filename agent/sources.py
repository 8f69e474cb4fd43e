"""Where an utterance comes from: XML text (MURML or a BML block), a file path or an already parsed model."""

from __future__ import annotations

import os
from pathlib import Path

from mura.bml import BmlBlock, is_bml, read_bml
from mura.errors import SourceLocation, SpecError
from mura.model import Utterance
from mura.murml import read_utterances
from mura.xml_source import XmlSource

UtteranceSource = str | bytes | os.PathLike[str] | Utterance | BmlBlock


def read_utterance(source: UtteranceSource) -> tuple[Utterance, str]:
    """An utterance and a name for it, from XML text, a file path or a parsed model."""
    utterance, name, _ = read_spec(source)
    return utterance, name


def read_spec(source: UtteranceSource) -> tuple[Utterance, str, BmlBlock | None]:
    """The utterance, a name for it and, for BML, its block (``<bml>`` root; MURML otherwise).

    A BML block read from text is named by its id, from a file by the file's stem."""
    if isinstance(source, BmlBlock):
        return source.utterance, source.id, source
    if isinstance(source, Utterance):
        return source, Path(source.source).stem or "utterance", None
    if isinstance(source, bytes) or (isinstance(source, str) and source.lstrip().startswith("<")):
        raw = source.encode("utf-8") if isinstance(source, str) else source
        xml, name = XmlSource.from_bytes(raw, "<utterance>"), None
    else:
        path = Path(source)
        xml, name = XmlSource.from_path(path), path.stem
    if is_bml(xml.root):
        block = read_bml(xml)
        return block.utterance, name or block.id, block
    utterances = read_utterances(xml)
    if len(utterances) != 1:
        raise SpecError(f"expected one utterance, found {len(utterances)}", SourceLocation(xml.file, 1, 1))
    return utterances[0], name or "utterance", None
