"""Many hand turns at once (:func:`motor.arm.hand_turn.turn_ways`) are each turn on its
own (the arc of least cost, then the rotations along it: ``_arc`` and ``_along_arc``),
bit for bit: turns short and long, none, half turns, empty and single fractions, both
sides, both avatars."""

from __future__ import annotations

import numpy as np
import pytest

from motor.arm.hand_turn import _along_arc, _arc, turn_ways
from motor.body.avatar import load_avatar

RNG = np.random.default_rng(73)


def _unit(count: int) -> np.ndarray:
    q = RNG.normal(size=(count, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


@pytest.mark.parametrize("name", ["max", "kim"])
@pytest.mark.parametrize("side", ["l", "r"])
def test_many_turns_are_each_turn_bit_for_bit(name, side):
    avatar = load_avatar(name)
    befores, afters = list(_unit(40)), list(_unit(40))
    afters[3] = befores[3].copy()  # no turn
    afters[5] = -befores[5]  # the same rotation, the other sign
    afters[7] = np.array([-befores[7][1], befores[7][0], befores[7][3], -befores[7][2]])  # a half turn away (about z)
    fractions = [np.linspace(0.0, 1.0, int(count)) for count in RNG.integers(0, 12, 40)]
    fractions[9] = np.array([0.5])
    got = turn_ways(avatar, side, befores, afters, fractions)
    each = [_along_arc(before, *_arc(avatar, side, before, after), part) for before, after, part in zip(befores, afters, fractions)]
    assert np.array_equal(got, np.concatenate(each))


def test_no_turns_are_no_rotations():
    assert turn_ways(load_avatar("max"), "r", [], [], []).shape == (0, 4)
