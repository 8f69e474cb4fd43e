"""The items of a corpus: every sign of SiGML collections, every utterance of MURML folders.

Inputs are files or folders (searched recursively, files in name order). A file's root
element says what it holds: ``<sigml>``/``<sigml_collection>`` give one item per sign
(parsed here, so that a broken sign is an item that failed with its reason and place);
anything else (``<definition>``/``<utterance>`` MURML, ``<bml>``) is one utterance item,
read where it is rendered. Folders contribute files ending ``.sigml``, ``.xml``, ``.us``
and ``.bml``.

Each item gets a unique file-name stem from its gloss or file name
(:mod:`agent.batch.naming`) in input order — over the whole corpus, before any choice by
gloss, so that an item keeps its name whichever items are chosen — and a *key*: the hash of what it is made from
(the sign's element, or the utterance file's bytes), so that a resumed run knows whether
an item recorded as done is still the same item.
"""

from __future__ import annotations

import fnmatch
import hashlib
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from lxml import etree

from agent.batch.naming import unique_stem
from mura.errors import SpecError
from mura.sigml import ROOTS as SIGML_ROOTS
from mura.sigml import read_sign_element
from mura.signs import Sign
from mura.limits import DEFAULT_LIMITS, Limits
from mura.xml_source import XmlSource

#: File suffixes taken from a folder.
CORPUS_SUFFIXES: tuple[str, ...] = (".sigml", ".xml", ".us", ".bml")

SIGN = "sign"
UTTERANCE = "utterance"
#: Consecutive items rendered as one task (a chunk's signs are planned together).
CHUNK_ITEMS = 16


@dataclass(frozen=True)
class CorpusItem:
    """One thing to render.

    Attributes:
        index: position in the corpus (input order).
        name: unique file-name stem of its outputs.
        kind: :data:`SIGN` or :data:`UTTERANCE`.
        label: the gloss, or the utterance file's name.
        source: the file it comes from.
        key: hash of its input (module docstring).
        sign: the parsed sign (signs only).
        error: why it cannot be rendered (a sign that did not parse), else None.
    """

    index: int
    name: str
    kind: str
    label: str
    source: str
    key: str
    sign: Sign | None = None
    error: str | None = None


@dataclass(frozen=True)
class Corpus:
    """The items found, and the inputs that could not be read at all."""

    items: tuple[CorpusItem, ...]
    unreadable: tuple[tuple[str, str], ...] = ()


def corpus_files(inputs: Iterable[str | Path]) -> list[Path]:
    """The files named, and those under the folders named (sorted), in input order."""
    files: list[Path] = []
    for entry in inputs:
        path = Path(entry)
        if path.is_dir():
            files.extend(sorted(p for p in path.rglob("*") if p.is_file() and p.suffix.lower() in CORPUS_SUFFIXES))
        else:
            files.append(path)
    return files


def read_corpus(inputs: Iterable[str | Path], glosses: Sequence[str] = (), limits: Limits = DEFAULT_LIMITS) -> Corpus:
    """Every item of ``inputs``, only those whose label matches one of ``glosses`` (exact
    names or shell wildcards such as ``HOUSE*``) when any are given; files and signs are
    read within ``limits`` (a sign beyond them is a failed item)."""
    drafts: list[tuple[str, str, str, str, Sign | None, str | None]] = []
    unreadable: list[tuple[str, str]] = []
    for path in corpus_files(inputs):
        try:
            source = XmlSource.from_path(path, limits=limits)
        except SpecError as error:
            unreadable.append((str(path), str(error)))
            continue
        except Exception as error:  # noqa: BLE001 - one document's failure is its own (out of memory included)
            unreadable.append((str(path), _failure(error)))
            continue
        if source.root.tag in SIGML_ROOTS:
            drafts.extend(_signs_of(source, limits))
        else:
            label = path.stem
            drafts.append((UTTERANCE, label, str(path), _digest(source.text.encode("utf-8")), None, None))
    taken: set[str] = set()
    items = tuple(
        CorpusItem(index, unique_stem(label, taken, kind), kind, label, source, key, sign, error)
        for index, (kind, label, source, key, sign, error) in enumerate(drafts)
    )
    if glosses:
        items = tuple(item for item in items if any(fnmatch.fnmatchcase(item.label, pattern) for pattern in glosses))
    return Corpus(items, tuple(unreadable))


def _signs_of(source: XmlSource, limits: Limits) -> list[tuple[str, str, str, str, Sign | None, str | None]]:
    """One draft per sign element of a SiGML document: parsed, or failed with its reason."""
    drafts = []
    for index, element in enumerate(e for e in source.root if isinstance(e.tag, str)):
        gloss = element.get("gloss", f"#{index}")
        key = _digest(etree.tostring(element, encoding="utf-8"))
        try:
            drafts.append((SIGN, gloss, source.file, key, read_sign_element(element, gloss, source.where, limits), None))
        except SpecError as error:
            drafts.append((SIGN, gloss, source.file, key, None, str(error)))
        except Exception as error:  # noqa: BLE001 - one sign's failure is its own
            drafts.append((SIGN, gloss, source.file, key, None, f"{source.file}: sign {gloss!r}: {_failure(error)}"))
    return drafts


def _failure(error: BaseException) -> str:
    """One line for an unexpected failure while reading (never a traceback)."""
    if isinstance(error, MemoryError):
        return "out of memory while reading it"
    if isinstance(error, RecursionError):
        return "nested too deeply to read"
    return f"{type(error).__name__}: {error}"


def _digest(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def chunks_of(items: Sequence[CorpusItem]) -> list[list[CorpusItem]]:
    """Items grouped by ``index // CHUNK_ITEMS``, in order."""
    groups: dict[int, list[CorpusItem]] = {}
    for item in items:
        groups.setdefault(item.index // CHUNK_ITEMS, []).append(item)
    return [groups[key] for key in sorted(groups)]


def corpus_title(corpus: Corpus) -> str:
    """The index page's title: the names of the corpus's files."""
    stems = list(dict.fromkeys(Path(item.source).stem for item in corpus.items))
    title = ", ".join(stems[:4]) + (f" and {len(stems) - 4} more" if len(stems) > 4 else "")
    return title or "corpus"
