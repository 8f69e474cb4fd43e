"""Sign planning's batched passes equal the one-at-a-time computations, bit for bit.

Cases: the wrist paths of real signs (every 25th parsed sign of both SiGML corpora,
planned up to, not including, the retiming) and synthetic paths (labelled by kind): a
straight line, a zigzag that reverses, a path with a hold, two and three points, a path
that does not move, one shorter than the millimetre whose law factor is measured, and
one of micrometres (a law-time kernel wider than its grid); the least durations of a
table of lengths in mixed manners. The clearing's spread of displacements along chains
is checked on synthetic chains.
"""

from __future__ import annotations

import gc
from pathlib import Path

import numpy as np
import pytest

from motor.body.avatar import load_avatar
from motor.body.conventions import ARMS
from motor.signing import path_shapes, planning
from motor.signing.collector import collector_paused
from motor.signing.lmp import REVERSAL_ANGLE, stopping_length
from motor.signing.path_batch import stopping_length_of
from motor.signing.plan import SignPlan
from motor.signing.reach import path_shift, path_shifts
from motor.signing.retiming import retimed_all, timing_length, timing_lengths
from motor.signing.sequence import realize_signs
from motor.signing.spreading import _spread_chains, spread_along_chains
from motor.trajectory.biocontrol import MANNERS, shortest_duration, shortest_durations
from mura.hamnosys import hamnosys_string, parse_hamnosys
from mura.sigml import parse_sigml
from tests.perf_equivalence import plain_spread

CORPORA = ("German_SL_DGS.sigml", "Indian_SL.sigml")
#: Every how many signs of each corpus the real cases take.
STRIDE = 25


def _synthetic(kind: str) -> np.ndarray:
    """A synthetic wrist path (metres) of one kind."""
    start = np.array([0.1, 1.2, 0.3])
    rng = np.random.default_rng(len(kind))
    if kind == "line":
        return np.linspace(start, start + [0.2, 0.05, 0.1], 8)
    if kind == "zigzag":  # reverses: cut into pieces
        return start + np.cumsum(np.where(np.arange(9)[:, None] % 3 == 2, -1.0, 1.0) * [0.04, 0.01, 0.005], axis=0)
    if kind == "hold":
        points = start + np.cumsum(0.03 * rng.standard_normal((7, 3)), axis=0)
        points[4] = points[3]
        return points
    if kind == "two points":
        return np.stack([start, start + [0.1, 0.0, 0.0]])
    if kind == "three points":
        return np.stack([start, start + [0.1, 0.0, 0.0], start + [0.1, 0.1, 0.0]])
    if kind == "still":
        return np.repeat(start[None], 5, axis=0)
    if kind == "submillimetre":
        return np.linspace(start, start + [4e-4, 3e-4, 0.0], 6) + 1e-5 * rng.standard_normal((6, 3))
    return start + np.cumsum(2e-6 * rng.standard_normal((9, 3)), axis=0)  # "micrometres"


SYNTHETIC = ("line", "zigzag", "hold", "two points", "three points", "still", "submillimetre", "micrometres")


@pytest.fixture(scope="module")
def drafts(shared: Path) -> list:
    """Plans of real signs before their retiming (the retiming left out)."""
    signs = [sign for name in CORPORA for sign in parse_sigml((shared / "corpora" / "sigml" / name).read_bytes(), file=name).signs[::STRIDE]]
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(planning, "retimed_all", lambda drafts, batched=True: drafts)
        return planning.plan_signs(load_avatar("max"), signs)


@pytest.fixture(scope="module")
def real_paths(drafts) -> list[np.ndarray]:
    return [move.values for plan in drafts if isinstance(plan, SignPlan) for arm in ARMS for move in plan.moves.get((arm, "wrist_position"), ())]


def test_real_paths_cover_many_sizes(real_paths):
    assert len(real_paths) > 200
    assert max(len(path) for path in real_paths) > 30  # cleared paths with inserted points
    assert len({path.shape[0] for path in real_paths}) >= 5  # many sizes: many groups of the batch


def test_timing_lengths_of_real_paths_equal_one_by_one(real_paths):
    batched = timing_lengths(real_paths)
    plain = [timing_length(path) for path in real_paths]
    assert batched == plain
    assert any(length > 0.0 for length in plain) and any(length == 0.0 for length in plain)


@pytest.mark.parametrize("kind", SYNTHETIC)
def test_timing_length_of_a_synthetic_path_equals_one_by_one(kind, real_paths):
    path = _synthetic(kind)
    table = [*real_paths[:40], path, path.copy(), *real_paths[40:80]]  # among others, repeated
    batched = timing_lengths(table)
    assert batched[40] == batched[41] == timing_length(path)


