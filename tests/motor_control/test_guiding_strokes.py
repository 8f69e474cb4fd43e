"""Guiding strokes of curves, circles, ellipses, wavy/zigzag paths and repetitions."""

from __future__ import annotations

import numpy as np
import pytest

from motor.trajectory.guiding_strokes import (
    circle_breakpoints,
    circle_from_start,
    curve_breakpoints,
    ellipse_breakpoints,
    repeat_strokes,
    wavy,
    zigzag,
)

START = np.array([0.0, 1.0, 0.3])
END = np.array([-0.4, 1.0, 0.3])  # a rightward chord, 0.4 m
FACING = np.array([0.0, 0.0, 1.0])


def _offsets(points: np.ndarray, side: np.ndarray) -> np.ndarray:
    return (points - START) @ side


@pytest.mark.parametrize(("shape", "sign"), [("LeftC", 1.0), ("RightC", -1.0)])
def test_c_curves_bulge_to_their_side(shape: str, sign: float) -> None:
    curve = curve_breakpoints(START, END, FACING, shape, extent=0.25)
    left = np.cross(FACING, (END - START) / 0.4)
    offsets = _offsets(curve.points, left)
    np.testing.assert_allclose(curve.points[[0, -1]], [START, END])
    assert np.all(sign * offsets >= -1e-12)
    assert np.max(np.abs(offsets)) == pytest.approx(0.25 * 0.4)
    assert curve.warnings == ()


def test_round_c_curve_with_extent_half_is_a_half_circle() -> None:
    curve = curve_breakpoints(START, END, FACING, "LeftC")
    radii = np.linalg.norm(curve.points - 0.5 * (START + END), axis=1)
    np.testing.assert_allclose(radii, 0.2, atol=1e-12)
    assert curve.points.shape[0] == 7


@pytest.mark.parametrize(("roundness", "count"), [(-1.0, 3), (0.0, 7), (1.0, 11)])
def test_roundness_sets_the_number_of_guiding_strokes(roundness: float, count: int) -> None:
    assert curve_breakpoints(START, END, FACING, "LeftC", 0.3, roundness).points.shape[0] == count


def test_sharp_curve_is_a_triangle_and_broad_curve_is_fuller() -> None:
    left = np.cross(FACING, (END - START) / 0.4)
    sharp = curve_breakpoints(START, END, FACING, "LeftC", 0.3, -1.0).points
    np.testing.assert_allclose(sharp[1], 0.5 * (START + END) + 0.12 * left)

    def height_at_quarter(points: np.ndarray) -> float:
        along = (points - START) @ ((END - START) / 0.4)
        return float(np.interp(0.1, along, _offsets(points, left)))
    heights = [height_at_quarter(curve_breakpoints(START, END, FACING, "LeftC", 0.3, r).points) for r in (-1.0, 0.0, 1.0)]
    assert heights[0] < heights[1] < heights[2]


@pytest.mark.parametrize(("skew", "apex"), [(-1.0, 0.1), (0.0, 0.5), (0.5, 0.7), (1.0, 0.9)])
def test_skewedness_moves_the_apex(skew: float, apex: float) -> None:
    points = curve_breakpoints(START, END, FACING, "RightC", 0.3, 0.0, skew).points
    left = np.cross(FACING, (END - START) / 0.4)
    top = np.argmin(_offsets(points, left))
    along = (points[top] - START) @ ((END - START) / 0.4) / 0.4
    assert along == pytest.approx(apex)


@pytest.mark.parametrize(("shape", "first_sign"), [("LeftS", 1.0), ("RightS", -1.0)])
def test_s_curves_bulge_both_ways(shape: str, first_sign: float) -> None:
    points = curve_breakpoints(START, END, FACING, shape, 0.5).points
    left = np.cross(FACING, (END - START) / 0.4)
    offsets = _offsets(points, left)
    half = points.shape[0] // 2
    assert first_sign * offsets[1:half].min() > 0 and first_sign * offsets[half + 1 : -1].max() < 0
    assert np.max(np.abs(offsets)) == pytest.approx(0.5 * 0.5 * 0.4)
    np.testing.assert_allclose(points[half], 0.5 * (START + END), atol=1e-12)


