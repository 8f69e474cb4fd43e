"""Where sign synthesis spends its time: cProfile of ``realize_signs`` over the SiGML corpora.

Not a test and not a bench module of ``mura bench``: a script that plans every parsed sign
of both corpora (not profiled), then writes the process time of one
:func:`motor.signing.sequence.realize_signs` call over all the planned signs at 25 fps
(the workload of :mod:`bench.signing_speed`) without the profiler, and the top entries
(cumulative and own time) of a profile of another such call. Pin it to one core::

    taskset -c 0 .venv/bin/python bench/signs_profile.py > docs/profile_signs_after.txt
"""

from __future__ import annotations

import cProfile
import io
import time

from bench.machine import machine_info
from bench.profile_listing import listings
from bench.signing_speed import CORPORA, FOLDER, FPS
from motor.body.avatar import load_avatar
from motor.compiled import warm_up
from motor.signing.plan import SignPlanningError
from motor.signing.planning import plan_signs
from motor.signing.sequence import realize_signs
from mura.sigml import parse_sigml

#: Entries of each listing.
TOP = 25


def profile(top: int = TOP) -> str:
    avatar = load_avatar("max")
    warm_up()
    signs = [sign for name in CORPORA for sign in parse_sigml((FOLDER / name).read_bytes(), file=name).signs]
    plans = [plan for plan in plan_signs(avatar, signs) if not isinstance(plan, SignPlanningError)]
    machine = machine_info()
    out = io.StringIO()
    out.write(
        f"realize_signs profile, commit {machine.get('git_commit')}; machine: {machine.get('cpu')}, {machine.get('cores')} cores, "
        f"Python {machine.get('python')}, numpy {machine.get('numpy')}\n\n"
    )
    started = time.process_time()
    frames = realize_signs(avatar, plans, FPS).motion.frame_count
    spent = time.process_time() - started
    profiler = cProfile.Profile()
    profiler.enable()
    realize_signs(avatar, plans, FPS)
    profiler.disable()
    out.write(
        f"=== realize_signs of {len(plans)} plans at {FPS:g} fps: {frames} frames; process time without profiler "
        f"{spent:.3f} s = {frames / spent:,.0f} frames/s\n"
    )
    out.write(listings(profiler, top))
    return out.getvalue()


if __name__ == "__main__":
    print(profile(), end="")
