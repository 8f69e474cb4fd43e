"""Signed distances and capsule depths against brute force and closed forms."""

import numpy as np
import pytest
from scipy.optimize import minimize

from bench.motion_audit.distance import Capsule, Ellipsoid, EllipticCylinder, capsule_depth, ellipsoid_surface_distance, signed_distance


def surface_point(angles: np.ndarray, radii: np.ndarray) -> np.ndarray:
    if radii.size == 2:
        return radii * np.stack((np.cos(angles[..., 0]), np.sin(angles[..., 0])), axis=-1)
    polar, azimuth = angles[..., 0], angles[..., 1]
    return radii * np.stack((np.sin(polar) * np.cos(azimuth), np.sin(polar) * np.sin(azimuth), np.cos(polar)), axis=-1)


def brute_force(points: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """Signed distance to an ellipse (2-D) or ellipsoid (3-D): the nearest of a grid of
    surface points, then polished by a local minimizer over the surface's angles."""
    axes = [np.linspace(0, 2 * np.pi, 3600, endpoint=False)] if radii.size == 2 else [np.linspace(0, np.pi, 181), np.linspace(0, 2 * np.pi, 360, endpoint=False)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, radii.size - 1)
    surface = surface_point(grid, radii)
    distances = []
    for point in points:
        start = grid[np.argmin(np.linalg.norm(surface - point, axis=1))]
        best = minimize(lambda angles: np.linalg.norm(surface_point(angles, radii) - point), start, method="Nelder-Mead", options={"xatol": 1e-10, "fatol": 1e-12})
        distances.append(best.fun)
    inside = np.sum((points / radii) ** 2, axis=1) < 1.0
    return np.where(inside, -np.array(distances), distances)


@pytest.mark.parametrize("radii", [(0.14, 0.11), (0.11, 0.14), (0.2, 0.05), (0.1, 0.1)])
def test_ellipse_distance_matches_brute_force(radii):
    radii = np.array(radii)
    rng = np.random.default_rng(3)
    points = np.concatenate((rng.uniform(-0.3, 0.3, (40, 2)), [[0.0, 0.0], [0.05, 0.0], [0.0, 0.02], [-0.3, 0.0], [0.0, -0.25]]))
    np.testing.assert_allclose(ellipsoid_surface_distance(points, radii), brute_force(points, radii), atol=2e-6)


@pytest.mark.parametrize("radii", [(0.09, 0.12, 0.1), (0.05, 0.05, 0.15), (0.1, 0.1, 0.1)])
def test_ellipsoid_distance_matches_brute_force(radii):
    radii = np.array(radii)
    rng = np.random.default_rng(4)
    points = np.concatenate((rng.uniform(-0.2, 0.2, (12, 3)), [[0.0, 0.0, 0.01], [0.02, 0.0, 0.0], [0.0, 0.3, 0.0]]))
    np.testing.assert_allclose(ellipsoid_surface_distance(points, radii), brute_force(points, radii), atol=2e-6)


CYLINDER = EllipticCylinder(np.array([0.0, 0.0, 0.0]), 0.1, 0.1, 0.0, 0.5)
CYLINDER_CASES = [
    ((0.0, 0.25, 0.0), -0.1),  # on the axis, half way: 0.1 from the side
    ((0.05, 0.25, 0.0), -0.05),
    ((0.0, 0.02, 0.0), -0.02),  # near the bottom cap
    ((0.3, 0.25, 0.0), 0.2),  # beside it
    ((0.0, 0.8, 0.0), 0.3),  # above it
    ((0.13, 0.54, 0.0), 0.05),  # beyond the rim: 0.03 out and 0.04 up
]


@pytest.mark.parametrize("point, expected", CYLINDER_CASES)
def test_elliptic_cylinder_distance_in_closed_form(point, expected):
    assert signed_distance(CYLINDER, np.array([point]))[0] == pytest.approx(expected, abs=1e-6)


DEPTH_CASES = [
    # (what, shape, axis start, axis end, radius, expected depth)
    ("through the middle of a cylinder", CYLINDER, (-0.3, 0.25, 0.0), (0.3, 0.25, 0.0), 0.03, 0.13),
    ("grazing a cylinder's side", CYLINDER, (0.12, 0.1, 0.0), (0.12, 0.4, 0.0), 0.03, 0.01),
    ("clear of a cylinder", CYLINDER, (0.2, 0.1, 0.0), (0.2, 0.4, 0.0), 0.03, -0.07),
    ("end inside a sphere", Ellipsoid(np.zeros(3), np.array([0.1, 0.1, 0.1])), (0.05, 0.0, 0.0), (0.5, 0.0, 0.0), 0.02, 0.07),
    ("crossing a capsule", Capsule(np.array([0.0, 0.0, -0.2]), np.array([0.0, 0.0, 0.2]), 0.025), (-0.2, 0.03, 0.0), (0.2, 0.03, 0.0), 0.025, 0.02),
    ("two hands on one point", Capsule(np.array([0.0, 0.0, 0.0]), np.array([0.0, -0.1, 0.0]), 0.0125), (0.0, 0.0, 0.0), (0.0, -0.1, 0.0), 0.0125, 0.025),
]


@pytest.mark.parametrize("what, shape, start, end, radius, expected", DEPTH_CASES, ids=[case[0] for case in DEPTH_CASES])
def test_capsule_depth_in_closed_form(what, shape, start, end, radius, expected):
    depth, _ = capsule_depth(np.array([start]), np.array([end]), radius, shape)
    assert depth[0] == pytest.approx(expected, abs=1e-6)


def test_capsule_depth_is_the_deepest_point_of_the_axis():
    rng = np.random.default_rng(5)
    shape = EllipticCylinder(np.array([0.0, 0.0, 0.005]), 0.14, 0.11, -0.05, 0.51)
    start, end = rng.uniform(-0.3, 0.3, (20, 3)), rng.uniform(-0.3, 0.3, (20, 3))
    depth, deepest = capsule_depth(start, end, 0.03, shape)
    fractions = np.linspace(0.0, 1.0, 20001)  # about 25 µm apart: the sampled maximum is that close
    sampled = np.array([np.max(0.03 - signed_distance(shape, a + fractions[:, None] * (b - a))) for a, b in zip(start, end)])
    assert np.all(depth >= sampled - 1e-9)
    np.testing.assert_allclose(depth, sampled, atol=3e-5)
    np.testing.assert_allclose(0.03 - signed_distance(shape, deepest), depth, atol=1e-12)
