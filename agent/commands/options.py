"""Options and messages every subcommand shares: ``--limit NAME=VALUE`` and one-line failures."""

from __future__ import annotations

import argparse
import sys

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
