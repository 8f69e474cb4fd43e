"""The fast paths give what the slow ones gave: quaternion helpers against numpy and
scipy, rotation keyframes against scipy's slerp composition, an extended channel timeline
against one built from scratch, and the motor control's swivel grid against a fresh one."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from motor import quaternion as quat
from motor.arm.swivel import SwivelLMP
from motor.arm.wrist_rotation import WristRotationLMP
from motor.body.avatar import load_avatar
from motor.arm.swivel_track import SWIVEL_PERIOD, TRACK_REACH
from motor.control import MotorControl
from motor.program.lmp import (
    ChannelState,
    ChannelTimeline,
    RetractionLMP,
    TimePegs,
    _locate,
    incoming_blend,
)

RNG = np.random.default_rng(7)
HALF_TURNS = np.array([[0.0, 0.0, 0.0, 1.0], [0.70710678, 0.0, 0.70710678, 0.0], [0.0, -1.0, 0.0, 0.0], [0.0, 0.0, -1.0, 0.0]])


def test_cross_and_norm_match_numpy():
    u, v = RNG.standard_normal((50, 3)), RNG.standard_normal((1, 3))
    np.testing.assert_allclose(quat.cross(u, v), np.cross(u, v), rtol=0, atol=1e-15)
    np.testing.assert_allclose(quat.norm(u), np.linalg.norm(u, axis=-1), rtol=1e-15)


@pytest.mark.parametrize("q", [*HALF_TURNS, *quat.normalize(RNG.standard_normal((6, 4)))])
def test_canonical_rotation_vectors_are_scipys(q):
    q = np.asarray(q) / np.linalg.norm(q)
    np.testing.assert_allclose(quat.to_rotation_vector(quat.canonical(q)), Rotation.from_quat(q).as_rotvec(), atol=1e-12)


def _scipy_sample(realization, times):
    """Rotation keyframes as they were sampled with scipy's Rotation."""
    rotations = realization.rotations
    segment, u, _ = _locate(realization.knots, times)
    steps = (rotations[:-1].inv() * rotations[1:]).as_rotvec()
    s = realization.time_profile.fraction(u)[:, None]
    planned = rotations[segment] * Rotation.from_rotvec(s * steps[segment])
    weight, _ = incoming_blend(times, realization.knots[0], realization.knots[1] - realization.knots[0])
    return (Rotation.from_rotvec(weight[:, None] * realization.incoming) * planned).as_quat()


@pytest.mark.parametrize("keys", [HALF_TURNS[[1, 0]], HALF_TURNS[[0, 2, 3]], quat.normalize(RNG.standard_normal((3, 4)))])
@pytest.mark.parametrize("incoming", [np.zeros(3), np.array([0.5, -1.0, 2.0])])
def test_rotation_keyframes_sample_as_scipy_did(keys, incoming):
    pegs = TimePegs(0.1, 0.5, 0.5, 0.8, 1.1, 1.2, 1.4)
    start = ChannelState(quat.normalize(np.array([0.1, 0.2, 0.3, 0.9])), incoming, 0.1)
    realization = WristRotationLMP("right", pegs, keys).activate(start)
    times = np.linspace(0.1, 1.5, 141)
    np.testing.assert_allclose(realization.sample(times), _scipy_sample(realization, times), rtol=0, atol=1e-12)
    state = realization.state(0.7)
    np.testing.assert_allclose(state.value, _scipy_sample(realization, np.array([0.7]))[0], atol=1e-12)
    assert np.all(np.isfinite(state.velocity))


def _swivel_lmps(starts):
    return [SwivelLMP("right", TimePegs.movement(s, s + 0.4, s + 0.6), [0.2 * k + 0.1]) for k, s in enumerate(starts)]


@pytest.mark.parametrize("starts", [[0.0, 0.5, 0.5, 1.2], [0.3], []])
def test_extended_timeline_is_the_built_one(starts):
    channel, initial = ("right", "swivel"), ChannelState.at_rest([0.0])
    lmps = _swivel_lmps(starts)
    built = ChannelTimeline.build(channel, lmps, initial)
    extended = ChannelTimeline.build(channel, [], initial)
    for lmp in lmps:
        extended = extended.extended(lmp)
    times = np.linspace(-0.2, 2.5, 271)
    np.testing.assert_array_equal(extended.sample(times), built.sample(times))
    np.testing.assert_array_equal(extended.starts, built.starts)
    assert extended.lmps == built.lmps


