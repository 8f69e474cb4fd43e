"""The batched wrist-path tracing (motor.signing.path_batch) equals the one-path functions,
and sign tracks sampled and activated many at once (motor.signing.track_batch) equal the
one-by-one tracks.

Cases are synthetic wrist paths (labelled by kind): smooth arcs, zigzags that reverse,
paths with repeated points (holds), two and three points, paths so short that their
law-time kernel is wider than their law-time grid, and paths that do not move; each case is traced together with the
others of the table, as the batch sees them in a sequence of signs.
"""

from __future__ import annotations

import numpy as np
import pytest

from motor.body.avatar import load_avatar
from motor.body.conventions import ARMS
from motor.control import _sample
from motor.program.lmp import ChannelState, ChannelTimeline, TimePegs
from motor.quaternion import continuous
from motor.signing.lmp import Move, SignChannelLMP, SignTrack, law_fractions, smooth_pieces, stopping_length
from motor.signing.law_time import pairwise_sum
from motor.signing.path_batch import law_fractions_many, smooth_pieces_many, stopping_lengths, trace_chains
from motor.signing.plan import HandPose
from motor.signing.reach import clear_paths, rotations_along
from motor.signing.sequence import MIN_TRANSITION_POINTS, TRANSITION_SPACING, _transition_ways
from motor.signing.track_batch import activate_in_turn, sample_tracks


