"""``mura sign FILE.sigml... -o DIR``: render SiGML (or HamNoSys) signs to BVH and the corpus viewer.

Every sign is rendered on its own — ``NAME.bvh``, ``NAME.face.json`` (the non-manuals'
morph weights), ``NAME.motion.js`` for ``DIR/index.html`` (one viewer for all the signs:
search by gloss, play, step through), ``NAME.glb`` unless ``--no-glb``, ``NAME.html`` with
``--pages`` — or with ``--sequence`` all signs of all files in order as one performance
(``sequence.bvh``, ``sequence.html`` …) with transitions between them. ``NAME`` is the
gloss with its letters of any script kept (:mod:`agent.batch.naming`); ``--gloss`` picks
signs by gloss. A sign that cannot be read or realized fails alone with its reason (any
exception, running out of memory included); the others still render. ``--report`` writes
a JSON record of every sign (whether it rendered, its duration, its warnings said once,
why not when it did not) and the failures and warnings grouped by kind. For a corpus on
many cores, resumably, see ``mura batch``.

A sign is refused when its repetitions expand to more than ``--limit max_movements``
movements. The files are staged and moved into the output folder when the run ends, so an
interrupted run leaves the folder (and the report) as they were.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
from dataclasses import dataclass
from pathlib import Path

from tqdm import tqdm

from agent.batch.items import SIGN, Corpus, CorpusItem, chunks_of, corpus_title, read_corpus
from agent.batch.manifest import Entry, entry_of
from agent.batch.naming import unique_stem
from agent.batch.outputs import report_of, write_corpus_pages
from agent.batch.report import summarize_warnings
from agent.batch.render import RenderOptions, planning_reason, render_chunk, timeline_of
from agent.commands.options import add_limit_option, describe_failure, limits_from, refuse
from agent.commands.table import SUMMARIES
from agent.export.bvh import bvh_text, write_bvh
from agent.export.face import face_json, page_face_json
from agent.export.gltf import motion_model, write_motion_glb
from agent.export.html import write_html
from agent.export.names import OutputNameError, OutputPlan
from agent.export.page_model import page_model
from agent.export.staging import OutputFolderError, StagedRun
from motor.body.avatar import load_avatar
from motor.body.conventions import DEFAULT_AVATAR
from motor.signing.plan import SignPlan, SignPlanningError
from motor.signing.planning import plan_signs
from motor.signing.sequence import SignedMotion, realize_signs
from mura.errors import SpecError
from mura.hamnosys import parse_hamnosys
from mura.limits import Limits

#: The files one rendered sign may be written as.
SIGN_SUFFIXES = (".bvh", ".face.json", ".motion.js", ".html", ".glb")

__all__ = ["SignRecord", "register", "run", "safe_stem", "timeline_of"]


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
        help=SUMMARIES["sign"],
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
    add_limit_option(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if not args.files and args.hamnosys is None:
        return refuse("sign", "give SiGML files or --hamnosys")
    try:
        limits = limits_from(args)
        fps = limits.check_fps(args.fps)
        avatar = load_avatar(args.avatar)
    except (OSError, ValueError) as error:
        return refuse("sign", error)
    if args.report and Path(args.report).is_dir():
        return refuse("sign", f"--report {args.report}: is a folder; give the report file's name")
    corpus, records = _read_signs(args, limits)
    if not corpus.items and not records:
        print(f"mura sign: no sign with gloss {', '.join(args.gloss)}", file=sys.stderr)
        return 1
    output = Path(args.output)
    try:
        with StagedRun(output) as staged:
            report_path = staged.beside(args.report) if args.report else None
            outputs = OutputPlan(output, args.files)
            if args.sequence:
                records.extend(_sequence(avatar, corpus, staged.folder, fps, outputs, args.glb))
            else:
                options = RenderOptions(args.avatar, fps, args.glb, args.pages, limits=tuple(args.limit))
                records.extend(_render_signs(corpus, staged.folder, output, options, outputs))
            report = _report(records)
            if report_path is not None:
                report_path.write_text(json.dumps(report, indent=1, ensure_ascii=False), encoding="utf-8")
            staged.commit()
    except OutputFolderError as error:
        return refuse("sign", error)
    rendered = sum(record.rendered for record in records)
    viewer = "" if args.sequence or not rendered else f" (viewer: {output / 'index.html'})"
    print(f"{rendered} of {len(records)} signs rendered to {output}{viewer}"
          + (f"; {len(records) - rendered} failed" if rendered < len(records) else ""))  # fmt: skip
    for record in records:
        if not record.rendered:
            print(f"{record.source}: {record.gloss}: {record.reason}")
    for kind, group in report["failures_by_kind"].items():
        print(f"{group['count']:5d} × {kind}")
    return 0 if rendered == len(records) else 1


def _read_signs(args: argparse.Namespace, limits: Limits) -> tuple[Corpus, list[SignRecord]]:
    """The signs of every file (a file that is no SiGML, or that cannot be read, is a
    failed record) and the HamNoSys sign."""
    glosses = args.gloss if args.files else ()
    corpus = read_corpus(args.files, glosses, limits)
    records = [SignRecord(source, "*", reason=f"cannot read the document: {reason}") for source, reason in corpus.unreadable]
    items = []
    for item in corpus.items:
        if item.kind == SIGN:
            items.append(item)
        else:
            records.append(SignRecord(item.source, "*", reason="cannot read the document: not a SiGML document (<sigml> or <sigml_collection>)"))
    if args.hamnosys is not None:
        gloss = args.gloss[0] if args.gloss and not args.files else "sign"
        name = unique_stem(gloss, {item.name.casefold() for item in items})
        try:
            sign = parse_hamnosys(args.hamnosys, gloss=gloss, file="--hamnosys", limits=limits)
            items.append(CorpusItem(len(corpus.items), name, SIGN, gloss, "--hamnosys", "", sign))
        except SpecError as error:
            records.append(SignRecord("--hamnosys", gloss, reason=str(error)))
        except Exception as error:  # noqa: BLE001 - the sign's failure is its own
            records.append(SignRecord("--hamnosys", gloss, reason=describe_failure(error)))
    return Corpus(tuple(items), corpus.unreadable), records


def _render_signs(corpus: Corpus, folder: Path, output: Path, options: RenderOptions, outputs: OutputPlan) -> list[SignRecord]:
    """Every sign rendered on its own into ``folder`` (chunk by chunk, as ``mura batch``
    renders them), then the corpus viewer for all of them; files are named as they end
    up, in ``output``."""
    records, entries = [], []
    items = [_claimed(item, outputs) for item in corpus.items]
    bar = tqdm(total=len(items), desc="rendering", unit="sign", file=sys.stderr, disable=len(items) < 20)
    for chunk in chunks_of(items):
        by_index = {item.index: item for item in chunk}
        for result in render_chunk(chunk, options, folder):
            item = by_index[result.index]
            files = tuple(str(output / f.name) for f in result.files)
            records.append(SignRecord(item.source, item.label, result.rendered, result.duration, files, result.reason, result.warnings))
            entries.append(entry_of(item, result, options.key()))
        bar.update(len(chunk))
    bar.close()
    if any(entry.rendered for entry in entries):
        write_corpus_pages(folder, entries, options, corpus_title(corpus))
    return records


def _claimed(item: CorpusItem, outputs: OutputPlan) -> CorpusItem:
    """``item``, failed when its files would overwrite an input of the run."""
    try:
        outputs.claim(f"sign {item.label!r}", item.name, SIGN_SUFFIXES)
    except OutputNameError as error:
        return dataclasses.replace(item, sign=None, error=f"{item.source}: {item.label}: {error}")
    return item


def safe_stem(gloss: str, taken: set[str]) -> str:
    """A file name stem from a gloss (letters of every script kept), unique in ``taken``
    (which it joins; see :mod:`agent.batch.naming`)."""
    return unique_stem(gloss, taken)


def _sequence(avatar, corpus: Corpus, folder: Path, fps: float, outputs: OutputPlan, glb: bool) -> list[SignRecord]:
    """All signs planned together (one by one if that fails), then realized in order as
    one performance."""
    records = [SignRecord(item.source, item.label, reason=item.error) for item in corpus.items]
    planned = [(record, item.sign) for record, item in zip(records, corpus.items) if item.sign is not None]
    try:
        results = plan_signs(avatar, [sign for _, sign in planned])
    except Exception:  # noqa: BLE001 - planned again one by one, where each failure stays with its sign
        results = [_plan_alone(avatar, sign) for _, sign in planned]
    plans: list[tuple[SignRecord, SignPlan]] = []
    for (record, sign), result in zip(planned, results):
        if isinstance(result, SignPlanningError):
            record.reason = planning_reason(sign, result)
        elif isinstance(result, Exception):
            record.reason = describe_failure(result)
        else:
            plans.append((record, result))
    _render_sequence(avatar, plans, folder, fps, outputs, glb)
    return records


def _plan_alone(avatar, sign) -> SignPlan | Exception:
    """One sign's plan, or whatever stopped it (one sign's failure is its own)."""
    try:
        (result,) = plan_signs(avatar, [sign])
    except Exception as error:  # noqa: BLE001 - reported on this sign alone
        return error
    return result


def _render_sequence(avatar, plans: list[tuple[SignRecord, SignPlan]], folder: Path, fps: float, outputs: OutputPlan,
                     glb: bool = True) -> None:
    if not plans:
        return
    try:
        outputs.claim("the sequence", "sequence", SIGN_SUFFIXES)
        signed = realize_signs(avatar, [plan for _, plan in plans], fps)
        files = _write_performance(signed, folder, "sequence", "sequence", outputs.folder, avatar if glb else None, avatar)
    except Exception as error:  # noqa: BLE001 - reported on every sign of the sequence
        for record, _ in plans:
            record.reason = f"the sequence failed: {describe_failure(error)}"
        return
    for (record, plan), timing in zip(plans, signed.timings):
        record.rendered = True
        record.duration = round(timing.end - timing.ready, 4)
        record.files = files
        record.warnings = summarize_warnings(plan.warnings)


def _write_performance(signed: SignedMotion, folder: Path, stem: str, name: str, output: Path, glb_avatar=None,
                       page_avatar=None) -> tuple[str, ...]:
    """BVH, face weights, page (drawing ``page_avatar``'s own model) and, with
    ``glb_avatar``, the GLB, written into ``folder``; returns their paths in ``output``,
    where they end up."""
    write_bvh(signed.motion, folder / f"{stem}.bvh")
    (folder / f"{stem}.face.json").write_text(face_json(signed.motion), encoding="ascii")
    files = [str(output / f"{stem}.bvh"), str(output / f"{stem}.face.json")]
    if glb_avatar is not None:
        write_motion_glb(signed.motion, folder / f"{stem}.glb", motion_model(glb_avatar), glb_avatar.root_height)
        files.append(str(output / f"{stem}.glb"))
    try:
        model = page_model(page_avatar) if page_avatar is not None else None
        write_html(folder / f"{stem}.html", name=name, bvh_text=bvh_text(signed.motion), timeline=timeline_of(signed, name),
                   wav_filename=None, model=model, face_json=page_face_json(signed.motion))
        files.append(str(output / f"{stem}.html"))
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
