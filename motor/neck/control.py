"""The neck motor module: torso, shoulders, neck, head and eyes of every frame.

:class:`NeckControl` is what :class:`motor.control.MotorControl` holds beside the arms.
It keeps the activated neck LMPs — gaze shifts on one :class:`ChannelTimeline`
(:mod:`motor.neck.gaze`), head lexemes (:mod:`motor.neck.lexemes`) and body and shoulder
movements (:mod:`motor.neck.trunk`), which add up — and :meth:`NeckControl.pose` applies
them to frames whose arms are already solved, in this order (seed 004: joint-angle LMPs
act on the solution configuration after the arm's IK):

1. the torso rotation at ``vl5`` and the shoulders' at the sternoclavicular joints
   (composed onto the clavicle rotation the IK chose);
2. the head: its world orientation faces the gaze channel's head direction (shortest
   arc from straight ahead, so it never rolls) turned by the head lexemes in its own
   frame; relative to the torso it is shared by the neck joints — :data:`motor.neck.posing.NECK_SHARES` of
   the rotation at ``vc7`` and ``vc4``, the rest at ``skullbase``, which takes exactly
   what is left so that the head's orientation is exact; a protrusion flexes ``vc7``
   and the skull base makes up for it;
3. each eye, from its actual centre in that pose, aims at the gaze channel's point:
   the shortest rotation from straight ahead in the head's frame (Listing's law: no
   torsion about the line of sight), at most :data:`motor.neck.posing.EYE_RANGE` from it. This is the
   vestibulo-ocular reflex of the model: while the head moves or nods, the eyes stay on
   the target.

The eyes turn at the H-Anim eyeball joints ``l_eyeball_joint``/``r_eyeball_joint`` when
the avatar has them. The trunk and the channels are sampled over all frames at once; steps
2 and 3 are compiled loops over the frames (:mod:`motor.neck.posing`).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from motor import quaternion as quat
from motor.body.avatar import Avatar
from motor.neck.gaze import GazeLMP, eye_centre, rest_state, sample_shifts
from motor.neck.lexemes import HeadMovementLMP
from motor.neck.posing import pose_head_and_eyes
from motor.neck.trunk import TrunkLMP
from motor.program.lmp import ChannelState, ChannelTimeline

EYES: tuple[str, ...] = ("l_eyeball_joint", "r_eyeball_joint")
GAZE_CHANNEL = ("neck", "gaze")
#: Gaze shifts that lost control are dropped this many at a time (:meth:`NeckControl.forget_before`).
FORGET_BATCH = 8

NeckLMP = GazeLMP | HeadMovementLMP | TrunkLMP


class NeckControl:
    """The neck LMPs activated so far, applied to frames (module docstring).

    ``hands(arm, times)`` gives the palm centre of ``"right"``/``"left"`` at sorted
    ``times``, for gaze that follows a hand.
    """

    def __init__(self, avatar: Avatar, hands: Callable[[str, np.ndarray], np.ndarray] | None = None) -> None:
        self.avatar = avatar
        self.hands = hands
        self.origin = eye_centre(avatar)
        self._initial = ChannelState.at_rest(rest_state(avatar))
        self._gazes: list[GazeLMP] = []
        self._timeline: ChannelTimeline | None = None
        self._heads: list[HeadMovementLMP] = []
        self._trunks: list[TrunkLMP] = []
        index = avatar.joint_index
        self._torso = index("vl5")
        self._clavicles = (index("l_sternoclavicular"), index("r_sternoclavicular"))
        self._neck = np.array([index("vc7"), index("vc4"), index("skullbase")])
        self._path = np.array(_path(avatar, int(self._neck[0])), dtype=np.int64)
        self._eyes = np.array([index(name) for name in EYES if name in avatar.joint_names], dtype=np.int64)
        self._joint_offsets = np.ascontiguousarray(avatar.offsets, dtype=float)
        self._eye_offsets = np.array([avatar.rest_positions[eye] - avatar.rest_positions[self._neck[2]] for eye in self._eyes]).reshape(-1, 3)

    # -- activation ---------------------------------------------------------------

    def activate(self, lmp: NeckLMP) -> float:
        """Hand an LMP to its channel; returns the time (s) from which it changes frames."""
        if isinstance(lmp, GazeLMP):
            self._activate_gaze(lmp)
            return lmp.pegs.start
        if isinstance(lmp, HeadMovementLMP):
            self._heads.append(lmp)
        elif isinstance(lmp, TrunkLMP):
            self._trunks.append(lmp)
        else:
            raise TypeError(f"the neck has no channel for {type(lmp).__name__}")
        return lmp.first

    def _activate_gaze(self, lmp: GazeLMP) -> None:
        """Add a gaze LMP; returns to rest of earlier behaviours that would start after it
        are dropped (the new gaze keeps the eyes)."""
        kept = [g for g in self._gazes if lmp.returning or not (g.returning and g.pegs.start > lmp.pegs.start)]
        dropped = len(kept) < len(self._gazes)
        self._gazes = [*kept, lmp]
        last = self._timeline.starts[-1] if self._timeline is not None and self._timeline.starts.size else -np.inf
        if self._timeline is not None and not dropped and lmp.pegs.start >= last:
            self._timeline = self._timeline.extended(lmp)
        else:
            self._timeline = None

    def timeline(self) -> ChannelTimeline:
        """The gaze channel's timeline of everything activated so far."""
        if self._timeline is None:
            self._timeline = ChannelTimeline.build(GAZE_CHANNEL, self._gazes, self._initial)
        return self._timeline

    def gaze_state(self, time: float) -> ChannelState:
        """Gaze point and head direction at ``time`` given what is activated."""
        return self.timeline().state(time)

    def shift_duration(self, lmp: GazeLMP, at: float) -> float:
        """Seconds ``lmp`` would take to bring eyes and head on target from the gaze at ``at``."""
        state = self.gaze_state(at)
        return lmp.natural_duration(state.value[:3], state.value[3:6], at)

    def head_moves(self, time: float) -> bool:
        """Whether a head lexeme is in progress at ``time``."""
        return any(lmp.first <= time <= lmp.last for lmp in self._heads)

    def interrupt(self, at: float, back: GazeLMP) -> None:
        """Drop what would start after ``at`` and look back to rest with ``back``."""
        self._heads = [lmp for lmp in self._heads if lmp.first <= at]
        self._trunks = [lmp for lmp in self._trunks if lmp.first <= at]
        self._gazes = [lmp for lmp in self._gazes if lmp.pegs.start <= at]
        self._timeline = None
        self._activate_gaze(back)

    def forget_before(self, horizon: float) -> None:
        """Drop what lost control before ``horizon`` seconds (memory stays flat): gaze
        shifts :data:`FORGET_BATCH` at a time (or all but the last), as each drop computes
        the gaze where the kept history starts."""
        self._heads = [lmp for lmp in self._heads if lmp.last >= horizon]
        self._trunks = [lmp for lmp in self._trunks if lmp.last >= horizon]
        timeline = self.timeline()
        keep = int(np.searchsorted(timeline.starts, horizon, side="right")) - 1
        if keep <= 0 or keep < min(FORGET_BATCH, timeline.starts.size - 1):
            return
        start = float(timeline.starts[keep])
        state = timeline.realizations[keep - 1].state(start)
        self._initial = ChannelState(np.asarray(state.value, dtype=float), np.asarray(state.velocity, dtype=float), start)
        self._timeline = ChannelTimeline(GAZE_CHANNEL, self._initial, timeline.lmps[keep:], timeline.realizations[keep:], timeline.starts[keep:])
        self._gazes = list(timeline.lmps[keep:])

    # -- frames -------------------------------------------------------------------

    def pose(self, times: np.ndarray, rotations: np.ndarray) -> np.ndarray:
        """``rotations (n, J, 4)`` (arms solved) with torso, shoulders, neck, head and eyes
        set for ``times`` (module docstring); changed in place and returned."""
        t = np.asarray(times, dtype=float)
        if t.size == 0:
            return rotations
        self._trunk(t, rotations)
        gaze = _sample(self.timeline(), t)
        offsets = np.zeros((t.size, 4))
        for lmp in self._heads:
            if lmp.last >= t[0] and lmp.first <= t[-1]:
                offsets += lmp.sample(t)
        rows = np.ascontiguousarray(rotations)
        pose_head_and_eyes(rows, self._path, self._neck, self._eyes, self._joint_offsets, self._eye_offsets, gaze, offsets)
        if rows is not rotations:
            rotations[...] = rows
        return rotations

    def _trunk(self, t: np.ndarray, rotations: np.ndarray) -> None:
        active = [lmp for lmp in self._trunks if lmp.last >= t[0] and lmp.first <= t[-1]]
        if not active:
            return
        total = sum(lmp.sample(t) for lmp in active)
        rotations[:, self._torso] = quat.multiply(quat.from_rotation_vector(total[:, :3]), rotations[:, self._torso])
        for joint, part in zip(self._clavicles, (total[:, 3:6], total[:, 6:9])):
            rotations[:, joint] = quat.multiply(quat.from_rotation_vector(part), rotations[:, joint])


def _sample(timeline: ChannelTimeline, times: np.ndarray) -> np.ndarray:
    """The gaze timeline's values at sorted ``times``: the initial value before its first
    shift, then the shifts in control, all in one pass (:func:`motor.neck.gaze.sample_shifts`)."""
    out = np.empty((times.size, np.size(timeline.initial.value)))
    out[:] = timeline.initial.value
    owner = np.searchsorted(timeline.starts, times, side="right") - 1
    first = int(np.searchsorted(owner, 0, side="left"))
    if first == times.size:
        return out
    low = int(owner[first])
    out[first:] = sample_shifts(timeline.realizations[low : int(owner[-1]) + 1], owner[first:] - low, times[first:])
    return out


def _path(avatar: Avatar, joint: int) -> tuple[int, ...]:
    """The joints from the root down to ``joint``'s parent."""
    chain = []
    parent = int(avatar.parents[joint])
    while parent >= 0:
        chain.append(parent)
        parent = int(avatar.parents[parent])
    return tuple(reversed(chain))
