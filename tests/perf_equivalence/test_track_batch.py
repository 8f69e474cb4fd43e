"""Sign tracks prepared, activated and sampled per channel (motor.signing.prepared_tracks,
motor.signing.joined_tracks, motor.signing.track_batch) equal the plain path
(``plain_track_batch.py``: each LMP realized on its own) and the sequential timeline, bit
for bit.

Cases are synthetic sign LMPs of every sign channel of both arms: with and without moves
(values that chain from one activation to the next), with and without way points (and the
hand's fractions at them), rotations of axis-aligned quaternions (dot products of exactly
zero, where the hemisphere tests keep a value as it is), starts in either hemisphere, a
first activation after the transition's end (left to the LMP's own realize), and wrist
chains traced ahead from the expected start or from elsewhere.
"""

from __future__ import annotations

import numpy as np
import pytest

from motor.program.lmp import ChannelState, ChannelTimeline, TimePegs
from motor.quaternion import continuous
from motor.signing.joined_tracks import BatchedTrack
from motor.signing.lmp import Move, SignChannelLMP, SignTrack
from motor.signing.path_batch import trace_chains
from motor.signing.prepared_tracks import _continued
from motor.signing.track_batch import activate_in_turn, sample_tracks
from tests.perf_equivalence import plain_track_batch as plain

#: Quaternions at right angles to each other or equal up to sign: dot products of exactly zero.
AXES = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0], [0.0, 0.0, 0.92387953, 0.38268343], [0.92387953, -0.38268343, 0.0, 0.0], [0.5, 0.5, -0.5, 0.5]])


def _lmps(arm: str, channel: str, signs: int, seed: int, axes: bool = False, traced: str = "none") -> list[SignChannelLMP]:
    """``signs`` synthetic sign LMPs of a channel one after another."""
    rng = np.random.default_rng(seed)
    size = {"wrist_position": 3, "hand_rotation": 4, "handshape": 5}[channel]

    def values(count: int) -> np.ndarray:
        if channel == "wrist_position":
            return np.array([0.1, 1.2, 0.3]) + np.cumsum(0.03 * rng.standard_normal((count, 3)), axis=0)
        if channel == "hand_rotation":
            if axes:
                return AXES[rng.integers(len(AXES), size=count)] * rng.choice([-1.0, 1.0], size=(count, 1))
            points = rng.standard_normal((count, size))
            return points / np.linalg.norm(points, axis=1, keepdims=True)
        return rng.standard_normal((count, size))

    lmps, clock = [], 0.1
    for _ in range(signs):
        ready = clock + rng.uniform(0.1, 0.4)
        moves, at = [], ready
        for _ in range(int(rng.integers(0, 3))):
            moves.append(Move(at, at + rng.uniform(0.1, 0.5), ("lax", "targetted", "fast")[int(rng.integers(3))], values(int(rng.integers(2, 6)))))
            at = moves[-1].end + rng.uniform(0.0, 0.1)
        end = at + 0.05
        pegs = TimePegs(clock, ready, ready, ready, end, end, end)
        via = values(3)[1:] if rng.uniform() < 0.6 else None
        fractions = np.sort(rng.uniform(0.1, 0.9, via.shape[0])) if via is not None and channel != "wrist_position" and rng.uniform() < 0.7 else None
        lmps.append(SignChannelLMP((arm, channel), pegs, values(1)[0], tuple(moves), "lax", via, None, fractions))
        clock = end
    if channel == "wrist_position" and traced != "none":
        lmps = _traced(lmps, elsewhere=traced == "elsewhere")
    return lmps


def _traced(lmps: list[SignChannelLMP], elsewhere: bool) -> list[SignChannelLMP]:
    """The wrist LMPs with their chains traced ahead from where the LMP before ends (or from
    a millimetre off it, for every other LMP: those are traced again at activation)."""
    out, here = [], lmps[0].first - 0.05
    for index, lmp in enumerate(lmps):
        start = here + (1e-3 if elsewhere and index % 2 else 0.0)
        way = np.concatenate([start[None], lmp.via if lmp.via is not None else np.empty((0, 3)), lmp.first[None]])
        chain = trace_chains([(lmp.pegs.start, lmp.pegs.ready, lmp.transition, way)], [lmp.moves])[0]
        out.append(SignChannelLMP(lmp.channel, lmp.pegs, lmp.first, lmp.moves, lmp.transition, lmp.via, chain))
        here = lmp.moves[-1].values[-1] if lmp.moves else lmp.first
    return out


