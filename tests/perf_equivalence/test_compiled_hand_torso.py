"""The compiled hand push out of the torso (:func:`motor.body.collision.hand_push_out_of_torso`,
loops in :mod:`motor.body.torso_push`) is the numpy one (``plain_collision.py``) bit for
bit: hands pointing back into the chest, down into the hip, in from the side and behind,
wrists in front of, inside, beside and behind the torso and across its top and bottom
edges, far ones, non-finite and huge numbers, on every avatar and both sides, for 0, 1 and
many rows; and the torso's push of wrists (:func:`motor.body.collision.kept_out_of_torso`),
whose loops skip points that cannot move, at huge and non-finite coordinates too."""

from __future__ import annotations

import numpy as np
import pytest

from motor import quaternion as quat
from motor.body.avatar import load_avatar
from motor.body.collision import TORSO_MARGIN, hand_push_out_of_torso, kept_out_of_torso
from motor.body.torso_push import EDGE_BAND, SOFT_BAND
from tests.perf_equivalence import plain_collision as plain

RNG = np.random.default_rng(83)
AVATARS = ["max", "kim", "makehuman"]
#: Where the hands point (the way from the wrist to the knuckles), per kind of case.
KINDS = ["chest", "hip", "side", "behind", "inside", "edges", "around", "far", "non-finite", "huge"]


def _hands(avatar, side: str, ways: np.ndarray) -> np.ndarray:
    """Global hand rotations turning the hand's capsule axis to ``ways`` ``(n, 3)``, each
    twisted about it by a random angle."""
    capsule = avatar.collision.arm(side, "hand")
    axis = (capsule.b - capsule.a) / np.linalg.norm(capsule.b - capsule.a)
    ways = ways / np.linalg.norm(ways, axis=1, keepdims=True)
    twist = quat.from_axis_angle(ways, RNG.uniform(-np.pi, np.pi, len(ways)))
    return quat.multiply(twist, quat.between_vectors(axis, ways))


def _case(avatar, side: str, kind: str, count: int = 300) -> tuple[np.ndarray, np.ndarray]:
    """Wrists ``(count, 3)`` (trunk frame) and hand rotations ``(count, 4)`` of a kind."""
    torso = avatar.torso
    cx, cz, hw, hd = torso.center[0], torso.center[2], torso.half_width, torso.half_depth
    front = cz + hd + TORSO_MARGIN
    wrists = np.stack([cx + RNG.uniform(-1.0, 1.0, count) * hw, RNG.uniform(torso.bottom, torso.top, count), front + RNG.uniform(-0.03, 0.08, count)], axis=1)
    ways = RNG.normal(0.0, 0.5, (count, 3)) + [0.0, 0.0, -1.0]  # back into the chest
    if kind == "hip":
        wrists[:, 1] = torso.bottom + RNG.uniform(-0.12, 0.12, count)
        ways = RNG.normal(0.0, 0.4, (count, 3)) + [0.0, -0.7, -0.7]
    if kind == "side":
        outward = np.where(RNG.random(count) < 0.5, -1.0, 1.0)
        wrists[:, 0] = cx + outward * (hw + RNG.uniform(0.0, 0.12, count))
        wrists[:, 2] = cz + RNG.uniform(-1.0, 1.0, count) * hd
        ways = RNG.normal(0.0, 0.4, (count, 3)) - outward[:, None] * [1.0, 0.0, 0.0]
    if kind == "behind":
        wrists[:, 2] = cz - hd - RNG.uniform(-0.02, 0.15, count)
        ways = RNG.normal(0.0, 0.5, (count, 3)) + [0.0, 0.0, 1.0]
    if kind == "inside":
        wrists[:, 0], wrists[:, 2] = cx + RNG.uniform(-0.9, 0.9, count) * hw, cz + RNG.uniform(-0.9, 0.9, count) * hd
        ways = RNG.normal(size=(count, 3))
    if kind == "edges":
        wrists[:, 1] = np.where(RNG.random(count) < 0.5, torso.top, torso.bottom) + RNG.uniform(-1.2, 1.2, count) * (EDGE_BAND + 0.1)
    if kind in ("around", "non-finite", "huge"):
        wrists = np.array([cx, 0.5 * (torso.bottom + torso.top), cz]) + RNG.uniform(-1.0, 1.0, (count, 3)) * [hw + 0.3, 0.5 * (torso.top - torso.bottom) + 0.3, hd + 0.3]
        ways = RNG.normal(size=(count, 3))
    if kind == "far":
        wrists = wrists + RNG.choice([-1.0, 1.0], (count, 3)) * RNG.uniform(0.6, 3.0, (count, 3))
    hands = _hands(avatar, side, ways)
    if kind == "non-finite":
        wrists[::7, 0] = np.nan
        wrists[3::11, 2] = -np.inf
        wrists[5::13, 1] = np.inf
        hands[2::9] = np.nan
        hands[4::17, 3] = np.inf
    if kind == "huge":
        wrists[::5] *= 1e6
        wrists[1::5, 2] = -1e300
        wrists[2::5, 0] = 1e300
        hands[3::5] *= 1e150
    return wrists, hands


