"""Gaze: eyes and head turned together toward a target, with the eye–head split.

**Targets** (:class:`GazeTarget`): a point in space (a scene place ``$Loc-…`` resolves to
one), a direction from the eyes, the listener (:func:`listener`: an addressee of the
avatar's height :data:`LISTENER_DISTANCE` ahead), a hand (its palm centre, moving with
it), or rest (straight ahead, far away). :func:`gaze_target` is the constructor a
realizer calls with a name (``Listener``, ``RightHand``, ``Ahead``, ``Up`` …), and
:func:`gaze` builds the LMP — for MURML ``GazeDirection``, the HamNoSys eye-gaze tier and
BML ``<gaze target=…/>`` alike.

**The split.** For a gaze direction at angle ``A`` from straight ahead the head turns
``H = max(GAIN · (A − EYE_ONLY), A − EYE_LIMIT)``, at most :data:`HEAD_LIMIT`, along the
great circle toward the target; the eyes do the rest. Small shifts (under
:data:`EYE_ONLY`, 15°) are made by the eyes alone; beyond that the head takes
:data:`GAIN` (0.65) of the excess, and all of what the eyes cannot reach (they stay
within :data:`EYE_LIMIT`, 35°, of the head's direction). The numbers are mura's, chosen
after the well-known pattern of human gaze shifts: an eye-only range of 15–20°, a head
contribution growing about linearly with the amplitude beyond it, and an oculomotor range
of about ±45° that people rarely use to its end.

**Timing.** The eyes lead: they reach the target in a saccade of the main sequence,
``0.021 + 0.0022 · A°`` seconds (A the change of gaze, degrees); the head starts
:data:`HEAD_LAG` later and takes ``0.25 + 0.004 · ΔH°`` seconds (mura's numbers for a
head movement of ΔH degrees), both along minimum-jerk profiles. Once the eyes are on the
target they stay on it while the head is still turning — the vestibulo-ocular reflex —
because the eye rotations are solved per frame from the head's actual pose
(:mod:`motor.neck.control`). A moving target (a hand) is pursued.

The gaze channel's value is the point looked at (3, metres, avatar frame) followed by the
direction the head faces (3, unit, avatar frame); gaze LMPs hand over on a
:class:`motor.program.lmp.ChannelTimeline` (the latest to start is in control, starting
from where the previous one left the eyes and the head).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from motor import quaternion as quat
from motor.body.avatar import Avatar
from motor.neck.shift_sampling import shift_values
from motor.program.lmp import ChannelState, TimePegs
from motor.trajectory.biocontrol import minimum_jerk

CHANNEL = ("neck", "gaze")
FORWARD = np.array([0.0, 0.0, 1.0])
#: Eye–head split (module docstring), radians.
EYE_ONLY = np.radians(15.0)
GAIN = 0.65
EYE_LIMIT = np.radians(35.0)
HEAD_LIMIT = np.radians(70.0)
#: Saccade main sequence: seconds = SACCADE_BASE + SACCADE_RATE · degrees.
SACCADE_BASE, SACCADE_RATE = 0.021, 0.0022
#: Head movement: seconds = HEAD_BASE + HEAD_RATE · degrees; it starts HEAD_LAG after the eyes.
HEAD_BASE, HEAD_RATE, HEAD_LAG = 0.25, 0.004, 0.03
#: Distance of the listener and of "far ahead", metres.
LISTENER_DISTANCE = 1.2
FAR = 10.0
#: Names of targets :func:`gaze_target` knows (lower case, without ``_``/``-``/spaces).
TARGET_NAMES: dict[str, str] = {
    "listener": "listener", "addressee": "listener", "user": "listener", "interlocutor": "listener",
    "camera": "listener", "ad": "listener",
    "righthand": "right", "lefthand": "left", "hand": "right", "hands": "both", "dominanthand": "right",
    "ahead": "ahead", "front": "ahead", "forward": "ahead", "far": "ahead", "fr": "ahead", "rest": "ahead",
    "up": "up", "down": "down", "left": "left_side", "right": "right_side",
}  # fmt: skip
_DIRECTIONS = {
    "ahead": (0.0, 0.0, 1.0), "up": (0.0, 0.45, 1.0), "down": (0.0, -0.5, 1.0),
    "left_side": (0.6, 0.0, 1.0), "right_side": (-0.6, 0.0, 1.0),
}  # fmt: skip


class UnknownGazeTarget(ValueError):
    """A gaze target name no table knows."""


def eye_centre(avatar: Avatar) -> np.ndarray:
    """The point between the eyes at rest, metres: the eyeball joints' midpoint, or the
    ``eyes`` site set back 1 cm, or 0.1 m above the skull base."""
    names = [n for n in ("l_eyeball_joint", "r_eyeball_joint") if n in avatar.joint_names]
    if len(names) == 2:
        return np.mean([avatar.rest_positions[avatar.joint_index(n)] for n in names], axis=0)
    if "eyes" in avatar.sites:
        site = avatar.sites["eyes"]
        return avatar.rest_positions[site.bone] + site.offset - 0.01 * FORWARD
    return avatar.rest_positions[avatar.joint_index("skullbase")] + np.array([0.0, 0.1, 0.08])


@dataclass(frozen=True, eq=False)
class GazeTarget:
    """Where to look: ``points(times) → (n, 3)`` metres in the avatar frame, a label for
    messages, and whether it stands still (then the point of any time will do)."""

    label: str
    points: Callable[[np.ndarray], np.ndarray]
    fixed: bool = False


def point(position: np.ndarray, label: str = "") -> GazeTarget:
    """A fixed point (metres, avatar frame)."""
    p = np.asarray(position, dtype=float).reshape(3)
    if not np.all(np.isfinite(p)):
        raise ValueError(f"gaze target {label or p}: not a finite point")
    return GazeTarget(label or f"point {np.round(p, 3).tolist()}", lambda times: np.broadcast_to(p, (np.size(times), 3)).copy(), fixed=True)


def direction(avatar: Avatar, vector: np.ndarray, label: str = "", distance: float = FAR) -> GazeTarget:
    """A direction from the eyes (avatar frame), looked at ``distance`` metres away."""
    v = np.asarray(vector, dtype=float).reshape(3)
    length = float(np.linalg.norm(v))
    if not np.isfinite(length) or length < 1e-9:
        raise ValueError(f"gaze direction {label or v.tolist()}: has no length")
    return point(eye_centre(avatar) + distance * v / length, label or f"direction {np.round(v / length, 3).tolist()}")


def listener(avatar: Avatar) -> GazeTarget:
    """An addressee of the avatar's height, :data:`LISTENER_DISTANCE` ahead."""
    return point(eye_centre(avatar) + LISTENER_DISTANCE * FORWARD, "the listener")


