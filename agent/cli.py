"""The ``mura`` command line: one entry point, one module per subcommand.

Each module in :mod:`agent.commands` exposes ``register(subparsers)``, which adds its
subparser and sets ``func`` to a callable ``(args) -> int`` returning the exit status.
Only the module of the command named on the line is imported (the others are listed by
their line in :data:`agent.commands.table.SUMMARIES`): the motor's compiled kernels and
the plotting and clustering libraries take seconds to load, which ``mura --help`` and
``mura check`` need not wait for.
Ctrl-C and SIGTERM end a command alike (status 130 and 143) after its cleanup has run;
anything unexpected is one line on stderr (status 70), never a traceback — set
``MURA_DEBUG=1`` to see it.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
import traceback
from collections.abc import Sequence

from agent.commands.table import SUMMARIES
from agent.signals import exit_status, sigterm_interrupts

#: Exit status for an internal failure (BSD's EX_SOFTWARE).
INTERNAL_ERROR = 70


def build_parser(commands: Sequence[str] = tuple(SUMMARIES)) -> argparse.ArgumentParser:
    """The argument parser: every subcommand listed, and those in ``commands`` (default:
    all) registered with their own arguments from their modules."""
    parser = argparse.ArgumentParser(
        prog="mura",
        description="Synchronized speech and gesture for conversational agents, and signing from SiGML.",
    )
    subparsers = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, summary in SUMMARIES.items():
        if name in commands:
            importlib.import_module(f"agent.commands.{name}").register(subparsers)
        else:
            subparsers.add_parser(name, help=summary)
    return parser


def named_command(argv: Sequence[str]) -> tuple[str, ...]:
    """The command a command line names (its first word not an option, as the top-level
    parser has none but ``--help``), as a tuple of none or one known command."""
    first = next((word for word in argv if not word.startswith("-")), None)
    return (first,) if first in SUMMARIES else ()


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the process exit status."""
    words = sys.argv[1:] if argv is None else list(argv)
    args = build_parser(named_command(words)).parse_args(words)
    try:
        with sigterm_interrupts():
            return int(args.func(args))
    except KeyboardInterrupt as interrupt:
        print("interrupted", file=sys.stderr)
        return exit_status(interrupt)
    except BrokenPipeError:
        # The reader went away (``mura check … | head``): stop quietly, as Unix tools do.
        sys.stderr.close()
        return 141
    except Exception as error:  # noqa: BLE001 - the last line of defence: one line, no traceback
        if os.environ.get("MURA_DEBUG"):
            traceback.print_exc()
        from agent.commands.options import describe_failure  # noqa: PLC0415 - the command's module has loaded it

        print(f"mura {args.command}: internal error: {describe_failure(error)}", file=sys.stderr)
        return INTERNAL_ERROR


if __name__ == "__main__":
    sys.exit(main())
