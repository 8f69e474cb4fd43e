"""``mura sign FILE.sigml... -o DIR``: render SiGML (or HamNoSys) signs to BVH and the corpus viewer.

Every sign is rendered on its own — ``NAME.bvh``, ``NAME.motion.js`` for ``DIR/index.html``
(one viewer for all the signs: search by gloss, play, step through), ``NAME.glb`` unless
``--no-glb``, ``NAME.html`` with ``--pages`` — or with ``--sequence`` all signs of all
files in order as one performance (``sequence.bvh``, ``sequence.html``) with transitions
between them. ``NAME`` is the gloss with its letters of any script kept
(:mod:`agent.batch.naming`); ``--gloss`` picks signs by gloss. A sign that cannot be read
or realized fails alone with its reason; the others still render. ``--report`` writes a
JSON record of every sign (whether it rendered, its duration, its warnings said once, why
not when it did not) and the failures and warnings grouped by kind. For a corpus on many
cores, resumably, see ``mura batch``.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import dataclass
from pathlib import Path

from tqdm import tqdm

from agent.batch.items import SIGN, Corpus, CorpusItem, read_corpus
from agent.batch.manifest import Entry, entry_of
from agent.batch.naming import unique_stem
from agent.batch.outputs import report_of, write_corpus_pages
from agent.batch.report import summarize_warnings
from agent.batch.render import RenderOptions, planning_reason, render_chunk, timeline_of
from agent.batch.items import chunks_of, corpus_title
from agent.export.bvh import bvh_text, write_bvh
from agent.export.gltf import motion_model, write_motion_glb
from agent.export.html import write_html
from agent.export.page_model import page_model
from agent.export.staging import staged_text
from motor.body.avatar import DEFAULT_AVATAR, load_avatar
from motor.signing.plan import SignPlan, SignPlanningError
from motor.signing.planning import plan_sign
from motor.signing.sequence import SignedMotion, realize_signs
from mura.errors import SpecError
from mura.hamnosys import parse_hamnosys

@dataclass
class SignRecord:
    """One line of the report."""

    source: str
    gloss: str
    rendered: bool = False
    duration: float | None = None
    files: tuple[str, ...] = ()
    reason: str | None = None
    warnings: tuple[str, ...] = ()

    def as_json(self) -> dict:
        return {
            "source": self.source, "gloss": self.gloss, "rendered": self.rendered, "duration": self.duration,
            "files": list(self.files), "reason": self.reason, "warnings": list(self.warnings),
        }  # fmt: skip


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "sign",
        help="render SiGML/HamNoSys signs to BVH and the corpus viewer",
        description="Render every sign of SiGML files (or a HamNoSys string) to BVH and DIR/index.html, the viewer "
        "of all the signs; each sign fails alone with its reason.",
    )
    parser.add_argument("files", nargs="*", metavar="FILE.sigml", help="SiGML documents")
    parser.add_argument("-o", "--output", required=True, metavar="DIR", help="output folder (created if missing)")
    parser.add_argument("--avatar", default=DEFAULT_AVATAR, help=f"avatar name or file, or your own .vrm/.glb/.gltf (default: {DEFAULT_AVATAR})")
    parser.add_argument("--no-glb", dest="glb", action="store_false", help="do not write <gloss>.glb")
    parser.add_argument("--pages", action="store_true", help="also write a stand-alone page <gloss>.html per sign")
    parser.add_argument("--fps", type=float, default=25.0, help="frames per second (default: 25)")
    parser.add_argument("--sequence", action="store_true", help="render all signs in order as one performance")
    parser.add_argument("--report", metavar="report.json", help="write a JSON record of every sign, failures and warnings by kind")
    parser.add_argument("--hamnosys", metavar="TEXT", help="a HamNoSys 4 Unicode string to render as a sign")
    parser.add_argument("--gloss", action="append", default=[], metavar="NAME",
                        help="render only the signs with this gloss (wildcards * ? allowed); repeatable. "
                        "With --hamnosys, the first names that sign (default: sign)")  # fmt: skip
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if not args.files and args.hamnosys is None:
        print("mura sign: give SiGML files or --hamnosys", file=sys.stderr)
        return 2
    if not args.fps > 0:
        print(f"mura sign: --fps must be positive, got {args.fps}", file=sys.stderr)
        return 2
    try:
        avatar = load_avatar(args.avatar)
    except (OSError, ValueError) as error:
        print(f"mura sign: {error}", file=sys.stderr)
        return 2
    output = Path(args.output)
    output.mkdir(parents=True, exist_ok=True)
    corpus, records = _read_signs(args)
    if not corpus.items and not records:
        print(f"mura sign: no sign with gloss {', '.join(args.gloss)}", file=sys.stderr)
        return 1
    if args.sequence:
        plans: list[tuple[SignRecord, SignPlan]] = []
        for item in corpus.items:
            record = SignRecord(item.source, item.label, reason=item.error)
            records.append(record)
            try:
                if item.sign is not None:
                    plans.append((record, plan_sign(avatar, item.sign)))
            except SignPlanningError as error:
                record.reason = planning_reason(item.sign, error)
        _render_sequence(avatar, plans, output, args.fps, args.glb)
    else:
        records.extend(_render_signs(corpus, output, RenderOptions(args.avatar, args.fps, args.glb, args.pages)))
    report = _report(records)
    if args.report:
        _write_json(Path(args.report), report)
    rendered = sum(record.rendered for record in records)
    print(f"{rendered} of {len(records)} signs rendered to {output}" + ("" if args.sequence else f" (viewer: {output / 'index.html'})"))
    for record in records:
        if not record.rendered:
            print(f"{record.source}: {record.gloss}: {record.reason}")
    for kind, group in report["failures_by_kind"].items():
        print(f"{group['count']:5d} × {kind}")
    return 0 if rendered == len(records) else 1


def _read_signs(args: argparse.Namespace) -> tuple[Corpus, list[SignRecord]]:
    """The signs of every file (a file that is no SiGML, or that cannot be read, is a
    failed record) and the HamNoSys sign."""
    glosses = args.gloss if args.files else ()
    corpus = read_corpus(args.files, [] if args.hamnosys is not None and not args.files else glosses)
    records = [SignRecord(source, "*", reason=f"cannot read the document: {reason}") for source, reason in corpus.unreadable]
    items = []
    for item in corpus.items:
        if item.kind == SIGN:
            items.append(item)
        else:
            records.append(SignRecord(item.source, "*", reason="cannot read the document: not a SiGML document (<sigml> or <sigml_collection>)"))
    if args.hamnosys is not None:
        gloss = args.gloss[0] if args.gloss and not args.files else "sign"
        taken = {item.name.casefold() for item in items}
        name = unique_stem(gloss, taken)
        try:
            sign = parse_hamnosys(args.hamnosys, gloss=gloss, file="--hamnosys")
            items.append(CorpusItem(len(corpus.items), name, SIGN, gloss, "--hamnosys", "", sign))
        except SpecError as error:
            records.append(SignRecord("--hamnosys", gloss, reason=str(error)))
    return Corpus(tuple(items), corpus.unreadable), records


def _render_signs(corpus: Corpus, output: Path, options: RenderOptions) -> list[SignRecord]:
    """Every sign rendered on its own (chunk by chunk, as ``mura batch`` renders them),
    then the corpus viewer for all of them."""
    records, entries = [], []
    items = list(corpus.items)
    bar = tqdm(total=len(items), desc="rendering", unit="sign", file=sys.stderr, disable=len(items) < 20)
    for chunk in chunks_of(items):
        by_index = {item.index: item for item in chunk}
        for result in render_chunk(chunk, options, output):
            item = by_index[result.index]
            files = tuple(str(output / f.name) for f in result.files)
            records.append(SignRecord(item.source, item.label, result.rendered, result.duration, files, result.reason, result.warnings))
            entries.append(entry_of(item, result, options.key()))
        bar.update(len(chunk))
    bar.close()
    if entries:
        write_corpus_pages(output, entries, options, corpus_title(corpus))
    return records


def safe_stem(gloss: str, taken: set[str]) -> str:
    """A file name stem from a gloss (letters of every script kept), unique in ``taken``
    (which it joins; see :mod:`agent.batch.naming`)."""
    return unique_stem(gloss, taken)


def _render_sequence(avatar, plans: list[tuple[SignRecord, SignPlan]], output: Path, fps: float, glb: bool = True) -> None:
    if not plans:
        return
    try:
        signed = realize_signs(avatar, [plan for _, plan in plans], fps)
        files = _write_performance(signed, output, "sequence", "sequence", avatar if glb else None, avatar)
    except (SignPlanningError, ValueError, FloatingPointError, OSError) as error:
        for record, _ in plans:
            record.reason = f"the sequence failed: {type(error).__name__}: {error}"
        return
    for (record, plan), timing in zip(plans, signed.timings):
        record.rendered = True
        record.duration = round(timing.end - timing.ready, 4)
        record.files = files
        record.warnings = summarize_warnings(plan.warnings)


def _write_performance(signed: SignedMotion, output: Path, stem: str, name: str, glb_avatar=None, page_avatar=None) -> tuple[str, ...]:
    """BVH, page (drawing ``page_avatar``'s own model) and, with ``glb_avatar``, the GLB."""
    bvh_path = output / f"{stem}.bvh"
    write_bvh(signed.motion, bvh_path)
    files = [str(bvh_path)]
    if glb_avatar is not None:
        glb_path = output / f"{stem}.glb"
        write_motion_glb(signed.motion, glb_path, motion_model(glb_avatar), glb_avatar.root_height)
        files.append(str(glb_path))
    try:
        html_path = output / f"{stem}.html"
        model = page_model(page_avatar) if page_avatar is not None else None
        write_html(html_path, name=name, bvh_text=bvh_text(signed.motion), timeline=timeline_of(signed, name), wav_filename=None, model=model)
        files.append(str(html_path))
    except Exception as error:  # noqa: BLE001 - the page is optional; the BVH is the sign
        print(f"mura sign: no avatar page for {name!r}: {error}", file=sys.stderr)
    return tuple(files)


def _report(records: list[SignRecord]) -> dict:
    """Totals, the failures and warnings grouped by kind, and every sign's record."""
    entries = [
        Entry({"label": r.gloss, "source": r.source, "status": "rendered" if r.rendered else "failed", "reason": r.reason or "unknown", "warnings": list(r.warnings)})
        for r in records
    ]  # fmt: skip
    grouped = report_of(entries)
    return {
        "total": len(records),
        "rendered": sum(r.rendered for r in records),
        "failures_by_kind": grouped["failures_by_kind"],
        "warnings_by_kind": grouped["warnings_by_kind"],
        "signs": [record.as_json() for record in records],
    }


def _write_json(path: Path, data: dict) -> None:
    """Write JSON under a temporary name in the same folder, then rename."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with staged_text(path) as stream:
        json.dump(data, stream, indent=1, ensure_ascii=False)
