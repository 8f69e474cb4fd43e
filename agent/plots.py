"""Plots of performed gestures for users (PNG, matplotlib's Agg backend, no display needed).

:func:`plot_wrist_paths` draws the seed's Fig. 5 for every gesture of a performance: the
wrist's path in space and its speed over time, with the guiding-stroke breakpoints marked
on both, so that the bell-shaped speed profiles and the slower passage through sharp
breakpoints can be seen. :func:`plot_timeline` draws the seed's Fig. 6: chunks with their
states, speech and gesture phases on one time axis.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from motor.arm.wrist_position import WristPositionLMP  # noqa: E402
from motor.body.avatar import Avatar  # noqa: E402
from motor.body.conventions import AVATAR_SIDE  # noqa: E402
from motor.body.kinematics import forward_kinematics  # noqa: E402
from motor.motion import Motion  # noqa: E402
from motor.program.gesture import MotorProgram  # noqa: E402


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


_STATE_COLOURS = {
    "InPrep": "#9ecae1", "Pending": "#c6dbef", "Lurking": "#fdd0a2", "InExec": "#74c476",
    "Subsiding": "#fdae6b", "Completed": "#d9d9d9", "Failed": "#fb6a4a",
}
_PHASE_COLOURS = {"preparation": "#6baed6", "stroke": "#de2d26", "hold": "#fc9272", "retraction": "#bdbdbd"}


def plot_timeline(timeline: dict, path: str | Path) -> Path:
    """Draw the seed's Fig. 6 for ``timeline`` (the JSON dict of a performance) into a PNG at ``path``: per chunk a lane with its
    states, its speech words and its gestures' phases (preparation, stroke, hold, retraction)
    with the affiliate, on one time axis; stretched pauses are shaded."""
    data = timeline
    chunks = data["chunks"]
    end = max([data["duration"], 1.0] + [s["time"] for c in chunks for s in c["states"]])
    lanes = max(1, len(chunks))
    fig, ax = plt.subplots(figsize=(max(8.0, end * 2.5), 1.0 + 1.6 * lanes))
    for lane, chunk in enumerate(chunks):
        base = (lanes - 1 - lane) * 3.0
        _draw_states(ax, chunk, base + 2.0, end)
        for word in (w for w in data["words"] if w["chunk"] == chunk["index"]):
            ax.broken_barh([(word["start"], word["end"] - word["start"])], (base + 1.0, 0.8), color="#fff7bc", edgecolor="#999")
            ax.text((word["start"] + word["end"]) / 2, base + 1.4, word["text"], ha="center", va="center", fontsize=7)
        behaviors = [b for b in data["behaviors"] if b["chunk"] == chunk["index"]]
        for k, behavior in enumerate(behaviors):
            _draw_phases(ax, behavior, base + 0.1 + k * 0.8 / max(1, len(behaviors)), 0.7 / max(1, len(behaviors)))
        ax.text(-0.05, base + 1.5, f"chunk {chunk['index']}", ha="right", va="center", fontsize=8)
    for stretch in data["stretches"]:
        onset = next(c["speech_onset"] for c in chunks if c["index"] == stretch["chunk"])
        ax.axvspan(onset - stretch["amount"], onset, color="#fee0d2", alpha=0.5, zorder=0)
    ax.set_xlim(-0.1, end + 0.1)
    ax.set_ylim(-0.2, lanes * 3.0)
    ax.set_yticks([])
    ax.set_xlabel("time (s)")
    ax.set_title(f"{data['name']}: incremental chunk processing")
    fig.tight_layout()
    out = Path(path)
    fig.savefig(out, dpi=100)
    plt.close(fig)
    return out


def _draw_states(ax, chunk: dict, y: float, end: float) -> None:
    states = chunk["states"]
    for current, following in zip(states, states[1:] + [None]):
        stop = following["time"] if following else (current["time"] if current["state"] in ("Completed", "Failed") else end)
        width = max(stop - current["time"], 0.01)
        ax.broken_barh([(current["time"], width)], (y, 0.8), color=_STATE_COLOURS[current["state"]], edgecolor="#666")
        ax.text(current["time"] + width / 2, y + 0.4, current["state"], ha="center", va="center", fontsize=6)


def _draw_phases(ax, behavior: dict, y: float, height: float) -> None:
    p = behavior["phases"]
    spans = {
        "preparation": (p["start"], p["stroke_start"]),
        "stroke": (p["stroke_start"], p["stroke_end"]),
        "hold": (p["stroke_end"], p["relax"]),
        "retraction": (p["relax"], p["end"]),
    }
    for phase, (a, b) in spans.items():
        if b > a:
            ax.broken_barh([(a, b - a)], (y, height), color=_PHASE_COLOURS[phase])
    if behavior["affiliate"]:
        ax.plot([behavior["affiliate"]["onset"], behavior["affiliate"]["end"]], [y + height / 2] * 2, color="k", lw=1)
    ax.text(p["start"], y + height / 2, behavior["id"], ha="right", va="center", fontsize=6)
