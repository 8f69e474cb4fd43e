"""The ``mura`` command line: one entry point, one module per subcommand.

Each module in :mod:`agent.commands` exposes ``register(subparsers)``, which adds its
subparser and sets ``func`` to a callable ``(args) -> int`` returning the exit status.
Ctrl-C and SIGTERM end a command alike (status 130 and 143) after its cleanup has run;
anything unexpected is one line on stderr (status 70), never a traceback — set
``MURA_DEBUG=1`` to see it.
"""

from __future__ import annotations

import argparse
import os
import sys
import traceback
from collections.abc import Sequence

from agent.commands import COMMANDS
from agent.commands.options import describe_failure
from agent.signals import exit_status, sigterm_interrupts

#: Exit status for an internal failure (BSD's EX_SOFTWARE).
INTERNAL_ERROR = 70


def build_parser() -> argparse.ArgumentParser:
    """The full argument parser with every registered subcommand."""
    parser = argparse.ArgumentParser(
        prog="mura",
        description="Synchronized speech and gesture for conversational agents, and signing from SiGML.",
    )
    subparsers = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for command in COMMANDS:
        command.register(subparsers)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the process exit status."""
    args = build_parser().parse_args(argv)
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
        print(f"mura {args.command}: internal error: {describe_failure(error)}", file=sys.stderr)
        return INTERNAL_ERROR


if __name__ == "__main__":
    sys.exit(main())