def _path(kind: str, count: int, seed: int) -> np.ndarray:
    """A synthetic wrist path (metres) of ``count`` points."""
    rng = np.random.default_rng(seed)
    start = np.array([0.1, 1.2, 0.3]) + 0.05 * rng.standard_normal(3)
    if kind == "arc":
        angle = np.linspace(0.0, rng.uniform(0.5, 3.0), count)
        radius = rng.uniform(0.03, 0.2)
        return start + radius * np.stack([np.cos(angle), np.sin(angle), 0.3 * angle], axis=1)
    if kind == "zigzag":  # back and forth: reversals
        steps = np.where(np.arange(count - 1) % 3 == 2, -1.0, 1.0)[:, None] * rng.uniform(0.02, 0.06, (count - 1, 1)) * np.array([1.0, 0.2, 0.1])
        return start + np.concatenate([np.zeros((1, 3)), np.cumsum(steps + 0.004 * rng.standard_normal((count - 1, 3)), axis=0)])
    if kind == "holds":  # some points repeated
        points = start + np.cumsum(0.03 * rng.standard_normal((count, 3)), axis=0)
        points[count // 2] = points[count // 2 - 1]
        return points
    if kind == "tiny":  # micrometres long: a wide law-time kernel
        return start + np.cumsum(2e-6 * rng.standard_normal((count, 3)), axis=0)
    if kind == "still":  # no length: evenly spaced law time
        return np.repeat(start[None], count, axis=0)
    return start + np.cumsum(0.03 * rng.standard_normal((count, 3)), axis=0)  # "random"


CASES = [(kind, count) for kind in ("arc", "zigzag", "holds", "random") for count in (2, 3, 4, 5, 8, 13, 33)] + [("tiny", 6), ("tiny", 9), ("still", 3), ("still", 8)]
PATHS = [_path(kind, count, seed) for seed, (kind, count) in enumerate(CASES)]
IDS = [f"{kind}-{count}" for kind, count in CASES]


@pytest.mark.parametrize("through", [False, True], ids=["within", "through"])
@pytest.mark.parametrize("case", range(len(CASES)), ids=IDS)
def test_batched_pieces_equal_one_path_pieces(case: int, through: bool) -> None:
    batched = smooth_pieces_many(PATHS, through)[case]
    plain = smooth_pieces(PATHS[case], through)
    assert len(batched) == len(plain)
    for fast, slow in zip(batched, plain):
        assert fast.shape == slow.shape
        np.testing.assert_allclose(fast, slow, rtol=0.0, atol=1e-12)
        if not through:  # the B-spline's basis sums in scipy's order: identical
            np.testing.assert_array_equal(fast, slow)


@pytest.mark.parametrize("case", range(len(CASES)), ids=IDS)
def test_batched_law_fractions_equal_one_path_fractions(case: int) -> None:
    dense = [piece for pieces in smooth_pieces_many(PATHS, through=False) for piece in pieces]
    index = sum(len(smooth_pieces(path, False)) for path in PATHS[:case])
    for offset, piece in enumerate(smooth_pieces(PATHS[case], False)):
        np.testing.assert_array_equal(law_fractions_many(dense)[index + offset], law_fractions(piece))


@pytest.mark.parametrize("count", [0, 1, 7, 8, 9, 15, 16, 17, 127, 128, 129, 136, 255, 256, 257, 1000])
def test_compiled_pairwise_sum_equals_numpy_sum(count: int) -> None:
    """The law time's sums (kernel weights, chords) add in numpy's pairwise order."""
    values = np.exp(3.0 * np.random.default_rng(count).standard_normal(count + 5))
    assert pairwise_sum(values, 5, count) == values[5:].sum() == values[None, 5:].sum(axis=1)[0]


@pytest.mark.parametrize("case", range(len(CASES)), ids=IDS)
def test_batched_stopping_length_equals_one_path_length(case: int) -> None:
    assert stopping_lengths(PATHS)[case] == stopping_length(PATHS[case])


@pytest.mark.parametrize("manner", ["lax", "targetted"])
@pytest.mark.parametrize("case", range(len(CASES)), ids=IDS)
def test_traced_chain_samples_as_the_plain_activation(case: int, manner: str) -> None:
    """A wrist LMP given its chain traced ahead samples as the one that traces at activation,
    and one activated from another state than the chain's falls back to tracing."""
    way = PATHS[case]
    moves = (Move(0.9, 1.4, "lax", PATHS[(case + 1) % len(PATHS)]), Move(1.5, 1.8, manner, PATHS[(case + 3) % len(PATHS)]))
    pegs = TimePegs(0.2, 0.7, 0.7, 1.2, 1.8, 1.8, 1.8)
    chain = trace_chains([(0.2, 0.7, manner, way)], [moves])[0]
    traced = SignChannelLMP(("right", "wrist_position"), pegs, way[-1], moves, manner, way[1:-1], chain)
    plain = SignChannelLMP(("right", "wrist_position"), pegs, way[-1], moves, manner, way[1:-1])
    times = np.linspace(0.0, 2.0, 401)
    state = ChannelState(way[0].copy(), np.zeros(3), 0.2)
    np.testing.assert_allclose(traced.activate(state).sample(times), plain.activate(state).sample(times), rtol=0.0, atol=1e-12)
    elsewhere = ChannelState(way[0] + 1e-3, np.zeros(3), 0.2)
    np.testing.assert_array_equal(traced.activate(elsewhere).sample(times), plain.activate(elsewhere).sample(times))


def _timeline(channel: str, signs: int, seed: int) -> ChannelTimeline:
    """A channel's timeline of ``signs`` synthetic sign LMPs one after another."""
    rng = np.random.default_rng(seed)
    size = {"wrist_position": 3, "hand_rotation": 4, "handshape": 5}[channel]

    def values(count: int) -> np.ndarray:
        if channel == "wrist_position":
            return _path(("arc", "zigzag", "random")[int(rng.integers(3))], count, int(rng.integers(1000)))
        points = rng.standard_normal((count, size))
        return points / np.linalg.norm(points, axis=1, keepdims=True) if channel == "hand_rotation" else points

    lmps, clock = [], 0.1
    for _ in range(signs):
        ready = clock + rng.uniform(0.1, 0.4)
        moves, at = [], ready
        for _ in range(int(rng.integers(0, 3))):
            moves.append(Move(at, at + rng.uniform(0.1, 0.5), ("lax", "targetted", "fast")[int(rng.integers(3))], values(int(rng.integers(2, 9)))))
            at = moves[-1].end + rng.uniform(0.0, 0.1)
        end = at + 0.05
        pegs = TimePegs(clock, ready, ready, ready, end, end, end)
        via = values(4)[1:3] if channel == "wrist_position" else None
        lmps.append(SignChannelLMP(("right", channel), pegs, values(1)[0], tuple(moves), "lax", via))
        clock = end
    initial = values(1)[0]
    return ChannelTimeline.build(("right", channel), lmps, ChannelState(initial, np.zeros(3 if size == 4 else size), 0.0))


@pytest.mark.parametrize("channel", ["wrist_position", "hand_rotation", "handshape"])
@pytest.mark.parametrize("signs", [1, 2, 7])
def test_sign_tracks_sampled_in_one_pass_equal_each_track(channel: str, signs: int) -> None:
    timeline = _timeline(channel, signs, seed=signs)
    times = np.linspace(0.0, float(timeline.starts[-1]) + 1.0, 997)
    owner = np.searchsorted(timeline.starts, times, side="right") - 1
    inside = owner >= 0
    joined = sample_tracks(timeline.realizations, owner[inside], times[inside])
    assert joined is not None
    each = np.concatenate([timeline.realizations[i].sample(times[inside][owner[inside] == i]) for i in range(len(timeline.realizations))])
    np.testing.assert_array_equal(joined, each)
    np.testing.assert_array_equal(_sample(timeline, times), timeline.sample(times))


@pytest.mark.parametrize("flip", [False, True], ids=["same-hemisphere", "opposite-hemisphere"])
@pytest.mark.parametrize("channel", ["hand_rotation", "handshape"])
@pytest.mark.parametrize("seed", range(4))
def test_keyframe_activation_equals_the_chain_of_moves(channel: str, seed: int, flip: bool) -> None:
    """Rotation and hand-shape LMPs activate into the track that the chain of their moves
    (the transition, then each move, rotations continued from the value before) makes."""
    timeline = _timeline(channel, 3, seed=10 + seed)
    lmp = timeline.lmps[-1]
    here = np.asarray(timeline.realizations[-2].state(lmp.pegs.start).value)
    here = -here if flip and channel == "hand_rotation" else here
    state = ChannelState(here, np.zeros(3 if channel == "hand_rotation" else here.size), lmp.pegs.start)
    first = np.asarray(lmp.first, dtype=float)
    first = -first if channel == "hand_rotation" and here @ first < 0.0 else first
    chain = [Move(lmp.pegs.start, lmp.pegs.ready, lmp.transition, np.stack([here, first]))]
    for move in lmp.moves:
        values = continuous(np.concatenate([chain[-1].values[-1:], move.values]))[1:] if channel == "hand_rotation" else move.values
        chain.append(Move(move.start, move.end, move.manner, values))
    expected = SignTrack.of(channel == "hand_rotation", here, chain, by_distance=False)
    times = np.linspace(lmp.pegs.start - 0.1, lmp.pegs.end + 0.2, 301)
    np.testing.assert_array_equal(lmp.activate(state).sample(times), expected.sample(times))


@pytest.mark.parametrize("channel", ["wrist_position", "hand_rotation", "handshape"])
@pytest.mark.parametrize("signs", [1, 2, 9, 30])
def test_sign_lmps_activated_in_turn_equal_the_sequential_timeline(channel: str, signs: int) -> None:
    """activate_in_turn (guessed values, vectorized samples, then a pass in order) makes
    the tracks ChannelTimeline.build makes one after another; the synthetic LMPs include
    runs without moves, whose values chain from one activation to the next."""
    sequential = _timeline(channel, signs, seed=100 + signs)
    tracks = activate_in_turn(sequential.lmps, np.asarray(sequential.initial.value, dtype=float), sequential.lmps[0].pegs.start)
    times = np.linspace(0.0, float(sequential.starts[-1]) + 1.0, 1201)
    for track, realization in zip(tracks, sequential.realizations, strict=True):
        np.testing.assert_array_equal(track.sample(times), realization.sample(times))


@pytest.mark.parametrize("legs", [1, 3, 12])
def test_transition_ways_in_one_pass_equal_the_ways_leg_by_leg(legs: int) -> None:
    """sequence._transition_ways builds every leg's straight path and hand turns in one
    pass; leg by leg (linspace, rotations_along) gives the same paths to clear."""
    avatar = load_avatar("max")
    rng = np.random.default_rng(legs)

    def pose() -> HandPose:
        rotation = rng.standard_normal(4)
        return HandPose(np.array([0.0, 1.2, 0.35]) + 0.15 * rng.standard_normal(3), rotation / np.linalg.norm(rotation), np.zeros(5))

    chain = [{arm: pose() for arm in ARMS} for _ in range(legs + 1)]
    pairs = list(zip(chain[:-1], chain[1:]))
    ways = _transition_ways(avatar, pairs)
    for arm in ARMS:
        paths, turns = [], []
        for before, after in pairs:
            count = max(MIN_TRANSITION_POINTS, int(np.ceil(float(np.linalg.norm(after[arm].wrist - before[arm].wrist)) / TRANSITION_SPACING)))
            fractions = np.linspace(0.0, 1.0, count + 2)
            paths.append(before[arm].wrist + fractions[:, None] * (after[arm].wrist - before[arm].wrist))
            turns.append(rotations_along(np.stack([before[arm].rotation, after[arm].rotation]), fractions))
        cleared, _ = clear_paths(avatar, arm, paths, turns, keep_ends=True, across=False)
        for way, path in zip(ways, cleared, strict=True):
            np.testing.assert_array_equal(way[arm], path[1:-1])
