"""Guiding strokes: the breakpoints that approximate a movement segment (seed 004, 4.1).

A movement phase is a polyline of breakpoints; the wrist trajectory (``motor.trajectory.spline``)
later bends it into a smooth curve. This module turns the segment descriptions of MURML
and HamNoSys into breakpoints: curves with a normal, shape, extent, roundness and
skewedness; circles and ellipses; wavy and zigzag modulation of a straight path; and
repetition of a stroke sequence. Positions are metres, in the avatar frame (y up, +z
forward, +x the avatar's left).

Conventions (chosen here, documented because MURML leaves them open):

* **Side of a bulge.** ``LeftC`` bulges towards ``n × ĉ`` (ĉ the unit chord, n the unit
  normal): the arc turns counterclockwise about the normal, i.e. it lies to the left of
  the chord when the normal points at the viewer. ``RightC`` bulges the other way.
  ``LeftS``/``RightS`` split the chord in two halves bulging to opposite sides, the first
  half to the named side.
* **No normal.** The plane then contains the chord and whichever of up (+y) and forward
  (+z) is most perpendicular to it, oriented so that ``LeftC`` bulges up (forward for a
  vertical chord); a warning records the choice.
* **Extent** is the bulge height over the chord length (default 0.5: with roundness 0
  and no skew a ``LeftC`` is then exactly a half circle). For S-curves each half bulges
  by ``extent`` times its own half chord.
* **Roundness** r ∈ [-1, 1] sets the profile of each bulge side as the superellipse
  quadrant ``(1 − σ)^q + b^q = 1`` with ``q = 2^(1 + r)``: r = -1 gives straight flanks
  meeting in a sharp apex (q = 1), r = 0 a circular/elliptic arc (q = 2), r = 1 a broad,
  box-like arc (q = 4). It also sets how many guiding strokes approximate each flank:
  ``1 + round(2 (1 + r))`` (1 for a sharp curve, 3 round, 5 broad).
* **Skewedness** s ∈ [-1, 1] moves the apex along the chord to the fraction
  ``0.5 + 0.4 s`` (towards the start for s < 0, towards the end for s > 0).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from motor import quaternion as quat

UP = np.array([0.0, 1.0, 0.0])
FORWARD = np.array([0.0, 0.0, 1.0])
CURVE_SHAPES: tuple[str, ...] = ("LeftC", "RightC", "LeftS", "RightS")
_EPS = 1e-9


@dataclass(frozen=True, eq=False)
class GuidingStrokes:
    """Breakpoints approximating a segment, and what was assumed to make them.

    Attributes:
        points: ``(n, 3)`` breakpoints, metres, the first at the segment's start.
        warnings: defaults that were chosen because the spec left something open.
    """

    points: np.ndarray
    warnings: tuple[str, ...] = ()


def unit(vector: np.ndarray | tuple[float, ...], name: str) -> np.ndarray:
    """``vector`` scaled to length 1; ValueError naming ``name`` if it has no length."""
    v = np.asarray(vector, dtype=float)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name}: expected a finite 3-vector, got {vector!r}")
    norm = quat.length(v)
    if norm < _EPS:
        raise ValueError(f"{name} has zero length")
    return v / norm


def default_normal(chord: np.ndarray) -> np.ndarray:
    """The normal of the plane through ``chord`` and the more perpendicular of up/forward.

    Oriented so that ``n × ĉ`` (the ``LeftC`` side) points up, or forward for a vertical
    chord.
    """
    c = unit(chord, "curve chord")
    side = UP if abs(float(c @ UP)) <= abs(float(c @ FORWARD)) else FORWARD
    return unit(quat.cross(c, side), "curve normal (chord parallel to both up and forward)")


def _in_plane_frame(chord: np.ndarray, normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit chord ĉ and the left side ``n × ĉ`` (normal projected perpendicular to ĉ)."""
    c = chord / quat.length(chord)
    n = normal - (normal @ c) * c
    norm = quat.length(n)
    if norm < 1e-6:
        raise ValueError("curve normal is parallel to the chord from start to end")
    n /= norm
    return c, quat.cross(n, c)


def _bulge_profile(roundness: float, skewedness: float) -> tuple[np.ndarray, np.ndarray]:
    """Chord fractions and unit bulge heights of one C-shaped bulge, apex height 1."""
    q = 2.0 ** (1.0 + roundness)
    per_flank = 1 + int(round(2.0 * (1.0 + roundness)))
    apex = 0.5 + 0.4 * skewedness
    theta = np.linspace(0.0, np.pi / 2.0, per_flank + 1)
    sigma = 1.0 - np.cos(theta) ** (2.0 / q)
    height = np.sin(theta) ** (2.0 / q)
    rising = apex * sigma
    falling = 1.0 - (1.0 - apex) * sigma[::-1][1:]
    return np.concatenate([rising, falling]), np.concatenate([height, height[::-1][1:]])


