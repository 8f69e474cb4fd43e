"""Blinks: spontaneous ones at a natural rate, and one at every chunk boundary.

People blink spontaneously some 15–20 times a minute at rest and more while talking,
and speakers tend to blink at the boundaries of intonational phrases. :class:`Blinks`
gives both, deterministically for a given seed:

* **Spontaneous** blinks form a Poisson process of rate :data:`SPONTANEOUS_RATE`, drawn
  block by block (:data:`BLOCK` seconds of the utterance clock each, block ``k`` from the
  random generator seeded with ``(seed, k)``), so a blink's time depends only on the seed
  and its block — never on how the frames are windowed. A spontaneous blink closer than
  :data:`REFRACTORY` seconds after the one drawn before it, or to a boundary blink, is
  dropped.
* **Boundary** blinks start :data:`BOUNDARY_DELAY` seconds after a chunk's last word.

Each blink closes the lids in :data:`CLOSING` seconds (minimum jerk), keeps them closed
for :data:`CLOSED` and reopens them, more slowly, in :data:`OPENING`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from motor.face.arkit import FACE_INDEX
from motor.trajectory.biocontrol import minimum_jerk

#: Spontaneous blinks per second (17 a minute).
SPONTANEOUS_RATE = 17.0 / 60.0
#: Length of a block of the utterance clock drawn at once, seconds.
BLOCK = 10.0
#: Shortest time between a spontaneous blink and the blink before it, seconds.
REFRACTORY = 1.0
#: Phases of one blink, seconds.
CLOSING, CLOSED, OPENING = 0.08, 0.03, 0.17
#: A boundary blink follows the chunk's last word by this much, seconds.
BOUNDARY_DELAY = 0.05
DURATION = CLOSING + CLOSED + OPENING


def closure(elapsed: np.ndarray) -> np.ndarray:
    """Lid closure (0 open – 1 closed) ``elapsed`` seconds after a blink began."""
    ease = minimum_jerk()
    closing = ease.fraction(elapsed / CLOSING)
    opening = 1.0 - ease.fraction((elapsed - CLOSING - CLOSED) / OPENING)
    shape = np.where(elapsed < CLOSING + CLOSED, closing, opening)
    return np.where((elapsed < 0.0) | (elapsed > DURATION), 0.0, shape)


class Blinks:
    """The blinks of one performance (module docstring); ``seed`` fixes the spontaneous ones."""

    def __init__(self, seed: int = 0) -> None:
        self.seed = int(seed)
        self._boundaries: list[float] = []

    def add(self, onset: float) -> None:
        """A blink beginning at ``onset`` seconds, besides the spontaneous ones (which keep
        :data:`REFRACTORY` away from it)."""
        self._boundaries.append(float(onset))
        self._boundaries.sort()

    def add_boundary(self, last_word_end: float) -> None:
        """The blink after a chunk whose last word ends at ``last_word_end`` (seconds)."""
        self.add(float(last_word_end) + BOUNDARY_DELAY)

    def forget_before(self, horizon: float) -> None:
        """Drop boundary blinks over before ``horizon`` (memory stays flat)."""
        self._boundaries = [b for b in self._boundaries if b + DURATION + REFRACTORY >= horizon]

    def spontaneous(self, start: float, end: float) -> np.ndarray:
        """Spontaneous blink onsets in ``[start, end)``, sorted."""
        first, last = math.floor(start / BLOCK) - 1, math.floor(end / BLOCK)
        drawn = np.concatenate([self._block(k) for k in range(first, last + 1)])
        keep = np.ones(drawn.size, dtype=bool)
        keep[1:] = np.diff(drawn) >= REFRACTORY
        onsets = drawn[keep]
        boundaries = np.array(self._boundaries)
        if boundaries.size:
            nearest = np.min(np.abs(onsets[:, None] - boundaries[None, :]), axis=1)
            onsets = onsets[nearest >= REFRACTORY]
        return onsets[(onsets >= start) & (onsets < end)]

    def onsets(self, start: float, end: float) -> np.ndarray:
        """Every blink onset whose blink shows in ``[start, end)``, sorted."""
        spontaneous = self.spontaneous(start - DURATION, end)
        boundaries = np.array([b for b in self._boundaries if start - DURATION <= b < end])
        return np.sort(np.concatenate([spontaneous, boundaries]))

    def sample(self, times: np.ndarray) -> np.ndarray:
        """Lid closure at sorted ``times``, ``(n,)``."""
        t = np.asarray(times, dtype=float)
        if t.size == 0:
            return np.zeros(0)
        onsets = self.onsets(float(t[0]), float(t[-1]) + 1e-9)
        if onsets.size == 0:
            return np.zeros(t.size)
        latest = np.searchsorted(onsets, t, side="right") - 1
        current = np.where(latest >= 0, closure(t - onsets[np.maximum(latest, 0)]), 0.0)
        previous = np.where(latest >= 1, closure(t - onsets[np.maximum(latest - 1, 0)]), 0.0)
        return np.maximum(current, previous)

    def _block(self, index: int) -> np.ndarray:
        rng = np.random.default_rng([self.seed & 0xFFFFFFFF, index & 0xFFFFFFFF, index < 0])
        count = rng.poisson(SPONTANEOUS_RATE * BLOCK)
        return np.sort(index * BLOCK + rng.uniform(0.0, BLOCK, count))


@dataclass(frozen=True, eq=False)
class BlinkLMP:
    """One blink beginning at ``onset`` seconds, as a face track (a HamNoSys ``BB`` eyelid
    code, a BML blink)."""

    onset: float
    channel: tuple[str, str] = ("face", "blink")

    @property
    def columns(self) -> np.ndarray:
        return np.array([FACE_INDEX["eyeBlinkLeft"], FACE_INDEX["eyeBlinkRight"]])

    @property
    def start(self) -> float:
        return self.onset

    @property
    def end(self) -> float:
        return self.onset + DURATION

    def sample(self, times: np.ndarray) -> np.ndarray:
        return np.repeat(closure(np.asarray(times, dtype=float) - self.onset)[:, None], 2, axis=1)