def rest(avatar: Avatar) -> GazeTarget:
    """Straight ahead, far away: where the eyes rest."""
    return direction(avatar, FORWARD, "rest")


def gaze_target(avatar: Avatar, name: str, hands: Callable[[str, np.ndarray], np.ndarray] | None = None) -> GazeTarget:
    """The target a name stands for (:data:`TARGET_NAMES`, case-insensitive); ``hands(arm,
    times)`` gives a hand's palm centre for the hand targets. Raises
    :class:`UnknownGazeTarget` listing the known names."""
    key = TARGET_NAMES.get(name.strip().lower().replace("_", "").replace("-", "").replace(" ", ""))
    if key is None:
        raise UnknownGazeTarget(f"unknown gaze target {name!r} (known: {', '.join(sorted(set(TARGET_NAMES)))})")
    if key == "listener":
        return listener(avatar)
    if key in _DIRECTIONS:
        return direction(avatar, np.array(_DIRECTIONS[key]), name)
    if hands is None:
        raise UnknownGazeTarget(f"gaze target {name!r}: no hands to look at here")
    if key == "both":
        return GazeTarget("both hands", lambda times: 0.5 * (hands("right", times) + hands("left", times)))
    return GazeTarget(f"the {key} hand", lambda times, arm=key: hands(arm, times))


