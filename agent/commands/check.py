"""``mura check FILE...``: parse and validate spec files, one line per file."""

from __future__ import annotations

import argparse

from agent.commands.render import add_lexicon_option, lexicon_of
from mura.check import check_file
from mura.errors import SpecError


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "check",
        help="parse and validate spec files",
        description="Parse and validate MURML utterances, gesture lexicons and SiGML signs. "
        "Prints 'FILE: OK' or each error as 'FILE:LINE:COL: message'; exits 0 only if every file is valid.",
    )
    parser.add_argument("files", nargs="+", metavar="FILE", help="spec files to check")
    add_lexicon_option(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    try:
        lexicon = lexicon_of(args)
    except SpecError as error:
        print(str(error))
        return 1
    status = 0
    for path in args.files:
        result = check_file(path, lexicon)
        if result.ok:
            print(f"{path}: OK ({result.summary})")
            continue
        status = 1
        for error in result.errors:
            print(str(error))
    return status
