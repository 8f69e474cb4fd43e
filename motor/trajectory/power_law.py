"""The curvature–speed power law, applied to a whole movement phase as it is assembled.

A *phase* is a wrist movement from rest to rest through breakpoints ``p_0 … p_n``
(metres) over ``[t_0, t_1]`` (seconds). It is formed in two steps:

1. **Geometry.** The C² cubic spline through the breakpoints, parametrised by chord
   length (not-a-knot ends; the straight line for two breakpoints): its curvature κ is
   continuous along the path.
2. **Timing.** The whole path is re-timed by arc length ``s`` and curvature: the wrist
   advances in *law time* ``τ(s) = ∫ R̃(s)^{−β} ds`` (β = 1/3) along an envelope
   ``τ = Φ(t)``, so its speed is ``v = R̃^β · Φ′(t)``: speed ∝ radius^{1/3} wherever the
   envelope is flat. ``R̃`` is the radius of curvature ``1/κ`` softly clamped to
   :data:`RADIUS_RANGE` (a straight part moves as if its radius were 1 m, a kink as if it
   were 5 mm).

The envelope ``Φ′`` rises as the first half of a minimum-jerk bell over a ramp of ``r``
seconds, stays constant, and falls as the second half over the last ``r`` seconds; with
``r = T/2`` it is the whole minimum-jerk bell ``30u²(1 − u)²`` (``T = t_1 − t_0``). Speed
and acceleration are therefore zero at both ends (normal acceleration ``v²κ`` too) and the
acceleration is continuous. The ramp is ``T/2`` for a straight phase (a single straight
stroke is exactly the minimum-jerk movement) and shrinks linearly with the phase's total
turning to :data:`RAMP_FRACTION` ``· T`` from :data:`CURVED_TURN` on, so that a curved
stroke follows the law over most of its duration.

The result is sampled as knots (time, position, velocity, acceleration) every
``1/``:data:`KNOT_RATE` seconds; a quintic Hermite through them (``motor.trajectory.spline``)
is C² and stays on the path within micrometres.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.ndimage import gaussian_filter1d

#: Exponent of the law: speed ∝ radius^EXPONENT.
EXPONENT = 1.0 / 3.0
#: Soft clamp of the radius of curvature the timing uses, metres.
RADIUS_RANGE = (0.005, 1.0)
#: Sharpness of the soft clamp (a p-norm: larger is closer to a hard clamp).
_CLAMP_POWER = 4.0
#: Ramp of a curved phase's envelope, as a fraction of the phase's duration.
RAMP_FRACTION = 0.1
#: Shortest ramp of a curved phase, seconds (at most half the phase).
MIN_RAMP = 0.08
#: Total turning (radians) from which a phase counts as fully curved.
CURVED_TURN = math.pi / 3.0
#: Width (standard deviation, seconds) of the Gaussian that smooths the logarithm of the
#: curvature along the law time before the law uses it: the speed cannot change faster
#: than the hand accelerates (an inflection or a kink would otherwise ask for a jump).
SMOOTHING = 0.008
#: Knots per second of the sampled phase.
KNOT_RATE = 240.0
#: Fewest knots of a phase.
MIN_KNOTS = 9
#: Samples of the law time per spline interval.
_SAMPLES_PER_INTERVAL = 24
#: Peak of the minimum-jerk bell 30u²(1 − u)² (at u = ½).
_BELL_PEAK = 1.875


def chord_parameters(points: np.ndarray) -> np.ndarray:
    """Cumulative chord length at each breakpoint, metres (the spline's parameter)."""
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])


def path_spline(points: np.ndarray) -> CubicSpline:
    """The C² cubic spline through ``points`` ``(n ≥ 2, 3)`` by chord length (module docstring)."""
    u = chord_parameters(points)
    if points.shape[0] == 2:
        return CubicSpline(u, points, bc_type="natural")
    return CubicSpline(u, points, bc_type="not-a-knot")


def total_turning(points: np.ndarray) -> float:
    """Sum of the turning angles (radians) at the interior breakpoints."""
    d = np.diff(points, axis=0)
    a, b = d[:-1], d[1:]
    denominator = np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1)
    cos = np.divide(np.einsum("ij,ij->i", a, b), denominator, out=np.ones_like(denominator), where=denominator > 0.0)
    return float(np.sum(np.arccos(np.clip(cos, -1.0, 1.0))))


def ramp_of(points: np.ndarray, duration: float) -> float:
    """Envelope ramp (s) of a phase through ``points`` lasting ``duration`` (module docstring)."""
    curved = min(0.5 * duration, max(RAMP_FRACTION * duration, MIN_RAMP))
    share = min(1.0, total_turning(points) / CURVED_TURN)
    return 0.5 * duration - (0.5 * duration - curved) * share


def clamped_curvature(curvature: np.ndarray) -> np.ndarray:
    """Curvature softly clamped to ``[1/R_max, 1/R_min]`` (1/m)."""
    low, high = 1.0 / RADIUS_RANGE[1], 1.0 / RADIUS_RANGE[0]
    p = _CLAMP_POWER
    lifted = (curvature**p + low**p) ** (1.0 / p)
    return (lifted ** (-p) + high ** (-p)) ** (-1.0 / p)


