"""Sign paths cleared out of the body and into reach keep their shape and stay joined.

Tables of synthetic wrist paths (labelled synthetic: straight lines and circles placed
through the torso's front, across the body and beyond the arm's reach of the reference
avatar) are cleared as a sign's moves are; the properties hold for every case.
"""

from __future__ import annotations

import numpy as np
import pytest

from motor.body.collision import inside_torso
from motor.signing.reach import clear_paths, within_reach
from motor.trajectory.spline import turning_angles

#: Synthetic paths (metres, avatar frame: root at the origin, y up, +z forward, +x the
#: avatar's left; the reference avatar's torso spans x ±0.14, z −0.105…0.115, y −0.05…0.51,
#: its right shoulder is at (−0.18, 0.49, −0.015), its arm 0.58 long), each from its
#: start to its end in straight chords or round a circle.
CASES = {
    "through the chest": ("line", [-0.10, 0.30, 0.12], [0.10, 0.30, 0.12]),
    "into the belly": ("line", [-0.20, 0.10, 0.40], [0.00, 0.10, 0.05]),
    "across the body": ("line", [-0.30, 0.35, 0.30], [0.30, 0.35, 0.12]),
    "beyond reach": ("line", [-0.20, 0.30, 0.30], [-0.20, 0.30, 0.80]),
    "circle at the chest": ("circle", [0.00, 0.30, 0.14], 0.10),
    "circle far ahead": ("circle", [-0.20, 0.40, 0.55], 0.12),
}

#: Largest turn (degrees) between consecutive chords of a cleared path that was a line;
#: clearing point by point left turns of 100–180° (a zigzag).
LINE_TURN = 60.0
#: Largest turn between chords of a cleared circle of 40 chords (9° each when round).
CIRCLE_TURN = 30.0


def synthetic_path(kind: str, a: list[float], b) -> np.ndarray:
    if kind == "line":
        return np.linspace(a, b, 13)
    angle = np.linspace(0.0, 2.0 * np.pi, 41)
    return np.asarray(a) + b * np.stack([np.cos(angle), np.sin(angle), np.zeros_like(angle)], axis=1)


def level_hand(count: int) -> np.ndarray:
    return np.tile([0.0, 0.0, 0.0, 1.0], (count, 1))


@pytest.fixture(scope="module", params=list(CASES))
def cleared(request, avatar):
    kind, a, b = CASES[request.param]
    path = synthetic_path(kind, a, b)
    result, _ = clear_paths(avatar, "right", [path], [level_hand(len(path))])
    return kind, path, result[0]


def test_cleared_points_need_no_more_clearing(avatar, cleared):
    _, _, path = cleared
    assert not np.any(inside_torso(avatar, path))
    again, moved, _ = within_reach(avatar, "right", path, level_hand(len(path)))
    assert moved == 0 and np.array_equal(again, path)


def test_cleared_paths_do_not_zigzag(cleared):
    kind, _, path = cleared
    chords = np.linalg.norm(np.diff(path, axis=0), axis=1)
    distinct = path[np.concatenate([[True], chords > 1e-6])]
    limit = LINE_TURN if kind == "line" else CIRCLE_TURN
    assert np.degrees(turning_angles(distinct)).max(initial=0.0) <= limit


def test_cleared_paths_keep_their_ends_where_asked(avatar):
    paths = [synthetic_path(*CASES[name]) for name in CASES]
    result, moved = clear_paths(avatar, "right", paths, [level_hand(len(p)) for p in paths], keep_ends=True)
    assert moved > 0
    for before, after in zip(paths, result):
        assert np.array_equal(after[[0, -1]], before[[0, -1]])


def test_moves_of_one_chain_still_meet(avatar):
    """A hand's first posture and consecutive moves are one chain: cleared, each move
    still starts where the one before ends, bit for bit."""
    line = synthetic_path(*CASES["into the belly"])
    back = line[::-1]
    paths = [line[:1], line, back, line]
    result, moved = clear_paths(avatar, "right", paths, [level_hand(len(p)) for p in paths], chains=np.zeros(4, dtype=int))
    assert moved > 0
    for before, after in zip(result[:-1], result[1:]):
        assert np.array_equal(before[-1], after[0])
