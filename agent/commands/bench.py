"""``mura bench [--json FILE] [--quick] [--readme]``: speed, synchrony and naturalness figures."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from agent.commands.table import SUMMARIES
from bench.machine import REPO_ROOT
from bench.motion_audit.report import format_summary
from bench.runner import MODULES, format_table, readme_section, run_bench, update_readme


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "bench",
        help=SUMMARIES["bench"],
        description="Run every benchmark module (median of several runs each), print the figures with the "
        "design's targets, optionally write them as JSON or into README.md. Figures, not pass/fail.",
    )
    parser.add_argument("--json", metavar="FILE", type=Path, help="write every figure and the machine as JSON")
    parser.add_argument("--quick", action="store_true", help="fewer and shorter runs (about a minute)")
    parser.add_argument("--readme", action="store_true", help="update the README section between the bench markers")
    parser.add_argument("--only", metavar="MODULE", action="append", choices=MODULES,
                        help="run only this bench module (repeatable), e.g. bench.head_face")  # fmt: skip
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    command = "mura bench" + (" --quick" if args.quick else "") + "".join(f" --only {name}" for name in args.only or ())
    chosen = {"modules": tuple(args.only)} if args.only else {}
    report = run_bench(**chosen, quick=args.quick, command=command, progress=lambda name: print(f"running {name} …", file=sys.stderr))
    print(format_table(report))
    audit = report["results"].get("bench.motion_audit", {})
    if "corpus" in audit:
        print()
        print(format_summary(audit["corpus"]["overall"], "motion audit (look at the renders: python -m bench.motion_audit --corpus --keep DIR)"))
    if args.json is not None:
        args.json.write_text(json.dumps(report, indent=2, default=str) + "\n", encoding="utf-8")
    if args.readme:
        try:
            update_readme(REPO_ROOT / "README.md", readme_section(report))
        except ValueError as error:
            print(f"mura bench: {error}", file=sys.stderr)
            return 1
    return 0
