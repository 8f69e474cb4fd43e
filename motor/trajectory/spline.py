"""Wrist trajectory formation from guiding strokes (seed 004, section 4.1).

A movement phase is a sequence of guiding strokes between breakpoints ``p_0 … p_n`` at
times ``t_0 … t_n``. The trajectory is the C¹ cubic Hermite curve through the breakpoints
with velocities estimated from the local geometry (the non-uniform cubic B-spline with
double interior knots of the seed is the same curve):

* at an interior breakpoint the mean speed is
  ``v̄_i = ½ (|p_i − p_{i−1}| / (t_i − t_{i−1}) + |p_{i+1} − p_i| / (t_{i+1} − t_i))``,
  the direction is parallel to the chord ``p_{i+1} − p_{i−1}``, the turning angle ``α``
  between the adjacent strokes gives the normalized radius ``ρ_i = 1 − α/π``, and the
  speed is ``v_i = k · v̄_i · ρ_i^{1/3}`` (``k`` = 1, 0.8 next to curved strokes);
* the ends of a phase have zero velocity unless boundary velocities are given; a
  zero-length stroke is a hold and also ends a phase (zero velocity on both sides).

When the caller gives only a duration, :func:`time_breakpoints` distributes it over the
strokes so that the speed follows the two-thirds power law: stroke ``i`` gets time
``∝ L_i / R_i^{1/3}``, ``L_i`` its length and ``R_i`` the radius of curvature of the path
there (turning angle per arc length at its breakpoints, clamped to [5 mm, 1 m]). For a
traced ellipse this makes the speed ∝ R^{1/3}; for collinear strokes, constant speed.

Speeds above :data:`MAX_WRIST_SPEED` (3 m/s) are not produced: the timing of the whole
phase is stretched about its start until the peak speed is the maximum, with a warning.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

#: Fastest wrist speed the planner produces, m/s; faster requests are slowed (warning).
MAX_WRIST_SPEED = 3.0
#: Gain of the breakpoint speed rule, and its value next to curved strokes.
K_STRAIGHT = 1.0
K_CURVED = 0.8
#: Exponent of the curvature–speed power law (speed ∝ radius^β).
POWER_LAW_EXPONENT = 1.0 / 3.0
#: Clamp of the radius-of-curvature estimate used for timing, metres.
RADIUS_RANGE = (0.005, 1.0)
_HOLD = 1e-9


def fitts_duration(amplitude: np.ndarray | float) -> np.ndarray:
    """Movement time from Fitts' law as ACE uses it: ``T = 0.24 · ln(100·A + 1)`` seconds.

    ``amplitude`` in metres (any shape, non-negative); returns an array of that shape.
    """
    a = np.asarray(amplitude, dtype=float)
    if np.any(~np.isfinite(a)) or np.any(a < 0.0):
        raise ValueError(f"Fitts amplitude must be finite and non-negative, got {amplitude!r}")
    return 0.24 * np.log(100.0 * a + 1.0)


def _as_points(points: np.ndarray, name: str = "breakpoints") -> np.ndarray:
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[0] < 2:
        raise ValueError(f"{name}: expected (n ≥ 2, d) positions, got shape {p.shape}")
    if not np.all(np.isfinite(p)):
        raise ValueError(f"{name}: positions must be finite")
    return p


def _as_times(times: np.ndarray, count: int) -> np.ndarray:
    t = np.asarray(times, dtype=float)
    if t.shape != (count,) or not np.all(np.isfinite(t)):
        raise ValueError(f"breakpoint times: expected {count} finite times, got shape {t.shape}")
    steps = np.diff(t)
    if np.any(steps <= 0.0):
        bad = int(np.argmax(steps <= 0.0))
        raise ValueError(f"breakpoint times must increase: t[{bad}]={t[bad]} ≥ t[{bad + 1}]={t[bad + 1]}")
    return t


def turning_angles(points: np.ndarray) -> np.ndarray:
    """Angle α (radians, 0…π) between the strokes meeting at each interior breakpoint.

    Zero at a breakpoint next to a zero-length stroke (a hold).
    """
    p = _as_points(points)
    d = np.diff(p, axis=0)
    a, b = d[:-1], d[1:]
    na, nb = np.linalg.norm(a, axis=1), np.linalg.norm(b, axis=1)
    denom = na * nb
    cos = np.divide(np.einsum("ij,ij->i", a, b), denom, out=np.ones_like(denom), where=denom > _HOLD)
    return np.arccos(np.clip(cos, -1.0, 1.0))


def _radii(points: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """Radius of curvature per stroke: geometric mean of its breakpoints' estimates."""
    alpha = turning_angles(points)
    arc = 0.5 * (lengths[:-1] + lengths[1:])
    lo, hi = RADIUS_RANGE
    at_breaks = np.clip(np.divide(arc, alpha, out=np.full_like(arc, hi), where=alpha > 1e-12), lo, hi)
    if at_breaks.size == 0:
        return np.full(lengths.shape, hi)
    left = np.concatenate([at_breaks[:1], at_breaks])
    right = np.concatenate([at_breaks, at_breaks[-1:]])
    return np.sqrt(left * right)


