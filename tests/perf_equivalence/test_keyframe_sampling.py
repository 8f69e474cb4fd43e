"""The compiled sampling of keyframe realizations (:mod:`motor.program.keyframe_sampling`)
and of wrist splines (:mod:`motor.trajectory.spline_positions`) is the numpy sampling it
replaced (``plain_keyframes.py``) bit for bit: one key and many, vector channels of one to
twenty values, every manner's time profile and small tables, with and without an incoming
velocity, rotations through half turns and the long way round, at times before, at, just
around and after the knots, inside and outside the incoming blend, none, NaN and infinite."""

from __future__ import annotations

import numpy as np
import pytest

from motor import quaternion as quat
from motor.program import keyframe_sampling
from motor.program.lmp import ChannelState, RetractionLMP, TimePegs, VectorKeyframeLMP, rotation_keyframes, rotation_turn
from motor.trajectory import spline_positions
from motor.trajectory.biocontrol import MANNERS, TimeProfile, minimum_jerk, profile
from motor.trajectory.spline import approach, held, plan_wrist_trajectory
from tests.perf_equivalence import plain_keyframes as plain

RNG = np.random.default_rng(91)
HALF_TURNS = np.array([[0.0, 0.0, 0.0, 1.0], [0.70710678, 0.0, 0.70710678, 0.0], [0.0, -1.0, 0.0, 0.0], [0.0, 0.0, -1.0, 0.0]])
PROFILES = {
    "minimum_jerk": minimum_jerk(),
    **{name: profile(name) for name in MANNERS},
    "two_entries": TimeProfile("two_entries", np.array([0.0, 1.0]), np.ones(2)),
    "seven_entries": TimeProfile("seven_entries", np.array([0.0, 0.01, 0.2, 0.5, 0.8, 0.99, 1.0]), np.ones(7)),
}


def _times(knots: np.ndarray) -> np.ndarray:
    """Sample times around ``knots``: frames across them and beyond, each knot, its
    neighbouring floats, the middle of the blend, and non-finite and signed-zero times."""
    frames = np.arange(np.floor((knots[0] - 0.3) * 60.0), np.ceil((knots[-1] + 0.3) * 60.0)) / 60.0
    near = np.concatenate([knots, np.nextafter(knots, -np.inf), np.nextafter(knots, np.inf)])
    blend = knots[0] + (knots[1] - knots[0]) * np.array([1e-9, 0.25, 0.5, 0.999999])
    odd = np.array([np.nan, np.inf, -np.inf, -0.0, 0.0, -1e300, 1e300])
    return np.concatenate([frames, near, blend, odd, RNG.uniform(knots[0] - 1.0, knots[-1] + 1.0, 50)])


def _knots(count: int, start: float) -> np.ndarray:
    return start + np.concatenate([[0.0], np.cumsum(RNG.uniform(0.05, 0.6, count))])


@pytest.mark.parametrize("size", [1, 3, 20])
@pytest.mark.parametrize("keys", [1, 2, 6])
@pytest.mark.parametrize("start", [0.0, 1.7])
@pytest.mark.parametrize("name", list(PROFILES))
def test_vector_keyframes_sample_as_numpy_did(size, keys, start, name):
    shape = PROFILES[name]
    state = ChannelState(RNG.normal(size=size), RNG.normal(size=size) * (start > 0.0), start)
    knots = _knots(keys, start)
    lmp = VectorKeyframeLMP(("right", "handshape"), TimePegs.movement(start, knots[1], knots[-1]), RNG.normal(size=(keys, size)), knots[1:], shape)
    realization = lmp.activate(state)
    times = _times(knots)
    expected = plain.vector_keyframes(realization.knots, realization.values, realization.incoming, shape.fractions, times)
    np.testing.assert_array_equal(realization.sample(times), expected)
    assert np.array_equal(np.signbit(realization.sample(times)), np.signbit(expected))
    assert realization.sample(np.empty(0)).shape == (0, size)


@pytest.mark.parametrize("keys", [HALF_TURNS[[1]], HALF_TURNS[[1, 0]], HALF_TURNS[[0, 2, 3]], HALF_TURNS, quat.normalize(RNG.normal(size=(5, 4)))])
@pytest.mark.parametrize("incoming", [np.zeros(3), np.array([0.5, -1.0, 2.0]), np.array([-0.0, 0.0, -1e-13])])
@pytest.mark.parametrize("name", ["minimum_jerk", "lax", "sudden_stop", "seven_entries"])
def test_rotation_keyframes_sample_as_numpy_did(keys, incoming, name):
    shape = PROFILES[name]
    state = ChannelState(quat.normalize(np.array([0.1, 0.2, 0.3, 0.9])), incoming, 0.4)
    knots = _knots(len(keys), 0.4)
    realization = rotation_keyframes(("right", "hand_rotation"), state, keys, knots[1:], shape)
    times = _times(knots)
    expected = plain.rotation_keyframes(realization.knots, realization._keys, realization._steps, realization.incoming, shape.fractions, times)
    sampled = realization.sample(times)
    np.testing.assert_array_equal(sampled, expected)
    assert np.array_equal(np.signbit(sampled), np.signbit(expected))
    assert realization.sample(np.empty(0)).shape == (0, 4)