def _check_unit_interval(value: float, name: str) -> float:
    if not np.isfinite(value) or not -1.0 <= value <= 1.0:
        raise ValueError(f"curve {name} must lie in [-1, 1], got {value}")
    return float(value)


def curve_breakpoints(
    start: np.ndarray | tuple[float, float, float],
    end: np.ndarray | tuple[float, float, float],
    normal: np.ndarray | tuple[float, float, float] | None = None,
    shape: str = "LeftC",
    extent: float = 0.5,
    roundness: float = 0.0,
    skewedness: float = 0.0,
) -> GuidingStrokes:
    """Breakpoints of a MURML curve segment from ``start`` to ``end`` (metres).

    See the module docstring for the meaning of the parameters. Raises ValueError for an
    unknown shape, a zero-length chord or normal, a normal parallel to the chord, or
    roundness/skewedness outside [-1, 1].
    """
    p0 = np.asarray(start, dtype=float)
    p1 = np.asarray(end, dtype=float)
    if shape not in CURVE_SHAPES:
        raise ValueError(f"curve shape {shape!r} is not one of {CURVE_SHAPES}")
    if not np.isfinite(extent) or extent < 0.0:
        raise ValueError(f"curve extent must be a non-negative number, got {extent}")
    roundness = _check_unit_interval(roundness, "roundness")
    skewedness = _check_unit_interval(skewedness, "skewedness")
    chord = p1 - p0
    unit(chord, "curve chord from start to end")
    warnings: tuple[str, ...] = ()
    if normal is None:
        n = default_normal(chord)
        warnings = (f"curve {shape} has no normal; using {np.round(n, 3).tolist()} (plane of chord and up/forward)",)
    else:
        n = unit(normal, "curve normal")
    c, left = _in_plane_frame(chord, n)
    length = quat.length(chord)
    fractions, heights = _bulge_profile(roundness, skewedness)
    sign = 1.0 if shape.startswith("Left") else -1.0
    if shape.endswith("C"):
        offsets = sign * extent * length * heights
    else:
        fractions = np.concatenate([0.5 * fractions, 0.5 + 0.5 * fractions[1:]])
        half = 0.5 * extent * length * heights
        offsets = sign * np.concatenate([half, -half[1:]])
    points = p0 + np.outer(fractions * length, c) + np.outer(offsets, left)
    points[-1] = p1
    return GuidingStrokes(points, warnings)


