"""Subcommands of the ``mura`` command line, in the order ``mura --help`` lists them."""

from agent.commands import check, say

COMMANDS = (check, say)
