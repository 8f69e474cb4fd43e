"""Where sign planning spends its time: cProfile of ``plan_signs`` over the SiGML corpora.

Not a test and not a bench module of ``mura bench``: a script that writes the top entries
(cumulative and own time) of a profile of one :func:`motor.signing.planning.plan_signs`
call over the quick selection (every 20th parsed sign) and over all the signs of both
corpora, each after a short warm-up and beside the call's process time without the
profiler (CPU time of this process, steadier than the wall clock on a shared machine)::

    .venv/bin/python bench/planning_profile.py > docs/profile_planning_after.txt
"""

from __future__ import annotations

import argparse
import cProfile
import io
import sys
import time
from pathlib import Path

from bench.machine import machine_info
from bench.profile_listing import listings
from motor.body.avatar import load_avatar
from motor.signing.planning import plan_signs
from mura.sigml import parse_sigml

CORPORA = ("German_SL_DGS.sigml", "Indian_SL.sigml")
FOLDER = Path(__file__).resolve().parents[1].parent / "shared" / "corpora" / "sigml"
#: Entries of each listing.
TOP = 15


def profile(folder: Path = FOLDER, top: int = TOP) -> str:
    avatar = load_avatar("max")
    parsed = [parse_sigml((folder / name).read_bytes(), file=name).signs for name in CORPORA]
    machine = machine_info()
    out = io.StringIO()
    out.write(
        f"plan_signs profile, commit {machine.get('git_commit')}; machine: {machine.get('cpu')}, {machine.get('cores')} cores, "
        f"Python {machine.get('python')}, numpy {machine.get('numpy')}\n\n"
    )
    for label, stride in (("quick (every 20th sign)", 20), ("full", 1)):
        signs = [sign for signs in parsed for sign in signs[::stride]]
        plan_signs(avatar, signs[:5])  # first use: imports, the manner tables
        started = time.process_time()
        plan_signs(avatar, signs)
        spent = time.process_time() - started
        profiler = cProfile.Profile()
        profiler.enable()
        plan_signs(avatar, signs)
        profiler.disable()
        out.write(f"=== plan_signs over {label}: {len(signs)} signs; process time without profiler {spent:.3f} s = {1e3 * spent / len(signs):.3f} ms/sign\n")
        out.write(listings(profiler, top))
    return out.getvalue()


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--corpora", type=Path, default=FOLDER, help="folder of the SiGML corpora")
    sys.stdout.write(profile(parser.parse_args().corpora))
