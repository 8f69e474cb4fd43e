"""Synthesis fast paths (issue 19) give the frames of the plain paths.

* A stream of short windows over activated programs computes frames further and further
  ahead (:data:`motor.control.MAX_FRAME_LOOKAHEAD`): its frames are those of one call over
  the whole span, whatever the window length and frame rate.
* It looks no further than :data:`motor.control.FRAME_LOOKAHEAD` past the arms' last
  activated LMP (unless a window asks): a stream that ends soon after pays little more
  than it shows.
* An activation after the look-ahead has grown brings it back and forgets what it changes:
  the frames after it are those of a control given everything at once.
* LMPs that lost control are dropped a few at a time, the latest kept: the frames above
  are those of a control that never drops any.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from motor.body.avatar import load_avatar
from motor.control import FORGET_BATCH, FRAME_LOOKAHEAD, HISTORY, MAX_FRAME_LOOKAHEAD, MotorControl
from motor.program.lmp import TimePegs
from mura.murml import load_utterance

UTTERANCES = Path(__file__).resolve().parents[2] / "specs" / "utterances"
#: Seconds from one gesture's start to the next's (the next starts during the retraction).
SPACING = 2.2


@pytest.fixture(scope="module")
def avatar():
    return load_avatar("max")


@pytest.fixture(scope="module")
def gestures():
    """Every gesture of the example utterances: a long utterance (about 40 s)."""
    return [b for path in sorted(UTTERANCES.glob("*.xml")) for b in load_utterance(path).behaviors if b.gesture is not None]


def _programs(control: MotorControl, gestures) -> list:
    programs = []
    for index, spec in enumerate(gestures):
        t = 0.3 + SPACING * index
        programs.append(control.plan(spec, TimePegs(t, t + 0.6, t + 0.7, t + 1.0, t + 1.4, t + 1.7, t + 2.3)))
    return programs


def _control(avatar, fps: float, programs) -> MotorControl:
    control = MotorControl(avatar, fps)
    for program in programs:
        control.activate(program)
    return control


def _streamed(control: MotorControl, start: float, end: float, window: float) -> np.ndarray:
    edges = np.append(np.arange(start, end, window), end)
    return np.concatenate([control.frames(a, b).rotations for a, b in zip(edges, edges[1:])])


@pytest.mark.parametrize(("fps", "window"), [(60.0, 0.1), (25.0, 0.1), (30.0, 0.37), (60.0, 1.0)])
def test_streamed_windows_give_the_frames_of_one_call(avatar, gestures, fps, window):
    programs = _programs(MotorControl(avatar), gestures)
    end = max(program.pegs.end for program in programs) + 0.3
    assert end > 2 * MAX_FRAME_LOOKAHEAD  # the look-ahead grows to its largest, is used up, and is cut at the arms' rest
    streaming = _control(avatar, fps, programs)
    reached = []
    rotations = streaming._rotations
    streaming._rotations = lambda times: reached.append(streaming._lookahead) or rotations(times)
    streamed = _streamed(streaming, 0.0, end, window)
    assert MAX_FRAME_LOOKAHEAD in reached and reached[-1] == FRAME_LOOKAHEAD
    whole = _control(avatar, fps, programs).frames(0.0, end).rotations
    assert streamed.shape == whole.shape
    np.testing.assert_allclose(streamed, whole, rtol=0, atol=1e-12)


@pytest.mark.parametrize(("fps", "tail"), [(60.0, 0.3), (25.0, 3.5)])
def test_a_stream_computes_no_frame_past_the_arms_activity_unless_asked(avatar, gestures, fps, tail):
    """Frames are computed ahead at most :data:`FRAME_LOOKAHEAD` past the arms' last LMP
    (or as far as a window asks): a stream that ends ``tail`` s after the last gesture
    pays for little more than it shows, and its frames are still those of one call."""
    programs = _programs(MotorControl(avatar), gestures[:9])
    streaming = _control(avatar, fps, programs)
    end = max(streaming.busy_until(arm) for arm in ("left", "right")) + tail
    computed = []
    rotations = streaming._rotations
    streaming._rotations = lambda times: computed.append(times) or rotations(times)
    streamed = _streamed(streaming, 0.0, end, 0.1)
    assert max(float(times[-1]) for times in computed) < end + FRAME_LOOKAHEAD
    assert sum(times.size for times in computed) < 1.25 * streamed.shape[0]
    whole = _control(avatar, fps, programs).frames(0.0, end).rotations
    np.testing.assert_allclose(streamed, whole, rtol=0, atol=1e-12)


@pytest.mark.parametrize("late", [3, 6])
def test_an_activation_after_the_lookahead_grew_gives_the_frames_of_a_fresh_control(avatar, gestures, late):
    """Programs from the ``late``-th on are activated only after frames were streamed to
    0.5 s before the first of them starts (more than the swivel track looks ahead)."""
    programs = _programs(MotorControl(avatar), gestures[: late + 3])
    early, rest = programs[:late], programs[late:]
    switch = rest[0].pegs.start - 0.5
    end = max(program.pegs.end for program in programs) + 0.3
    streaming = _control(avatar, 30.0, early)
    before = _streamed(streaming, 0.0, switch, 0.1)
    held, ahead, _ = streaming._ahead
    assert (held + ahead.shape[0]) / 30.0 > rest[0].pegs.start  # computed ahead past what is activated next
    for program in rest:
        streaming.activate(program)
    assert streaming._lookahead == FRAME_LOOKAHEAD
    after = _streamed(streaming, switch, end, 0.1)
    whole = _control(avatar, 30.0, programs).frames(0.0, end).rotations
    np.testing.assert_allclose(np.concatenate([before, after]), whole, rtol=0, atol=1e-12)


def test_lmps_are_dropped_a_few_at_a_time_as_windows_pass_them(avatar, gestures):
    """After streaming, each arm channel keeps the LMP in control a second (``HISTORY``)
    before the last window and those after it, and fewer than ``FORGET_BATCH`` LMPs that
    lost control before that (they are dropped a few at a time)."""
    programs = _programs(MotorControl(avatar), gestures[:8])
    end = max(program.pegs.end for program in programs) + 0.3
    streaming = _control(avatar, 30.0, programs)
    _streamed(streaming, 0.0, end, 0.1)
    horizon = streaming.frame_times(end - 0.1, end)[0] - HISTORY
    dropped_some = False
    for channel, lmps in streaming.activated().items():
        starts = sorted(lmp.pegs.start for program in programs for lmp in program.lmps if tuple(lmp.channel) == channel)
        kept = sorted(lmp.pegs.start for lmp in lmps)
        assert kept == starts[len(starts) - len(kept) :], channel  # the latest ones
        lost_control = sum(1 for start in starts if start <= horizon) - 1  # before the one in control
        assert 0 <= lost_control - (len(starts) - len(kept)) < FORGET_BATCH, channel
        dropped_some |= len(kept) < len(starts)
    assert dropped_some