def head_direction(gaze: np.ndarray, share: float | None = None) -> np.ndarray:
    """Directions ``(n, 3)`` the head faces for unit gaze directions ``(n, 3)``: the split
    of the module docstring, or ``share`` of the way when given (1: facing the target)."""
    g = quat.normalize(np.asarray(gaze, dtype=float))
    angle = np.arccos(np.clip(g @ FORWARD, -1.0, 1.0))
    if share is None:
        head = np.minimum(np.maximum(GAIN * np.maximum(angle - EYE_ONLY, 0.0), angle - EYE_LIMIT), HEAD_LIMIT)
    else:
        head = np.minimum(share * angle, HEAD_LIMIT)
    fraction = np.where(angle > 1e-9, head / np.where(angle > 1e-9, angle, 1.0), 0.0)
    turn = quat.between_vectors(FORWARD, g)
    return quat.rotate(quat.slerp(quat.IDENTITY, turn, fraction), FORWARD)


def saccade_duration(angle: float) -> float:
    """Seconds of a saccade of ``angle`` radians (main sequence)."""
    return SACCADE_BASE + SACCADE_RATE * float(np.degrees(angle))


def head_duration(angle: float) -> float:
    """Seconds of a head movement of ``angle`` radians."""
    return HEAD_BASE + HEAD_RATE * float(np.degrees(angle))


@dataclass(frozen=True, eq=False)
class GazeLMP:
    """Look at ``target`` from ``pegs.start`` on until another gaze LMP takes over.

    ``head`` is what the head faces instead of the eye–head split's direction (a MURML
    ``Neck`` direction), ``head_share`` a fixed share of the gaze angle the head takes
    instead of the split (1: the head faces the target). ``origin`` is the point between
    the eyes at rest, from which directions are measured. ``returning`` marks the return
    to rest after a behaviour, which gives way to any gaze activated later that starts
    before it.
    """

    pegs: TimePegs
    target: GazeTarget
    origin: np.ndarray
    head: GazeTarget | None = None
    head_share: float | None = None
    returning: bool = False
    channel: tuple[str, str] = CHANNEL

    def activate(self, state: ChannelState) -> GazeShift:
        value = np.asarray(state.value, dtype=float)
        return GazeShift(self, float(state.time), value[:3].copy(), quat.normalize(value[3:6]))

    def natural_duration(self, from_point: np.ndarray, from_head: np.ndarray, at: float) -> float:
        """Seconds from ``at`` until eyes and head are on target, starting from the given gaze."""
        shift = GazeShift(self, at, np.asarray(from_point, dtype=float), quat.normalize(np.asarray(from_head, dtype=float)))
        return shift.duration


