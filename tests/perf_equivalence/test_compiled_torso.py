"""The compiled torso push (:func:`motor.body.collision.kept_out_of_torso`) is the numpy one
(``plain_collision.py``) bit for bit: points all round the torso, inside, in front, behind,
in the soft band, across its top and bottom edge bands, at both margins and on both
avatars, with non-finite rows; and a point it leaves alone is the caller's own array."""

from __future__ import annotations

import numpy as np
import pytest

from motor.body.avatar import load_avatar
from motor.body.collision import EDGE_BAND, SOFT_BAND, TORSO_MARGIN, kept_out_of_torso
from tests.perf_equivalence import plain_collision as plain

RNG = np.random.default_rng(47)


def _points(avatar, kind: str, count: int = 400) -> np.ndarray:
    torso = avatar.torso
    reach = np.array([torso.half_width, 0.0, torso.half_depth]) + TORSO_MARGIN + SOFT_BAND
    middle = np.array([torso.center[0], 0.5 * (torso.bottom + torso.top), torso.center[2]])
    spread = RNG.uniform(-1.6, 1.6, (count, 3)) * reach
    spread[:, 1] = RNG.uniform(torso.bottom - 2.0 * EDGE_BAND, torso.top + 2.0 * EDGE_BAND, count) - middle[1]
    points = middle + spread
    if kind == "band":  # on rays just outside the grown ellipse: the soft band
        angle = RNG.uniform(0.0, np.pi, count)
        grow = TORSO_MARGIN + RNG.uniform(-0.002, SOFT_BAND + 0.004, count)
        points[:, 0] = torso.center[0] + (torso.half_width + grow) * np.cos(angle)
        points[:, 2] = torso.center[2] + (torso.half_depth + grow) * np.sin(angle)
    if kind == "edges":  # heights in the bands over the top and under the bottom
        points[:, 1] = np.where(RNG.random(count) < 0.5, torso.top, torso.bottom) + RNG.uniform(-EDGE_BAND, EDGE_BAND, count) * 1.2
    if kind == "non-finite":
        points[::7, 0] = np.nan
        points[3::11, 2] = np.inf
        points[5::13, 1] = -np.inf
    return points


@pytest.mark.parametrize("name", ["max", "kim"])
@pytest.mark.parametrize("kind", ["around", "band", "edges", "non-finite"])
@pytest.mark.parametrize("margin", [TORSO_MARGIN, 0.013])
def test_the_compiled_push_is_numpy_s_bit_for_bit(name, kind, margin):
    avatar = load_avatar(name)
    points = _points(avatar, kind)
    got = kept_out_of_torso(avatar, points, margin)
    with np.errstate(invalid="ignore"):
        expected = plain.kept_out_of_torso(avatar, points, margin)
    assert np.array_equal(got, expected, equal_nan=True)
    assert np.array_equal(np.signbit(got), np.signbit(expected))


@pytest.mark.parametrize("count", [0, 1, 5])
def test_points_left_alone_come_back_as_given(count):
    """Far from the torso nothing moves: the very array given (as before), not a copy;
    an empty array too."""
    avatar = load_avatar("max")
    far = np.tile([[2.0, 5.0, 3.0]], (count, 1))
    assert kept_out_of_torso(avatar, far) is far


def test_a_strided_view_is_measured_as_its_copy():
    """A column slice of a wider array (what the motor control passes) gives what its
    contiguous copy gives."""
    avatar = load_avatar("max")
    wide = np.concatenate([_points(avatar, "band"), RNG.random((400, 4))], axis=1)
    view = wide[:, :3]
    assert np.array_equal(kept_out_of_torso(avatar, view), plain.kept_out_of_torso(avatar, np.ascontiguousarray(view)))
