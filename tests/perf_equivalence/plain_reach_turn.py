"""The trunk's turn for reaching across the body as it stood before the reach check was
limited to the instants where it can matter (issue 19): :func:`motor.arm.reach_turn.trunk_turn`
with every instant's reach worked out — the plain path ``test_reach_turn.py`` holds the
narrowed one to, bit for bit. Not used by mura itself."""

from __future__ import annotations

import numpy as np

from motor.arm.reach_turn import MAX_TURN, TrunkTurn, _demand, _out_of_reach, turned
from motor.body.avatar import Avatar


def trunk_turn(avatar: Avatar, left: np.ndarray, right: np.ndarray) -> TrunkTurn | None:
    front = avatar.grid.front
    toward_left = MAX_TURN * _demand(right, -1.0, front)
    toward_right = MAX_TURN * _demand(left, 1.0, front)
    toward_left = toward_left * (1.0 - _out_of_reach(avatar, "l", left, toward_left))
    toward_right = toward_right * (1.0 - _out_of_reach(avatar, "r", right, -toward_right))
    return turned(avatar, toward_left - toward_right)
