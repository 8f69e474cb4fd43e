"""Options and messages every subcommand shares: ``--limit NAME=VALUE``, ``--lexicon FILE`` and one-line failures."""

from __future__ import annotations

import argparse
import sys

from mura.lexicon import GestureLexicon, load_lexicons
from mura.limits import DEFAULT_LIMITS, LIMIT_INFO, Limits

_LIMIT_HELP = "raise or lower an input limit for this run (repeatable); NAME is one of " + ", ".join(
    f"{name} ({info.unit}, default {getattr(DEFAULT_LIMITS, name)})" for name, info in LIMIT_INFO.items()
)


def add_limit_option(parser: argparse.ArgumentParser) -> None:
    """``--limit NAME=VALUE``, repeatable (see :mod:`mura.limits`)."""
    parser.add_argument("--limit", action="append", default=[], metavar="NAME=VALUE", help=_LIMIT_HELP.replace("%", "%%"))


def limits_from(args: argparse.Namespace) -> Limits:
    """The limits this run asked for; :class:`~mura.limits.LimitError` names a bad ``--limit``."""
    return DEFAULT_LIMITS.with_overrides(getattr(args, "limit", []) or [])


def refuse(command: str, message: object, status: int = 2) -> int:
    """Print ``mura COMMAND: message`` on stderr and return ``status`` (2: the command line or set-up is wrong)."""
    print(f"mura {command}: {message}", file=sys.stderr)
    return status


def describe_failure(error: BaseException) -> str:
    """One line for an unexpected failure of one item of a batch (never a traceback)."""
    if isinstance(error, MemoryError):
        return "out of memory while processing it (the input is too large for this machine; lower the limits)"
    if isinstance(error, RecursionError):
        return "nested too deeply to process"
    return f"{type(error).__name__}: {error}"


def add_lexicon_option(parser: argparse.ArgumentParser) -> None:
    """``--lexicon FILE`` (repeatable): gesture lexicons or symbol tables layered over the bundled lexicon."""
    parser.add_argument("--lexicon", action="append", default=[], metavar="FILE",
                        help="a gesture lexicon (<lexicon> or the published <gestures>) or symbol table (<hns>) whose "
                        "functions and names utterances may use; repeatable, later files win")  # fmt: skip


def lexicon_of(args: argparse.Namespace) -> GestureLexicon | None:
    """The lexicon the command's ``--lexicon`` files make (None: the bundled one); raises
    :class:`~mura.errors.SpecError` for a malformed file."""
    paths = getattr(args, "lexicon", []) or []
    return load_lexicons(paths) if paths else None
