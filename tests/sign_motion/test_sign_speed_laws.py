"""Sign moves as a viewer sees them at 60 fps: stops at reversals, no speed steps, the
speed budget, and speed that falls into tight bends (the power law's direction)."""

from __future__ import annotations

import numpy as np
import pytest

from motor.program.lmp import ChannelState, TimePegs
from motor.signing.lmp import Move, SignChannelLMP, law_fractions, stopping_length, stopping_times
from motor.trajectory.biocontrol import MANNERS, profile, shortest_duration
from motor.trajectory.speed_budget import budget

FPS = 60.0
STEP = 0.5  # m/s of velocity change in one frame: a visible speed step
START = np.array([0.0, 1.2, 0.3])


def _there_and_back(reach: float, turns: int) -> np.ndarray:
    """A back-and-forth path along x with ``turns`` reversals (synthetic test path)."""
    ends = [START + np.array([reach * (i % 2), 0.0, 0.0]) for i in range(turns + 2)]
    return np.concatenate([np.linspace(a, b, 6)[(1 if i else 0) :] for i, (a, b) in enumerate(zip(ends[:-1], ends[1:]))])


def _zigzag(depth: float) -> np.ndarray:
    """A path forward with a sharp sideways jog at its middle (synthetic test path)."""
    xs = np.linspace(0.0, 0.3, 13)
    ys = np.where(np.arange(13) == 6, depth, 0.0)
    return START + np.stack([xs, ys, np.zeros(13)], axis=1)


def _track(path: np.ndarray, duration: float, manner: str = "targetted") -> np.ndarray:
    pegs = TimePegs(0.0, 0.2, 0.2, 0.2 + duration / 2, 0.2 + duration, 0.2 + duration, 0.2 + duration)
    lmp = SignChannelLMP(("right", "wrist_position"), pegs, path[0], (Move(0.2, 0.2 + duration, manner, path),))
    realized = lmp.activate(ChannelState.at_rest(START - np.array([0.0, 0.1, 0.0]), 0.0))
    return realized.sample(np.arange(0.0, 0.2 + duration + 0.2, 1.0 / FPS))


@pytest.mark.parametrize(("reach", "turns", "duration"), [(0.1, 1, 0.6), (0.15, 2, 0.9), (0.08, 3, 0.8), (0.2, 1, 0.5)])
def test_a_reversing_move_stops_at_each_reversal_without_a_speed_step(reach: float, turns: int, duration: float) -> None:
    wrist = _track(_there_and_back(reach, turns), duration)
    change = np.linalg.norm(np.diff(wrist, 2, axis=0), axis=1) * FPS
    assert change.max() < STEP
    speed = np.linalg.norm(np.diff(wrist, axis=0), axis=1) * FPS
    x = wrist[:, 0]
    extremes = [i for i in range(1, x.size - 1) if (x[i] - x[i - 1]) * (x[i + 1] - x[i]) < 0]
    assert len(extremes) == turns
    for i in extremes:
        assert min(speed[i - 1], speed[i]) < 0.05 * speed.max(), "the hand stops where it reverses"


@pytest.mark.parametrize("lengths", [[0.1, 0.1], [0.02, 0.18], [0.05, 0.2, 0.01], [0.3]])
def test_pieces_between_reversals_peak_at_the_same_acceleration(lengths: list[float]) -> None:
    times = stopping_times(np.array(lengths), 1.0, 2.0)
    assert times[0] == 1.0 and times[-1] == pytest.approx(2.0)
    peaks = np.array(lengths) / np.diff(times) ** 2
    np.testing.assert_allclose(peaks, peaks[0], rtol=1e-6)


@pytest.mark.parametrize("turns", [0, 1, 3])
def test_stopping_length_is_the_path_length_without_reversals_and_more_with(turns: int) -> None:
    path = _there_and_back(0.1, turns)
    length = float(np.linalg.norm(np.diff(path, axis=0), axis=1).sum())
    if turns == 0:
        assert stopping_length(path) == pytest.approx(length)
    else:
        assert stopping_length(path) >= length * (1.0 - 1e-9) + 0.05


