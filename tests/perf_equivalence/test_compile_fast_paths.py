"""Sign compiling's and placing's shortcuts rest on facts the plain computation bears out.

A leaf's duration is the greater of its movement's duration and the time its paths need
(their stopping lengths); a straight path is not measured when its chord, with a margin,
needs no more (:meth:`motor.signing.sign_compiler.SignCompiler.shortest`). That holds if a
straight path's stopping length never exceeds :func:`motor.signing.sign_compiler._chord_bound`:
checked here on straight paths (labelled synthetic) of every kind the compiler draws.

The rotations of the hand orientations a collection writes are computed in one
vectorized pass (:meth:`motor.signing.hand_geometry.HandGeometry.prefetch_rotations`):
each equals the one computed alone, checked on a table of orientations (labelled
synthetic) among many others, and on those the corpora write. The placed wrist rows are
cut into moves as :func:`numpy.split` cuts them.
"""

from __future__ import annotations

import numpy as np
import pytest

from motor.body.avatar import load_avatar
from motor.signing.hand_geometry import HandGeometry
from motor.signing.lmp import Move, stopping_length
from motor.signing.orientations import written_orientations
from motor.signing.path_batch import stopping_length_of
from motor.signing.path_shapes import line
from motor.signing.sign_compiler import _chord_bound
from motor.signing.reach import split_runs
from motor.trajectory.spline import HOLD_LENGTH
from motor.trajectory.symmetry import mirror_directions
from mura.constraints import Symmetry
from mura.sigml import parse_sigml

CORPORA = ("German_SL_DGS.sigml", "Indian_SL.sigml")
START = np.array([0.1, 1.2, 0.3])
#: Straight paths by kind: (start, end) of a :func:`line`, and how the path is then moved
#: (as :meth:`~motor.signing.sign_compiler.SignCompiler.follower_path` moves a lead's path).
STRAIGHT_CASES = {
    "small move": (START, START + [0.0, 0.05, 0.0], None),
    "normal move": (START, START + [0.09, -0.12, 0.04], None),
    "long move": (START, START + [-0.6, 0.4, 0.5], None),
    "across the body": ([0.35, 1.1, 0.25], [-0.35, 1.1, 0.25], None),
    "one coordinate still": (START, START + [0.0, 0.0, 0.15], None),
    "steps at the hold length": (START, START + [7.0 * HOLD_LENGTH, 0.0, 0.0], None),
    "steps below the hold length": (START, START + [3.0 * HOLD_LENGTH, 1e-9, 0.0], None),
    "no move": (START, START, None),
    "mirrored": (START, START + [0.09, -0.12, 0.04], "lr"),
    "mirrored alternating": (START, START + [0.2, 0.1, -0.05], "alternating"),
    "translated": (START, START + [-0.1, 0.2, 0.1], "par"),
}


def _straight(case: str) -> np.ndarray:
    start, end, moved = STRAIGHT_CASES[case]
    path = line(np.asarray(start, dtype=float), np.asarray(end, dtype=float))
    if moved is None:
        return path
    planes = frozenset() if moved == "par" else frozenset({"S"})
    displacement = mirror_directions(path - path[0], Symmetry(planes, "path"))
    if moved == "alternating":
        displacement = -displacement
    return np.array([-0.2, 1.0, 0.35]) + displacement


@pytest.mark.parametrize("case", STRAIGHT_CASES)
def test_a_straight_paths_stopping_length_is_within_its_chord_bound(case):
    path = _straight(case)
    assert stopping_length_of(path) == stopping_length(path) <= _chord_bound(path)


def test_the_chord_bound_is_close_to_the_stopping_length_of_a_straight_path():
    """The bound is no blunter than its margin: a straight path's stopping length is its chord."""
    path = _straight("normal move")
    assert stopping_length(path) == pytest.approx(_chord_bound(path), rel=1e-5)


#: Hand orientations (extended fingers, palm), labelled synthetic: ordinary, the palm
#: along the fingers (the parallel conventions), diagonal, mirrored with a −0, unnormalized.
ORIENTATION_CASES = {
    "fingers out, palm down": ((0.0, 0.0, 1.0), (0.0, -1.0, 0.0)),
    "fingers up, palm left": ((0.0, 1.0, 0.0), (1.0, 0.0, 0.0)),
    "palm along the fingers": ((0.0, 1.0, 0.0), (0.0, 1.0, 0.0)),
    "palm against the fingers": ((1.0, 0.0, 0.0), (-1.0, 0.0, 0.0)),
    "diagonal": ((0.7071067811865476, 0.0, 0.7071067811865476), (0.0, -0.7071067811865476, 0.7071067811865476)),
    "mirrored zero": ((-0.0, 0.0, 1.0), (-1.0, 0.0, 0.0)),
    "unnormalized": ((0.0, 2.0, 0.5), (0.3, 0.0, -4.0)),
}


