"""Subcommands of the ``mura`` command line, in the order ``mura --help`` lists them."""

from agent.commands import avatar, batch, bench, check, demo, play, plot, render, say, serve, sign, verbs

COMMANDS = (check, say, render, play, plot, demo, bench, sign, batch, avatar, serve, verbs)
