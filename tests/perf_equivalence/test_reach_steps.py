"""The reach check's compiled steps (:mod:`motor.signing.reach_steps`, inside
:func:`motor.signing.reach.within_reach`) move positions as its numpy passes did
(``plain_reach.py``), bit for bit, with the largest shortfall and which moved: over both
avatars and arms, positions in front, across the chest, out of reach, too near the
shoulder and on it, behind the back, with and without hand rotations, with and without
the step back from across the body."""

from __future__ import annotations

import numpy as np
import pytest

from motor.body.avatar import load_avatar
from motor.body.conventions import AVATAR_SIDE
from motor.signing.reach import _within_reach
from tests.perf_equivalence import plain_reach

RNG = np.random.default_rng(41)
N = 200
#: Where the positions lie from the shoulder (metres, avatar frame: +x the avatar's
#: left, y up, z forward; "across": toward the other shoulder), and how far they scatter.
PLACES = {
    "front": ((0.0, -0.3, 0.3), 0.1),
    "across the chest": ("across", 0.1),
    "out of reach": ((0.0, 0.0, 0.8), 0.3),
    "near the shoulder": ((0.0, 0.0, 0.05), 0.04),
    "behind": ((0.0, -0.2, -0.3), 0.1),
    "anywhere": ((0.0, 0.0, 0.0), 0.6),
}


def positions(avatar, arm: str, place: str) -> np.ndarray:  # noqa: ANN001
    shoulder = avatar.rest_positions[avatar.joint_index(f"{AVATAR_SIDE[arm]}_shoulder")]
    toward, spread = PLACES[place]
    offset = np.array([-1.5 * shoulder[0], -0.2, 0.15]) if toward == "across" else np.array(toward)
    points = shoulder + offset + RNG.normal(0.0, spread, (N, 3))
    points[0] = shoulder  # no direction away from it
    return points


@pytest.mark.parametrize("avatar_name", ["max", "kim"])
@pytest.mark.parametrize("arm", ["left", "right"])
@pytest.mark.parametrize("place", sorted(PLACES))
@pytest.mark.parametrize("hands", [True, False], ids=["hand rotations", "no hand rotations"])
@pytest.mark.parametrize("across", [True, False], ids=["across", "not across"])
def test_the_compiled_steps_move_as_the_numpy_passes(avatar_name, arm, place, hands, across):
    avatar = load_avatar(avatar_name)
    points = positions(avatar, arm, place)
    rotations = None
    if hands:
        rotations = RNG.normal(size=(N, 4))
        rotations /= np.linalg.norm(rotations, axis=1, keepdims=True)
    fixed, moved, worst = _within_reach(avatar, arm, points, rotations, across)
    plain_fixed, plain_moved, plain_worst = plain_reach.within_reach(avatar, arm, points, rotations, across)
    assert fixed.tobytes() == plain_fixed.tobytes()
    assert moved.tolist() == plain_moved.tolist()
    assert np.float64(worst).tobytes() == np.float64(plain_worst).tobytes()


def test_the_table_reaches_every_kind_of_step():
    avatar = load_avatar("max")
    kinds = set()
    for place in PLACES:
        points = positions(avatar, "right", place)
        fixed, moved, _ = _within_reach(avatar, "right", points, None)
        _, no_cross, _ = _within_reach(avatar, "right", points, None, across=False)
        if np.any(moved & ~no_cross):
            kinds.add("across")
        if np.any(no_cross):
            kinds.add("reach")
    assert kinds == {"across", "reach"}
