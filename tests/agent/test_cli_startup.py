"""The command line imports only the module of the command that runs: ``mura --help`` and
``mura check`` start without the motor's compiled kernels and the heavy libraries, and
every command still registers under its name with its line of the table."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from agent.cli import build_parser, named_command
from agent.commands.table import SUMMARIES
from mura.resources import SPECS_DIR

HEAVY = ("numba", "motor.control", "motor.arm.ik", "sklearn", "matplotlib", "scipy.interpolate", "networkx")


def loaded_after(argv: list[str]) -> tuple[int, list[str]]:
    """Exit status of ``mura ARGV`` run in a fresh interpreter, and which heavy modules it loaded."""
    script = (
        "import json, sys\n"
        "from agent.cli import main\n"
        "try:\n    status = main(sys.argv[1:])\nexcept SystemExit as stop:\n    status = stop.code\n"
        f"print(json.dumps([status, [m for m in {HEAVY!r} if m in sys.modules]]))\n"
    )
    done = subprocess.run([sys.executable, "-c", script, *argv], capture_output=True, text=True, check=True)
    status, loaded = json.loads(done.stdout.strip().splitlines()[-1])
    return status, loaded


@pytest.mark.parametrize("argv", [["--help"], [], ["nosuch"], ["check", "--help"]], ids=["help", "no command", "unknown command", "check help"])
def test_the_light_command_lines_load_nothing_heavy(argv):
    status, loaded = loaded_after(argv)
    assert status == (0 if "--help" in argv else 2)
    assert loaded == []


@pytest.mark.parametrize("spec", sorted(str(path) for path in (SPECS_DIR / "utterances").glob("*.xml"))[:2])
def test_checking_a_file_loads_nothing_heavy(spec):
    status, loaded = loaded_after(["check", spec])
    assert status == 0
    assert loaded == []


def test_every_command_registers_under_its_name():
    parser = build_parser()
    (action,) = [a for a in parser._subparsers._group_actions]
    assert list(action.choices) == list(SUMMARIES)
    assert {choice.dest: choice.help for choice in action._choices_actions} == SUMMARIES


@pytest.mark.parametrize(
    ("argv", "named"),
    [(["sign", "x.sigml"], ("sign",)), (["--help"], ()), (["-h", "check"], ("check",)), (["nosuch"], ()), ([], ())],
)
def test_the_named_command_is_the_first_word_that_is_no_option(argv, named):
    assert named_command(argv) == named
