"""Helpers of the hostile-input suite: running ``mura`` in a bounded subprocess, generated inputs.

Every subprocess runs with an address-space limit (:data:`ADDRESS_SPACE_MB`, about three
times what mura needs for the largest input the suite renders) and a wall-clock timeout
that is the test's only use of time: a hang fails the test, nothing is asserted about
durations.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
#: Address-space limit of every mura subprocess, MiB (mura itself maps about 400 MiB).
ADDRESS_SPACE_MB = 1536
#: Timeout of one mura subprocess, seconds (a run that hangs fails the test).
SUBPROCESS_TIMEOUT = 60.0
#: Options for runs whose output files a test lists: the light test avatar, no GLB (the
#: skinned default avatar adds NAME.glb and a shared model script beside the page).
LIGHT = ("--avatar", "max", "--no-glb")


@dataclass(frozen=True)
class Run:
    """What a mura subprocess did."""

    status: int
    out: str
    err: str


def run_mura(*args: str, hooks: list[dict] | None = None, address_space_mb: int = ADDRESS_SPACE_MB,
             env: dict[str, str] | None = None, cwd: Path | None = None) -> Run:
    """``mura ARGS`` in a fresh Python with the address-space limit and the hooks of
    ``mura_runner.py``; asserts that it printed no traceback."""
    config = json.dumps({"address_space_mb": address_space_mb, "hooks": hooks or []})
    environment = {**os.environ, "PYTHONPATH": str(REPO), **(env or {})}
    environment.pop("MURA_DEBUG", None)
    done = subprocess.run(
        [sys.executable, str(HERE / "mura_runner.py"), config, "--", *args],
        capture_output=True, text=True, timeout=SUBPROCESS_TIMEOUT, env=environment, cwd=cwd or REPO, check=False,
    )  # fmt: skip
    assert "Traceback" not in done.stderr, done.stderr
    return Run(done.returncode, done.stdout, done.stderr)


def all_files(folder: Path) -> list[str]:
    """Every file and folder under ``folder``, hidden ones included, relative and sorted."""
    if not folder.exists():
        return []
    return sorted(str(path.relative_to(folder)) for path in folder.rglob("*"))


def utterance(text: str = "Hello there.", behaviors: str = "") -> str:
    """A MURML utterance with ``text`` (may hold ``<time>`` tags) and behaviour specs."""
    return f"<utterance><specification>{text}</specification>{behaviors}</utterance>"


def absolute_gesture(onset: str, end: str, ident: str = "g1", constraint: str | None = None) -> str:
    """A behaviour spec with an absolutely timed gesture (``<timing onset end>``)."""
    constraint = constraint or '<static slot="HandShape" value="BSifinger"/>'
    return (f'<behaviorspec id="{ident}"><gesture><constraints>{constraint}</constraints></gesture>'
            f'<timing onset="{onset}" end="{end}"/></behaviorspec>')
