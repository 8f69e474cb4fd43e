"""``mura check FILE...``: parse and validate spec files, one line per file."""

from __future__ import annotations

import argparse
import sys

from agent.commands.options import add_lexicon_option, add_limit_option, describe_failure, lexicon_of, limits_from, refuse
from agent.commands.table import SUMMARIES
from mura.check import check_file
from mura.errors import SpecError
from mura.limits import LimitError


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "check",
        help=SUMMARIES["check"],
        description="Parse and validate MURML utterances, BML 1.0 blocks, gesture lexicons and SiGML signs, "
        "against the input limits too. Prints 'FILE: OK' (then each warning as 'FILE:LINE:COL: warning: message') "
        "or each error as 'FILE:LINE:COL: message'; exits 0 only if every file is valid.",
    )
    parser.add_argument("files", nargs="+", metavar="FILE", help="spec files to check")
    add_limit_option(parser)
    add_lexicon_option(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    try:
        limits = limits_from(args)
        lexicon = lexicon_of(args)
    except (LimitError, SpecError) as error:
        return refuse("check", error)
    invalid = 0
    for path in args.files:
        try:
            result = check_file(path, limits, lexicon)
        except Exception as error:  # noqa: BLE001 - one file never stops the others
            invalid += 1
            print(f"{path}: {describe_failure(error)}")
            continue
        if result.ok:
            print(f"{path}: OK ({result.summary})")
            for warning in result.warnings:
                print(warning)
            continue
        invalid += 1
        for error in result.errors:
            print(str(error))
    if len(args.files) > 1 and invalid:
        print(f"{invalid} of {len(args.files)} files have errors", file=sys.stderr)
    return 1 if invalid else 0
