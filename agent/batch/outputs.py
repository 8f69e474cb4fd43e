"""The files a corpus run writes once for all its items: the report and the index page.

``report.json`` holds the totals, the failures grouped by kind and the warnings grouped by
kind (:mod:`agent.batch.report`), each kind with its count and a few examples, and the
inputs that could not be read at all. ``index.html`` is the corpus viewer
(:mod:`agent.export.corpus_index`) listing every item of the run.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Sequence
from pathlib import Path

from agent.batch.manifest import Entry
from agent.batch.render import RenderOptions
from agent.batch.report import Example, split_subject, group_by_kind
from agent.export.corpus_index import IndexEntry, skeleton_of, write_index
from agent.export.page_model import page_model
from agent.export.staging import staged_text
from agent.performance import rest_motion
from motor.body.avatar import load_avatar

INDEX = "index.html"
REPORT = "report.json"


def report_of(entries: Sequence[Entry], unreadable: Iterable[tuple[str, str]] = ()) -> dict:
    """The report of a run's entries (module docstring)."""
    failures = [Example(str(e.fields["label"]), str(e.fields["source"]), str(e.fields.get("reason", "unknown"))) for e in entries if not e.rendered]
    warnings = [
        Example(str(e.fields["label"]), str(e.fields["source"]), split_subject(str(line))[1])
        for e in entries for line in e.fields.get("warnings", ())  # type: ignore[union-attr]
    ]  # fmt: skip
    rendered = sum(entry.rendered for entry in entries)
    return {
        "total": len(entries),
        "rendered": rendered,
        "failed": len(entries) - rendered,
        "unreadable": [{"source": source, "reason": reason} for source, reason in unreadable],
        "failures_by_kind": group_by_kind(failures),
        "warnings_by_kind": group_by_kind(warnings),
    }


def write_report(path: Path, entries: Sequence[Entry], unreadable: Iterable[tuple[str, str]] = ()) -> dict:
    """Write ``report.json``; returns what it holds."""
    report = report_of(entries, unreadable)
    with staged_text(path) as stream:
        json.dump(report, stream, indent=1, ensure_ascii=False)
        stream.write("\n")
    return report


def index_entries(entries: Sequence[Entry]) -> list[IndexEntry]:
    """The index page's list: every entry, rendered ones with their motion file."""
    listed = []
    for entry in entries:
        fields = entry.fields
        files = fields.get("files", {}) if entry.rendered else {}
        motion, audio = f"{entry.name}.motion.js", f"{entry.name}.wav"
        listed.append(IndexEntry(
            entry.name, str(fields["label"]), str(fields["source"]), str(fields["status"]),
            fields.get("duration"), fields.get("reason"),  # type: ignore[arg-type]
            motion if motion in files else None, audio if audio in files else None,  # type: ignore[operator]
        ))  # fmt: skip
    return listed


def write_corpus_pages(folder: Path, entries: Sequence[Entry], options: RenderOptions, title: str) -> Path:
    """Write ``index.html`` for ``entries`` rendered with ``options`` into ``folder``."""
    avatar = load_avatar(options.avatar)
    skeleton = skeleton_of(rest_motion(avatar, options.fps or 25.0))
    path = folder / INDEX
    write_index(path, title=title, skeleton=skeleton, entries=index_entries(entries), model=page_model(avatar))
    return path