#: Movement lengths (m) whose least durations are compared: none, tiny, a sign's, the arm's span.
LENGTHS = [0.0, 1e-9, 1e-4, 0.003, 0.01, 0.05, 0.12, 0.3, 0.7, 1.5]


@pytest.mark.parametrize("manner", sorted(MANNERS))
def test_shortest_durations_equal_one_by_one(manner):
    manners = [(manner, "lax", "fast")[index % 3] for index in range(len(LENGTHS))]  # mixed, as a corpus's moves
    batched = shortest_durations(np.array(LENGTHS), manners)
    assert batched.tolist() == [shortest_duration(length, name) for length, name in zip(LENGTHS, manners)]


def test_retimed_plans_equal_plans_retimed_one_by_one(drafts):
    fast = retimed_all(drafts)
    plain = retimed_all(drafts, batched=False)
    assert any(a is not b for a, b in zip(fast, drafts))  # some moves were slowed
    for a, b in zip(fast, plain):
        if not isinstance(b, SignPlan):
            assert str(a) == str(b)
            continue
        assert (a.duration, a.warnings) == (b.duration, b.warnings)
        for key, moves in b.moves.items():
            assert [(m.start, m.end) for m in a.moves[key]] == [(m.start, m.end) for m in moves], (b.gloss, key)


def synthetic_chains(seed: int, dense: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Synthetic chains (labelled synthetic: random arcs and needs, seeded), some needing
    nothing, some needing less than the threshold of a needy point, some anchored, with a
    point repeated where one move ends and the next starts; ``dense``: points a few
    millimetres apart in long chains, so that a need reaches past the window of
    neighbours, as in a corpus's wrist paths."""
    rng = np.random.default_rng(seed)
    sizes = rng.integers(60, 200, 12) if dense else rng.integers(1, 40, 30)
    chain = np.repeat(np.arange(sizes.size), sizes)
    arc = np.concatenate([np.cumsum(rng.uniform(0.0, 0.006 if dense else 0.03, size)) for size in sizes])
    arc[5] = arc[4]
    need = rng.normal(0.0, 0.02, (chain.size, 3)) * (rng.random(chain.size) < 0.2)[:, None]
    need[chain % 3 == 0] = 0.0
    need[chain == 4] = 1e-13  # below the needy threshold, still spread
    anchored = (chain == 6) & (rng.random(chain.size) < 0.5)
    return need, arc, chain, anchored


@pytest.mark.parametrize("dense", [False, True], ids=["sparse", "dense"])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_spreading_only_the_chains_that_need_it_changes_no_displacement(seed, dense):
    need, arc, chain, anchored = synthetic_chains(seed, dense)
    whole = _spread_chains(need, arc, chain, anchored)
    fast = spread_along_chains(need, arc, chain, anchored)
    assert fast.tobytes() == whole.tobytes()
    assert np.any(fast[chain == 4] != 0.0) and np.all(fast[chain == 3] == 0.0)


@pytest.mark.parametrize("dense", [False, True], ids=["sparse", "dense"])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_compiled_spreading_adds_as_the_numpy_passes(seed, dense):
    need, arc, chain, anchored = synthetic_chains(seed, dense)
    assert _spread_chains(need, arc, chain, anchored).tobytes() == plain_spread.spread_chains(need, arc, chain, anchored).tobytes()


def test_a_chain_of_one_point_and_no_points_spread_nothing_else():
    one = _spread_chains(np.array([[0.01, 0.0, 0.0]]), np.zeros(1), np.zeros(1, dtype=np.int64), np.zeros(1, dtype=bool))
    assert one.tolist() == plain_spread.spread_chains(np.array([[0.01, 0.0, 0.0]]), np.zeros(1), np.zeros(1, dtype=np.int64), np.zeros(1, dtype=bool)).tolist()
    assert spread_along_chains(np.zeros((0, 3)), np.zeros(0), np.zeros(0, dtype=np.int64), np.zeros(0, dtype=bool)).shape == (0, 3)


def test_one_path_stopping_length_of_real_paths_equals_the_plain_one(real_paths):
    assert [stopping_length_of(path) for path in real_paths] == [stopping_length(path) for path in real_paths]


@pytest.mark.parametrize("kind", SYNTHETIC)
def test_one_path_stopping_length_of_a_synthetic_path_equals_the_plain_one(kind):
    path = _synthetic(kind)
    assert stopping_length_of(path) == stopping_length(path)


#: Turns (radians from straight on) of a path's middle point, labelled synthetic: around
#: the reversal angle, where the one-path function's shortcut for paths without a
#: reversal gives way to measuring every turn, and far from it on either side.
TURNS = {
    "gentle": 0.3,
    "the shortcut's sharpest turn": REVERSAL_ANGLE - 2.1e-6,
    "short of a reversal, each turn measured": REVERSAL_ANGLE - 1e-7,
    "at the reversal": REVERSAL_ANGLE,
    "just past the reversal": REVERSAL_ANGLE + 1e-12,
    "back on itself": np.pi - 1e-3,
}


@pytest.mark.parametrize("turn", TURNS)
def test_one_path_stopping_length_of_a_turning_path_equals_the_plain_one(turn):
    angle = TURNS[turn]
    path = np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.2, 0.0, 0.0], [0.2 + 0.1 * np.cos(angle), 0.1 * np.sin(angle), 0.0], [0.3, 0.05, 0.02]])
    assert stopping_length_of(path) == stopping_length(path)


