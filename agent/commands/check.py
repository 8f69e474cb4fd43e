"""``mura check FILE...``: parse and validate spec files, one line per file."""

from __future__ import annotations

import argparse

from mura.check import check_file


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "check",
        help="parse and validate spec files",
        description="Parse and validate MURML utterances, BML 1.0 blocks, gesture lexicons and SiGML signs. "
        "Prints 'FILE: OK' (then each warning as 'FILE:LINE:COL: warning: message') or each error as "
        "'FILE:LINE:COL: message'; exits 0 only if every file is valid.",
    )
    parser.add_argument("files", nargs="+", metavar="FILE", help="spec files to check")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    status = 0
    for path in args.files:
        result = check_file(path)
        if result.ok:
            print(f"{path}: OK ({result.summary})")
            for warning in result.warnings:
                print(warning)
            continue
        status = 1
        for error in result.errors:
            print(str(error))
    return status
