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
1% of the target (or, when truncated, until it arrives), with time rescaled to one unit
and ``f`` normalized to end at exactly 1. The end speed is then not zero: that is the
"sharp stop" of targetted movement — and the start is a step in acceleration. A movement
starts and ends at rest with zero acceleration, so the speed profile ``f′`` is then
windowed: multiplied by ``w(u/ε) · w((1 − u)/ε)`` with the smoothstep ``w(x) = 3x² − 2x³``
(1 from x = 1 on) over :data:`END_SMOOTHING` ``= ε`` of the duration at each end, and
integrated again. The sharp stop stays sharp (it takes the last tenth of the movement)
but is continuous in speed and acceleration.

Durations: seed 000 keeps a movement's duration independent of its size, longer for
curved arcs and longer still for circles; :func:`movement_duration` gives
``BASE_DURATION · MOVEMENT_KIND_DURATION[kind] · manner.duration_scale``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import numpy as np
from scipy.integrate import solve_ivp

#: Samples of each profile table.
TABLE_SIZE = 1025
#: Duration of a plain straight movement in the normal (targetted) manner, seconds.
BASE_DURATION = 0.4
#: Relative durations per movement kind (seed 000, 4.5: arcs slower, circles slower still).
MOVEMENT_KIND_DURATION: dict[str, float] = {"straight": 1.0, "curved": 1.3, "circle": 1.7}
#: The fraction of the path counted as arrived ("settled to within 1%").
SETTLED = 0.99
#: Fraction of a movement's duration over which its speed profile is brought to rest
#: with zero acceleration at each end (module docstring).
END_SMOOTHING = 0.1


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
    """

    name: str
    fractions: np.ndarray
    rates: np.ndarray

    def fraction(self, u: np.ndarray | float) -> np.ndarray:
        """Path fraction at time fractions ``u`` (clipped to [0, 1]), any shape."""
        grid = np.linspace(0.0, 1.0, self.fractions.size)
        return np.interp(np.clip(u, 0.0, 1.0), grid, self.fractions)

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


def _smoothstep(x: np.ndarray) -> np.ndarray:
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


def at_rest(name: str, speeds: np.ndarray) -> TimeProfile:
    """The profile of a speed curve sampled at equal time steps over a movement, windowed
    to start and stop at rest with zero acceleration (module docstring) and normalized."""
    u = np.linspace(0.0, 1.0, speeds.size)
    rates = speeds * _smoothstep(u / END_SMOOTHING) * _smoothstep((1.0 - u) / END_SMOOTHING)
    cumulative = np.concatenate([[0.0], np.cumsum(0.5 * (rates[1:] + rates[:-1]) * np.diff(u))])
    total = float(cumulative[-1])
    fractions = cumulative / total
    fractions[-1] = 1.0
    return TimeProfile(name, fractions, rates / total)


@cache
def profile(manner: str) -> TimeProfile:
    """The time profile of a named manner (computed once, then cached)."""
    if manner not in MANNERS:
        raise ValueError(f"unknown manner {manner!r}; known: {sorted(MANNERS)}")
    return integrate_manner(MANNERS[manner])


@cache
def minimum_jerk() -> TimeProfile:
    """The minimum-jerk ease ``10u³ − 15u⁴ + 6u⁵``: zero speed and acceleration at both ends."""
    u = np.linspace(0.0, 1.0, TABLE_SIZE)
    return TimeProfile("minimum_jerk", u**3 * (10.0 - 15.0 * u + 6.0 * u * u), 30.0 * u * u * (1.0 - u) ** 2)


def movement_duration(kind: str, manner: str = "targetted", base: float = BASE_DURATION) -> float:
    """Duration (seconds) of a sign's movement of ``kind`` performed in ``manner``."""
    if kind not in MOVEMENT_KIND_DURATION:
        raise ValueError(f"unknown movement kind {kind!r}; known: {sorted(MOVEMENT_KIND_DURATION)}")
    if manner not in MANNERS:
        raise ValueError(f"unknown manner {manner!r}; known: {sorted(MANNERS)}")
    return base * MOVEMENT_KIND_DURATION[kind] * MANNERS[manner].duration_scale
