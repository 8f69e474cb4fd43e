"""The record of a corpus run, ``DIR/manifest.json``, that makes it resumable.

Every item has an entry: its name, label, source, kind, the key of its input, the key of
the render options, its status (``rendered`` or ``failed``), the reason when it failed,
its duration, warnings, and the files it wrote with their SHA-256 hashes and sizes. A
rerun skips every item whose entry says ``rendered`` for the same input and options and
whose files are all there with their recorded sizes; everything else is rendered (again).

While a run goes, each finished item is appended to ``DIR/.manifest.journal`` (one JSON
line, flushed and synced), so that a run killed at any moment loses no finished item;
``manifest.json`` is rewritten whole, atomically, at the end (and read back, with the
journal, by the next run). Entries are listed in corpus order and hold no clock times, so
the manifest of a corpus is the same whatever the number of workers that made it.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

from agent.batch.items import CorpusItem
from agent.batch.render import RENDERED, ItemResult
from agent.export.staging import staged_text

MANIFEST = "manifest.json"
JOURNAL = ".manifest.journal"
VERSION = 1


@dataclass(frozen=True)
class Entry:
    """One item's line of the manifest, as JSON-ready fields."""

    fields: Mapping[str, object]

    @property
    def name(self) -> str:
        return str(self.fields["name"])

    @property
    def rendered(self) -> bool:
        return self.fields.get("status") == RENDERED


def entry_of(item: CorpusItem, result: ItemResult, options_key: str) -> Entry:
    """The manifest entry of an item and what became of it."""
    fields: dict[str, object] = {
        "index": item.index,
        "name": item.name,
        "label": item.label,
        "source": item.source,
        "kind": item.kind,
        "key": item.key,
        "options": options_key,
        "status": result.status,
    }
    if result.reason is not None:
        fields["reason"] = result.reason
    if result.duration is not None:
        fields["duration"] = result.duration
    if result.warnings:
        fields["warnings"] = list(result.warnings)
    fields["files"] = {f.name: {"sha256": f.sha256, "size": f.size} for f in result.files}
    return Entry(fields)


def read_manifest(folder: Path) -> dict[str, Entry]:
    """The entries recorded in ``folder`` by earlier runs, by item name (the journal's
    later lines over the manifest's). Unreadable lines, such as the last line of a run
    killed while writing it, are skipped."""
    entries: dict[str, Entry] = {}
    manifest = folder / MANIFEST
    if manifest.is_file():
        try:
            data = json.loads(manifest.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            data = {}
        for fields in data.get("items", []) if isinstance(data, dict) else []:
            if isinstance(fields, dict) and "name" in fields:
                entries[str(fields["name"])] = Entry(fields)
    journal = folder / JOURNAL
    if journal.is_file():
        for line in journal.read_text(encoding="utf-8", errors="replace").splitlines():
            try:
                fields = json.loads(line)
            except ValueError:
                continue
            if isinstance(fields, dict) and "name" in fields:
                entries[str(fields["name"])] = Entry(fields)
    return entries


def is_done(entry: Entry | None, item: CorpusItem, options_key: str, folder: Path) -> bool:
    """Whether ``entry`` records ``item`` rendered, unchanged, with the same options, and
    its files are all in ``folder`` with their recorded sizes."""
    if entry is None or not entry.rendered:
        return False
    fields = entry.fields
    if fields.get("key") != item.key or fields.get("options") != options_key:
        return False
    files = fields.get("files")
    if not isinstance(files, dict) or not files:
        return False
    for name, record in files.items():
        path = folder / name
        if not path.is_file() or not isinstance(record, dict) or path.stat().st_size != record.get("size"):
            return False
    return True


class Journal:
    """The append-only journal of a run: one synced JSON line per finished item."""

    def __init__(self, folder: Path) -> None:
        self.path = folder / JOURNAL
        self._stream = self.path.open("a", encoding="utf-8")

    def append(self, entry: Entry) -> None:
        self._stream.write(json.dumps(entry.fields, ensure_ascii=False, separators=(",", ":")) + "\n")
        self._stream.flush()
        os.fsync(self._stream.fileno())

    def close(self) -> None:
        self._stream.close()


def write_manifest(folder: Path, entries: Iterable[Entry], options: Mapping[str, object]) -> None:
    """Write ``manifest.json`` (entries in corpus order, then older entries by name) and
    remove the journal it now contains."""
    ordered = sorted(entries, key=lambda e: (0, int(e.fields["index"])) if "index" in e.fields else (1, e.name))  # type: ignore[arg-type]
    rendered = sum(entry.rendered for entry in ordered)
    data = {
        "version": VERSION,
        "options": dict(options),
        "summary": {"items": len(ordered), "rendered": rendered, "failed": len(ordered) - rendered},
        "items": [dict(entry.fields) for entry in ordered],
    }
    with staged_text(folder / MANIFEST) as stream:
        json.dump(data, stream, indent=1, ensure_ascii=False)
        stream.write("\n")
    (folder / JOURNAL).unlink(missing_ok=True)
