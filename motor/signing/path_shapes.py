"""The shapes of a sign's movement paths (seed 000, section 4.3): straight lines, arcs,
wavy and zigzag lines, and circles, ellipses and arcs of them between clock positions.

Each shape is a polyline of wrist positions ``(k, 3)`` (avatar frame, metres) from where
the hand is; the sign compiler (:mod:`motor.signing.sign_compiler`) times it. Sizes are fractions
of the arm's length, so a sign keeps its proportions on any avatar.
"""

from __future__ import annotations

import numpy as np

from motor import quaternion as quat
from motor.trajectory.guiding_strokes import (
    curve_breakpoints,
    default_normal,
    ellipse_breakpoints,
    wavy,
    zigzag,
)
from mura.constraints import Segment
from mura.values import AXES

#: Length of a straight movement by HamNoSys size, fractions of the arm's length.
SIZE_FRACTIONS: dict[str, float] = {"small": 0.12, "normal": 0.25, "large": 0.4}
#: Radius of a circle by size, fractions of the arm's length; stirring is "small".
CIRCLE_FRACTIONS: dict[str, float] = {"small": 0.05, "normal": 0.09, "large": 0.15}
#: Bulge of an arc over its chord; amplitude of wavy and zigzag paths over their length.
ARC_EXTENT = 0.3
WAVE_AMPLITUDE = 0.12
WAVES = 2
ZIGS = 4
#: Points of a straight path and of a circle.
PATH_POINTS = 8
CIRCLE_POINTS = 32
#: Minor over major semi-axis of an ellipse.
ELLIPSE_RATIO = 0.55
_SAMPLES = np.arange(PATH_POINTS, dtype=float).reshape(-1, 1)
_FRACTIONS = _SAMPLES / (PATH_POINTS - 1)


def line(start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """``np.linspace(start, end, PATH_POINTS)`` for points ``(3,)``, with numpy's
    arithmetic (its step, its care for zero steps, the end placed exactly) and without its
    overhead: a collection of signs draws thousands of straight paths."""
    delta = end - start
    step = delta / (PATH_POINTS - 1)
    points = _FRACTIONS * delta if 0.0 in step.tolist() else _SAMPLES * step
    points += start
    points[-1] = end
    return points


def curve(start: np.ndarray, end: np.ndarray, segment: Segment) -> tuple[np.ndarray, str | None]:
    """A wavy, zigzag or arc path from ``start`` to ``end``, and a note when the arc's
    named side lies along its own chord (it then bulges in the default plane)."""
    chord = end - start
    normal = None if segment.normal is None else np.asarray(segment.normal.vector, dtype=float)
    if segment.shape == "wavy":
        return wavy(start, end, WAVE_AMPLITUDE * quat.length(chord), WAVES, normal), None
    if segment.shape == "zigzag":
        return zigzag(start, end, WAVE_AMPLITUDE * quat.length(chord), ZIGS, normal), None
    letter = (segment.shape or "arcu").removeprefix("arc")
    bulge = np.asarray(AXES.get(letter, AXES["u"]), dtype=float)
    across = bulge - (bulge @ chord) / (chord @ chord) * chord
    note = None
    if quat.length(across) < 1e-6:
        note = f"arc {segment.shape!r} bulges along its own chord; bulging in the default plane"
        plane = default_normal(chord)
    else:
        plane = quat.cross(chord, across)  # LeftC bulges toward plane × chord = across
    return curve_breakpoints(start, end, plane, "LeftC", ARC_EXTENT).points, note


def circle(start: np.ndarray, segment: Segment, arm_length: float) -> np.ndarray:
    """A circle (or ellipse, or arc between clock positions) starting at ``start``, sized
    by ``arm_length`` (m)."""
    stirring = segment.shape in ("stircw", "stirccw")
    if segment.normal is not None:
        axis = unit(segment.normal.vector)
    else:
        axis = np.array([0.0, -1.0 if segment.shape == "stircw" else 1.0, 0.0]) if stirring else np.array([0.0, 0.0, 1.0])
    size = "small" if stirring else (segment.size if segment.size in CIRCLE_FRACTIONS else "normal")
    radius = CIRCLE_FRACTIONS[size] * arm_length
    modifiers = dict(m.split("=", 1) for m in segment.modifiers if "=" in m)
    e1, e2 = circle_axes(axis)
    begin = clock_angle(modifiers.get("start"), axis, e1, e2, default=np.pi)
    sweep = 2.0 * np.pi
    if modifiers.get("end") not in (None, "full"):
        finish = clock_angle(modifiers["end"], axis, e1, e2, default=begin)
        sweep = (finish - begin) % (2.0 * np.pi) or 2.0 * np.pi
    ellipse = modifiers.get("ellipse")
    semi = (radius, radius * ELLIPSE_RATIO) if ellipse else (radius, radius)
    major = {"h": AXES["l"], "v": AXES["u"], "ur": (-0.7071, 0.7071, 0.0), "ul": (0.7071, 0.7071, 0.0)}.get(ellipse or "", e1)
    points = ellipse_breakpoints(np.zeros(3), semi, axis, e1 if ellipse is None else major, begin, sweep, CIRCLE_POINTS)
    return points - points[0] + start


def unit(vector: tuple[float, ...] | np.ndarray) -> np.ndarray:
    """``vector`` of length 1; ValueError for a zero vector."""
    v = np.asarray(vector, dtype=float)
    norm = quat.length(v)
    if norm < 1e-9:
        raise ValueError("direction of zero length")
    return v / norm


def circle_axes(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """In-plane axes: up (forward for a vertical axis) projected, and axis × e1."""
    up, forward = np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0])
    reference = up if abs(axis @ up) <= abs(axis @ forward) else forward
    e1 = reference - (reference @ axis) * axis
    e1 /= quat.length(e1)
    return e1, quat.cross(axis, e1)


def clock_angle(letters: str | None, axis: np.ndarray, e1: np.ndarray, e2: np.ndarray, default: float) -> float:
    """Angle on the circle of a clock position (direction letters from the centre)."""
    if not letters or any(letter not in AXES for letter in letters):
        return default
    direction = np.sum([AXES[letter] for letter in letters], axis=0)
    direction = direction - (direction @ axis) * axis
    if quat.length(direction) < 1e-9:
        return default
    # the hand starts at that clock position: the angle of the point from the centre
    return float(np.arctan2(direction @ e2, direction @ e1))