@pytest.mark.parametrize("running", [True, False])
@pytest.mark.parametrize("work", ["plan", "realize"])
def test_planning_and_realizing_leave_the_garbage_collector_as_they_found_it(running, work):
    """The collector is paused while signs are planned or realized (a fast path) and
    resumed only if it ran."""
    sign = parse_hamnosys(hamnosys_string(["hamflathand", "hamextfingero", "hampalmd", "hamchest", "hammoveu"]), gloss="move up")
    was = gc.isenabled()
    try:
        gc.enable() if running else gc.disable()
        if work == "plan":
            (plan,) = planning.plan_signs(load_avatar("max"), [sign])
            assert isinstance(plan, SignPlan)
        else:
            assert realize_signs(load_avatar("max"), [sign]).motion.frame_count > 0
        assert gc.isenabled() == running
    finally:
        gc.enable() if was else gc.disable()


def test_the_collector_waits_within_the_pause_and_resumes_after_an_error():
    was = gc.isenabled()
    try:
        gc.enable()
        with pytest.raises(RuntimeError), collector_paused():
            assert not gc.isenabled()
            raise RuntimeError("planning failed")
        assert gc.isenabled()
    finally:
        gc.enable() if was else gc.disable()


LINE_CASES = {
    "ordinary": ([0.1, 1.2, 0.3], [0.3, 1.05, 0.45]),
    "one coordinate still": ([0.1, 1.2, 0.3], [0.1, 1.0, 0.5]),
    "a hold": ([0.1, 1.2, 0.3], [0.1, 1.2, 0.3]),
    "denormal step": ([0.0, 1.0, 0.0], [1e-320, 1.0, 0.0]),
    "negative and large": ([-3.0, 1e3, -1e-9], [2.5, -1e3, 1e-9]),
}


@pytest.mark.parametrize("case", LINE_CASES)
def test_a_straight_path_is_numpys_linspace(case):
    start, end = (np.array(point) for point in LINE_CASES[case])
    assert path_shapes.line(start, end).tobytes() == np.linspace(start, end, path_shapes.PATH_POINTS).tobytes()


#: Moved paths and the originals they came from (labelled synthetic, seeded): points per
#: moved path, points per original, and what else the original has.
SHIFT_CASES = {
    "one point each": (1, 1, ""),
    "one-point original": (12, 1, ""),
    "two-point original": (5, 2, ""),
    "long paths": (40, 30, ""),
    "a zero chord": (9, 6, "hold"),
    "unmoved": (8, 8, "same"),
}


@pytest.mark.parametrize("case", SHIFT_CASES)
def test_path_shifts_of_many_paths_equal_one_by_one(case):
    """:func:`motor.signing.reach.path_shifts` of a batch of paths of every case at once
    equals :func:`path_shift` of each, bit for bit."""
    moved_points, original_points, extra = SHIFT_CASES[case]
    rng = np.random.default_rng(len(case))
    moved, originals = [], []
    for _ in range(20):
        original = np.array([0.1, 1.2, 0.3]) + np.cumsum(rng.normal(0.0, 0.02, (original_points, 3)), axis=0)
        if extra == "hold":
            original[2] = original[1]
        shift = 0.0 if extra == "same" else 0.01
        moved.append(original[rng.integers(0, original_points, moved_points)] + shift * rng.normal(size=(moved_points, 3)))
        originals.append(original)
    assert path_shifts(moved, originals).tolist() == [path_shift(a, b) for a, b in zip(moved, originals)]
