"""Subcommands of the ``mura`` command line, one module each, named as the command.

Each module exposes ``register(subparsers)``, which adds its subparser (with its line
from :data:`agent.commands.table.SUMMARIES`) and sets ``func`` to a callable
``(args) -> int`` returning the exit status. :mod:`agent.cli` imports only the module of
the command that runs."""