@pytest.mark.parametrize("case", ORIENTATION_CASES)
def test_a_prefetched_rotation_equals_one_computed_alone(case):
    avatar = load_avatar("max")
    fingers, palm = (np.array(vector) for vector in ORIENTATION_CASES[case])
    others = np.random.default_rng(len(case)).normal(size=(2, 40, 3))  # among many others
    fast = HandGeometry(avatar)
    fast.prefetch_rotations(np.vstack([others[0], fingers]), np.vstack([others[1], palm]))
    plain = HandGeometry(avatar, memoize=False)
    for side in ("l", "r"):
        assert fast._memo[("rotation", side, fingers.tobytes(), palm.tobytes())].tobytes() == plain.rotation(side, fingers, palm).tobytes()


def test_prefetched_rotations_of_the_corpora_equal_those_computed_alone(shared):
    signs = [sign for name in CORPORA for sign in parse_sigml((shared / "corpora" / "sigml" / name).read_bytes(), file=name).signs]
    fingers, palms = written_orientations(signs, [(0.0, 0.0, 1.0)], [(1.0, 0.0, 0.0)])
    avatar = load_avatar("max")
    fast = HandGeometry(avatar)
    fast.prefetch_rotations(fingers, palms)
    plain = HandGeometry(avatar, memoize=False)
    for side in ("l", "r"):
        for finger, palm in zip(fingers[::7], palms[::7]):
            assert fast._memo[("rotation", side, finger.tobytes(), palm.tobytes())].tobytes() == plain.rotation(side, finger, palm).tobytes()


def test_written_orientations_keep_a_mirrored_zero_apart():
    fingers, palms = written_orientations([], [(0.0, 0.0, 1.0)], [(1.0, 0.0, 0.0)])
    assert {row.tobytes() for row in fingers} == {np.array(v).tobytes() for v in [(0.0, 0.0, 1.0), (-0.0, 0.0, 1.0)]}
    assert len(fingers) == len(palms) == 4


#: Runs of rows (counts), labelled synthetic: one run, many, runs of one row, a long one.
SPLIT_CASES = {"one run": [8], "many runs": [8, 8, 33, 7, 8], "runs of one row": [1, 1, 1], "a long run": [2, 300, 2]}


@pytest.mark.parametrize("case", SPLIT_CASES)
def test_placed_rows_are_cut_as_numpy_split_cuts_them(case):
    counts = SPLIT_CASES[case]
    rows = np.random.default_rng(len(case)).normal(size=(sum(counts), 3))
    fast = split_runs(rows, counts)
    plain = np.split(rows, np.cumsum(counts)[:-1])
    assert [(piece.shape, piece.tobytes()) for piece in fast] == [(piece.shape, piece.tobytes()) for piece in plain]


_PATH = np.array([[0.1, 1.2, 0.3], [0.2, 1.1, 0.35], [0.25, 1.0, 0.4]])
#: Rows of moves ``(start, end, manner, values)`` made at once, labelled synthetic: all
#: valid, and one refused among valid ones for each check the constructor makes (or
#: values it converts: a list, integers).
MOVE_CASES = {
    "valid": [(0.0, 0.2, "targetted", _PATH), (0.2, 0.5, "lax", _PATH[:2]), (0.5, 0.9, "linear", _PATH.T.copy())],
    "none": [],
    "a nan": [(0.0, 0.2, "targetted", _PATH), (0.2, 0.5, "lax", np.where(_PATH > 1.1, np.nan, _PATH))],
    "an infinity": [(0.0, 0.2, "targetted", _PATH), (0.2, 0.5, "lax", np.where(_PATH > 1.1, -np.inf, _PATH))],
    "one row": [(0.0, 0.2, "targetted", _PATH), (0.2, 0.5, "lax", _PATH[:1])],
    "one dimension": [(0.0, 0.2, "targetted", _PATH[0])],
    "no time": [(0.0, 0.2, "targetted", _PATH), (0.2, 0.2, "lax", _PATH)],
    "backwards in time": [(0.3, 0.2, "targetted", _PATH)],
    "unknown manner": [(0.0, 0.2, "targetted", _PATH), (0.2, 0.5, "brisk", _PATH)],
    "a list": [(0.0, 0.2, "targetted", _PATH.tolist())],
    "integers": [(0.0, 0.2, "fast", np.array([[0, 1, 2], [3, 4, 5]]))],
}


def _made(make):
    """What ``make`` gives as comparable numbers, or the error it raises."""
    try:
        moves = make()
    except ValueError as error:
        return str(error)
    return [(m.start, m.end, m.manner, m.values.dtype, m.values.shape, m.values.tobytes()) for m in moves]


@pytest.mark.parametrize("case", MOVE_CASES)
def test_moves_made_at_once_are_those_made_one_by_one(case):
    rows = MOVE_CASES[case]
    assert _made(lambda: Move.many(rows)) == _made(lambda: [Move(*row) for row in rows])
