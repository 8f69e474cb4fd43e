"""Mirror symmetry of points, directions and rotations."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from motor.trajectory.spline import plan_wrist_trajectory
from motor.trajectory.symmetry import (
    mirror_directions,
    mirror_points,
    mirror_quaternions,
    mirror_trajectory,
    reflection_signs,
)
from mura.constraints import Symmetry


def sym(planes: str) -> Symmetry:
    return Symmetry(frozenset(planes), "SymM" + planes)


CENTER = np.array([0.0, 1.2, 0.3])
POINT = np.array([0.2, 1.0, 0.5])


@pytest.mark.parametrize(
    ("planes", "expected"),
    [
        ("S", [-0.2, 1.0, 0.5]),
        ("T", [0.2, 1.4, 0.5]),
        ("F", [0.2, 1.0, 0.1]),
        ("ST", [-0.2, 1.4, 0.5]),
        ("SF", [-0.2, 1.0, 0.1]),
        ("STF", [-0.2, 1.4, 0.1]),
    ],
)
def test_mirror_points_table(planes: str, expected: list[float]) -> None:
    np.testing.assert_allclose(mirror_points(POINT, sym(planes), CENTER), expected)
    np.testing.assert_allclose(mirror_points(mirror_points(POINT, sym(planes), CENTER), sym(planes), CENTER), POINT)


def test_mirror_points_and_directions_are_vectorized() -> None:
    points = np.arange(24.0).reshape(2, 4, 3)
    assert mirror_points(points, sym("S")).shape == (2, 4, 3)
    np.testing.assert_allclose(mirror_directions(np.array([[1.0, 2.0, 3.0]]), sym("SF")), [[-1.0, 2.0, -3.0]])


@pytest.mark.parametrize("planes", ["S", "T", "F", "ST", "SF", "TF", "STF"])
def test_mirror_quaternions_equal_m_r_m(planes: str) -> None:
    rotations = Rotation.random(50, random_state=7)
    m = np.diag(reflection_signs(sym(planes)))
    expected = m @ rotations.as_matrix() @ m
    mirrored = Rotation.from_quat(mirror_quaternions(rotations.as_quat(), sym(planes)))
    np.testing.assert_allclose(mirrored.as_matrix(), expected, atol=1e-12)


def test_sagittal_mirror_of_a_left_turn_is_a_right_turn() -> None:
    turn_left = Rotation.from_rotvec([0.0, 0.5, 0.0]).as_quat()
    np.testing.assert_allclose(Rotation.from_quat(mirror_quaternions(turn_left, sym("S"))).as_rotvec(), [0.0, -0.5, 0.0])


def test_bad_input_is_named() -> None:
    with pytest.raises(ValueError, match="unknown mirror plane 'X'"):
        mirror_points(POINT, sym("X"))
    with pytest.raises(ValueError, match="mirror_quaternions"):
        mirror_quaternions(np.zeros((3, 3)), sym("S"))


@pytest.mark.parametrize("planes", ["S", "ST", "STF"])
def test_mirrored_trajectory_is_the_reflected_curve(planes: str) -> None:
    points = np.array([[0.0, 1.0, 0.3], [0.2, 1.1, 0.4], [0.1, 1.3, 0.35]])
    trajectory = plan_wrist_trajectory(points, np.array([0.0, 0.3, 0.7]))
    mirrored = mirror_trajectory(trajectory, sym(planes), CENTER)
    t = np.linspace(-0.1, 0.8, 91)
    np.testing.assert_allclose(mirrored.position(t), mirror_points(trajectory.position(t), sym(planes), CENTER), atol=1e-12)