@pytest.mark.parametrize("step", [np.array([0.0, 4.0, 0.0]), np.array([-3.0, 1.0, 0.5]), np.zeros(3)])
def test_a_turn_the_long_way_samples_as_numpy_did(step):
    state = ChannelState(HALF_TURNS[0], np.array([0.2, 0.0, -0.4]), 1.0)
    target = quat.normalize(quat.multiply(HALF_TURNS[0], quat.from_rotation_vector(step)))
    turned = rotation_turn(("left", "hand_rotation"), state, target, 1.8, profile("targetted"), step)
    times = _times(turned.knots)
    expected = plain.rotation_keyframes(turned.knots, turned._keys, turned._steps, turned.incoming, profile("targetted").fractions, times)
    np.testing.assert_array_equal(turned.sample(times), expected)


@pytest.mark.parametrize("rotation", [False, True])
def test_a_retraction_samples_as_numpy_did(rotation):
    pegs = TimePegs.movement(2.0, 2.7, 3.0)
    lax = profile("lax").fractions
    if rotation:
        state = ChannelState(HALF_TURNS[1], np.array([1.0, -2.0, 0.5]), 2.0)
        realization = RetractionLMP(("right", "hand_rotation"), pegs, HALF_TURNS[0], "lax").activate(state)
        times = _times(realization.knots)
        expected = plain.rotation_keyframes(realization.knots, realization._keys, realization._steps, realization.incoming, lax, times)
    else:
        state = ChannelState(np.array([0.2, 1.1, 0.3]), np.array([0.5, 0.0, -0.2]), 2.0)
        realization = RetractionLMP(("right", "wrist_position"), pegs, np.array([0.25, 0.9, 0.05]), "lax").activate(state)
        times = _times(realization.knots)
        expected = plain.vector_keyframes(realization.knots, realization.values, realization.incoming, lax, times)
    np.testing.assert_array_equal(realization.sample(times), expected)


def _trajectories():
    points = np.array([[0.2, 1.0, 0.3], [0.3, 1.1, 0.35], [0.35, 1.0, 0.3], [0.35, 1.0, 0.3], [0.2, 1.2, 0.4], [0.1, 1.0, 0.3]])
    planned = plan_wrist_trajectory(points, np.array([0.5, 0.8, 1.0, 1.3, 1.6, 1.9]))
    return {
        "planned": planned,
        "shifted": planned.shifted(0.35),
        "held": held(points[0], 0.0, 0.4),
        "approach": approach(points[0], np.array([0.3, -0.1, 0.0]), 0.1, points[1], 0.6),
        "fast": plan_wrist_trajectory(RNG.uniform(-0.3, 0.3, (12, 3)), start=0.0, end=0.4),
    }


@pytest.mark.parametrize("name", list(_trajectories()))
def test_wrist_spline_positions_as_numpy_did(name):
    trajectory = _trajectories()[name]
    times = _times(trajectory.times)
    expected = plain.spline_position(trajectory.times, trajectory._coefficients, times)
    np.testing.assert_array_equal(trajectory.position(times), expected)
    assert np.array_equal(np.signbit(trajectory.position(times)), np.signbit(expected))
    assert trajectory.position(np.empty(0)).shape == (0, 3)
    assert trajectory.position(times[::3]).shape == (times[::3].size, 3)


@pytest.mark.parametrize("name", list(PROFILES))
def test_profile_fractions_as_numpy_did(name):
    shape = PROFILES[name]
    u = np.concatenate([np.linspace(-0.5, 1.5, 401), [np.nan, -0.0, 1.0, np.nextafter(1.0, 0.0)], RNG.uniform(0.0, 1.0, 100)])
    np.testing.assert_array_equal(shape.fraction(u), plain.fraction(shape.fractions, u))
    assert shape.fraction(0.3) == plain.fraction(shape.fractions, 0.3)


def test_strided_read_only_and_integer_times_need_no_other_compilation():
    state = ChannelState(np.zeros(2), np.ones(2), 0.0)
    vector = VectorKeyframeLMP(("left", "handshape"), TimePegs.movement(0.0, 1.0, 2.0), np.ones((2, 2)), np.array([1.0, 2.0])).activate(state)
    rotation = rotation_keyframes(("left", "hand_rotation"), ChannelState(HALF_TURNS[0], np.ones(3), 0.0), HALF_TURNS[1:3], np.array([1.0, 2.0]), minimum_jerk())
    trajectory = _trajectories()["planned"]
    strided = np.linspace(-1.0, 3.0, 41)[::2]
    read_only = np.broadcast_to(np.array([0.5]), (4,))
    integers = np.arange(-1, 4)
    for realization in (vector, rotation, trajectory):
        sample = realization.position if realization is trajectory else realization.sample
        np.testing.assert_array_equal(sample(strided), sample(strided.copy()))
        np.testing.assert_array_equal(sample(read_only), sample(np.full(4, 0.5)))
        np.testing.assert_array_equal(sample(integers), sample(integers.astype(float)))
    loops = (keyframe_sampling._vector_rows, keyframe_sampling._rotation_rows, spline_positions._position_rows)
    assert all(len(loop.signatures) == 1 for loop in loops)