def test_curve_without_normal_bulges_up_and_warns() -> None:
    curve = curve_breakpoints(START, END)
    assert len(curve.warnings) == 1 and "no normal" in curve.warnings[0]
    assert np.max(curve.points[:, 1]) == pytest.approx(1.2)
    vertical = curve_breakpoints(START, START + np.array([0.0, 0.3, 0.0]))
    assert np.max(vertical.points[:, 2]) == pytest.approx(0.3 + 0.15)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"end": START}, "chord"),
        ({"normal": (0.0, 0.0, 0.0)}, "curve normal has zero length"),
        ({"normal": (1.0, 0.0, 0.0)}, "parallel to the chord"),
        ({"shape": "Spiral"}, "shape"),
        ({"roundness": 1.5}, "roundness"),
        ({"skewedness": -2.0}, "skewedness"),
        ({"extent": -0.1}, "extent"),
    ],
)
def test_bad_curves_are_named(kwargs: dict, message: str) -> None:
    arguments = {"start": START, "end": END, "normal": FACING} | kwargs
    with pytest.raises(ValueError, match=message):
        curve_breakpoints(**arguments)


def test_circle_breakpoints_lie_on_the_circle_counterclockwise() -> None:
    center = np.array([0.1, 1.1, 0.35])
    points = circle_breakpoints(center, 0.08, FACING, count=12)
    assert points.shape == (13, 3)
    np.testing.assert_allclose(np.linalg.norm(points - center, axis=1), 0.08)
    np.testing.assert_allclose(points[0], points[-1], atol=1e-12)
    np.testing.assert_allclose(points[0], center + [0.0, 0.08, 0.0])
    turns = np.cross(points[:-1] - center, points[1:] - center) @ FACING
    assert np.all(turns > 0)


def test_circle_from_start_begins_at_the_start() -> None:
    points = circle_from_start(START, (0.0, 0.0, -1.0), 0.05, count=8)
    np.testing.assert_allclose(points[0], START)
    center = START + np.array([0.0, 0.05, 0.0])
    np.testing.assert_allclose(np.linalg.norm(points - center, axis=1), 0.05, atol=1e-12)


def test_ellipse_breakpoints_satisfy_the_ellipse_equation() -> None:
    center = np.array([0.0, 1.2, 0.3])
    points = ellipse_breakpoints(center, (0.1, 0.04), FACING, major_axis=(1.0, 0.0, 0.0), count=20)
    x, y = (points - center)[:, 0], (points - center)[:, 1]
    np.testing.assert_allclose((x / 0.1) ** 2 + (y / 0.04) ** 2, 1.0)
    with pytest.raises(ValueError, match="ellipse normal has zero length"):
        ellipse_breakpoints(center, (0.1, 0.04), (0.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="semi-axes"):
        ellipse_breakpoints(center, (0.1, 0.0), FACING)


def test_wavy_path_oscillates_about_the_line() -> None:
    points = wavy(START, END, 0.02, 3, FACING)
    np.testing.assert_allclose(points[[0, -1]], [START, END], atol=1e-12)
    left = np.cross(FACING, (END - START) / 0.4)
    assert np.max(np.abs(_offsets(points, left))) == pytest.approx(0.02)
    assert points.shape[0] == 3 * 8 + 1


def test_zigzag_has_alternating_sharp_teeth() -> None:
    points = zigzag(START, END, 0.03, 4, FACING)
    left = np.cross(FACING, (END - START) / 0.4)
    np.testing.assert_allclose(_offsets(points, left), [0.0, 0.03, -0.03, 0.03, -0.03, 0.0], atol=1e-12)
    with pytest.raises(ValueError, match="path from start to end has zero length"):
        zigzag(START, START, 0.03, 4)


@pytest.mark.parametrize(
    ("points", "count", "back_and_forth", "expected"),
    [
        (np.array([[0.0, 0, 0], [1.0, 0, 0]]), 3, True, [0, 1, 0, 1]),
        (np.array([[0.0, 0, 0], [1.0, 0, 0]]), 2, False, [0, 1, 0, 1]),
        (np.array([[0.0, 0, 0], [1.0, 0, 0], [0.0, 0, 0]]), 2, False, [0, 1, 0, 1, 0]),
        (np.array([[0.0, 0, 0], [1.0, 0, 0], [2.0, 0, 0]]), 2, True, [0, 1, 2, 1, 0]),
    ],
)
def test_repeat_strokes_table(points: np.ndarray, count: int, back_and_forth: bool, expected: list[float]) -> None:
    np.testing.assert_allclose(repeat_strokes(points, count, back_and_forth)[:, 0], expected)
