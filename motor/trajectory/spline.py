"""Wrist trajectories: guiding strokes assembled into C² motion (seed 004, 4.1, with the speed laws).

A movement phase is a sequence of guiding strokes between breakpoints ``p_0 … p_n`` at
times ``t_0 … t_n`` (metres, seconds). The seed bends them into a C¹ Hermite curve whose
breakpoint speeds follow ``k · v̄ · ρ^{1/3}``; measured on the rendered wrist, that law
brakes at every breakpoint and starts from rest with a step in acceleration. Here the
movement is assembled so that the laws hold on the motion itself:

* **Phases.** The breakpoints are cut where the wrist must stop: at a hold (a zero-length
  stroke) and at a reversal (a turning angle of at least :data:`CUSP_ANGLE`; the seed's
  ``ρ = 1 − α/π`` tends to a stop there too). Each phase moves from rest to rest between
  the times of its first and last breakpoint; its interior breakpoints are passed at the
  times the power law gives (times given for them only shape the phases' boundaries).
* **Power law.** Within a phase the path is the C² spline through the breakpoints,
  re-timed as a whole by arc length and curvature (:mod:`motor.trajectory.power_law`):
  speed ∝ radius^{1/3}, zero speed and acceleration at both ends, a single straight stroke
  exactly the minimum-jerk movement.
* **Approach.** A preparation from the channel's current state (value and velocity, maybe
  moving) to a breakpoint where it must arrive at rest is the quintic with those end
  conditions (:func:`approach`): the minimum-jerk movement between the two states.
* **Budget.** :func:`plan_wrist_trajectory` keeps a movement within a peak speed (default
  :data:`MAX_WRIST_SPEED`) and, when given, a peak acceleration: a phase that would exceed
  them is slowed by stretching the whole movement about its first breakpoint, with a
  warning giving the amount.

The result is a :class:`WristTrajectory`: a quintic Hermite spline through knots (time,
position, velocity, acceleration), so position, velocity and acceleration are continuous;
before the first and after the last knot the position is held.

:func:`time_breakpoints` spreads a duration over the strokes (stroke ``i`` gets time
``∝ L_i / R_i^{1/3}``, ``R_i`` clamped to [5 mm, 1 m]); the gesture planner uses it to
place the keys of the other channels along a stroke.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from motor.trajectory.power_law import EXPONENT, RADIUS_RANGE, phase_knots
from motor.trajectory.speed_budget import ABSOLUTE_PEAK_SPEED
from motor.trajectory.spline_positions import spline_positions

#: Fastest wrist speed the planner produces, m/s; faster requests are slowed (warning).
MAX_WRIST_SPEED = ABSOLUTE_PEAK_SPEED
#: Exponent of the curvature–speed power law (speed ∝ radius^β).
POWER_LAW_EXPONENT = EXPONENT
#: Turning angle (radians) at a breakpoint from which the wrist stops there.
CUSP_ANGLE = 2.0 * np.pi / 3.0
#: Strokes shorter than this (metres) are holds.
HOLD_LENGTH = 1e-6
#: A chord length (m), or the product of two (m²), at or below which a chord has no
#: direction to turn from.
DEGENERATE_CHORD = 1e-9


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
    cos = np.divide(np.einsum("ij,ij->i", a, b), denom, out=np.ones_like(denom), where=denom > DEGENERATE_CHORD)
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
    if np.any(lengths <= DEGENERATE_CHORD):
        bad = int(np.argmax(lengths <= DEGENERATE_CHORD))
        raise ValueError(f"guiding stroke {bad} (breakpoint {bad} to {bad + 1}) has zero length")
    weights = lengths * _radii(p, lengths) ** (-exponent)
    cumulative = np.concatenate([[0.0], np.cumsum(weights)])
    return start + (end - start) * cumulative / cumulative[-1]


@dataclass(frozen=True, eq=False)
class WristTrajectory:
    """The quintic Hermite spline through knots: C² wrist motion.

    Attributes:
        times: ``(k ≥ 2,)`` increasing knot times, seconds.
        positions: ``(k, d)`` positions at the knots (metres for the wrist, d = 3).
        velocities: ``(k, d)`` velocities there, per second.
        accelerations: ``(k, d)`` accelerations there, per second squared.
        warnings: what the planner changed (slowed movements).

    Before the first and after the last knot the position is held (zero velocity).
    """

    times: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray
    accelerations: np.ndarray
    warnings: tuple[str, ...] = ()
    _coefficients: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        p = _as_points(self.positions, "knot positions")
        t = _as_times(self.times, p.shape[0])
        v = np.asarray(self.velocities, dtype=float)
        a = np.asarray(self.accelerations, dtype=float)
        for name, values in (("velocities", v), ("accelerations", a)):
            if values.shape != p.shape or not np.all(np.isfinite(values)):
                raise ValueError(f"knot {name}: expected a finite array of shape {p.shape}, got {values.shape}")
        h = np.diff(t)[:, None]
        d = p[1:] - p[:-1]
        m0, m1 = v[:-1] * h, v[1:] * h
        c0, c1 = a[:-1] * h * h, a[1:] * h * h
        coefficients = np.stack(
            [
                p[:-1],
                m0,
                0.5 * c0,
                10.0 * d - 6.0 * m0 - 4.0 * m1 - 0.5 * (3.0 * c0 - c1),
                -15.0 * d + 8.0 * m0 + 7.0 * m1 + 0.5 * (3.0 * c0 - 2.0 * c1),
                6.0 * d - 3.0 * m0 - 3.0 * m1 - 0.5 * (c0 - c1),
            ],
            axis=1,
        )
        object.__setattr__(self, "times", np.ascontiguousarray(t))
        object.__setattr__(self, "positions", p)
        object.__setattr__(self, "velocities", v)
        object.__setattr__(self, "accelerations", a)
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
        h = self.times[index + 1] - self.times[index]
        return index, (clipped - self.times[index]) / h, h, inside

    def position(self, times: np.ndarray) -> np.ndarray:
        """Positions ``(len(times), d)`` at ``times`` (seconds), in one compiled pass
        (:func:`motor.trajectory.spline_positions.spline_positions`)."""
        return spline_positions(self.times, self._coefficients, times)

    def velocity(self, times: np.ndarray) -> np.ndarray:
        """Velocities ``(len(times), d)``, per second; zero outside the knot span."""
        index, u, h, inside = self._locate(times)
        c = self._coefficients[index]
        u = u[:, None]
        v = c[:, 1] + u * (2.0 * c[:, 2] + u * (3.0 * c[:, 3] + u * (4.0 * c[:, 4] + u * 5.0 * c[:, 5])))
        return np.where(inside[:, None], v / h[:, None], 0.0)

    def acceleration(self, times: np.ndarray) -> np.ndarray:
        """Accelerations ``(len(times), d)``, per second squared; zero outside the span."""
        index, u, h, inside = self._locate(times)
        c = self._coefficients[index]
        u = u[:, None]
        a = 2.0 * c[:, 2] + u * (6.0 * c[:, 3] + u * (12.0 * c[:, 4] + u * 20.0 * c[:, 5]))
        return np.where(inside[:, None], a / (h * h)[:, None], 0.0)

    def _dense(self, per_interval: int = 4) -> np.ndarray:
        u = np.linspace(0.0, 1.0, per_interval + 1)[:-1]
        return np.append((self.times[:-1, None] + np.diff(self.times)[:, None] * u).ravel(), self.times[-1])

    def peak_speed(self) -> float:
        """Largest speed along the trajectory (m/s), sampled densely between the knots."""
        return float(np.max(np.linalg.norm(self.velocity(self._dense()), axis=1)))

    def peak_acceleration(self) -> float:
        """Largest acceleration (m/s²), sampled densely between the knots."""
        return float(np.max(np.linalg.norm(self.acceleration(self._dense()), axis=1)))

    def shifted(self, delay: float) -> WristTrajectory:
        """The same motion ``delay`` seconds later."""
        return WristTrajectory(self.times + delay, self.positions, self.velocities, self.accelerations, self.warnings)

    def with_warnings(self, warnings: Sequence[str]) -> WristTrajectory:
        """The same trajectory carrying ``warnings`` after its own."""
        return WristTrajectory(self.times, self.positions, self.velocities, self.accelerations, (*self.warnings, *warnings))


def joined(pieces: Sequence[WristTrajectory]) -> WristTrajectory:
    """One trajectory of ``pieces`` in time order; each starts where the previous ends (in
    position; a later start is a hold in between, which needs both to be at rest)."""
    if not pieces:
        raise ValueError("joined: no trajectories to join")
    times, positions, velocities, accelerations, warnings = [], [], [], [], []
    for index, piece in enumerate(pieces):
        first = 0
        if index:
            previous_end = times[-1][-1]
            if piece.start < previous_end - 1e-12:
                raise ValueError(f"joined: trajectory {index} starts at {piece.start} before the previous ends at {previous_end}")
            if np.linalg.norm(piece.positions[0] - positions[-1][-1]) > 1e-9:
                raise ValueError(f"joined: trajectory {index} does not start where the previous one ends")
            first = 1 if piece.start - previous_end <= 1e-12 else 0
        times.append(piece.times[first:])
        positions.append(piece.positions[first:])
        velocities.append(piece.velocities[first:])
        accelerations.append(piece.accelerations[first:])
        warnings.extend(piece.warnings)
    return WristTrajectory(
        np.concatenate(times), np.concatenate(positions), np.concatenate(velocities), np.concatenate(accelerations), tuple(warnings)
    )


def held(position: np.ndarray, start: float, end: float) -> WristTrajectory:
    """A wrist held still at ``position`` over ``[start, end]`` (end > start)."""
    p = np.asarray(position, dtype=float)
    return WristTrajectory(np.array([start, end]), np.stack([p, p]), np.zeros((2, p.size)), np.zeros((2, p.size)))


def approach(
    position: np.ndarray,
    velocity: np.ndarray,
    start: float,
    target: np.ndarray,
    arrival: float,
    acceleration: np.ndarray | None = None,
) -> WristTrajectory:
    """From ``position`` moving at ``velocity`` (and ``acceleration``, default zero) at
    ``start`` to rest at ``target`` at ``arrival``: the quintic with those end conditions,
    the minimum-jerk movement between the two states (a straight minimum-jerk reach from
    rest)."""
    p0, p1 = np.asarray(position, dtype=float), np.asarray(target, dtype=float)
    a0 = np.zeros_like(p0) if acceleration is None else np.asarray(acceleration, dtype=float)
    return WristTrajectory(
        np.array([start, arrival]),
        np.stack([p0, p1]),
        np.stack([np.asarray(velocity, dtype=float), np.zeros_like(p1)]),
        np.stack([a0, np.zeros_like(p1)]),
    )


def phases(points: np.ndarray) -> list[tuple[int, int]]:
    """``(first, last)`` breakpoint indices of the rest-to-rest phases (module docstring)."""
    p = _as_points(points)
    lengths = np.linalg.norm(np.diff(p, axis=0), axis=1)
    moving = lengths > HOLD_LENGTH
    cusp = np.zeros(p.shape[0], dtype=bool)
    if p.shape[0] > 2:
        cusp[1:-1] = turning_angles(p) >= CUSP_ANGLE
    out: list[tuple[int, int]] = []
    first = None
    for stroke in range(lengths.size):
        if not moving[stroke]:
            if first is not None:
                out.append((first, stroke))
                first = None
            continue
        if first is None:
            first = stroke
        elif cusp[stroke]:
            out.append((first, stroke))
            first = stroke
    if first is not None:
        out.append((first, lengths.size))
    return out


def _assembled(points: np.ndarray, times: np.ndarray) -> WristTrajectory:
    pieces = []
    for first, last in phases(points):
        knots = phase_knots(points[first : last + 1], float(times[first]), float(times[last]))
        pieces.append(WristTrajectory(*knots))
    if not pieces:
        return held(points[0], float(times[0]), float(times[-1]))
    out = joined(pieces)
    if out.start > times[0]:
        out = joined([held(points[0], float(times[0]), out.start), out])
    if out.end < times[-1]:
        out = joined([out, held(points[-1], out.end, float(times[-1]))])
    return out


def plan_wrist_trajectory(
    points: np.ndarray,
    times: np.ndarray | None = None,
    *,
    start: float | None = None,
    end: float | None = None,
    max_speed: float = MAX_WRIST_SPEED,
    max_acceleration: float | None = None,
    warnings: tuple[str, ...] = (),
) -> WristTrajectory:
    """A wrist trajectory through guiding-stroke breakpoints (metres, seconds; module docstring).

    Give either breakpoint ``times`` or a ``start`` and ``end`` spread over the strokes by
    :func:`time_breakpoints`. If the movement would peak above ``max_speed`` (or
    ``max_acceleration``), its timing is stretched about the first breakpoint until it
    peaks at the limit, and a warning says by how much.
    """
    p = _as_points(points)
    if times is None:
        if start is None or end is None:
            raise ValueError("plan_wrist_trajectory: give breakpoint times or a start and an end")
        t = time_breakpoints(p, start, end)
    else:
        t = _as_times(times, p.shape[0])
    trajectory = _assembled(p, t)
    factor = stretch_factor(trajectory, max_speed, max_acceleration)
    if factor <= 1.0:
        return trajectory.with_warnings(warnings)
    length = float(np.sum(np.linalg.norm(np.diff(p, axis=0), axis=1)))
    note = (
        f"movement of {length:.3f} m in {t[-1] - t[0]:.3f} s would peak at {trajectory.peak_speed():.2f} m/s "
        f"and {trajectory.peak_acceleration():.1f} m/s²; slowed to {factor * (t[-1] - t[0]):.3f} s "
        f"(limits {max_speed} m/s" + ("" if max_acceleration is None else f", {max_acceleration} m/s²") + ")"
    )
    return _assembled(p, t[0] + (t - t[0]) * factor).with_warnings((*warnings, note))


def stretch_factor(trajectory: WristTrajectory, max_speed: float, max_acceleration: float | None = None) -> float:
    """By how much the trajectory's timing must be stretched to stay within the limits (≥ 1
    when it exceeds them; speed scales with 1/factor, acceleration with 1/factor²)."""
    factor = trajectory.peak_speed() / max_speed
    if max_acceleration is not None:
        factor = max(factor, float(np.sqrt(trajectory.peak_acceleration() / max_acceleration)))
    return factor