@dataclass(frozen=True, eq=False)
class GazeShift:
    """An activated :class:`GazeLMP`: the shift from the gaze at ``time`` to its target."""

    lmp: GazeLMP
    time: float
    from_point: np.ndarray
    from_head: np.ndarray
    warnings: tuple[str, ...] = ()

    def _goal(self, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Target points and head directions at ``times``."""
        target = self.lmp.target.points(times)
        look = quat.normalize(target - self.lmp.origin)
        if self.lmp.head is not None:
            return target, quat.normalize(self.lmp.head.points(times) - self.lmp.origin)
        return target, head_direction(look, self.lmp.head_share)

    @cached_property
    def _goal_at_start(self) -> tuple[np.ndarray, np.ndarray]:
        goal, head = self._goal(np.array([self.time]))
        return goal[0], head[0]

    @cached_property
    def amplitudes(self) -> tuple[float, float]:
        """Angles (radians) the eyes and the head turn, measured at the shift's start."""
        goal, head = self._goal_at_start
        before = quat.normalize(self.from_point - self.lmp.origin)
        after = quat.normalize(goal - self.lmp.origin)
        return float(np.arccos(np.clip(before @ after, -1.0, 1.0))), float(np.arccos(np.clip(self.from_head @ head, -1.0, 1.0)))

    @property
    def duration(self) -> float:
        eyes, head = self.amplitudes
        return max(saccade_duration(eyes), HEAD_LAG + head_duration(head))

    @property
    def fixed(self) -> bool:
        """Whether the eyes' and the head's goals stand still (then fixed from the start)."""
        return self.lmp.target.fixed and (self.lmp.head is None or self.lmp.head.fixed)

    def sample(self, times: np.ndarray) -> np.ndarray:
        t = np.asarray(times, dtype=float)
        return sample_shifts((self,), np.zeros(t.size, dtype=np.int64), t)

    def state(self, time: float) -> ChannelState:
        step = 1e-4
        values = self.sample(np.array([time - step, time]))
        return ChannelState(values[1], (values[1] - values[0]) / step, float(time))


def sample_shifts(shifts: Sequence[GazeShift], owner: np.ndarray, times: np.ndarray) -> np.ndarray:
    """The gaze channel's values ``(n, 6)`` at sorted ``times`` (s), each from the shift
    ``owner`` names (indices into ``shifts``, sorted): the eyes along a minimum-jerk
    saccade and the head, :data:`HEAD_LAG` later, along its own, each the shortest arc
    from where the shift found it toward its goal. A shift whose goal stands still, with
    all its rows here after it is over, gives that goal exactly (rows of a pass that
    starts before it is over come within rounding of it). All rows are worked out in one
    pass (a timeline's shifts together, :func:`motor.neck.shift_sampling.shift_values`);
    each row's arithmetic is the same whichever shifts share the pass."""
    t = np.asarray(times, dtype=float)
    counts = np.bincount(owner, minlength=len(shifts)) if t.size else np.zeros(len(shifts), dtype=np.int64)
    ends = np.cumsum(counts)
    per_row = lambda values: np.repeat(np.asarray(values, dtype=float), counts, axis=0)
    goal, goal_head = np.empty((t.size, 3)), np.empty((t.size, 3))
    for shift, end, count in zip(shifts, ends, counts):
        rows = slice(end - count, end)
        if count and shift.fixed:
            goal[rows], goal_head[rows] = shift._goal_at_start
        elif count:
            goal[rows], goal_head[rows] = shift._goal(t[rows])
    ease = minimum_jerk()
    amplitudes = np.array([shift.amplitudes for shift in shifts]).reshape(-1, 2)
    began = per_row([shift.time for shift in shifts])
    s_eye = ease.fraction((t - began) / per_row([saccade_duration(eyes) for eyes in amplitudes[:, 0]]))
    s_head = ease.fraction((t - began - HEAD_LAG) / per_row([head_duration(head) for head in amplitudes[:, 1]]))
    origin = per_row([shift.lmp.origin for shift in shifts]).reshape(-1, 3)
    start = per_row([shift.from_point - shift.lmp.origin for shift in shifts]).reshape(-1, 3)
    from_head = per_row([shift.from_head for shift in shifts]).reshape(-1, 3)
    reach = per_row([float(np.linalg.norm(shift.from_point - shift.lmp.origin)) for shift in shifts])
    values = shift_values(origin, start, from_head, reach, goal, goal_head, s_eye, s_head)
    for shift, end, count in zip(shifts, ends, counts):
        if count and shift.fixed and t[end - count] >= shift.time + shift.duration:
            values[end - count : end] = np.concatenate(shift._goal_at_start)
    return values


def gaze(avatar: Avatar, target: GazeTarget, start: float, hold_until: float | None = None, *, head: GazeTarget | None = None,
         head_share: float | None = None, returning: bool = False) -> GazeLMP:  # fmt: skip
    """The LMP looking at ``target`` from ``start`` (seconds) on; ``hold_until`` only marks
    its pegs' end (another LMP takes over whenever it starts)."""
    end = start if hold_until is None else max(start, hold_until)
    pegs = TimePegs(start, start, start, start, start, end, end)
    return GazeLMP(pegs, target, eye_centre(avatar), head, head_share, returning)


def rest_state(avatar: Avatar) -> np.ndarray:
    """The gaze channel at rest: far straight ahead, the head facing forward."""
    return np.concatenate([eye_centre(avatar) + FAR * FORWARD, FORWARD])