def _plane_axes(normal: np.ndarray, reference: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """In-plane unit axes (e1, e2 = n × e1) of the plane with unit ``normal``.

    ``e1`` is ``reference`` projected into the plane, or by default the more
    perpendicular of up and forward.
    """
    if reference is None:
        reference = UP if abs(float(normal @ UP)) <= abs(float(normal @ FORWARD)) else FORWARD
    r = np.asarray(reference, dtype=float)
    e1 = r - (r @ normal) * normal
    e1 = unit(e1, "reference axis projected into the circle's plane")
    return e1, quat.cross(normal, e1)


def ellipse_breakpoints(
    center: np.ndarray | tuple[float, float, float],
    semi_axes: tuple[float, float],
    normal: np.ndarray | tuple[float, float, float],
    major_axis: np.ndarray | tuple[float, float, float] | None = None,
    start_angle: float = 0.0,
    sweep: float = 2.0 * np.pi,
    count: int = 16,
) -> np.ndarray:
    """``count + 1`` breakpoints on an ellipse, equally spaced in its parametric angle.

    The point at angle θ is ``center + a cos θ e1 + b sin θ e2`` with ``e1`` the major
    axis (projected into the plane; default up/forward as for curves) and ``e2 = n × e1``,
    so a positive ``sweep`` runs counterclockwise about ``normal``. Equal angle steps put
    the breakpoints closer together where the ellipse bends more, as guiding strokes
    should be. Radians and metres.
    """
    a, b = (float(v) for v in semi_axes)
    if not (a > 0.0 and b > 0.0 and np.isfinite(a) and np.isfinite(b)):
        raise ValueError(f"ellipse semi-axes must be positive, got {semi_axes}")
    if count < 3:
        raise ValueError(f"an ellipse needs at least 3 guiding strokes, got count={count}")
    if not np.isfinite(sweep) or abs(sweep) < _EPS:
        raise ValueError(f"ellipse sweep must be a non-zero angle, got {sweep}")
    n = unit(normal, "ellipse normal")
    e1, e2 = _plane_axes(n, None if major_axis is None else np.asarray(major_axis, dtype=float))
    theta = start_angle + np.linspace(0.0, sweep, count + 1)
    return np.asarray(center, dtype=float) + np.outer(a * np.cos(theta), e1) + np.outer(b * np.sin(theta), e2)


def circle_breakpoints(
    center: np.ndarray | tuple[float, float, float],
    radius: float,
    normal: np.ndarray | tuple[float, float, float],
    start_angle: float = 0.0,
    sweep: float = 2.0 * np.pi,
    count: int = 16,
    reference: np.ndarray | tuple[float, float, float] | None = None,
) -> np.ndarray:
    """``count + 1`` breakpoints on a circle (or arc of ``sweep`` radians) about ``center``.

    Angles are measured from ``reference`` (default: up, or forward for a vertical
    normal) counterclockwise about ``normal``.
    """
    return ellipse_breakpoints(center, (radius, radius), normal, reference, start_angle, sweep, count)


def circle_from_start(
    start: np.ndarray | tuple[float, float, float],
    axis: np.ndarray | tuple[float, float, float],
    radius: float,
    start_angle: float = np.pi,
    sweep: float = 2.0 * np.pi,
    count: int = 16,
    reference: np.ndarray | tuple[float, float, float] | None = None,
) -> np.ndarray:
    """A HamNoSys-style circle: it begins at the hand's current ``start`` position.

    ``axis`` is the circle's axis (the hand moves counterclockwise about it for a
    positive ``sweep``), ``radius`` its size, and ``start_angle`` where ``start`` lies on
    the circle (measured as in :func:`circle_breakpoints`; the default π puts the centre
    ``radius`` above the start for a horizontal axis).
    """
    n = unit(axis, "circle axis")
    e1, e2 = _plane_axes(n, None if reference is None else np.asarray(reference, dtype=float))
    center = np.asarray(start, dtype=float) - radius * (np.cos(start_angle) * e1 + np.sin(start_angle) * e2)
    points = circle_breakpoints(center, radius, n, start_angle, sweep, count, e1)
    points[0] = np.asarray(start, dtype=float)
    return points


def _straight_frame(start: np.ndarray, end: np.ndarray, normal: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    chord = end - start
    unit(chord, "path from start to end")
    n = default_normal(chord) if normal is None else unit(normal, "modulation normal")
    return _in_plane_frame(chord, n)


def wavy(
    start: np.ndarray | tuple[float, float, float],
    end: np.ndarray | tuple[float, float, float],
    amplitude: float,
    waves: int,
    normal: np.ndarray | tuple[float, float, float] | None = None,
    points_per_wave: int = 8,
) -> np.ndarray:
    """Breakpoints of a straight path modulated by ``waves`` sine periods (HamNoSys wavy).

    The offset ``amplitude · sin(2π waves s)`` (metres) lies along ``n × ĉ``, in the plane
    of the chord and the normal's default (up/forward) when no normal is given.
    """
    if waves < 1 or points_per_wave < 4:
        raise ValueError(f"wavy needs waves ≥ 1 and points_per_wave ≥ 4, got {waves}, {points_per_wave}")
    p0, p1 = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    _, left = _straight_frame(p0, p1, None if normal is None else np.asarray(normal, dtype=float))
    s = np.linspace(0.0, 1.0, waves * points_per_wave + 1)
    return p0 + np.outer(s, p1 - p0) + np.outer(amplitude * np.sin(2.0 * np.pi * waves * s), left)


def zigzag(
    start: np.ndarray | tuple[float, float, float],
    end: np.ndarray | tuple[float, float, float],
    amplitude: float,
    zigs: int,
    normal: np.ndarray | tuple[float, float, float] | None = None,
) -> np.ndarray:
    """Breakpoints of a straight path broken into ``zigs`` sharp zigzag teeth.

    Each tooth goes out to ``amplitude`` on one side and the next to the other side; the
    path starts and ends on the straight line.
    """
    if zigs < 1:
        raise ValueError(f"zigzag needs at least one zig, got {zigs}")
    p0, p1 = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    _, left = _straight_frame(p0, p1, None if normal is None else np.asarray(normal, dtype=float))
    s = np.concatenate([[0.0], (np.arange(zigs) + 0.5) / zigs, [1.0]])
    side = np.concatenate([[0.0], np.where(np.arange(zigs) % 2 == 0, 1.0, -1.0), [0.0]])
    return p0 + np.outer(s, p1 - p0) + np.outer(amplitude * side, left)


def repeat_strokes(points: np.ndarray, count: int, back_and_forth: bool = False) -> np.ndarray:
    """Breakpoints of a stroke sequence performed ``count`` times in a row.

    ``back_and_forth`` alternates forward and reversed passes (HamNoSys repetition with
    a significant return). Otherwise each pass starts where the sequence starts: closed
    sequences (a circle) just continue; open ones return to the start along a straight
    return stroke between passes.
    """
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[0] < 2:
        raise ValueError(f"repeat_strokes needs at least two breakpoints, got shape {p.shape}")
    if count < 1:
        raise ValueError(f"repetition count must be at least 1, got {count}")
    passes = [p]
    for index in range(1, count):
        if back_and_forth:
            forward = index % 2 == 0
            passes.append((p if forward else p[::-1])[1:])
        else:
            closed = np.allclose(p[0], p[-1])
            passes.append(p[1:] if closed else p)
    return np.concatenate(passes)
