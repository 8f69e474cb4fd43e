"""The wrist rotation LMP: the hand's global orientation slerped through key orientations.

Keys are scalar-last unit quaternions in the avatar frame; the targets come from the
extended-finger direction and palm orientation (:mod:`motor.arm.hand_orientation`).
The hand's retraction to rest (:class:`HandRetractionLMP`) turns the way of least cost
(:mod:`motor.arm.hand_turn`), which a slerp need not.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from motor.arm.hand_turn import turn_vector
from motor.body.avatar import Avatar
from motor.body.conventions import AVATAR_SIDE
from motor.program.lmp import (
    Channel,
    ChannelState,
    RetractionLMP,
    RotationKeyframes,
    TimePegs,
    as_profile,
    key_times,
    rotation_keyframes,
    rotation_turn,
)
from motor.trajectory.biocontrol import TimeProfile, minimum_jerk


@dataclass(frozen=True, eq=False)
class WristRotationLMP:
    """Slerp of the hand's orientation through key quaternions ``(m, 4)`` (scalar-last)."""

    side: str
    pegs: TimePegs
    keys: np.ndarray
    key_times: np.ndarray | None = None
    time_profile: TimeProfile | str = field(default_factory=minimum_jerk)

    def __post_init__(self) -> None:
        keys = np.atleast_2d(np.asarray(self.keys, dtype=float))
        norms = np.linalg.norm(keys, axis=-1) if keys.ndim == 2 and keys.shape[1] == 4 else np.zeros(1)
        if keys.ndim != 2 or keys.shape[1] != 4 or np.any(~np.isfinite(norms)) or np.any(norms < 1e-9):
            raise ValueError(f"{self.channel}: keys must be non-zero (m, 4) quaternions, got shape {np.shape(self.keys)}")
        object.__setattr__(self, "keys", keys / norms[:, None])
        object.__setattr__(self, "key_times", key_times(self.pegs, keys.shape[0], self.key_times, str(self.channel)))
        object.__setattr__(self, "time_profile", as_profile(self.time_profile))

    @property
    def channel(self) -> Channel:
        return (self.side, "hand_rotation")

    def activate(self, state: ChannelState) -> RotationKeyframes:
        return rotation_keyframes(self.channel, state, self.keys, self.key_times, self.time_profile)


@dataclass(frozen=True, eq=False)
class HandRetractionLMP(RetractionLMP):
    """The hand's orientation (``(arm, "hand_rotation")``) back to rest, turning the way of
    least cost for the hand of ``avatar`` (None: a slerp's way): fingers raised and
    lowered to rest turn about half a turn either way, and a slerp may sweep them back
    toward the body."""

    avatar: Avatar | None = field(default=None, kw_only=True)

    def activate(self, state: ChannelState) -> RotationKeyframes:
        if self.avatar is None:
            return super().activate(state)
        rest = np.asarray(self.rest, dtype=float)
        step = turn_vector(self.avatar, AVATAR_SIDE[self.channel[0]], np.asarray(state.value, dtype=float), rest)
        return rotation_turn(self.channel, state, rest, self.pegs.ready, self.time_profile, step)
