"""The compiled signed distances (:mod:`motor.body.distance`) give the numbers of their
numpy definitions (``plain_distance.py``) bit for bit, over tables of segment families
that reach every branch: segments crossing a volume, lying on its axis or through its
centre, level (a horizontal segment against a vertical cylinder), degenerate (points),
above and below a cylinder's ends, and broadcast shapes as the swivel search passes them
(``(n, K)`` candidates against ``(n, 1)`` fixed ends)."""

from __future__ import annotations

import numpy as np
import pytest

from motor.body import distance
from motor.body.avatar import load_avatar
from motor.body.volumes import Capsule, Ellipsoid, EllipticCylinder
from tests.perf_equivalence import plain_distance as plain

RNG = np.random.default_rng(19)
N, K = 64, 24


def _family(kind: str, center: np.ndarray, spread: float) -> tuple[np.ndarray, np.ndarray]:
    """End points ``(N, K, 3)`` of a family of segments about ``center``."""
    a = center + RNG.normal(0.0, spread, (N, K, 3))
    b = center + RNG.normal(0.0, spread, (N, K, 3))
    if kind == "level":
        b[..., 1] = a[..., 1]
    elif kind == "points":
        b = a.copy()
    elif kind == "on axis":
        a[..., [0, 2]] = center[[0, 2]]
        b[..., [0, 2]] = center[[0, 2]]
    elif kind == "through centre":
        b = 2.0 * center - a
    elif kind == "above and below":
        a[..., 1] = center[1] + np.abs(a[..., 1] - center[1]) + 3.0 * spread
        b[..., 1] = center[1] - np.abs(b[..., 1] - center[1]) - 3.0 * spread
    elif kind == "far":
        a, b = a + 10.0 * spread, b + 10.0 * spread
    return a, b


KINDS = ("scattered", "level", "points", "on axis", "through centre", "above and below", "far")
VOLUMES = (
    EllipticCylinder("torso", "vl5", np.array([0.0, 1.2, 0.01]), 0.16, 0.11, 0.95, 1.45),
    EllipticCylinder("round", "vl5", np.array([0.02, 1.0, 0.0]), 0.12, 0.12, 0.9, 1.1),
    Ellipsoid("head", "head", np.array([0.0, 1.62, 0.02]), np.array([0.08, 0.11, 0.1])),
    Ellipsoid("ball", "head", np.array([0.0, 1.62, 0.02]), np.array([0.1, 0.1, 0.1])),
    Capsule("neck", "neck", np.array([0.0, 1.45, 0.0]), np.array([0.0, 1.56, 0.01]), 0.05),
    Capsule("dot", "neck", np.array([0.0, 1.45, 0.0]), np.array([0.0, 1.45, 0.0]), 0.05),
)


def _center(volume) -> np.ndarray:
    if isinstance(volume, Capsule):
        return 0.5 * (volume.a + volume.b)
    if isinstance(volume, EllipticCylinder):
        return np.array([volume.center[0], 0.5 * (volume.bottom + volume.top), volume.center[2]])
    return volume.center


@pytest.mark.parametrize("volume", VOLUMES, ids=lambda v: v.name)
@pytest.mark.parametrize("kind", KINDS)
def test_capsule_distances_are_the_numpy_ones_bit_for_bit(volume, kind):
    a, b = _family(kind, _center(volume), 0.15)
    for radius in (0.04, RNG.uniform(0.0, 0.05, (N, 1))):
        expected = plain.capsule_distance(volume, a, b, radius)
        got = distance.capsule_distance(volume, a, b, radius)
        assert got.shape == expected.shape
        assert np.array_equal(got, expected), np.nanmax(np.abs(got - expected))


@pytest.mark.parametrize("avatar_name", ["max", "kim"])
def test_the_avatars_volumes_against_swivel_shaped_arms(avatar_name):
    """Coordinate arrays as the swivel search passes them: candidate ends ``(n, K)``
    against fixed ends ``(n, 1)``, against every body volume of the avatar."""
    avatar = load_avatar(avatar_name)
    shoulder = avatar.rest_positions[avatar.joint_index("r_shoulder")]
    fixed = tuple(shoulder[i] + RNG.normal(0.0, 0.05, (N, 1)) for i in range(3))
    moving = tuple(shoulder[i] + RNG.normal(0.0, 0.25, (N, K)) for i in range(3))
    checked = 0
    for volume in avatar.collision.body(frozenset()):
        expected = plain.capsule_apart(volume, fixed, moving, 0.04)
        got = distance.capsule_apart(volume, fixed, moving, 0.04)
        assert np.array_equal(got, expected), volume.name
        checked += 1
    assert checked >= 4


@pytest.mark.parametrize("kind", KINDS)
def test_segment_distances_and_closest_points_are_the_numpy_ones(kind):
    p0, p1 = _family(kind, np.zeros(3), 0.2)
    q0, q1 = _family("scattered" if kind == "far" else kind, np.zeros(3), 0.2)
    for got, expected in (
        (distance.closest_parameters(p0, p1, q0, q1), plain.closest_parameters(p0, p1, q0, q1)),
        ((distance.segment_distance(p0, p1, q0, q1),), (plain.segment_distance(p0, p1, q0, q1),)),
        ((distance.point_segment_distance(p0, q0, q1),), (plain.point_segment_distance(p0, q0, q1),)),
    ):
        for value, reference in zip(got, expected, strict=True):
            assert np.array_equal(value, reference)


def test_parallel_and_crossing_segments_meet_their_known_distances():
    """Independent of the numpy definitions: distances a drawing gives."""
    x = np.array([1.0, 0.0, 0.0])
    assert distance.segment_distance(np.zeros(3), x, np.array([0.0, 0.3, 0.0]), np.array([1.0, 0.3, 0.0])) == pytest.approx(0.3)
    assert distance.segment_distance(-x, x, np.array([0.0, -1.0, 0.2]), np.array([0.0, 1.0, 0.2])) == pytest.approx(0.2)
    cylinder = VOLUMES[1]
    side = np.array([0.02 + 0.3, 1.0, 0.0])
    assert distance.capsule_distance(cylinder, side, side + [0.0, 0.05, 0.0], 0.01) == pytest.approx(0.3 - 0.12 - 0.01)
    above = np.array([0.02, 1.3, 0.0])
    assert distance.capsule_distance(cylinder, above, above + [0.0, 0.1, 0.0], 0.0) == pytest.approx(0.2)
