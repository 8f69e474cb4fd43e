"""The Fig. 5 plot of wrist paths and speed profiles."""

from __future__ import annotations

from pathlib import Path

import pytest

from agent.plots import plot_wrist_paths
from mura.murml import load_utterance
from tests.motor_program.conftest import pegs, render

FIG2 = Path(__file__).resolve().parents[2] / "specs" / "utterances" / "fig2_take_this_bar.xml"


def test_plot_wrist_paths_writes_a_png_per_gesture(avatar, tmp_path) -> None:
    deictic, iconic = load_utterance(FIG2).behaviors
    planned = [(deictic, pegs(0.2, 0.8, 1.0, 1.5, 1.8)), (iconic, pegs(2.0, 2.6, 2.8, 3.4, 3.6))]
    control, motion = render(avatar, planned)
    programs = [control.plan(spec, timing) for spec, timing in planned]
    written = plot_wrist_paths(avatar, motion, programs, tmp_path / "fig5.png")
    data = written.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20_000


def test_plot_wrist_paths_refuses_what_it_cannot_draw(avatar, tmp_path) -> None:
    deictic, _ = load_utterance(FIG2).behaviors
    control, motion = render(avatar, [(deictic, pegs(0.2, 0.8, 1.0, 1.5))], end=0.5)
    with pytest.raises(ValueError, match="no gesture moves a wrist"):
        plot_wrist_paths(avatar, motion, [], tmp_path / "empty.png")
    program = control.plan(deictic, pegs(0.2, 0.8, 1.0, 1.5))
    with pytest.raises(ValueError, match="lies outside the motion"):
        plot_wrist_paths(avatar, motion, [program], tmp_path / "outside.png")
