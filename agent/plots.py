"""Plots of performed gestures for users (PNG, matplotlib's Agg backend, no display needed).

:func:`plot_wrist_paths` draws the seed's Fig. 5 for every gesture of a performance: the
wrist's path in space and its speed over time, with the guiding-stroke breakpoints marked
on both, so that the bell-shaped speed profiles and the slower passage through sharp
breakpoints can be seen.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from motor.avatar import Avatar  # noqa: E402
from motor.kinematics import forward_kinematics  # noqa: E402
from motor.lmp import WristPositionLMP  # noqa: E402
from motor.motion import Motion  # noqa: E402
from motor.program import AVATAR_SIDE, MotorProgram  # noqa: E402


def _wrist_lmps(program: MotorProgram) -> list[WristPositionLMP]:
    return [lmp for lmp in program.lmps if isinstance(lmp, WristPositionLMP)]


def plot_wrist_paths(avatar: Avatar, motion: Motion, programs: Sequence[MotorProgram], path: str | Path) -> Path:
    """Write a PNG with one row per gesture and arm: the wrist path in 3D (metres, avatar
    frame) and its speed (m/s) over the gesture's time, breakpoints marked.

    ``motion`` must be the rendering of ``programs`` on ``avatar``, covering every gesture
    from its start through its stroke (the retraction is drawn as far as the motion goes).
    Raises ValueError when no program moves a wrist or a gesture lies outside the motion.
    """
    rows = [(program, lmp) for program in programs for lmp in _wrist_lmps(program)]
    if not rows:
        raise ValueError("plot_wrist_paths: no gesture moves a wrist")
    pose = forward_kinematics(avatar, motion.rotations)
    times = motion.times
    figure = plt.figure(figsize=(11.0, 3.6 * len(rows)))
    for row, (program, lmp) in enumerate(rows):
        arm = lmp.channel[0]
        step = 1.0 / motion.fps
        if motion.frame_count < 3 or times[0] > program.pegs.start + step or times[-1] < program.pegs.stroke_end - step:
            raise ValueError(
                f"plot_wrist_paths: gesture {program.behavior!r} ({program.pegs.start:.2f}–{program.pegs.stroke_end:.2f} s) "
                f"lies outside the motion ({motion.start_time:.2f}–{motion.start_time + motion.duration:.2f} s)"
            )
        inside = (times >= program.pegs.start) & (times <= program.pegs.end)
        wrist = pose.positions[inside, avatar.joint_index(f"{AVATAR_SIDE[arm]}_wrist")]
        t = times[inside]
        speed = np.linalg.norm(np.gradient(wrist, t, axis=0), axis=1)
        title = f"{program.behavior} — {arm} wrist"
        space = figure.add_subplot(len(rows), 2, 2 * row + 1, projection="3d")
        space.plot(wrist[:, 0], wrist[:, 2], wrist[:, 1], color="tab:blue", linewidth=1.5)
        space.scatter(lmp.breakpoints[:, 0], lmp.breakpoints[:, 2], lmp.breakpoints[:, 1], color="tab:red", s=18, label="breakpoints")
        space.set_xlabel("x (left) m")
        space.set_ylabel("z (forward) m")
        space.set_zlabel("y (up) m")
        space.set_title(title)
        space.legend(loc="upper left", fontsize="small")
        profile = figure.add_subplot(len(rows), 2, 2 * row + 2)
        profile.plot(t, speed, color="tab:blue", linewidth=1.5)
        for k, moment in enumerate(lmp.breakpoint_times):
            profile.axvline(moment, color="tab:red", linestyle=":", linewidth=1.0, label="breakpoints" if k == 0 else None)
        profile.axvspan(program.pegs.stroke_start, program.pegs.stroke_end, color="tab:orange", alpha=0.15, label="stroke")
        profile.set_xlabel("time (s)")
        profile.set_ylabel("wrist speed (m/s)")
        profile.set_title(f"{title}: speed profile")
        profile.legend(loc="upper right", fontsize="small")
    figure.tight_layout()
    target = Path(path)
    figure.savefig(target, format="png", dpi=90)
    plt.close(figure)
    return target
