"""Attack, sustain and release: the temporal trajectory of a non-manual movement (seed 000, 4).

Seed 000 times every non-manual movement and facial morph with the same temporal
trajectories as the hands: an amount that ramps up from zero to its full value during an
*attack*, holds it during a *sustain* and falls back to zero during a *release*. The ramps
follow the biocontrol time profiles of :mod:`motor.trajectory.biocontrol` (the attack in
the movement's manner, targetted by default; the release lax), so a head tilt, a raised
brow and a mouth picture speed up and settle like a hand movement of the same manner.

An :class:`Envelope` is that amount as a function of time, 0 before ``start`` and after
``end``, 1 between ``peak`` and ``release``; :meth:`Envelope.sample` takes an array of
times (seconds on the utterance clock) and returns the amounts.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from motor.trajectory.biocontrol import MANNERS, TimeProfile, profile

#: Attack and release of a non-manual movement when nothing else is known, seconds.
DEFAULT_ATTACK = 0.2
DEFAULT_RELEASE = 0.25


@dataclass(frozen=True, eq=False)
class Envelope:
    """Amount 0 → 1 → 0 over ``start ≤ peak ≤ release ≤ end`` (seconds).

    ``attack`` and ``decay`` are the time profiles of the rise (``start`` → ``peak``) and
    the fall (``release`` → ``end``).
    """

    start: float
    peak: float
    release: float
    end: float
    attack: TimeProfile
    decay: TimeProfile

    def __post_init__(self) -> None:
        values = (self.start, self.peak, self.release, self.end)
        if not all(np.isfinite(v) for v in values):
            raise ValueError(f"envelope times must be finite, got {values}")
        if not self.start <= self.peak <= self.release <= self.end:
            raise ValueError(f"envelope times out of order: start {self.start}, peak {self.peak}, release {self.release}, end {self.end}")

    @classmethod
    def around(cls, peak: float, release: float, attack: float = DEFAULT_ATTACK, decay: float = DEFAULT_RELEASE,
               manner: str = "targetted") -> Envelope:  # fmt: skip
        """Full from ``peak`` to ``release``, rising over ``attack`` seconds before it in
        ``manner`` and falling over ``decay`` seconds after it along the lax profile."""
        name = manner if manner in MANNERS else "targetted"
        release = max(release, peak)
        return cls(peak - max(attack, 0.0), peak, release, release + max(decay, 0.0), profile(name), profile("lax"))

    def sample(self, times: np.ndarray) -> np.ndarray:
        """The amount (0–1) at each of ``times``."""
        t = np.asarray(times, dtype=float)
        rise = self.attack.fraction((t - self.start) / max(self.peak - self.start, 1e-9))
        fall = 1.0 - self.decay.fraction((t - self.release) / max(self.end - self.release, 1e-9))
        amount = np.where(t < self.peak, rise, np.where(t > self.release, fall, 1.0))
        return np.where((t < self.start) | (t > self.end), 0.0, amount)