def _same(got: np.ndarray, expected: np.ndarray) -> bool:
    return np.array_equal(got, expected, equal_nan=True) and np.array_equal(np.signbit(got), np.signbit(expected))


@pytest.mark.parametrize("name", AVATARS)
@pytest.mark.parametrize("side", ["l", "r"])
@pytest.mark.parametrize("kind", KINDS)
def test_the_compiled_hand_push_is_numpy_s_bit_for_bit(name, side, kind):
    avatar = load_avatar(name)
    wrists, hands = _case(avatar, side, kind)
    got = hand_push_out_of_torso(avatar, side, wrists, hands)
    with np.errstate(invalid="ignore", over="ignore"):
        expected = plain.hand_push_out_of_torso(avatar, side, wrists, hands)
    assert _same(got, expected)


@pytest.mark.parametrize("count", [0, 1, 2])
@pytest.mark.parametrize("kind", ["chest", "far"])
def test_few_rows_are_pushed_as_numpy_pushes_them(count, kind):
    avatar = load_avatar("max")
    wrists, hands = _case(avatar, "r", kind, count)
    got = hand_push_out_of_torso(avatar, "r", wrists, hands)
    assert got.shape == (count, 3)
    assert _same(got, plain.hand_push_out_of_torso(avatar, "r", wrists, hands))


def test_strided_wrists_and_single_precision_hands_are_taken_as_their_float_copies():
    """What a caller may pass: wrists a column slice of a wider array, hands in float32."""
    avatar = load_avatar("max")
    wrists, hands = _case(avatar, "l", "chest")
    wide = np.concatenate([wrists, RNG.random((len(wrists), 2))], axis=1)
    single = hands.astype(np.float32)
    got = hand_push_out_of_torso(avatar, "l", wide[:, :3], single)
    assert _same(got, plain.hand_push_out_of_torso(avatar, "l", np.ascontiguousarray(wide[:, :3]), single.astype(float)))


def test_the_cases_push_hands_and_some_twice():
    """The table is not vacuous: hands pointing into the chest are pushed, most of them;
    some wrists move in the second round too (a push differing from the first round's
    alone); far hands are not."""
    avatar = load_avatar("max")
    wrists, hands = _case(avatar, "r", "chest")
    push = hand_push_out_of_torso(avatar, "r", wrists, hands)
    assert np.count_nonzero(np.any(push != 0.0, axis=1)) > 100
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(plain, "_HAND_ROUNDS", 1)
        once = plain.hand_push_out_of_torso(avatar, "r", wrists, hands)
    assert np.count_nonzero(np.any(once != push, axis=1)) > 10
    assert not np.any(hand_push_out_of_torso(avatar, "r", *_case(avatar, "r", "far")))


@pytest.mark.parametrize("name", AVATARS)
@pytest.mark.parametrize("margin", [TORSO_MARGIN, 0.013])
def test_wrists_at_huge_and_non_finite_coordinates_are_kept_out_as_numpy_keeps_them(name, margin):
    """:func:`motor.body.collision.kept_out_of_torso` skips the points that cannot move
    (:func:`motor.body.torso_push.reachable`): at the box's edges and at huge and
    non-finite coordinates, what it gives is numpy's."""
    avatar = load_avatar(name)
    torso = avatar.torso
    count = 600
    reach = np.array([torso.half_width + margin + SOFT_BAND, 0.0, torso.half_depth + margin + SOFT_BAND])
    points = np.array([torso.center[0], 0.0, torso.center[2]]) + RNG.choice([-1.0, 1.0], (count, 3)) * reach * RNG.uniform(0.98, 1.02, (count, 3))
    points[:, 1] = np.where(RNG.random(count) < 0.5, torso.top, torso.bottom) + RNG.uniform(-1.02, 1.02, count) * EDGE_BAND
    points[::9] *= 1e6
    points[1::9, 2] = -1e300
    points[2::9, 0] = 1e300
    points[3::9, 1] = np.nan
    points[4::9, 2] = np.inf
    points[5::9, 0] = -np.inf
    with np.errstate(invalid="ignore", over="ignore"):
        expected = plain.kept_out_of_torso(avatar, points, margin)
    assert _same(kept_out_of_torso(avatar, points, margin), expected)
