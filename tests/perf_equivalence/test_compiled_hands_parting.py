"""The compiled hands' separation (:func:`motor.body.collision.hand_separation`, loops in
:mod:`motor.body.hands_parting`) is the numpy one (``plain_collision.py``) bit for bit:
hands through each other, touching, crossed over, palm to palm, fingers into fingers, far
apart, with and without an allowance, on both avatars, with non-finite rotations."""

from __future__ import annotations

import numpy as np
import pytest

from motor.body.avatar import load_avatar
from motor.body.collision import hand_separation
from tests.perf_equivalence import plain_collision as plain

RNG = np.random.default_rng(59)


def _rotations(count: int) -> np.ndarray:
    q = RNG.normal(size=(count, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def _case(kind: str, count: int = 300) -> tuple[np.ndarray, ...]:
    """Wrists ``left``, ``right`` and hand rotations of a kind of meeting."""
    centre = np.array([0.0, 1.2, 0.3]) + RNG.normal(0.0, 0.05, (count, 3))
    spread = {"through": 0.03, "touching": 0.08, "near": 0.15, "far": 0.6}.get(kind, 0.1)
    offset = RNG.normal(0.0, spread, (count, 3))
    left, right = centre + offset, centre - offset
    left_hands, right_hands = _rotations(count), _rotations(count)
    if kind == "crossed":  # the left wrist right of the right one
        left[:, 0], right[:, 0] = centre[:, 0] - np.abs(offset[:, 0]), centre[:, 0] + np.abs(offset[:, 0])
    if kind == "mirrored":  # mirror-image hands: palm to palm, fingers into fingers
        right_hands = left_hands * np.array([1.0, -1.0, -1.0, 1.0])
    if kind == "non-finite":
        left_hands[::9] = np.nan
        right_hands[4::11, 3] = np.inf
    return left, right, left_hands, right_hands


@pytest.mark.parametrize("name", ["max", "kim"])
@pytest.mark.parametrize("kind", ["through", "touching", "near", "far", "crossed", "mirrored", "non-finite"])
@pytest.mark.parametrize("allowance", [0.0, 0.003])
def test_the_compiled_separation_is_numpy_s_bit_for_bit(name, kind, allowance):
    avatar = load_avatar(name)
    case = _case(kind)
    got = hand_separation(avatar, *case, allowance)
    with np.errstate(invalid="ignore"):
        expected = plain.hand_separation(avatar, *case, allowance)
    assert np.array_equal(got, expected, equal_nan=True)
    assert np.array_equal(np.signbit(got), np.signbit(expected))


def test_the_cases_move_hands():
    """The table is not vacuous: hands through each other are moved apart, far ones not."""
    avatar = load_avatar("max")
    assert np.count_nonzero(np.any(hand_separation(avatar, *_case("through")) != 0.0, axis=1)) > 30
    assert not np.any(hand_separation(avatar, *_case("far", 50)))
