"""How fast a wrist may move: the peak-speed and acceleration budget per movement manner.

Human gesture mostly keeps the wrist below about 1.5 m/s; a minimum-jerk movement of
amplitude ``A`` (m) over ``T`` (s) peaks at ``1.875 A / T`` m/s and ``5.774 A / T²`` m/s².
Planning never squeezes a stroke or a preparation beyond its manner's budget: when an
affiliate or an absolute timing asks for more, the scheduler relaxes the timing (in the
documented order) and reports it instead. Both the trajectory former and the scheduler
read the budget from here, so they agree on what is performable.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: Peak speed (m/s) and peak acceleration (m/s²) of a minimum-jerk movement, per A/T and A/T².
MIN_JERK_PEAK_SPEED = 1.875
MIN_JERK_PEAK_ACCELERATION = 10.0 / math.sqrt(3.0)


@dataclass(frozen=True)
class SpeedBudget:
    """The most a manner allows: peak wrist speed (m/s) and peak acceleration (m/s²)."""

    peak_speed: float
    peak_acceleration: float

    def shortest_duration(self, amplitude: float) -> float:
        """Shortest time (s) for a rest-to-rest movement of ``amplitude`` metres that stays
        within the budget, on a minimum-jerk profile."""
        if amplitude <= 0.0:
            return 0.0
        by_speed = MIN_JERK_PEAK_SPEED * amplitude / self.peak_speed
        by_acceleration = math.sqrt(MIN_JERK_PEAK_ACCELERATION * amplitude / self.peak_acceleration)
        return max(by_speed, by_acceleration)


#: Budgets per manner (HamNoSys/MURML manner names; ``targetted`` is the default).
BUDGETS: dict[str, SpeedBudget] = {
    "targetted": SpeedBudget(1.5, 15.0),
    "lax": SpeedBudget(1.2, 10.0),
    "slow": SpeedBudget(0.8, 6.0),
    "fast": SpeedBudget(2.5, 30.0),
    "sudden_stop": SpeedBudget(2.5, 40.0),
    "tense": SpeedBudget(1.2, 12.0),
    "hard_contact": SpeedBudget(2.0, 40.0),
    "linear": SpeedBudget(1.5, 15.0),
}
#: The ceiling no relaxation goes beyond (the design's target for peak wrist speed).
ABSOLUTE_PEAK_SPEED = 3.0
#: The acceleration ceiling that goes with it, m/s² (the most abrupt manners' budget).
ABSOLUTE_PEAK_ACCELERATION = 40.0
#: Both ceilings as a budget: what the motion never exceeds, whatever the timing.
CEILING = SpeedBudget(ABSOLUTE_PEAK_SPEED, ABSOLUTE_PEAK_ACCELERATION)


def budget(manner: str | None) -> SpeedBudget:
    """The budget of ``manner`` (unknown or None: ``targetted``)."""
    return BUDGETS.get(manner or "targetted", BUDGETS["targetted"])
