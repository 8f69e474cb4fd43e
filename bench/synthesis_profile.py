"""Where gesture synthesis spends its time: cProfile of the motion-speed workload.

Not a test and not a bench module of ``mura bench``: a script that plans the utterance of
:mod:`bench.motion_speed` (every gesture of the examples in a row) on avatar ``max``, then
writes the process time of rendering it at 60 fps in one ``frames`` call and in 0.1 s
windows (the live path), each on freshly activated controls without the profiler (medians
of five), and the top entries (cumulative and own time) of a profile of five such
renders. Pin it to one core::

    taskset -c 0 .venv/bin/python bench/synthesis_profile.py > docs/profile_synthesis_after.txt
"""

from __future__ import annotations

import cProfile
import io

from bench.machine import machine_info
from bench.motion_speed import _fresh, _gestures, _programs, _streamed, _timed_frames
from bench.profile_listing import listings
from motor.body.avatar import load_avatar
from motor.compiled import warm_up
from motor.control import MotorControl

#: Entries of each listing, renders timed and profiled, frames per second.
TOP = 20
RENDERS = 5
FPS = 60.0


def profile(top: int = TOP) -> str:
    warm_up()
    avatar = load_avatar("max")
    programs = _programs(MotorControl(avatar), _gestures())
    end = max(program.pegs.end for program in programs) + 0.3
    machine = machine_info()
    out = io.StringIO()
    out.write(
        f"gesture synthesis profile, commit {machine.get('git_commit')}; machine: {machine.get('cpu')}, {machine.get('cores')} cores, "
        f"Python {machine.get('python')}, numpy {machine.get('numpy')}\n\n"
    )
    for label, render in (("one frames call", lambda control: control.frames(0.0, end)), ("streamed 0.1 s windows", lambda control: _streamed(control, end))):
        frames = _fresh(avatar, FPS, programs).frames(0.0, end).frame_count
        median = _timed_frames(avatar, FPS, programs, render, RENDERS)
        controls = [_fresh(avatar, FPS, programs) for _ in range(RENDERS)]
        profiler = cProfile.Profile()
        profiler.enable()
        for control in controls:
            render(control)
        profiler.disable()
        out.write(f"=== {label}, {len(programs)} gestures, {frames} frames at {FPS:g} fps: process time without profiler {median * 1e3:.1f} ms = {frames / median:,.0f} frames/s (median of {RENDERS}); profile of {RENDERS} renders\n")
        out.write(listings(profiler, top))
    return out.getvalue()


if __name__ == "__main__":
    print(profile(), end="")
