"""The wrist's retraction to rest, bowed around the body where the straight way would
crowd the arm (:mod:`motor.arm.bowed_way`).

:class:`WristRetractionLMP` is a :class:`motor.program.lmp.RetractionLMP` (so a channel
timeline drops it as it drops any retraction a later gesture takes over) that looks at
its straight way when it is activated, as the time profile travels it, and adds the bow
:func:`motor.arm.bowed_way.find_bow` finds (:class:`BowedRetraction`).

Positions are metres in the avatar frame, times seconds.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from motor.arm.bowed_way import SAMPLES, Bow, bow, find_bow
from motor.body.avatar import Avatar
from motor.body.conventions import AVATAR_SIDE
from motor.program.lmp import ChannelState, RetractionLMP, VectorKeyframes


@dataclass(frozen=True, eq=False)
class WristRetractionLMP(RetractionLMP):
    """A wrist's retraction (``(arm, "wrist_position")``) whose way bows around the body
    where the straight way would crowd the arm of ``avatar`` (None: straight)."""

    avatar: Avatar | None = field(default=None, kw_only=True)

    def activate(self, state: ChannelState) -> VectorKeyframes | BowedRetraction:
        straight = super().activate(state)
        if self.avatar is None:
            return straight
        start, rest = straight.values[0], straight.values[-1]
        way = start + straight.time_profile.fraction(np.linspace(0.0, 1.0, SAMPLES))[:, None] * (rest - start)
        found = find_bow(self.avatar, AVATAR_SIDE[self.channel[0]], way)
        return straight if found is None else BowedRetraction(straight, found)


@dataclass(frozen=True, eq=False)
class BowedRetraction:
    """A straight retraction plus ``bow(u) · displacement`` at fraction ``u`` of its time."""

    straight: VectorKeyframes
    bowed: Bow

    @property
    def warnings(self) -> tuple[str, ...]:
        return self.straight.warnings

    def sample(self, times: np.ndarray) -> np.ndarray:
        shape = bow(self._fractions(np.asarray(times, dtype=float)), self.bowed.window)[0]
        return self.straight.sample(times) + shape[:, None] * self.bowed.displacement

    def state(self, time: float) -> ChannelState:
        straight = self.straight.state(time)
        knots = self.straight.knots
        value, slope = bow(self._fractions(np.array([time])), self.bowed.window)
        rate = slope[0] / float(knots[-1] - knots[0]) if knots[0] <= time < knots[-1] else 0.0
        displacement = self.bowed.displacement
        return ChannelState(straight.value + value[0] * displacement, straight.velocity + rate * displacement, float(time))

    def _fractions(self, times: np.ndarray) -> np.ndarray:
        knots = self.straight.knots
        return np.clip((times - knots[0]) / (knots[-1] - knots[0]), 0.0, 1.0)