def time_breakpoints(points: np.ndarray, start: float, end: float, exponent: float = POWER_LAW_EXPONENT) -> np.ndarray:
    """Breakpoint times spreading ``[start, end]`` (seconds) over the strokes.

    Stroke ``i`` gets a share ``∝ L_i · R_i^{−exponent}`` (see the module docstring), so
    the resulting speed follows speed ∝ R^exponent. Raises ValueError for a zero-length
    stroke (give explicit times for holds) or an empty interval.
    """
    p = _as_points(points)
    if not (np.isfinite(start) and np.isfinite(end) and end > start):
        raise ValueError(f"stroke interval must be finite with end > start, got [{start}, {end}]")
    lengths = np.linalg.norm(np.diff(p, axis=0), axis=1)
    if np.any(lengths <= _HOLD):
        bad = int(np.argmax(lengths <= _HOLD))
        raise ValueError(f"guiding stroke {bad} (breakpoint {bad} to {bad + 1}) has zero length")
    weights = lengths * _radii(p, lengths) ** (-exponent)
    cumulative = np.concatenate([[0.0], np.cumsum(weights)])
    return start + (end - start) * cumulative / cumulative[-1]


def breakpoint_velocities(
    points: np.ndarray,
    times: np.ndarray,
    start_velocity: np.ndarray | None = None,
    end_velocity: np.ndarray | None = None,
    curved: Sequence[bool] | np.ndarray | None = None,
    k: float = K_STRAIGHT,
    k_curved: float = K_CURVED,
) -> np.ndarray:
    """Velocities ``(n, d)`` at the breakpoints by the seed-004 rule (module docstring).

    ``curved[i]`` marks stroke ``i`` (from breakpoint i to i+1) as part of a curve: its
    breakpoints use ``k_curved``. Boundary velocities default to zero.
    """
    p = _as_points(points)
    t = _as_times(times, p.shape[0])
    d = np.diff(p, axis=0)
    lengths = np.linalg.norm(d, axis=1)
    velocities = np.zeros_like(p)
    velocities[0] = 0.0 if start_velocity is None else np.asarray(start_velocity, dtype=float)
    velocities[-1] = 0.0 if end_velocity is None else np.asarray(end_velocity, dtype=float)
    if p.shape[0] == 2:
        return velocities
    dt = np.diff(t)
    mean_speed = 0.5 * (lengths[:-1] / dt[:-1] + lengths[1:] / dt[1:])
    rho = 1.0 - turning_angles(p) / np.pi
    gains = np.full(p.shape[0] - 2, k)
    if curved is not None:
        flags = np.asarray(curved, dtype=bool)
        if flags.shape != (p.shape[0] - 1,):
            raise ValueError(f"curved: expected one flag per stroke ({p.shape[0] - 1}), got {flags.shape}")
        gains = np.where(flags[:-1] | flags[1:], k_curved, k)
    chord = p[2:] - p[:-2]
    chord_length = np.linalg.norm(chord, axis=1)
    moving = (lengths[:-1] > _HOLD) & (lengths[1:] > _HOLD) & (chord_length > _HOLD)
    direction = np.divide(chord, chord_length[:, None], out=np.zeros_like(chord), where=moving[:, None])
    speed = np.where(moving, gains * mean_speed * np.cbrt(rho), 0.0)
    velocities[1:-1] = direction * speed[:, None]
    return velocities


