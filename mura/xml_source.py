"""Safe XML reading with exact source positions for every element and attribute.

Specs come from users and from the web, so reading one never touches the network, never
loads an external DTD (published MURML declares ``<!DOCTYPE definition SYSTEM
"./utterances.dtd">``, which is ignored), refuses entity declarations (the road to
expansion bombs) in whatever encoding the document is written, refuses oversized inputs
by the bytes actually read (a pipe, a FIFO or ``/dev/zero`` report no size), and turns
every failure into a :class:`SpecError`.

lxml gives an element's line but not its column, and for a start tag spread over several
lines it reports the line where the tag ends; :class:`XmlSource` recovers the line and
column where each start tag begins by scanning the decoded text once. The scan is a
hand-written loop over ``str.find`` and anchored matches — no regular expression that
can backtrack — so its time is linear in the document's length whatever the document
holds (a ``<!DOCTYPE`` full of brackets once made a backtracking pattern run for hours).
"""

from __future__ import annotations

import bisect
import codecs
import os
import re
import select
import stat
from dataclasses import dataclass, field

from lxml import etree

from mura.errors import SourceLocation, SpecError
from mura.limits import DEFAULT_LIMITS, Limits, hint

#: Largest spec accepted by default, bytes (``Limits.max_input_bytes``).
MAX_SPEC_BYTES = DEFAULT_LIMITS.max_input_bytes
#: Bytes read from a file or stream at a time.
READ_BLOCK = 1 << 16

_NAME = re.compile(r"[A-Za-z_][\w.\-:]*")
_DECLARATION_MARK = re.compile(r"[\"'\[\]>]|<!--")
_ENCODING_DECLARATION = re.compile(rb"<\?xml[^>]{0,200}?encoding\s*=\s*[\"']([A-Za-z][A-Za-z0-9._\-]{0,40})[\"']")
_ENTITY_DECLARATION = "<!ENTITY"
#: Byte-order marks and the first bytes of ``<?`` in encodings that are not ASCII-compatible (XML 1.0, Appendix F).
_SIGNATURES: tuple[tuple[bytes, str], ...] = (
    (codecs.BOM_UTF32_BE, "utf-32"),
    (codecs.BOM_UTF32_LE, "utf-32"),
    (codecs.BOM_UTF8, "utf-8-sig"),
    (codecs.BOM_UTF16_BE, "utf-16"),
    (codecs.BOM_UTF16_LE, "utf-16"),
    (b"\x00\x00\x00<", "utf-32-be"),
    (b"<\x00\x00\x00", "utf-32-le"),
    (b"\x00<\x00?", "utf-16-be"),
    (b"<\x00?\x00", "utf-16-le"),
)


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


def _line_column(text: str, offset: int) -> tuple[int, int]:
    line = text.count("\n", 0, offset) + 1
    column = offset - (text.rfind("\n", 0, offset) + 1) + 1
    return line, column