@pytest.mark.parametrize(
    "lmp, message",
    [
        (_swivel_lmps([0.2])[0], r"cannot follow one starting at 0\.5"),
        (RetractionLMP(("left", "swivel"), TimePegs.movement(0.9, 1.0), np.zeros(1)), r"was given an LMP on \('left', 'swivel'\)"),
    ],
)
def test_extending_out_of_order_or_channel_is_refused(lmp, message):
    timeline = ChannelTimeline.build(("right", "swivel"), _swivel_lmps([0.5]), ChannelState.at_rest([0.0]))
    with pytest.raises(ValueError, match=message):
        timeline.extended(lmp)


@pytest.fixture(scope="module")
def avatar():
    return load_avatar("max")


def _programs(control):
    from pathlib import Path

    from mura.murml import load_utterance

    path = Path(__file__).resolve().parents[2] / "specs" / "utterances" / "assembly_two_bars.xml"
    gestures = [b for b in load_utterance(path).behaviors if b.gesture is not None]
    return [control.plan(g, TimePegs(t, t + 0.6, t + 0.7, t + 1.0, t + 1.4, t + 1.7, t + 2.3)) for g, t in zip(gestures, (0.3, 1.6))]


def test_frames_after_a_late_activation_are_those_of_a_fresh_control(avatar):
    """Swivel track states solved ahead are forgotten from ``TRACK_REACH`` grid points
    before a new LMP's start on, frames computed ahead from two swivel periods before
    that, and the appended timelines equal rebuilt ones: the frames match a control given
    everything at once (the LMP comes 0.5 s after the frames handed out, more than the
    track looks ahead)."""
    streaming = MotorControl(avatar, fps=30.0)
    first, second = _programs(streaming)
    streaming.activate(first)
    early = [streaming.frames(0.0, 1.0), streaming.frames(1.0, 1.1)]  # swivels solved to 1.9 s
    assert streaming._grid.last * SWIVEL_PERIOD > second.pegs.start
    streaming.activate(second)
    late = [streaming.frames(a, b) for a, b in ((1.1, 1.2), (1.2, 1.5), (1.5, 1.9), (1.9, 5.0))]  # partly from frames computed ahead
    fresh = MotorControl(avatar, fps=30.0)
    fresh.activate(first)
    fresh.activate(second)
    whole = fresh.frames(0.0, 5.0)
    np.testing.assert_allclose(np.concatenate([m.rotations for m in early + late]), whole.rotations, rtol=0, atol=1e-12)


def test_frames_after_an_interrupt_are_those_of_a_fresh_control(avatar):
    """An interrupt forgets the frames computed ahead from where it changes the motion.

    Frames handed out before it are those of a control that knew of it when it comes no
    sooner than the swivel track looks ahead (``TRACK_REACH`` grid points, and two more
    for the interpolation) after them; the frames after it are in any case."""
    streaming = MotorControl(avatar, fps=30.0)
    programs = _programs(streaming)
    for program in programs:
        streaming.activate(program)
    handed_out = 0.5
    interrupt = handed_out + (TRACK_REACH + 2) * SWIVEL_PERIOD
    early = streaming.frames(0.0, handed_out)  # frames computed ahead, uninterrupted
    streaming.interrupt(interrupt)
    late = [streaming.frames(a, b) for a, b in ((handed_out, interrupt + 0.3), (interrupt + 0.3, 3.0), (3.0, 5.0))]
    fresh = MotorControl(avatar, fps=30.0)
    for program in programs:
        fresh.activate(program)
    fresh.interrupt(interrupt)
    whole = fresh.frames(0.0, 5.0)
    np.testing.assert_allclose(np.concatenate([m.rotations for m in [early, *late]]), whole.rotations, rtol=0, atol=1e-12)
