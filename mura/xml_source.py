"""Safe XML reading with exact source positions for every element and attribute.

Specs come from users and from the web, so reading one never touches the network, never
loads an external DTD (published MURML declares ``<!DOCTYPE definition SYSTEM
"./utterances.dtd">``, which is ignored), refuses entity declarations (the road to
expansion bombs) and oversized inputs, and turns every failure into a :class:`SpecError`.

lxml gives an element's line but not its column, and for a start tag spread over several
lines it reports the line where the tag ends; :class:`XmlSource` recovers the line and
column where each start tag begins by scanning the text once, so messages can point at
``FILE:LINE:COL`` exactly.
"""

from __future__ import annotations

import bisect
import re
from dataclasses import dataclass, field
from pathlib import Path

from lxml import etree

from mura.errors import SourceLocation, SpecError

#: Largest spec accepted, bytes. Real utterances are a few kilobytes, sign corpora about 1 MB.
MAX_SPEC_BYTES = 32 * 1024 * 1024

_START_TAG = re.compile(rb"<([A-Za-z_][\w.\-:]*)")
_SKIPPED = re.compile(rb"<!--.*?-->|<!\[CDATA\[.*?\]\]>|<\?.*?\?>|<!DOCTYPE(?:[^\[>]|\[.*?\])*>", re.S)
_ENTITY_DECLARATION = re.compile(rb"<!ENTITY")


def _parser() -> etree.XMLParser:
    return etree.XMLParser(
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        dtd_validation=False,
        huge_tree=False,
        remove_comments=True,
        remove_pis=True,
    )


def _line_column(data: bytes, offset: int) -> tuple[int, int]:
    line = data.count(b"\n", 0, offset) + 1
    column = offset - (data.rfind(b"\n", 0, offset) + 1) + 1
    return line, column


@dataclass(frozen=True)
class XmlSource:
    """A parsed XML document and the source position of each of its elements."""

    file: str
    data: bytes
    root: etree._Element
    _starts: dict[etree._Element, int]
    _line_starts: list[int] = field(default_factory=list, repr=False)

    @classmethod
    def from_bytes(cls, data: bytes, file: str = "<input>", max_bytes: int = MAX_SPEC_BYTES) -> XmlSource:
        """Parse ``data`` safely; raises :class:`SpecError` naming file, line and column."""
        if len(data) > max_bytes:
            raise SpecError(f"input is {len(data)} bytes, more than the limit of {max_bytes}", SourceLocation(file, 1, 1))
        if not data.strip():
            raise SpecError("empty document", SourceLocation(file, 1, 1))
        entity = _ENTITY_DECLARATION.search(data)
        if entity is not None:
            line, column = _line_column(data, entity.start())
            raise SpecError("entity declarations are not allowed in specs", SourceLocation(file, line, column))
        try:
            root = etree.fromstring(data, _parser())
        except etree.XMLSyntaxError as error:
            line, column = error.position if error.position else (error.lineno or 0, 0)
            raise SpecError(f"malformed XML: {error.msg}", SourceLocation(file, line, column)) from None
        except ValueError as error:
            raise SpecError(f"malformed XML: {error}", SourceLocation(file, 1, 1)) from None
        line_starts = [0] + [match.end() for match in re.finditer(rb"\n", data)]
        return cls(file, data, root, _start_offsets(data, root), line_starts)

    @classmethod
    def from_path(cls, path: str | Path, max_bytes: int = MAX_SPEC_BYTES) -> XmlSource:
        """Read and parse a file; an unreadable or oversized file is a :class:`SpecError`."""
        path = Path(path)
        try:
            size = path.stat().st_size
            if size > max_bytes:
                raise SpecError(f"file is {size} bytes, more than the limit of {max_bytes}", SourceLocation(str(path), 1, 1))
            data = path.read_bytes()
        except OSError as error:
            raise SpecError(f"cannot read file: {error.strerror or error}", SourceLocation(str(path))) from None
        return cls.from_bytes(data, str(path), max_bytes)

    def where(self, element: etree._Element, attribute: str | None = None) -> SourceLocation:
        """Where ``element`` starts, or where its ``attribute`` is written when given."""
        offset = self._starts.get(element)
        if offset is None:
            return SourceLocation(self.file, element.sourceline or 0, 0)
        if attribute is not None:
            end = self.data.find(b">", offset)
            found = re.compile(rb"\s" + re.escape(attribute.encode()) + rb"\s*=").search(self.data, offset, end if end >= 0 else None)
            if found is not None:
                offset = found.start() + 1
        line = bisect.bisect_right(self._line_starts, offset)
        return SourceLocation(self.file, line, offset - self._line_starts[line - 1] + 1)

    def error(self, message: str, element: etree._Element, attribute: str | None = None) -> SpecError:
        """A :class:`SpecError` located at ``element`` (or its ``attribute``)."""
        return SpecError(message, self.where(element, attribute))


def _start_offsets(data: bytes, root: etree._Element) -> dict[etree._Element, int]:
    """Byte offset of each element's start tag, matched in document order."""
    skipped = [(m.start(), m.end()) for m in _SKIPPED.finditer(data)]
    tags = []
    region = 0
    for match in _START_TAG.finditer(data):
        while region < len(skipped) and skipped[region][1] <= match.start():
            region += 1
        if region < len(skipped) and skipped[region][0] <= match.start() < skipped[region][1]:
            continue
        tags.append((match.group(1).decode("utf-8", "replace"), match.start()))
    offsets: dict[etree._Element, int] = {}
    position = 0
    for element in root.iter(etree.Element):
        name = _qualified_name(element)
        while position < len(tags) and tags[position][0] != name:
            position += 1
        if position == len(tags):
            break
        offsets[element] = tags[position][1]
        position += 1
    return offsets


def _qualified_name(element: etree._Element) -> str:
    qname = etree.QName(element)
    if element.prefix:
        return f"{element.prefix}:{qname.localname}"
    return qname.localname
