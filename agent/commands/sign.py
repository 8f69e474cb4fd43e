"""``mura sign FILE.sigml... -o DIR``: render SiGML (or HamNoSys) signs to BVH and avatar pages.

Every sign is rendered on its own (``<gloss>.bvh``, ``<gloss>.face.json`` — the
non-manuals' morph weights — and ``<gloss>.html``), or with ``--sequence`` all signs of
all files in order as one performance (``sequence.bvh`` …) with transitions between them. A sign that cannot be read or realized
fails alone with its reason; the others still render. ``--report`` writes a JSON record
of every sign: whether it rendered, its duration, and why not when it did not.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from dataclasses import dataclass
from pathlib import Path

from tqdm import tqdm

from agent.export.bvh import bvh_text, write_bvh
from agent.export.face import face_json, page_face_json
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
from mura.sigml import parse_sigml
from mura.signs import Sign

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
    records: list[SignRecord] = []
    signs = _read_signs(args, records)
    plans: list[tuple[SignRecord, SignPlan]] = []
    for source, sign in tqdm(signs, desc="planning", unit="sign", file=sys.stderr, disable=len(signs) < 20):
        record = SignRecord(source, sign.gloss)
        records.append(record)
        try:
            plans.append((record, plan_sign(avatar, sign)))
        except SignPlanningError as error:
            record.reason = str(error)
    if args.sequence:
        _render_sequence(avatar, plans, output, args.fps, args.glb)
    else:
        names: set[str] = set()
        for record, plan in tqdm(plans, desc="rendering", unit="sign", file=sys.stderr, disable=len(plans) < 20):
            _render_one(avatar, record, plan, output, args.fps, names, args.glb)
    if args.report:
        _write_json(Path(args.report), _report(records))
    rendered = sum(record.rendered for record in records)
    print(f"{rendered} of {len(records)} signs rendered to {output}")
    for record in records:
        if not record.rendered:
            print(f"{record.source}: {record.gloss}: {record.reason}")
    return 0 if rendered == len(records) else 1


def _read_signs(args: argparse.Namespace, records: list[SignRecord]) -> list[tuple[str, Sign]]:
    """Signs of every file (failures go straight into the records) and the HamNoSys sign."""
    signs: list[tuple[str, Sign]] = []
    for path in args.files:
        try:
            result = parse_sigml(Path(path).read_bytes(), file=path)
        except (OSError, SpecError) as error:
            records.append(SignRecord(path, "*", reason=f"cannot read the document: {error}"))
            continue
        signs.extend((path, sign) for sign in result.signs)
        records.extend(SignRecord(path, failure.gloss, reason=str(failure.error)) for failure in result.failures)
    if args.hamnosys is not None:
        try:
            signs.append(("--hamnosys", parse_hamnosys(args.hamnosys, gloss=args.gloss)))
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


def _render_one(avatar, record: SignRecord, plan: SignPlan, output: Path, fps: float, names: set[str], glb: bool = True) -> None:
    try:
        signed = realize_signs(avatar, [plan], fps)
        stem = safe_stem(plan.gloss, names)
        record.files = _write_performance(signed, output, stem, plan.gloss, avatar if glb else None, avatar)
    except (SignPlanningError, ValueError, FloatingPointError, OSError) as error:
        record.reason = f"{type(error).__name__}: {error}"
        return
    record.rendered = True
    record.duration = round(signed.duration, 4)
    record.warnings = signed.warnings


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


def _write_performance(signed: SignedMotion, output: Path, stem: str, name: str, glb_avatar=None, page_avatar=None) -> tuple[str, ...]:
    """BVH, page (drawing ``page_avatar``'s own model) and, with ``glb_avatar``, the GLB."""
    bvh_path = output / f"{stem}.bvh"
    write_bvh(signed.motion, bvh_path)
    face_path = output / f"{stem}.face.json"
    with staged_text(face_path, "ascii") as stream:
        stream.write(face_json(signed.motion))
    files = [str(bvh_path), str(face_path)]
    if glb_avatar is not None:
        glb_path = output / f"{stem}.glb"
        write_motion_glb(signed.motion, glb_path, motion_model(glb_avatar), glb_avatar.root_height)
        files.append(str(glb_path))
    try:
        html_path = output / f"{stem}.html"
        model = page_model(page_avatar) if page_avatar is not None else None
        write_html(html_path, name=name, bvh_text=bvh_text(signed.motion), timeline=timeline_of(signed, name), wav_filename=None, model=model,
                   face_json=page_face_json(signed.motion))  # fmt: skip
        files.append(str(html_path))
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


def _write_json(path: Path, data: dict) -> None:
    """Write JSON under a temporary name in the same folder, then rename."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with staged_text(path) as stream:
        json.dump(data, stream, indent=1, ensure_ascii=False)
