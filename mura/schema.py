"""Validation of utterance documents against the RELAX NG schema in ``specs/schema/``.

The schema checks structure (which element may stand where, required attributes); the
reader in :mod:`mura.murml` then checks meaning (known symbols, time-tag references,
consistent timing). Schema errors carry the line and column of the offending element.
"""

from __future__ import annotations

from functools import lru_cache

from lxml import etree

from mura.errors import SourceLocation, SpecError
from mura.resources import SPECS_DIR
from mura.xml_source import XmlSource

MURML_SCHEMA = SPECS_DIR / "schema" / "murml.rng"


@lru_cache(maxsize=1)
def _murml_schema() -> etree.RelaxNG:
    return etree.RelaxNG(etree.parse(str(MURML_SCHEMA)))


def validate_murml(source: XmlSource) -> None:
    """Raise :class:`SpecError` at the first place where ``source`` breaks the schema."""
    schema = _murml_schema()
    if schema.validate(etree.ElementTree(source.root)):
        return
    entry = schema.error_log[0]
    raise SpecError(f"does not fit the MURML schema: {_plain(entry.message)}", _locate(source, entry.line))


def _locate(source: XmlSource, line: int) -> SourceLocation:
    for element in source.root.iter(etree.Element):
        if element.sourceline == line:
            return source.where(element)
    return SourceLocation(source.file, line, 0)


def _plain(message: str) -> str:
    return message.replace("Expecting element", "expected element").rstrip(".")