def _sequential(lmps: list[SignChannelLMP], here: np.ndarray, time: float) -> list[SignTrack]:
    """Each LMP realized from the value the track before has at its start."""
    tracks = [lmps[0].realize(here, time)]
    for lmp in lmps[1:]:
        tracks.append(lmp.realize(tracks[-1].sample(np.array([lmp.pegs.start]))[0], lmp.pegs.start))
    return tracks


CASES = [
    (arm, channel, signs, axes, traced)
    for arm in ("left", "right")
    for channel, axes, traced in (
        ("wrist_position", False, "none"), ("wrist_position", False, "ahead"), ("wrist_position", False, "elsewhere"),
        ("hand_rotation", False, "none"), ("hand_rotation", True, "none"), ("handshape", False, "none"),
    )
    for signs in (1, 2, 9, 40)
]  # fmt: skip
IDS = [f"{arm}-{channel}-{signs}{'-axes' if axes else ''}-{traced}" for arm, channel, signs, axes, traced in CASES]


def _start(lmps: list[SignChannelLMP], seed: int, flip: bool) -> np.ndarray:
    here = np.asarray(lmps[0].first, dtype=float) + (0.0 if lmps[0].channel[1] == "hand_rotation" else 0.05)
    if lmps[0].channel[1] == "hand_rotation":
        rng = np.random.default_rng(seed)
        here = here + 0.3 * rng.standard_normal(4)
        here = here / np.linalg.norm(here) * (-1.0 if flip else 1.0)
    return here


@pytest.mark.parametrize("flip", [False, True], ids=["here", "opposite"])
@pytest.mark.parametrize("case", range(len(CASES)), ids=IDS)
def test_activation_in_turn_equals_the_plain_and_sequential_tracks(case: int, flip: bool) -> None:
    arm, channel, signs, axes, traced = CASES[case]
    lmps = _lmps(arm, channel, signs, seed=case, axes=axes, traced=traced)
    here = _start(lmps, case, flip)
    tracks = activate_in_turn(lmps, here, lmps[0].pegs.start)
    old = plain.activate_in_turn(lmps, here, lmps[0].pegs.start) if signs > 1 else [lmps[0].realize(here, lmps[0].pegs.start)]
    sequential = _sequential(lmps, here, lmps[0].pegs.start)
    times = np.linspace(0.0, float(lmps[-1].pegs.end) + 0.5, 1501)
    for track, before, one_by_one in zip(tracks, old, sequential, strict=True):
        np.testing.assert_array_equal(track.sample(times), before.sample(times))
        np.testing.assert_array_equal(track.sample(times), one_by_one.sample(times))
        assert track.batch is tracks[0].batch


@pytest.mark.parametrize("channel", ["wrist_position", "hand_rotation", "handshape"])
def test_late_first_activation_is_left_to_the_lmp(channel: str) -> None:
    """A first activation at the transition's end is the LMP's own: its error."""
    lmps = _lmps("right", channel, 5, seed=7)
    here = _start(lmps, 7, False)
    with pytest.raises(ValueError, match="move must end after it starts"):
        _sequential(lmps, here, lmps[0].pegs.ready)
    with pytest.raises(ValueError, match="move must end after it starts"):
        activate_in_turn(lmps, here, lmps[0].pegs.ready)


@pytest.mark.parametrize("channel", ["wrist_position", "hand_rotation", "handshape"])
@pytest.mark.parametrize("signs", [1, 3, 25])
def test_batched_tracks_sample_as_the_plain_join(channel: str, signs: int) -> None:
    """A window of tracks is sampled through their batch, through the tracks joined anew
    when they come from two batches or one was realized alone, as the plain join samples."""
    lmps = _lmps("left", channel, 2 * signs, seed=signs, axes=channel == "hand_rotation")
    here = _start(lmps, signs, False)
    first = activate_in_turn(lmps[:signs], here, lmps[0].pegs.start)
    second = activate_in_turn(lmps[signs:], first[-1].sample(np.array([lmps[signs].pegs.start]))[0], lmps[signs].pegs.start)
    alone = lmps[-1].realize(second[-1].initial, lmps[-1].pegs.start)
    starts = np.array([lmp.pegs.start for lmp in lmps])
    times = np.linspace(float(starts[0]), float(lmps[-1].pegs.end) + 0.5, 997)
    windows = [
        (first, starts[:signs]), (second, starts[signs:]), (first + second, starts), (first[1:] + second[:-1] + [alone], starts[1:]),
        (second[:1], starts[signs : signs + 1]),
    ]  # fmt: skip
    for realizations, owners in windows:
        owned = np.searchsorted(owners, times, side="right") - 1
        inside = owned >= 0
        fast = sample_tracks(realizations, owned[inside], times[inside])
        plain_join = [r.batch.alone(r.index) if isinstance(r, BatchedTrack) else r for r in realizations]
        slow = plain.sample_tracks(plain_join, owned[inside], times[inside])
        np.testing.assert_array_equal(fast, slow)
        for index, realization in enumerate(realizations):
            np.testing.assert_array_equal(realization.sample(times[inside][owned[inside] == index]), fast[owned[inside] == index])


