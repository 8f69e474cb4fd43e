"""The offline frame window decides how many frames one motor call makes, never which.

Rendering with the offline default (1.0 s windows) gives the very frames and timeline of
rendering in the live window length (0.1 s) — up to floating-point rounding (1e-12) of
the same arithmetic done in batches of other sizes — and the motor control is never asked for
frames past the start of an LMP it has not been given yet.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from golden_cases import render, sources

from blackboard.scheduler import SchedulerConfig
from motor.control import MotorControl

CASES = sources()
#: Utterances with several chunks, co-articulated gestures and both arms.
WINDOWED = ["example_assembly_two_bars", "example_present_and_negate", "murml_41_tanedila_welle"]


@pytest.mark.parametrize("name", [n for n in WINDOWED if n in CASES])
def test_offline_windows_give_the_frames_of_short_windows(name):
    assert SchedulerConfig().offline_frame_window > SchedulerConfig().frame_window
    short = render(CASES[name], offline_frame_window=SchedulerConfig().frame_window)
    long = render(CASES[name])
    assert long.motion.frame_count == short.motion.frame_count
    assert long.motion.start_time == short.motion.start_time
    # the same arithmetic in batches of other sizes: at most a last-bit difference
    np.testing.assert_allclose(long.motion.rotations, short.motion.rotations, rtol=0.0, atol=1e-12)
    assert json.dumps(long.timeline, sort_keys=True) == json.dumps(short.timeline, sort_keys=True)


@pytest.mark.parametrize("window", [0.1, 1.0, 5.0])
def test_no_frame_is_sampled_past_an_unactivated_start(monkeypatch, window):
    """Every LMP is activated before any frame at or after its start is sampled."""
    sampled_until = [0.0]
    violations = []
    original_frames, original_activate = MotorControl.frames, MotorControl.activate

    def frames(self, start, end):
        sampled_until[0] = max(sampled_until[0], end)
        return original_frames(self, start, end)

    def activate(self, program):
        late = [lmp.pegs.start for lmp in program.lmps if lmp.pegs.start < sampled_until[0] - 1e-9]
        violations.extend(late)
        return original_activate(self, program)

    monkeypatch.setattr(MotorControl, "frames", frames)
    monkeypatch.setattr(MotorControl, "activate", activate)
    render(CASES["example_assembly_two_bars"], offline_frame_window=window)
    assert sampled_until[0] > 1.0 and violations == []


@pytest.mark.parametrize("name", ["frame_window", "offline_frame_window"])
@pytest.mark.parametrize("value", [0.0, -0.1, float("nan")])
def test_a_window_must_be_positive(name, value):
    with pytest.raises(ValueError, match=name):
        SchedulerConfig(**{name: value})
