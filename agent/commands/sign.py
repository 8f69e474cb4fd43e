"""``mura sign FILE.sigml... -o DIR``: render SiGML (or HamNoSys) signs to BVH and avatar pages.

Every sign is rendered on its own (``<gloss>.bvh``, ``<gloss>.face.json`` — the
non-manuals' morph weights — and ``<gloss>.html``), or with ``--sequence`` all signs of
all files in order as one performance (``sequence.bvh`` …) with transitions between them. A sign that cannot be read or realized
fails alone with its reason; the others still render. ``--report`` writes a JSON record
of every sign: whether it rendered, its duration, and why not when it did not.

A sign is refused when its repetitions expand to more than ``--limit max_movements``
movements; any failure of one sign (whatever the exception, running out of memory
included) is that sign's alone. The files are staged and moved into the output folder
when the run ends, so an interrupted run leaves the folder (and the report) as they were.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from dataclasses import dataclass
from pathlib import Path

from tqdm import tqdm

from agent.commands.options import add_limit_option, describe_failure, limits_from, refuse
from agent.export.bvh import bvh_text, write_bvh
from agent.export.face import face_json, page_face_json
from agent.export.gltf import motion_model, write_motion_glb
from agent.export.html import write_html
from agent.export.names import OutputNameError, OutputPlan
from agent.export.page_model import page_model
from agent.export.staging import OutputFolderError, StagedRun
from motor.body.avatar import DEFAULT_AVATAR, load_avatar
from motor.signing.plan import SignPlan
from motor.signing.planning import plan_sign
from motor.signing.sequence import SignedMotion, realize_signs
from mura.errors import SpecError
from mura.hamnosys import parse_hamnosys
from mura.limits import Limits
from mura.sigml import read_sigml
from mura.signs import Sign
from mura.xml_source import XmlSource

#: The files one rendered sign is written as.
SIGN_SUFFIXES = (".bvh", ".face.json", ".html", ".glb")

#: Longest file name stem derived from a gloss.
MAX_STEM = 80


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
        help="render SiGML/HamNoSys signs to BVH and avatar pages",
        description="Render every sign of SiGML files (or a HamNoSys string) to BVH and an avatar page; "
        "each sign fails alone with its reason.",
    )
    parser.add_argument("files", nargs="*", metavar="FILE.sigml", help="SiGML documents")
    parser.add_argument("-o", "--output", required=True, metavar="DIR", help="output folder (created if missing)")
    parser.add_argument("--avatar", default=DEFAULT_AVATAR, help=f"avatar name or file, or your own .vrm/.glb/.gltf (default: {DEFAULT_AVATAR})")
    parser.add_argument("--no-glb", dest="glb", action="store_false", help="do not write <gloss>.glb")
    parser.add_argument("--fps", type=float, default=25.0, help="frames per second (default: 25)")
    parser.add_argument("--sequence", action="store_true", help="render all signs in order as one performance")
    parser.add_argument("--report", metavar="report.json", help="write a JSON record of every sign")
    parser.add_argument("--hamnosys", metavar="TEXT", help="a HamNoSys 4 Unicode string to render as a sign")
    parser.add_argument("--gloss", default="sign", help="the gloss of the --hamnosys sign (default: sign)")
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
    output = Path(args.output)
    try:
        with StagedRun(output) as staged:
            report = staged.beside(args.report) if args.report else None
            records = _render_all(args, avatar, limits, fps, staged.folder, OutputPlan(output, args.files))
            if report is not None:
                report.write_text(json.dumps(_report(records), indent=1, ensure_ascii=False), encoding="utf-8")
            staged.commit()
    except OutputFolderError as error:
        return refuse("sign", error)
    rendered = sum(record.rendered for record in records)
    print(f"{rendered} of {len(records)} signs rendered to {output}" + (f"; {len(records) - rendered} failed" if rendered < len(records) else ""))
    for record in records:
        if not record.rendered:
            print(f"{record.source}: {record.gloss}: {record.reason}")
    return 0 if rendered == len(records) else 1


def _render_all(args: argparse.Namespace, avatar, limits: Limits, fps: float, folder: Path, outputs: OutputPlan) -> list[SignRecord]:
    """Read, plan and render every sign into ``folder``; one record per sign, failures included."""
    records: list[SignRecord] = []
    signs = _read_signs(args, records, limits)
    plans: list[tuple[SignRecord, SignPlan]] = []
    for source, sign in tqdm(signs, desc="planning", unit="sign", file=sys.stderr, disable=len(signs) < 20):
        record = SignRecord(source, sign.gloss)
        records.append(record)
        try:
            plans.append((record, plan_sign(avatar, sign)))
        except Exception as error:  # noqa: BLE001 - one sign's failure is its own
            record.reason = describe_failure(error)
    if args.sequence:
        _render_sequence(avatar, plans, folder, fps, outputs, args.glb)
        return records
    names: set[str] = set()
    for record, plan in tqdm(plans, desc="rendering", unit="sign", file=sys.stderr, disable=len(plans) < 20):
        _render_one(avatar, record, plan, folder, fps, names, outputs, args.glb)
    return records


def _read_signs(args: argparse.Namespace, records: list[SignRecord], limits: Limits) -> list[tuple[str, Sign]]:
    """Signs of every file (failures go straight into the records) and the HamNoSys sign."""
    signs: list[tuple[str, Sign]] = []
    for path in args.files:
        try:
            result = read_sigml(XmlSource.from_path(path, limits=limits), limits)
        except SpecError as error:
            records.append(SignRecord(path, "*", reason=f"cannot read the document: {error}"))
            continue
        except Exception as error:  # noqa: BLE001 - one document's failure is its own
            records.append(SignRecord(path, "*", reason=f"cannot read the document: {describe_failure(error)}"))
            continue
        signs.extend((path, sign) for sign in result.signs)
        records.extend(SignRecord(path, failure.gloss, reason=str(failure.error)) for failure in result.failures)
    if args.hamnosys is not None:
        try:
            signs.append(("--hamnosys", parse_hamnosys(args.hamnosys, gloss=args.gloss, file="--hamnosys", limits=limits)))
        except SpecError as error:
            records.append(SignRecord("--hamnosys", args.gloss, reason=str(error)))
    return signs


def safe_stem(gloss: str, taken: set[str]) -> str:
    """A file name stem from a gloss: letters, digits, ``-`` and ``_`` only, unique in
    ``taken`` (which it joins)."""
    stem = re.sub(r"[^A-Za-z0-9_-]+", "_", gloss).strip("_")[:MAX_STEM] or "sign"
    candidate, number = stem, 2
    while candidate.lower() in taken:
        candidate = f"{stem}_{number}"
        number += 1
    taken.add(candidate.lower())
    return candidate


def _render_one(avatar, record: SignRecord, plan: SignPlan, folder: Path, fps: float, names: set[str], outputs: OutputPlan,
                glb: bool = True) -> None:
    try:
        stem = safe_stem(plan.gloss, names)
        outputs.claim(f"sign {plan.gloss!r}", stem, SIGN_SUFFIXES)
        signed = realize_signs(avatar, [plan], fps)
        record.files = _write_performance(signed, folder, stem, plan.gloss, outputs.folder, avatar if glb else None, avatar)
    except OutputNameError as error:
        record.reason = str(error)
        return
    except Exception as error:  # noqa: BLE001 - one sign's failure is its own
        record.reason = describe_failure(error)
        return
    record.rendered = True
    record.duration = round(signed.duration, 4)
    record.warnings = signed.warnings


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
        record.warnings = plan.warnings


def timeline_of(signed: SignedMotion, name: str) -> dict:
    """The avatar page's timeline: one behaviour per sign with its phases."""
    arms = ["right_arm", "left_arm"]
    behaviors = [
        {
            "id": timing.gloss, "chunk": 0, "arms": arms,
            "phases": {
                "start": timing.start, "ready": timing.ready, "stroke_start": timing.ready,
                "stroke": 0.5 * (timing.ready + timing.end), "stroke_end": timing.end, "relax": timing.end, "end": timing.end,
            },
        }
        for timing in signed.timings
    ]  # fmt: skip
    return {
        "version": 1, "name": name, "duration": signed.duration, "fps": signed.motion.fps, "chunks": [],
        "behaviors": behaviors, "words": [], "phonemes": [], "time_tags": {},
    }  # fmt: skip


def _write_performance(signed: SignedMotion, folder: Path, stem: str, name: str, output: Path, glb_avatar=None,
                       page_avatar=None) -> tuple[str, ...]:
    """BVH, page (drawing ``page_avatar``'s own model) and, with ``glb_avatar``, the GLB,
    written into ``folder``; returns their paths in ``output``, where they end up."""
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
    failures: dict[str, int] = {}
    for record in records:
        if not record.rendered:
            key = (record.reason or "unknown").split(":")[-1].strip()[:80]
            failures[key] = failures.get(key, 0) + 1
    return {
        "total": len(records),
        "rendered": sum(r.rendered for r in records),
        "failures_by_reason": failures,
        "signs": [record.as_json() for record in records],
    }