@dataclass(frozen=True)
class XmlSource:
    """A parsed XML document and the source position of each of its elements.

    ``text`` is the document decoded (from UTF-8, UTF-16 or its declared encoding);
    columns count its characters.
    """

    file: str
    text: str
    root: etree._Element
    _starts: dict[etree._Element, int]
    _line_starts: list[int] = field(default_factory=list, repr=False)

    @classmethod
    def from_bytes(cls, data: bytes, file: str = "<input>", max_bytes: int | None = None,
                   limits: Limits = DEFAULT_LIMITS) -> XmlSource:
        """Parse ``data`` safely; raises :class:`SpecError` naming file, line and column.

        ``max_bytes`` (default ``limits.max_input_bytes``) bounds the document's size.
        """
        limit = limits.max_input_bytes if max_bytes is None else max_bytes
        if len(data) > limit:
            raise SpecError(f"input is {len(data)} bytes, more than the limit of {limit} ({hint('max_input_bytes')})",
                            SourceLocation(file, 1, 1))
        text = decode_document(data, file)
        if not text.strip():
            raise SpecError("empty document", SourceLocation(file, 1, 1))
        entity = text.find(_ENTITY_DECLARATION)
        if entity >= 0:
            raise SpecError("entity declarations are not allowed in specs", SourceLocation(file, *_line_column(text, entity)))
        try:
            root = etree.fromstring(data, _parser())
        except etree.XMLSyntaxError as error:
            line, column = error.position if error.position else (error.lineno or 0, 0)
            raise SpecError(f"malformed XML: {error.msg}", SourceLocation(file, line, column)) from None
        except ValueError as error:
            raise SpecError(f"malformed XML: {error}", SourceLocation(file, 1, 1)) from None
        _refuse_declared_entities(root, file)
        line_starts = [0] + [index + 1 for index in _all(text, "\n")]
        return cls(file, text, root, _start_offsets(text, root), line_starts)

    @classmethod
    def from_path(cls, path: str | os.PathLike[str], max_bytes: int | None = None,
                  limits: Limits = DEFAULT_LIMITS) -> XmlSource:
        """Read and parse a file, pipe or device; an unreadable or oversized input is a :class:`SpecError`."""
        limit = limits.max_input_bytes if max_bytes is None else max_bytes
        data = read_bounded(path, limit, limits.stream_timeout)
        return cls.from_bytes(data, str(path), limit, limits)

    def where(self, element: etree._Element, attribute: str | None = None) -> SourceLocation:
        """Where ``element`` starts, or where its ``attribute`` is written when given."""
        offset = self._starts.get(element)
        if offset is None:
            return SourceLocation(self.file, element.sourceline or 0, 0)
        if attribute is not None:
            offset = _attribute_offset(self.text, offset, attribute)
        line = bisect.bisect_right(self._line_starts, offset)
        return SourceLocation(self.file, line, offset - self._line_starts[line - 1] + 1)

    def error(self, message: str, element: etree._Element, attribute: str | None = None) -> SpecError:
        """A :class:`SpecError` located at ``element`` (or its ``attribute``)."""
        return SpecError(message, self.where(element, attribute))


def read_bounded(path: str | os.PathLike[str], max_bytes: int, stream_timeout: float) -> bytes:
    """The bytes of ``path``, at most ``max_bytes`` of them, else :class:`SpecError`.

    A regular file is refused by its size before it is read. Anything else (a pipe, a
    FIFO, ``/dev/zero``) is read until it ends, refused as soon as more than
    ``max_bytes`` arrived, and refused when it sends nothing for ``stream_timeout``
    seconds — a FIFO nobody writes to would otherwise block forever. Folders are refused.
    """
    name = str(path)
    where = SourceLocation(name)
    try:
        descriptor = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except OSError as error:
        raise SpecError(f"cannot read file: {error.strerror or error}", where) from None
    try:
        info = os.fstat(descriptor)
        if stat.S_ISDIR(info.st_mode):
            raise SpecError("cannot read file: it is a folder", where)
        regular = stat.S_ISREG(info.st_mode)
        if regular:
            if info.st_size > max_bytes:
                raise SpecError(f"file is {info.st_size} bytes, more than the limit of {max_bytes} ({hint('max_input_bytes')})",
                                SourceLocation(name, 1, 1))
            os.set_blocking(descriptor, True)
        return _read_up_to(descriptor, max_bytes, None if regular else stream_timeout, name)
    except OSError as error:
        raise SpecError(f"cannot read file: {error.strerror or error}", where) from None
    finally:
        os.close(descriptor)


def _read_up_to(descriptor: int, max_bytes: int, timeout: float | None, name: str) -> bytes:
    pieces: list[bytes] = []
    total = 0
    poller = select.poll() if timeout is not None else None
    if poller is not None:
        poller.register(descriptor, select.POLLIN | select.POLLPRI)
    while True:
        if poller is not None and not poller.poll(max(1, int(timeout * 1000))):
            raise SpecError(f"no data arrived for {timeout:g} s from this pipe or device ({hint('stream_timeout')})",
                            SourceLocation(name))
        try:
            piece = os.read(descriptor, min(READ_BLOCK, max_bytes + 1 - total))
        except BlockingIOError:
            continue
        if not piece:
            return b"".join(pieces)
        pieces.append(piece)
        total += len(piece)
        if total > max_bytes:
            raise SpecError(f"input is more than the limit of {max_bytes} bytes ({hint('max_input_bytes')})", SourceLocation(name, 1, 1))


