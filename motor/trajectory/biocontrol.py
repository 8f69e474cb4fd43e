"""Temporal profiles of movement manners from the seed-000 biocontrol model.

Seed 000 (section 4.5) times a movement along its path with a two-level cascade of
proportional controllers: the outer one demands a rate ``ẋ_r = k (x_t − x)``, the inner
one an acceleration ``ẍ = k′ (ẋ_r − ẋ)``, so that

    ẍ + k′ ẋ + k k′ x = k k′ x_t,

critically damped at ``k′/k = 4``. ``x`` is the fraction of the path travelled (0 → 1).
Constant gains are sluggish at the end, so the stiffness rises as the target nears: here
``k(e) = k₀ (1 + g · (1 − e)^p)`` with ``e = 1 − x`` the remaining error, ``k′ = ratio ·
k``. A manner is a parameter set (:class:`Manner`); linear and tense movement also cap
the demanded rate (a steady cruise), and sudden stop is underdamped and cut off the
moment it reaches the target.

Each manner is integrated once, lazily, into a lookup table ``f: [0, 1] → [0, 1]`` (time
fraction → path fraction) over the movement's main part: until it has settled to within
1% of the target (or, when truncated, until it arrives), with time rescaled to one unit.
As integrated, the model starts with a step in acceleration (the controller's full
command at once) and ends at speed (the "sharp stop" of targetted movement). A movement
starts and ends at rest with zero acceleration, and a hand's jerk stays near that of a
minimum-jerk movement (seed 000's stop is sharp, not a collision), so the table is the
profile *nearest the model's* (least squares on the speed ``f′``) among those that

* start and stop at rest with zero acceleration (``f′ = f″ = 0`` at both ends) and travel
  the whole way (``f(1) = 1``);
* keep the jerk ``|f‴(u)|`` within :data:`JERK_RATIO` times that of the minimum-jerk
  movement ``|60 (1 − 6u + 6u²)|``, floored at :data:`JERK_FLOOR` of its peak (so the
  bound follows the minimum-jerk jerk where it is large, at the ends, and allows
  :data:`JERK_RATIO` ``·`` :data:`JERK_FLOOR` ``· 60`` in between, where the speed peaks).

The jerk is piecewise constant over :data:`JERK_PIECES` equal pieces, so ``f`` is a
piecewise cubic, C² by construction; the bounded least-squares problem is solved once per
manner (:func:`scipy.optimize.lsq_linear`). Targetted movement keeps a late speed peak
(about 0.6 of its duration) and a stop steeper than its start; lax keeps its broad central
peak; linear and tense keep their cruise between a jerk-limited start and stop. The stop
is a zero-acceleration stop at any frame rate: no speed step.

Durations: seed 000 keeps a movement's duration independent of its size, longer for
curved arcs and longer still for circles; :func:`movement_duration` gives
``BASE_DURATION · MOVEMENT_KIND_DURATION[kind] · manner.duration_scale``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cache

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import lsq_linear

from motor.trajectory.speed_budget import budget

#: Samples of each profile table.
TABLE_SIZE = 1025
#: Duration of a plain straight movement in the normal (targetted) manner, seconds.
BASE_DURATION = 0.4
#: Relative durations per movement kind (seed 000, 4.5: arcs slower, circles slower still).
MOVEMENT_KIND_DURATION: dict[str, float] = {"straight": 1.0, "curved": 1.3, "circle": 1.7}
#: The fraction of the path counted as arrived ("settled to within 1%").
SETTLED = 0.99
#: Largest jerk of a profile relative to the minimum-jerk movement's at the same time
#: (module docstring); the design's target is 1.5, this leaves room for sampling.
JERK_RATIO = 1.4
#: Floor of that bound, as a fraction of the minimum-jerk movement's peak jerk (60).
JERK_FLOOR = 0.5
#: Pieces of constant jerk of a profile (they divide ``TABLE_SIZE − 1``).
JERK_PIECES = 32
#: Weight of the end conditions (at rest, whole way) against the fit of the speed.
_END_WEIGHT = 1e3


@dataclass(frozen=True)
class Manner:
    """Parameters of the biocontrol model for one manner of movement.

    Attributes:
        name: the manner (``targetted``, ``lax``, ``hard_contact``, ``linear``, ``fast``,
            ``slow``, ``tense``, ``sudden_stop``).
        ratio: ``k′/k``; 4 is critical damping, less is underdamped.
        growth: ``g``, how much the stiffness grows by arrival (``k`` ends at ``(1 + g) k₀``).
        sharpness: ``p``, how late in the movement the stiffness grows.
        rate_limit: cap on the demanded rate, in path fractions per unit of ``1/k₀``
            (``inf``: none); a small cap gives a constant-speed cruise.
        truncate: stop the movement the moment it first reaches the target (sudden stop).
        duration_scale: relative duration (fast < 1 < slow, tense).
    """

    name: str
    ratio: float = 4.0
    growth: float = 10.0
    sharpness: float = 2.0
    rate_limit: float = np.inf
    truncate: bool = False
    duration_scale: float = 1.0

    def __post_init__(self) -> None:
        if not (self.ratio > 0 and self.growth >= 0 and self.sharpness > 0 and self.rate_limit > 0):
            raise ValueError(f"manner {self.name!r}: ratio, sharpness and rate_limit must be positive, growth ≥ 0")
        if not self.duration_scale > 0:
            raise ValueError(f"manner {self.name!r}: duration_scale must be positive, got {self.duration_scale}")


MANNERS: dict[str, Manner] = {
    manner.name: manner
    for manner in (
        Manner("targetted"),
        Manner("lax", growth=4.0, sharpness=1.0),
        Manner("hard_contact", growth=30.0),
        Manner("linear", growth=0.0, sharpness=1.0, rate_limit=0.05),
        Manner("fast", duration_scale=0.6),
        Manner("slow", growth=5.0, sharpness=1.0, duration_scale=1.6),
        Manner("tense", growth=5.0, sharpness=1.0, rate_limit=0.2, duration_scale=1.5),
        Manner("sudden_stop", ratio=1.5, growth=20.0, truncate=True),
    )
}


@dataclass(frozen=True, eq=False)
class TimeProfile:
    """A tabulated time profile ``f: [0, 1] → [0, 1]`` and its derivative.

    Attributes:
        name: the manner (or other source) it was made from.
        fractions: ``(TABLE_SIZE,)`` path fraction at equally spaced time fractions.
        rates: ``(TABLE_SIZE,)`` derivative ``df/du`` there (path per unit time fraction).
        grid: the time fractions of ``fractions``, equally spaced from 0 to 1, made once
            (sampling asks for them on every call).
    """

    name: str
    fractions: np.ndarray
    rates: np.ndarray
    grid: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "fractions", np.ascontiguousarray(self.fractions, dtype=float))
        object.__setattr__(self, "grid", np.linspace(0.0, 1.0, self.fractions.size))

    def fraction(self, u: np.ndarray | float) -> np.ndarray:
        """Path fraction at time fractions ``u`` (clipped to [0, 1]), any shape."""
        return np.interp(np.clip(u, 0.0, 1.0), self.grid, self.fractions)

    def rate(self, u: np.ndarray | float) -> np.ndarray:
        """Speed profile ``df/du`` at ``u``; zero outside [0, 1]."""
        u = np.asarray(u, dtype=float)
        grid = np.linspace(0.0, 1.0, self.rates.size)
        return np.where((u >= 0.0) & (u <= 1.0), np.interp(u, grid, self.rates), 0.0)


def _dynamics(manner: Manner):
    def derivative(_: float, state: np.ndarray) -> np.ndarray:
        x, v = state
        error = 1.0 - x
        k = 1.0 + manner.growth * max(0.0, 1.0 - error) ** manner.sharpness
        demanded = min(k * error, manner.rate_limit)
        return np.array([v, manner.ratio * k * (demanded - v)])

    return derivative


def integrate_manner(manner: Manner) -> TimeProfile:
    """Integrate the biocontrol model for ``manner`` into a :class:`TimeProfile`."""
    target = 1.0 if manner.truncate else SETTLED

    def arrived(_: float, state: np.ndarray) -> float:
        return state[0] - target

    arrived.terminal = True
    arrived.direction = 1.0
    horizon = 50.0 / min(1.0, manner.rate_limit)
    solution = solve_ivp(
        _dynamics(manner), (0.0, horizon), [0.0, 0.0], events=arrived, dense_output=True, rtol=1e-9, atol=1e-12
    )
    if solution.t_events[0].size == 0:
        raise RuntimeError(f"manner {manner.name!r} did not reach its target within {horizon} time units")
    duration = float(solution.t_events[0][0])
    _, v = solution.sol(np.linspace(0.0, duration, TABLE_SIZE))
    return at_rest(manner.name, np.maximum(v, 0.0))


@cache
def _jerk_operators() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Maps from the :data:`JERK_PIECES` piece jerks to the acceleration, speed and path
    fraction at the ``TABLE_SIZE`` table points (exact integration of piecewise-constant
    jerk from rest, vectorized with cumulative sums)."""
    steps = TABLE_SIZE - 1
    h = 1.0 / steps
    jerk = np.repeat(np.eye(JERK_PIECES), steps // JERK_PIECES, axis=0)
    acceleration = np.cumsum(jerk * h, axis=0)
    acceleration_before = np.vstack([np.zeros((1, JERK_PIECES)), acceleration[:-1]])
    speed = np.cumsum(acceleration_before * h + jerk * h * h / 2.0, axis=0)
    speed_before = np.vstack([np.zeros((1, JERK_PIECES)), speed[:-1]])
    fraction = np.cumsum(speed_before * h + acceleration_before * h * h / 2.0 + jerk * h**3 / 6.0, axis=0)
    start = np.zeros((1, JERK_PIECES))
    return np.vstack([start, acceleration]), np.vstack([start, speed]), np.vstack([start, fraction])


def jerk_bound(u: np.ndarray) -> np.ndarray:
    """The largest jerk ``|f‴|`` a profile may have at time fractions ``u`` (module docstring)."""
    minimum_jerk_jerk = np.abs(60.0 * (1.0 - 6.0 * u + 6.0 * u * u))
    return JERK_RATIO * np.maximum(minimum_jerk_jerk, 60.0 * JERK_FLOOR)


def at_rest(name: str, speeds: np.ndarray) -> TimeProfile:
    """The profile nearest a speed curve sampled at ``TABLE_SIZE`` equal time steps over
    a movement that starts and stops at rest with zero acceleration and keeps its jerk
    within :func:`jerk_bound` (module docstring)."""
    if speeds.shape != (TABLE_SIZE,) or not np.all(np.isfinite(speeds)) or not speeds.sum() > 0:
        raise ValueError(f"profile {name!r}: speeds must be {TABLE_SIZE} finite samples, not all zero")
    u = np.linspace(0.0, 1.0, TABLE_SIZE)
    wanted = speeds / float(np.sum(0.5 * (speeds[1:] + speeds[:-1]) * np.diff(u)))
    acceleration, speed, fraction = _jerk_operators()
    ends = np.vstack([acceleration[-1], speed[-1], fraction[-1]])
    bound = jerk_bound((np.arange(JERK_PIECES) + 0.5) / JERK_PIECES)
    system = np.vstack([speed, _END_WEIGHT * ends]) * bound
    solution = lsq_linear(system, np.concatenate([wanted, _END_WEIGHT * np.array([0.0, 0.0, 1.0])]), bounds=(-1.0, 1.0), method="bvls")
    jerk = solution.x * bound
    # the end conditions exactly: the least change of the piece jerks that meets them
    jerk += ends.T @ np.linalg.solve(ends @ ends.T, np.array([0.0, 0.0, 1.0]) - ends @ jerk)
    fractions = fraction @ jerk
    fractions[0], fractions[-1] = 0.0, 1.0
    rates = speed @ jerk
    rates[0], rates[-1] = 0.0, 0.0
    return TimeProfile(name, np.maximum.accumulate(np.clip(fractions, 0.0, 1.0)), np.maximum(rates, 0.0))


@cache
def profile(manner: str) -> TimeProfile:
    """The time profile of a named manner (computed once, then cached)."""
    if manner not in MANNERS:
        raise ValueError(f"unknown manner {manner!r}; known: {sorted(MANNERS)}")
    return integrate_manner(MANNERS[manner])


def load_profiles() -> None:
    """Integrate every manner's profile and its peaks now (:func:`profile`,
    :func:`_profile_peaks`): eight integrations and fits, about 0.3 s, that would otherwise
    fall on the first movement of each manner (:func:`motor.compiled.warm_up`)."""
    for manner in MANNERS:
        _profile_peaks(manner)


@cache
def minimum_jerk() -> TimeProfile:
    """The minimum-jerk ease ``10u³ − 15u⁴ + 6u⁵``: zero speed and acceleration at both ends."""
    u = np.linspace(0.0, 1.0, TABLE_SIZE)
    return TimeProfile("minimum_jerk", u**3 * (10.0 - 15.0 * u + 6.0 * u * u), 30.0 * u * u * (1.0 - u) ** 2)


def shortest_duration(length: float, manner: str) -> float:
    """Shortest time (s) in which a rest-to-rest movement of ``length`` metres along the
    profile of ``manner`` stays within that manner's speed and acceleration budget
    (:mod:`motor.trajectory.speed_budget`): peak speed ``length · max f′ / T`` and peak
    acceleration ``length · max |f″| / T²``."""
    if length <= 0.0:
        return 0.0
    peak_rate, peak_acceleration = _profile_peaks(manner)
    limits = budget(manner)
    by_speed = length * peak_rate / limits.peak_speed
    by_acceleration = math.sqrt(length * peak_acceleration / limits.peak_acceleration)  # numpy's sqrt, correctly rounded alike
    return max(by_speed, by_acceleration)


def shortest_durations(lengths: np.ndarray, manners: Sequence[str]) -> np.ndarray:
    """:func:`shortest_duration` (s) of many movements — ``lengths`` (m) and one manner
    each — in one pass over them with its arithmetic (the same numbers, bit for bit)."""
    lengths = np.asarray(lengths, dtype=float)
    names = list(dict.fromkeys(manners))
    code = {name: index for index, name in enumerate(names)}
    which = np.array([code[manner] for manner in manners], dtype=np.int64)
    peaks = np.array([_profile_peaks(name) for name in names]).reshape(-1, 2)
    limits = np.array([(budget(name).peak_speed, budget(name).peak_acceleration) for name in names]).reshape(-1, 2)
    by_speed = lengths * peaks[which, 0] / limits[which, 0]
    by_acceleration = np.sqrt(lengths * peaks[which, 1] / limits[which, 1])
    return np.where(lengths <= 0.0, 0.0, np.maximum(by_speed, by_acceleration))


@cache
def _profile_peaks(manner: str) -> tuple[float, float]:
    """Peak ``f′`` and peak ``|f″|`` of the profile of ``manner`` (per unit time fraction)."""
    shape = profile(manner)
    u = np.linspace(0.0, 1.0, shape.rates.size)
    return float(shape.rates.max()), float(np.max(np.abs(np.gradient(shape.rates, u))))


def movement_duration(kind: str, manner: str = "targetted", base: float = BASE_DURATION) -> float:
    """Duration (seconds) of a sign's movement of ``kind`` performed in ``manner``."""
    if kind not in MOVEMENT_KIND_DURATION:
        raise ValueError(f"unknown movement kind {kind!r}; known: {sorted(MOVEMENT_KIND_DURATION)}")
    if manner not in MANNERS:
        raise ValueError(f"unknown manner {manner!r}; known: {sorted(MANNERS)}")
    return base * MOVEMENT_KIND_DURATION[kind] * MANNERS[manner].duration_scale
