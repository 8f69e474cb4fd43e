"""The compiled hand (:func:`motor.hand.shape.hand_rotations`) gives the numbers of numpy's
arithmetic on whole arrays (``plain_hand.py``) bit for bit: over both avatars and hands,
the parameters of every basic hand shape, random parameters within and beyond their
ranges (bends past a fist, negative splay), a single row and no rows."""

from __future__ import annotations

import numpy as np
import pytest

from motor.body.avatar import load_avatar
from motor.hand.shape import PARAMETER_COUNT, hand_rotations, handshape_params
from mura.values import BASIC_HANDSHAPES, HandShape
from tests.perf_equivalence import plain_hand

RNG = np.random.default_rng(317)


def _shapes() -> np.ndarray:
    return np.stack([handshape_params(HandShape(basic=name)) for name in sorted(BASIC_HANDSHAPES)])


@pytest.mark.parametrize("avatar_name", ["max", "kim"])
@pytest.mark.parametrize("side", ["l", "r"])
@pytest.mark.parametrize(
    "make",
    [
        _shapes,
        lambda: RNG.uniform(0.0, 1.0, (300, PARAMETER_COUNT)),
        lambda: RNG.uniform(-1.5, 2.5, (300, PARAMETER_COUNT)),
        lambda: RNG.uniform(0.0, 1.0, (1, PARAMETER_COUNT)),
        lambda: np.zeros((0, PARAMETER_COUNT)),
    ],
    ids=["basic hand shapes", "within ranges", "beyond ranges", "one row", "no rows"],
)
def test_the_compiled_hand_is_the_numpy_one_bit_for_bit(avatar_name, side, make):
    avatar = load_avatar(avatar_name)
    params = make()
    assert np.array_equal(hand_rotations(avatar, side, params), plain_hand.hand_rotations(avatar, side, params))


def test_parameters_of_the_wrong_width_are_refused():
    with pytest.raises(ValueError, match="columns"):
        hand_rotations(load_avatar("max"), "r", np.zeros((2, PARAMETER_COUNT - 1)))