@pytest.mark.parametrize("manner", sorted(MANNERS))
@pytest.mark.parametrize("length", [0.05, 0.3, 0.9])
def test_the_shortest_duration_keeps_the_manner_within_its_budget(manner: str, length: float) -> None:
    duration = shortest_duration(length, manner)
    path = START + np.linspace(0.0, 1.0, 8)[:, None] * np.array([length, 0.0, 0.0])
    wrist = _track(path, duration, manner)[int(0.2 * FPS) :]  # the move, after its transition
    speed = np.linalg.norm(np.diff(wrist, axis=0), axis=1) * FPS
    acceleration = np.linalg.norm(np.diff(wrist, 2, axis=0), axis=1) * FPS * FPS
    limits = budget(manner)
    assert speed.max() <= 1.02 * limits.peak_speed
    assert acceleration.max() <= 1.05 * limits.peak_acceleration


@pytest.mark.parametrize("depth", [0.01, 0.03, 0.05])
def test_the_hand_slows_into_a_tight_bend(depth: float) -> None:
    """Law time: on a path that jogs sideways the hand is slower at the jog than on the
    straight before it, though the manner's profile alone would have it speed up."""
    from motor.signing.lmp import smooth_path

    path = smooth_path(_zigzag(depth), through=False)
    fractions = law_fractions(path)
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(path, axis=0), axis=1))])
    rate = np.diff(arc) / np.maximum(np.diff(fractions), 1e-12)  # metres per law-time fraction
    middle = path.shape[0] // 2
    assert rate[middle - 2 : middle + 2].min() < 0.8 * rate[5:15].mean()
    assert np.all(np.diff(fractions) > 0) and fractions[-1] == pytest.approx(1.0)


def test_a_straight_move_in_law_time_is_timed_by_distance() -> None:
    path = START + np.linspace(0.0, 1.0, 9)[:, None] * np.array([0.2, 0.1, 0.0])
    np.testing.assert_allclose(law_fractions(path), np.linspace(0.0, 1.0, 9), atol=1e-9)


@pytest.mark.parametrize("manner", sorted(MANNERS))
def test_profiles_used_by_signs_reach_the_whole_way(manner: str) -> None:
    assert profile(manner).fractions[-1] == 1.0


@pytest.mark.parametrize(
    ("channel", "here", "velocity", "first"),
    [
        ("wrist_position", [0.05, 1.0, 0.3], [-0.3, -0.6, -0.3], [0.1, 1.2, 0.35]),
        ("wrist_position", [0.2, 1.1, 0.3], [0.8, 0.0, 0.0], [-0.1, 1.1, 0.3]),
        ("wrist_position", [0.0, 0.9, 0.25], [0.0, 1.2, 0.4], [0.0, 1.3, 0.3]),
        ("handshape", [0.1, 0.5, 0.9], [2.0, -1.0, 0.5], [0.8, 0.1, 0.2]),
        ("hand_rotation", [0.0, 0.0, 0.0, 1.0], [0.0, 3.0, 0.0], [0.0, 0.0, 0.38268343, 0.92387953]),
        ("hand_rotation", [0.0, 0.70710678, 0.0, 0.70710678], [1.5, 0.0, -2.0], [0.0, 0.0, 0.0, 1.0]),
    ],
)
def test_a_sign_taking_over_a_moving_channel_carries_its_velocity(channel: str, here: list[float], velocity: list[float], first: list[float]) -> None:
    """A sign activated mid-retraction continues the channel's velocity and fades it out
    by its first posture: no step at the hand-over, the first posture reached on time."""
    pegs = TimePegs(0.5, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0)
    lmp = SignChannelLMP(("right", channel), pegs, np.array(first))
    state = ChannelState(np.array(here), np.array(velocity), 0.5)
    realized = lmp.activate(state)
    carried = realized.state(0.5 + 1e-3)
    np.testing.assert_allclose(carried.velocity, velocity, atol=0.02 * np.linalg.norm(velocity))
    end = realized.sample(np.array([1.0, 1.2]))
    if channel == "hand_rotation":
        assert abs(abs(end[0] @ np.array(first)) / np.linalg.norm(first) - 1.0) < 1e-7
    else:
        np.testing.assert_allclose(end, [first, first], atol=1e-9)
    if channel == "wrist_position":
        times = np.arange(0.5 - 5 / FPS, 1.2, 1.0 / FPS)
        before = times < 0.5
        track = np.where(before[:, None], np.array(here) + np.outer(times - 0.5, velocity), realized.sample(times))
        assert np.linalg.norm(np.diff(track, 2, axis=0), axis=1).max() * FPS < STEP
