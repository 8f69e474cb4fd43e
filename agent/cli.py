"""The ``mura`` command line: one entry point, one module per subcommand.

Each module in :mod:`agent.commands` exposes ``register(subparsers)``, which adds its
subparser and sets ``func`` to a callable ``(args) -> int`` returning the exit status.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from agent.commands import COMMANDS


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
        return int(args.func(args))
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # The reader went away (``mura check … | head``): stop quietly, as Unix tools do.
        sys.stderr.close()
        return 141


if __name__ == "__main__":
    sys.exit(main())
