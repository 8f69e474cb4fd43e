"""What sign planning produces: each hand's first posture and its timed moves (plain data)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from motor.body.conventions import ARMS
from motor.signing.lmp import Move


class SignPlanningError(ValueError):
    """A sign that cannot be realized; the message names the sign and the reason."""


@dataclass(frozen=True, eq=False)
class HandPose:
    """A hand's posture in numbers: wrist ``(3,)`` m, global rotation ``(4,)``, parameters."""

    wrist: np.ndarray
    rotation: np.ndarray
    shape: np.ndarray

    def channel(self, name: str) -> np.ndarray:
        return {"wrist_position": self.wrist, "hand_rotation": self.rotation, "handshape": self.shape}[name]


@dataclass(frozen=True, eq=False)
class SignPlan:
    """A sign ready to be placed on the clock.

    Attributes:
        gloss: the sign's name.
        duration: length of the sign's own movement, seconds (0 < duration).
        first: each active hand's first posture.
        moves: ``(arm, channel)`` → moves on the sign's clock ``[0, duration]``.
        static: the sign has no movement (the transition into it is then targetted).
        nonmanual: the sign's nonmanual tiers, as parsed.
        warnings: what was assumed or changed to realize it.
    """

    gloss: str
    duration: float
    first: Mapping[str, HandPose]
    moves: Mapping[tuple[str, str], tuple[Move, ...]]
    static: bool
    nonmanual: Mapping[str, tuple] = field(default_factory=dict)
    warnings: tuple[str, ...] = ()

    @property
    def arms(self) -> tuple[str, ...]:
        return tuple(arm for arm in ARMS if arm in self.first)