def decode_document(data: bytes, file: str) -> str:
    """The document's text: its encoding from the byte-order mark or the first bytes, else
    its XML declaration, else UTF-8 (XML 1.0, Appendix F). Undecodable bytes are a :class:`SpecError`
    at their line and column."""
    encoding = _encoding(data, file)
    try:
        return data.decode(encoding)
    except UnicodeDecodeError as error:
        good = data[: error.start].decode(encoding, "replace")
        line, column = _line_column(good, len(good))
        raise SpecError(f"not valid {encoding.upper()}: byte 0x{data[error.start]:02x} cannot be decoded",
                        SourceLocation(file, line, column)) from None


def _encoding(data: bytes, file: str) -> str:
    for signature, encoding in _SIGNATURES:
        if data.startswith(signature):
            return encoding
    declared = _ENCODING_DECLARATION.match(data)
    if declared is None:
        return "utf-8"
    name = declared.group(1).decode("ascii").lower()
    try:
        info = codecs.lookup(name)
    except LookupError:
        raise SpecError(f"unknown encoding {name!r} in the XML declaration", SourceLocation(file, 1, declared.start(1) + 1)) from None
    if info.name.startswith(("utf-16", "utf-32")):
        return "utf-8"  # declared as 16 or 32 bits but written with 8-bit units: libxml2 names the mismatch
    return info.name


def _refuse_declared_entities(root: etree._Element, file: str) -> None:
    """Second line of defence: an internal DTD subset that declares entities, however written."""
    dtd = root.getroottree().docinfo.internalDTD
    if dtd is not None and any(True for _ in dtd.iterentities()):
        raise SpecError("entity declarations are not allowed in specs", SourceLocation(file, 1, 1))


def _all(text: str, needle: str):
    position = text.find(needle)
    while position >= 0:
        yield position
        position = text.find(needle, position + 1)


def _skip_to(text: str, closing: str, start: int) -> int:
    end = text.find(closing, start)
    return len(text) if end < 0 else end + len(closing)


def _declaration_end(text: str, start: int) -> int:
    """The offset after a ``<!DOCTYPE …>`` (or other ``<!`` declaration) starting at ``start``:
    quoted literals and comments are skipped whole, ``>`` inside ``[…]`` does not end it."""
    position = start + 2
    in_subset = False
    while True:
        mark = _DECLARATION_MARK.search(text, position)
        if mark is None:
            return len(text)
        token = mark.group()
        if token in ("'", '"'):
            position = _skip_to(text, token, mark.end())
        elif token == "<!--":
            position = _skip_to(text, "-->", mark.end())
        elif token == "[":
            in_subset, position = True, mark.end()
        elif token == "]":
            in_subset, position = False, mark.end()
        elif in_subset:
            position = mark.end()
        else:
            return mark.end()


def _start_tags(text: str) -> list[tuple[str, int]]:
    """Every start tag's name and offset, outside comments, CDATA, PIs and declarations."""
    tags: list[tuple[str, int]] = []
    position = text.find("<")
    while position >= 0:
        if text.startswith("<!--", position):
            position = _skip_to(text, "-->", position + 4)
        elif text.startswith("<![CDATA[", position):
            position = _skip_to(text, "]]>", position + 9)
        elif text.startswith("<?", position):
            position = _skip_to(text, "?>", position + 2)
        elif text.startswith("<!", position):
            position = _declaration_end(text, position)
        else:
            name = _NAME.match(text, position + 1)
            if name is not None:
                tags.append((name.group(), position))
                position = name.end()
            else:
                position += 1
        position = text.find("<", position)
    return tags


def _start_offsets(text: str, root: etree._Element) -> dict[etree._Element, int]:
    """Character offset of each element's start tag, matched in document order."""
    tags = _start_tags(text)
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


def _attribute_offset(text: str, offset: int, attribute: str) -> int:
    """Where ``attribute`` is written in the start tag at ``offset`` (the tag's offset when absent)."""
    end = text.find(">", offset)
    found = re.compile(r"\s" + re.escape(attribute) + r"\s*=").search(text, offset, end if end >= 0 else len(text))
    return found.start() + 1 if found is not None else offset


def _qualified_name(element: etree._Element) -> str:
    qname = etree.QName(element)
    if element.prefix:
        return f"{element.prefix}:{qname.localname}"
    return qname.localname