def _parameter_grid(spline: CubicSpline) -> np.ndarray:
    knots = spline.x
    fractions = np.linspace(0.0, 1.0, _SAMPLES_PER_INTERVAL + 1)[:-1]
    return np.concatenate([(knots[:-1, None] + np.diff(knots)[:, None] * fractions).ravel(), knots[-1:]])


def _cumulative(density: np.ndarray, u: np.ndarray) -> np.ndarray:
    return np.concatenate([[0.0], np.cumsum(0.5 * (density[1:] + density[:-1]) * np.diff(u))])


def law_time(spline: CubicSpline, flat_time: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Spline parameters ``u`` on a fine grid and the law time ``τ(u)`` there.

    ``τ`` accumulates ``R̃^{−β}`` per metre of arc. Given ``flat_time`` (s, what the phase's
    envelope amounts to at its flat rate, so that the law time runs at ``τ_total /
    flat_time`` per second there) the logarithm of the clamped curvature is smoothed over
    :data:`SMOOTHING` seconds of that motion first.
    """
    u = _parameter_grid(spline)
    first, second = spline(u, 1), spline(u, 2)
    speed = np.maximum(np.linalg.norm(first, axis=1), 1e-12)
    log_curvature = np.log(clamped_curvature(np.linalg.norm(np.cross(first, second), axis=1) / speed**3))
    tau = _cumulative(speed * np.exp(EXPONENT * log_curvature), u)
    if flat_time is None or tau[-1] <= 0.0:
        return u, tau
    width = SMOOTHING * float(tau[-1]) / flat_time
    step = min(width / 4.0, float(tau[-1]) / 8.0)
    grid = np.linspace(0.0, float(tau[-1]), int(math.ceil(float(tau[-1]) / step)) + 1)
    smooth = gaussian_filter1d(np.interp(grid, tau, log_curvature), width / (grid[1] - grid[0]), mode="nearest")
    return u, _cumulative(speed * np.exp(EXPONENT * np.interp(tau, grid, smooth)), u)


def _flat_time(duration: float, ramp: float) -> float:
    """∫Φ′ dt over Φ′'s flat value: the duration less what the ramps lose."""
    return duration - 2.0 * ramp * (1.0 - 1.0 / _BELL_PEAK)


def envelope(t: np.ndarray, duration: float, ramp: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Envelope ``Φ, Φ′, Φ″`` at ``t`` (s from the phase start), normalised to ``Φ(T) = 1``."""
    ramp = min(max(ramp, 1e-9), 0.5 * duration)
    rate = 1.0 / _flat_time(duration, ramp)
    t = np.clip(t, 0.0, duration)
    mirrored = t > 0.5 * duration
    edge = np.where(mirrored, duration - t, t)  # time from the nearer end
    rising = edge < ramp
    x = np.where(rising, edge / (2.0 * ramp), 0.5)
    position = np.where(
        rising,
        rate * 2.0 * ramp * x**3 * (10.0 - 15.0 * x + 6.0 * x * x) / _BELL_PEAK,
        rate * (ramp / _BELL_PEAK + edge - ramp),
    )
    speed = np.where(rising, rate * 30.0 * x * x * (1.0 - x) ** 2 / _BELL_PEAK, rate)
    acceleration = np.where(rising, rate * 60.0 * x * (1.0 - x) * (1.0 - 2.0 * x) / (2.0 * ramp * _BELL_PEAK), 0.0)
    position = np.where(mirrored, 1.0 - position, position)
    acceleration = np.where(mirrored, -acceleration, acceleration)
    return position, speed, acceleration


def phase_knots(
    points: np.ndarray, start: float, end: float, ramp: float | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Knots ``(times, positions, velocities, accelerations)`` of one rest-to-rest phase.

    ``points`` ``(n ≥ 2, 3)`` metres with no zero-length stroke; ``[start, end]`` seconds;
    ``ramp`` the envelope's ramp in seconds (default :func:`ramp_of`).
    """
    duration = end - start
    spline = path_spline(points)
    ramp = ramp_of(points, duration) if ramp is None else min(ramp, 0.5 * duration)
    u, tau = law_time(spline, _flat_time(duration, ramp))
    total = float(tau[-1])
    inverse = CubicSpline(tau, u)
    count = max(MIN_KNOTS, math.ceil(duration * KNOT_RATE) + 1)
    times = np.linspace(start, end, count)
    phi, phi_rate, phi_acceleration = envelope(times - start, duration, ramp)
    law = total * phi
    at = inverse(law)
    du, ddu = inverse(law, 1), inverse(law, 2)
    first, second = spline(at, 1), spline(at, 2)
    rate, rate_change = total * phi_rate, total * phi_acceleration
    along = first * du[:, None]
    bend = second * (du * du)[:, None] + first * ddu[:, None]
    positions = spline(at)
    positions[0], positions[-1] = points[0], points[-1]
    velocities = along * rate[:, None]
    accelerations = bend * (rate * rate)[:, None] + along * rate_change[:, None]
    velocities[[0, -1]] = 0.0
    accelerations[[0, -1]] = 0.0
    return times, positions, velocities, accelerations
