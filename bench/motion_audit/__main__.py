"""``python -m bench.motion_audit DIR [--avatar NAME] [--json FILE]`` — audit a folder of renders;
``python -m bench.motion_audit --corpus [--quick] [--keep DIR] [--json FILE]`` — render the
visible inputs first, then audit them.

Prints the figures with their targets and where each is worst (file, time, joint), then
the worst offenders, then one line per subfolder. Exit status 0 when the audit ran
(figures, not pass/fail), 2 when it could not (no such folder, no BVH, bad avatar).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path

from tqdm import tqdm

from bench.motion_audit.audit import audit_folder
from bench.motion_audit.avatar_file import AvatarError, known_avatars, read_avatar
from bench.motion_audit.corpus import audit_corpus
from bench.motion_audit.report import format_groups, format_leads, format_summary, summarize


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="python -m bench.motion_audit",
        description="Audit rendered motion (BVH, with timeline and WAV when present) with kinematics independent of mura.",
    )
    parser.add_argument("folder", nargs="?", type=Path, metavar="DIR", help="folder of renders (searched recursively for *.bvh)")
    parser.add_argument("--avatar", help="avatar name (specs/avatars, build/avatars) or file: the one the renders are audited against (default: the known avatar each file matches); with --corpus, the avatar rendered (default: mura's)")
    parser.add_argument("--json", type=Path, metavar="FILE", help="write every figure, and each file's, as JSON")
    parser.add_argument("--corpus", action="store_true", help="render the visible inputs (examples, published MURML, 200 signs) and audit them")
    parser.add_argument("--quick", action="store_true", help="with --corpus: a small subset")
    parser.add_argument("--keep", type=Path, metavar="DIR", help="with --corpus: leave the renders in DIR (must not exist)")
    return parser


def _write_json(path: Path, data: dict) -> None:
    """Write under a temporary name beside ``path``, then rename: never half a file."""
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(handle, "w", encoding="utf-8") as stream:
            json.dump(data, stream, indent=1, ensure_ascii=False)
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


def _group(name: str) -> str:
    """The subfolder a render lies in (``.`` at the top)."""
    return name.split("/", 1)[0] if "/" in name else "."


def _audit_folder(args: argparse.Namespace) -> int:
    folder: Path = args.folder
    if not folder.is_dir():
        print(f"motion audit: {folder}: no such folder", file=sys.stderr)
        return 2
    try:
        avatars = [read_avatar(args.avatar)] if args.avatar else known_avatars()
    except AvatarError as error:
        print(f"motion audit: {error}", file=sys.stderr)
        return 2
    files = sorted(folder.rglob("*.bvh"))
    if not files:
        print(f"motion audit: {folder}: no *.bvh files", file=sys.stderr)
        return 2
    bar = tqdm(total=len(files), desc="auditing", unit="file", file=sys.stderr, disable=len(files) < 20)
    audits, failures = audit_folder(folder, avatars, lambda _name: bar.update())
    bar.close()
    summary = summarize(audits, failures)
    groups = {}
    if any("/" in audit.file for audit in audits):
        names = sorted({_group(audit.file) for audit in audits})
        groups = {name: summarize([a for a in audits if _group(a.file) == name]) for name in names}
    print(format_summary(summary, f"motion audit of {folder}"))
    if leads := format_leads(summary):
        print(leads)
    if groups:
        print("\nper folder:")
        print(format_groups(groups))
    if args.json:
        _write_json(args.json, {"folder": str(folder), "summary": summary, "groups": groups, "files": [audit.as_json() for audit in audits]})
    return 0


def _audit_corpus(args: argparse.Namespace) -> int:
    if args.keep is not None and args.keep.exists():
        print(f"motion audit: --keep {args.keep}: already exists", file=sys.stderr)
        return 2
    if args.keep is not None:
        args.keep.parent.mkdir(parents=True, exist_ok=True)
    result = audit_corpus(args.quick, args.keep, avatar=args.avatar, progress=lambda text: print(text, file=sys.stderr) if not text.startswith("auditing") else None)
    print(f"corpus: {result['rendered']} of {result['items']} items rendered ({result['render_seconds']:.0f} s), audited in {result['audit_seconds']:.0f} s")
    for failure in result["render_failures"]:
        print(f"  not rendered: {failure['file']}: {failure['reason']}")
    print(format_summary(result["overall"], "motion audit, every render"))
    print()
    print(format_summary(result["speech"], "motion audit, renders with espeak-ng speech"))
    if leads := format_leads(result["speech"]):
        print(leads)
    print("\nper group:")
    print(format_groups(result["groups"]))
    if args.keep is not None:
        print(f"\nrenders kept in {args.keep}")
    if args.json:
        _write_json(args.json, result)
    return 0


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    if args.corpus == (args.folder is not None):
        print("motion audit: give a folder of renders or --corpus (not both)", file=sys.stderr)
        return 2
    try:
        return _audit_corpus(args) if args.corpus else _audit_folder(args)
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