@dataclass(frozen=True, eq=False)
class WristTrajectory:
    """The C¹ cubic Hermite curve through breakpoints with given velocities.

    Attributes:
        breakpoints: ``(n, d)`` positions (metres for the wrist, d = 3).
        times: ``(n,)`` increasing breakpoint times, seconds.
        velocities: ``(n, d)`` velocities at the breakpoints, per second.
        warnings: what the planner changed or assumed (slowed strokes, default normals).

    Before the first and after the last breakpoint the position is held constant.
    """

    breakpoints: np.ndarray
    times: np.ndarray
    velocities: np.ndarray
    warnings: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        p = _as_points(self.breakpoints)
        t = _as_times(self.times, p.shape[0])
        v = np.asarray(self.velocities, dtype=float)
        if v.shape != p.shape or not np.all(np.isfinite(v)):
            raise ValueError(f"velocities: expected finite array of shape {p.shape}, got {v.shape}")
        dt = np.diff(t)[:, None, None]
        p0, p1 = p[:-1, None, :], p[1:, None, :]
        m0, m1 = v[:-1, None, :] * dt, v[1:, None, :] * dt
        coefficients = np.concatenate([p0, m0, 3.0 * (p1 - p0) - 2.0 * m0 - m1, 2.0 * (p0 - p1) + m0 + m1], axis=1)
        object.__setattr__(self, "breakpoints", p)
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "velocities", v)
        object.__setattr__(self, "_coefficients", coefficients)

    @property
    def start(self) -> float:
        return float(self.times[0])

    @property
    def end(self) -> float:
        return float(self.times[-1])

    def _locate(self, times: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        t = np.asarray(times, dtype=float)
        inside = (t >= self.times[0]) & (t <= self.times[-1])
        clipped = np.clip(t, self.times[0], self.times[-1])
        index = np.clip(np.searchsorted(self.times, clipped, side="right") - 1, 0, len(self.times) - 2)
        dt = self.times[index + 1] - self.times[index]
        u = (clipped - self.times[index]) / dt
        return index, u, dt, inside

    def position(self, times: np.ndarray) -> np.ndarray:
        """Positions ``(len(times), d)`` at ``times`` (seconds)."""
        index, u, _, _ = self._locate(times)
        c = self._coefficients[index]
        u = u[:, None]
        return c[:, 0] + u * (c[:, 1] + u * (c[:, 2] + u * c[:, 3]))

    def velocity(self, times: np.ndarray) -> np.ndarray:
        """Velocities ``(len(times), d)``, per second; zero outside the breakpoint span."""
        index, u, dt, inside = self._locate(times)
        c = self._coefficients[index]
        u = u[:, None]
        v = (c[:, 1] + u * (2.0 * c[:, 2] + 3.0 * u * c[:, 3])) / dt[:, None]
        return np.where(inside[:, None], v, 0.0)

    def acceleration(self, times: np.ndarray) -> np.ndarray:
        """Accelerations ``(len(times), d)``, per second squared; zero outside the span."""
        index, u, dt, inside = self._locate(times)
        c = self._coefficients[index]
        a = (2.0 * c[:, 2] + 6.0 * u[:, None] * c[:, 3]) / (dt * dt)[:, None]
        return np.where(inside[:, None], a, 0.0)

    def peak_speed(self, samples_per_stroke: int = 32) -> float:
        """Largest speed along the curve, from dense sampling of every stroke."""
        u = np.linspace(0.0, 1.0, samples_per_stroke + 1)
        t = (self.times[:-1, None] + np.diff(self.times)[:, None] * u).ravel()
        return float(np.max(np.linalg.norm(self.velocity(t), axis=1)))


@dataclass(frozen=True)
class Accent:
    """Defer the speed peak of guiding stroke ``stroke`` to ``fraction`` of its duration.

    Realized by an extra breakpoint on the stroke's chord at path fraction ``fraction``
    and time fraction ``fraction``, with the stroke's peak speed along the chord: with
    zero end speeds both halves then accelerate/decelerate monotonically and the speed
    peaks exactly there (0.5 leaves the symmetric bell).
    """

    stroke: int
    fraction: float = 0.7


def _insert_accents(
    points: np.ndarray, times: np.ndarray, velocities: np.ndarray, accents: Sequence[Accent]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    strokes = points.shape[0] - 1
    inserts: list[tuple[int, np.ndarray, float, np.ndarray]] = []
    for accent in accents:
        if not 0 <= accent.stroke < strokes:
            raise ValueError(f"accent on stroke {accent.stroke}, but there are {strokes} strokes")
        if not 0.05 <= accent.fraction <= 0.95:
            raise ValueError(f"accent fraction must lie in [0.05, 0.95], got {accent.fraction}")
        i, phi = accent.stroke, accent.fraction
        chord = points[i + 1] - points[i]
        length = float(np.linalg.norm(chord))
        if length <= _HOLD:
            raise ValueError(f"accent on stroke {i}, which has zero length (a hold)")
        direction = chord / length
        duration = times[i + 1] - times[i]
        v0, v1 = velocities[i] @ direction, velocities[i + 1] @ direction
        speed = max(1.5 * length / duration - 0.5 * min(v0, v1), v0, v1)
        inserts.append((i + 1, points[i] + phi * chord, times[i] + phi * duration, speed * direction))
    if len({index for index, *_ in inserts}) != len(inserts):
        raise ValueError("at most one accent per guiding stroke")
    for index, point, time, velocity in sorted(inserts, key=lambda item: -item[0]):
        points = np.insert(points, index, point, axis=0)
        times = np.insert(times, index, time)
        velocities = np.insert(velocities, index, velocity, axis=0)
    return points, times, velocities


def plan_wrist_trajectory(
    points: np.ndarray,
    times: np.ndarray | None = None,
    *,
    start: float | None = None,
    end: float | None = None,
    start_velocity: np.ndarray | None = None,
    end_velocity: np.ndarray | None = None,
    curved: Sequence[bool] | np.ndarray | None = None,
    k: float = K_STRAIGHT,
    k_curved: float = K_CURVED,
    accents: Sequence[Accent] = (),
    max_speed: float = MAX_WRIST_SPEED,
    warnings: tuple[str, ...] = (),
) -> WristTrajectory:
    """A wrist trajectory through guiding-stroke breakpoints (metres, seconds).

    Give either explicit breakpoint ``times`` or a ``start`` and ``end`` to be spread
    over the strokes by :func:`time_breakpoints`. Velocities follow
    :func:`breakpoint_velocities`; ``accents`` defer single strokes' speed peaks. If the
    peak speed exceeds ``max_speed`` the timing is stretched about the first breakpoint
    (interior velocities shrink by the same factor; the boundary velocities are kept, so
    the phase still joins its neighbours) and a warning says by how much.
    """
    p = _as_points(points)
    if times is None:
        if start is None or end is None:
            raise ValueError("plan_wrist_trajectory: give breakpoint times or a start and an end")
        t = time_breakpoints(p, start, end)
    else:
        t = _as_times(times, p.shape[0])
    v = breakpoint_velocities(p, t, start_velocity, end_velocity, curved, k, k_curved)
    p, t, v = _insert_accents(p, t, v, accents)
    trajectory = WristTrajectory(p, t, v, tuple(warnings))
    peak = trajectory.peak_speed()
    if peak <= max_speed:
        return trajectory
    factor = peak / max_speed
    length = float(np.sum(np.linalg.norm(np.diff(p, axis=0), axis=1)))
    note = (
        f"movement of {length:.3f} m in {t[-1] - t[0]:.3f} s would peak at {peak:.2f} m/s; "
        f"slowed to {factor * (t[-1] - t[0]):.3f} s (max wrist speed {max_speed} m/s)"
    )
    slowed = v / factor
    slowed[0], slowed[-1] = v[0], v[-1]
    return WristTrajectory(p, t[0] + (t - t[0]) * factor, slowed, (*warnings, note))