@pytest.mark.parametrize("seed", range(6))
def test_continued_chains_equal_continuous(seed: int) -> None:
    """The chained rows' signs, both ways, are those quaternion.continuous gives, zero dot
    products included."""
    rng = np.random.default_rng(seed)
    pieces, chained = [], []
    for _ in range(12):
        head = AXES[rng.integers(len(AXES))] * rng.choice([-1.0, 1.0])
        rows = AXES[rng.integers(len(AXES), size=int(rng.integers(0, 6)))] * rng.choice([-1.0, 1.0], size=(1, 1))
        if seed % 2:
            rows = rows + 1e-3 * rng.standard_normal(rows.shape)
        pieces += [head[None], rows]
        chained += [False] + [True] * rows.shape[0]
    values = np.concatenate(pieces)
    kept, flipped = _continued(values, np.array(chained))
    at = 0
    for piece_head, rows in zip(pieces[::2], pieces[1::2]):
        expected = continuous(np.concatenate([piece_head, rows]))
        negated = continuous(np.concatenate([-piece_head, rows]))
        np.testing.assert_array_equal(kept[at : at + 1 + rows.shape[0]], expected)
        np.testing.assert_array_equal(flipped[at + 1 : at + 1 + rows.shape[0]], negated[1:])
        at += 1 + rows.shape[0]


def test_timeline_of_batched_tracks_samples_as_built() -> None:
    lmps = _lmps("right", "hand_rotation", 12, seed=3, axes=True)
    initial = ChannelState(_start(lmps, 3, True), np.zeros(3), 0.0)
    built = ChannelTimeline.build(("right", "hand_rotation"), lmps, initial)
    tracks = activate_in_turn(lmps, np.asarray(initial.value), lmps[0].pegs.start)
    times = np.linspace(0.0, float(lmps[-1].pegs.end) + 0.5, 801)
    owner = np.searchsorted(built.starts, times, side="right") - 1
    inside = owner >= 0
    np.testing.assert_array_equal(sample_tracks(tracks, owner[inside], times[inside]), built.sample(times)[inside])


@pytest.mark.parametrize("channel", ["wrist_position", "hand_rotation", "handshape"])
def test_samples_at_the_moves_edges_equal_each_track_alone(channel: str) -> None:
    """At every move's start and end, just inside and outside them, before the first, long
    after the last and at infinities, the compiled search gives what each track on its own gives."""
    lmps = _lmps("right", channel, 12, seed=5, axes=channel == "hand_rotation")
    tracks = activate_in_turn(lmps, _start(lmps, 5, False), lmps[0].pegs.start)
    for track, lmp in zip(tracks, lmps, strict=True):
        alone = track.batch.alone(track.index)
        edges = np.concatenate([alone.starts, alone.ends])
        times = np.sort(np.concatenate([edges, np.nextafter(edges, -np.inf), np.nextafter(edges, np.inf), [lmp.pegs.start - 1.0, lmp.pegs.end + 5.0, np.inf, -np.inf]]))
        np.testing.assert_array_equal(track.sample(times), alone.sample(times))
        finite = times[np.isfinite(times)]  # the plain join's complex keys take an infinite time's real part for NaN
        np.testing.assert_array_equal(track.sample(finite), plain.sample_tracks([alone], np.zeros(finite.size, dtype=int), finite))


def test_nan_times_are_refused() -> None:
    lmps = _lmps("left", "handshape", 3, seed=1)
    track = activate_in_turn(lmps, _start(lmps, 1, False), lmps[0].pegs.start)[1]
    with pytest.raises(ValueError, match="not NaN"):
        track.sample(np.array([0.5, np.nan]))
