"""Local motor programs (LMPs) and the per-channel timelines that hand control between them.

An LMP (seed 004, section 4) drives a limited set of degrees of freedom — a *channel*
such as ``("right", "wrist_position")`` (3 values, metres), ``("right", "hand_rotation")``
(a scalar-last quaternion), ``("right", "handshape")`` (P hand parameters) or
``("right", "swivel")`` (1 value, radians) — over a span of time marked by
:class:`TimePegs`. It is planned with its own targets but without knowing where the limb
will be: when it activates at its start time it takes the channel's current value and
velocity (a :class:`ChannelState`, from whichever LMP was in control: its predecessor,
or the retraction of a previous gesture) and connects to it fluently. The result of
activation is a *realization* with a vectorized ``sample(times)``.

On one channel the LMPs form a :class:`ChannelTimeline`: at any time exactly one is in
control, the latest to have started. A successor that starts before its predecessor has
finished takes over at its start and the predecessor's remainder (typically a
retraction) is skipped — co-articulation; a retraction of an earlier gesture that would
only start after the next gesture has begun is dropped altogether. Because each activation starts from the
predecessor's value and velocity at that instant, positions and velocities are
continuous at every hand-over.

Fluent starts:

* :class:`WristPositionLMP` inserts a preparatory guiding stroke from the current
  position with the current velocity to its first breakpoint (arriving at ``ready``);
  starting from rest it waits and takes the Fitts'-law duration ``0.24 ln(100 A + 1)``
  when the plan leaves more time than that.
* Keyframe LMPs (rotation, hand shape, swivel, retractions) interpolate along a time
  profile (default minimum jerk; retractions use the lax biocontrol profile) and add a
  blend ``Δv · τ · (1 − τ/T)²`` over the first transition (τ time since activation, T the
  transition's length) that carries the incoming velocity and fades out by the first key.
  Rotations blend the incoming angular velocity the same way, as a left-multiplied
  rotation vector.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, fields
from typing import Protocol

import numpy as np
from scipy.spatial.transform import Rotation

from motor import quaternion as quat
from motor.program import keyframe_sampling
from motor.trajectory.biocontrol import TimeProfile, minimum_jerk, profile

Channel = tuple[str, str]
#: Channels whose values are rotations (scalar-last quaternions); the rest are vectors.
ROTATION_CHANNELS: frozenset[str] = frozenset({"hand_rotation"})
#: Fixed value sizes of the vector channels; hand shapes take any size.
CHANNEL_SIZES: dict[str, int] = {"wrist_position": 3, "swivel": 1, "hand_rotation": 4}
#: Step of the backward differences that estimate velocities, seconds.
_DIFFERENCE_STEP = 1e-4


@dataclass(frozen=True)
class TimePegs:
    """The time pegs of an LMP, seconds on the utterance clock, non-decreasing.

    ``start`` is activation; the preparation arrives at ``ready``; the stroke runs from
    ``stroke_start`` through ``stroke`` (its most prominent point) to ``stroke_end``;
    ``relax`` is when retraction may begin and ``end`` when the LMP is done.
    """

    start: float
    ready: float
    stroke_start: float
    stroke: float
    stroke_end: float
    relax: float
    end: float

    def __post_init__(self) -> None:
        values = [(f.name, getattr(self, f.name)) for f in fields(self)]
        for name, value in values:
            if not np.isfinite(value):
                raise ValueError(f"time peg {name} must be finite, got {value}")
        for (first, a), (second, b) in zip(values, values[1:]):
            if b < a:
                raise ValueError(f"time pegs out of order: {second}={b} before {first}={a}")

    @classmethod
    def movement(cls, start: float, ready: float, end: float | None = None) -> TimePegs:
        """Pegs of a plain movement arriving at ``ready`` and lasting until ``end``."""
        end = ready if end is None else end
        return cls(start, ready, ready, ready, ready, end, end)


@dataclass(frozen=True, eq=False)
class ChannelState:
    """A channel's value and velocity at ``time``.

    For rotation channels ``value`` is a unit quaternion (x, y, z, w) and ``velocity`` the
    angular velocity (rad/s, world frame); otherwise both have the channel's size.
    """

    value: np.ndarray
    velocity: np.ndarray
    time: float

    @classmethod
    def at_rest(cls, value: np.ndarray | Sequence[float], time: float = 0.0, rotation: bool = False) -> ChannelState:
        """A state holding ``value`` still."""
        v = np.atleast_1d(np.asarray(value, dtype=float))
        return cls(v, np.zeros(3 if rotation else v.size), time)


class Realization(Protocol):
    """An activated LMP: its motion from the activation state on."""

    warnings: tuple[str, ...]

    def sample(self, times: np.ndarray) -> np.ndarray: ...

    def state(self, time: float) -> ChannelState: ...


class LMP(Protocol):
    """A local motor program on one channel."""

    channel: Channel
    pegs: TimePegs

    def activate(self, state: ChannelState) -> Realization: ...


def as_profile(source: TimeProfile | str) -> TimeProfile:
    return profile(source) if isinstance(source, str) else source


def _locate(knots: np.ndarray, times: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Segment index, time fraction in it (clipped to [0, 1]) and segment length."""
    t = np.asarray(times, dtype=float)
    segment = np.clip(np.searchsorted(knots, t, side="right") - 1, 0, knots.size - 2)
    length = knots[segment + 1] - knots[segment]
    return segment, np.clip((t - knots[segment]) / length, 0.0, 1.0), length


def incoming_blend(times: np.ndarray, start: float, window: float) -> tuple[np.ndarray, np.ndarray]:
    """Blend weight ``τ (1 − τ/T)²`` and its time derivative, zero outside [0, T]."""
    tau = np.clip(np.asarray(times, dtype=float) - start, 0.0, window)
    s = tau / window
    return tau * (1.0 - s) ** 2, np.where(tau < window, (1.0 - s) * (1.0 - 3.0 * s), 0.0)


@dataclass(frozen=True, eq=False)
class VectorKeyframes:
    """A vector channel moving through keys along a time profile, from an activation state.

    ``knots`` are ``[activation, key times…]`` and ``values`` ``[activation value, keys…]``.
    Sampling is one compiled pass (:func:`motor.program.keyframe_sampling.vector_keyframes`).
    """

    knots: np.ndarray
    values: np.ndarray
    incoming: np.ndarray
    time_profile: TimeProfile
    warnings: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        for name in ("knots", "values", "incoming"):
            object.__setattr__(self, name, np.ascontiguousarray(getattr(self, name), dtype=float))
        if self.values.ndim != 2 or self.incoming.shape != self.values.shape[1:] or self.knots.shape != self.values.shape[:1]:
            raise ValueError(f"keyframes: knots {self.knots.shape}, values {self.values.shape} and incoming velocity {self.incoming.shape} do not fit")

    def sample(self, times: np.ndarray) -> np.ndarray:
        return keyframe_sampling.vector_keyframes(self.knots, self.values, self.incoming, self.time_profile, times)

    def state(self, time: float) -> ChannelState:
        t = np.array([time])
        segment, u, length = _locate(self.knots, t)
        inside = self.knots[0] <= time < self.knots[-1]
        rate = self.time_profile.rate(u) / length if inside else np.zeros(1)
        _, blend_rate = incoming_blend(t, self.knots[0], self.knots[1] - self.knots[0])
        velocity = rate[0] * (self.values[segment[0] + 1] - self.values[segment[0]]) + blend_rate[0] * self.incoming
        return ChannelState(self.sample(t)[0], velocity, float(time))


@dataclass(frozen=True, eq=False)
class RotationKeyframes:
    """A rotation channel slerping through key orientations along a time profile.

    The keys as unit quaternions and the rotation vector of each segment are prepared once,
    at activation; sampling is one compiled pass over them
    (:func:`motor.program.keyframe_sampling.rotation_keyframes`).
    """

    knots: np.ndarray
    rotations: Rotation
    incoming: np.ndarray
    time_profile: TimeProfile
    warnings: tuple[str, ...] = ()
    _keys: np.ndarray = field(init=False, repr=False)
    _steps: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        keys = np.ascontiguousarray(self.rotations.as_quat().reshape(-1, 4))
        object.__setattr__(self, "knots", np.ascontiguousarray(self.knots, dtype=float))
        object.__setattr__(self, "incoming", np.ascontiguousarray(self.incoming, dtype=float))
        if self.incoming.shape != (3,) or self.knots.shape != keys.shape[:1]:
            raise ValueError(f"rotation keyframes: knots {self.knots.shape}, keys {keys.shape} and angular velocity {self.incoming.shape} do not fit")
        object.__setattr__(self, "_keys", keys)
        object.__setattr__(self, "_steps", quat.to_rotation_vector(quat.canonical(quat.multiply(quat.conjugate(keys[:-1]), keys[1:]))))

    def sample(self, times: np.ndarray) -> np.ndarray:
        return keyframe_sampling.rotation_keyframes(self.knots, self._keys, self._steps, self.incoming, self.time_profile, times)

    def state(self, time: float) -> ChannelState:
        """Rotation and angular velocity: second-order one-sided differences, looking back
        (the motion just before ``time``) except at activation, where they look ahead."""
        h = -_DIFFERENCE_STEP if time - 2 * _DIFFERENCE_STEP >= self.knots[0] else _DIFFERENCE_STEP
        q = quat.normalize(self.sample(np.array([time, time + h, time + 2 * h])))
        turns = quat.to_rotation_vector(quat.canonical(quat.multiply(q[1:], quat.conjugate(q[0]))))
        return ChannelState(q[0], (4.0 * turns[0] - turns[1]) / (2.0 * h), float(time))


def check_activation(channel: Channel, state: ChannelState, first_target: float) -> None:
    if not state.time < first_target:
        raise ValueError(f"{channel}: activated at {state.time}, not before its first target time {first_target}")


def rotation_keyframes(
    channel: Channel, state: ChannelState, keys: np.ndarray, times: np.ndarray, time_profile: TimeProfile
) -> RotationKeyframes:
    """Activation of a slerp through unit quaternions ``keys`` ``(m, 4)`` at ``times``."""
    check_activation(channel, state, float(times[0]))
    knots = np.concatenate([[state.time], times])
    rotations = Rotation.from_quat(np.concatenate([np.asarray(state.value, dtype=float)[None], keys]))
    return RotationKeyframes(knots, rotations, np.asarray(state.velocity, dtype=float), time_profile)


def rotation_turn(channel: Channel, state: ChannelState, target: np.ndarray, time: float, time_profile: TimeProfile, step: np.ndarray) -> RotationKeyframes:
    """Activation of one turn from the state to ``target`` by ``time``, along the local
    rotation vector ``step`` ``(3,)`` (the state's rotation times ``exp(step)`` is the
    target up to sign): a slerp's turn, or the long way round."""
    step = np.asarray(step, dtype=float)
    if step.shape != (3,):
        raise ValueError(f"{channel}: a turn's rotation vector must have shape (3,), got {step.shape}")
    turned = rotation_keyframes(channel, state, np.asarray(target, dtype=float)[None], np.array([time]), time_profile)
    object.__setattr__(turned, "_steps", np.ascontiguousarray(step[None]))
    return turned


def key_times(pegs: TimePegs, count: int, given: np.ndarray | Sequence[float] | None, name: str) -> np.ndarray:
    """Key times: given, or the first key at ``ready`` and the rest spread over the stroke."""
    if given is None:
        rest = np.linspace(pegs.stroke_start, pegs.stroke_end, count)[1:] if count > 1 else np.empty(0)
        times = np.concatenate([[pegs.ready], rest])
    else:
        times = np.asarray(given, dtype=float)
    if times.shape != (count,) or not np.all(np.isfinite(times)):
        raise ValueError(f"{name}: expected {count} finite key times, got {np.shape(times)}")
    if times[0] <= pegs.start:
        raise ValueError(f"{name}: first key time {times[0]} must come after the start peg {pegs.start}")
    if np.any(np.diff(times) <= 0.0):
        raise ValueError(f"{name}: key times must increase, got {times.tolist()}")
    return times


@dataclass(frozen=True, eq=False)
class VectorKeyframeLMP:
    """An LMP moving a vector channel through keyframes (hand shape, swivel, retractions).

    Attributes:
        channel: the channel, e.g. ``("right", "handshape")``.
        pegs: its time pegs.
        keys: ``(m, D)`` values to pass through.
        key_times: ``(m,)`` times of the keys, or None: the first at ``ready``, the rest
            spread evenly over the stroke.
        time_profile: a :class:`TimeProfile` or a manner name for each transition.
    """

    channel: Channel
    pegs: TimePegs
    keys: np.ndarray
    key_times: np.ndarray | None = None
    time_profile: TimeProfile | str = field(default_factory=minimum_jerk)

    def __post_init__(self) -> None:
        keys = np.asarray(self.keys, dtype=float)
        keys = keys[:, None] if keys.ndim == 1 else keys
        if keys.ndim != 2 or keys.shape[0] < 1 or not np.all(np.isfinite(keys)):
            raise ValueError(f"{self.channel}: keys must be finite (m, D) values, got shape {np.shape(self.keys)}")
        if self.channel[1] in ROTATION_CHANNELS:
            raise ValueError(f"{self.channel}: a rotation channel; use WristRotationLMP")
        expected = CHANNEL_SIZES.get(self.channel[1])
        if expected is not None and keys.shape[1] != expected:
            raise ValueError(f"{self.channel}: keys have {keys.shape[1]} values, the channel takes {expected}")
        object.__setattr__(self, "keys", keys)
        object.__setattr__(self, "key_times", key_times(self.pegs, keys.shape[0], self.key_times, str(self.channel)))
        object.__setattr__(self, "time_profile", as_profile(self.time_profile))

    def activate(self, state: ChannelState) -> VectorKeyframes:
        value = np.asarray(state.value, dtype=float)
        if value.shape != self.keys.shape[1:]:
            raise ValueError(f"{self.channel}: activation value has shape {value.shape}, keys {self.keys.shape[1:]}")
        check_activation(self.channel, state, float(self.key_times[0]))
        knots = np.concatenate([[state.time], self.key_times])
        values = np.concatenate([value[None], self.keys])
        return VectorKeyframes(knots, values, np.asarray(state.velocity, dtype=float), self.time_profile)


@dataclass(frozen=True, eq=False)
class RetractionLMP:
    """Back to a rest (or interim rest) value, arriving at ``pegs.ready``.

    Works on any channel: vector channels move along a straight line, rotation channels
    slerp. The default profile is the minimum-jerk one: a retraction from a hold is a
    single straight movement from rest to rest, and the smoothest is the most relaxed.
    """

    channel: Channel
    pegs: TimePegs
    rest: np.ndarray
    time_profile: TimeProfile | str = field(default_factory=minimum_jerk)

    def __post_init__(self) -> None:
        if self.pegs.ready <= self.pegs.start:
            raise ValueError(f"retraction on {self.channel}: ready {self.pegs.ready} must follow start {self.pegs.start}")
        object.__setattr__(self, "time_profile", as_profile(self.time_profile))

    def activate(self, state: ChannelState) -> Realization:
        rest = np.atleast_1d(np.asarray(self.rest, dtype=float))
        times = np.array([self.pegs.ready])
        if self.channel[1] in ROTATION_CHANNELS:
            return rotation_keyframes(self.channel, state, rest[None], times, self.time_profile)
        return VectorKeyframeLMP(self.channel, self.pegs, rest[None], times, self.time_profile).activate(state)


@dataclass(frozen=True, eq=False)
class ChannelTimeline:
    """The LMPs of one channel, activated in time order, sampled all at once.

    Build with :meth:`build`. ``starts[i]`` is when ``lmps[i]`` takes control; it keeps
    it until ``starts[i + 1]``. Before the first start the channel holds ``initial``.
    """

    channel: Channel
    initial: ChannelState
    lmps: tuple[LMP, ...]
    realizations: tuple[Realization, ...]
    starts: np.ndarray

    @classmethod
    def build(cls, channel: Channel, lmps: Sequence[LMP], initial: ChannelState) -> ChannelTimeline:
        """Sort ``lmps`` (given in the order they were activated) by start and activate each
        from the state the timeline has then. A retraction that an LMP activated after it
        starts before (or with) is dropped: the arm goes on to the later gesture instead of
        returning to rest first (co-articulation)."""
        for lmp in lmps:
            if tuple(lmp.channel) != tuple(channel):
                raise ValueError(f"timeline of {channel} was given an LMP on {lmp.channel}")
        kept = [
            lmp
            for index, lmp in enumerate(lmps)
            if not (isinstance(lmp, RetractionLMP) and any(later.pegs.start <= lmp.pegs.start for later in lmps[index + 1 :]))
        ]
        ordered = tuple(sorted(kept, key=lambda lmp: lmp.pegs.start))
        realizations: list[Realization] = []
        for lmp in ordered:
            start = lmp.pegs.start
            state = (
                realizations[-1].state(start)
                if realizations
                else ChannelState(np.asarray(initial.value, dtype=float), np.asarray(initial.velocity, dtype=float), start)
            )
            realizations.append(lmp.activate(state))
        starts = np.array([lmp.pegs.start for lmp in ordered], dtype=float)
        return cls(tuple(channel), initial, ordered, tuple(realizations), starts)

    def extended(self, lmp: LMP) -> ChannelTimeline:
        """This timeline with ``lmp`` added, which starts no earlier than any LMP on it:
        the timeline :meth:`build` makes of all of them, without activating the others
        again."""
        if tuple(lmp.channel) != self.channel:
            raise ValueError(f"timeline of {self.channel} was given an LMP on {lmp.channel}")
        start = lmp.pegs.start
        if self.starts.size and start < self.starts[-1]:
            raise ValueError(f"{self.channel}: an LMP starting at {start} cannot follow one starting at {self.starts[-1]}")
        state = (
            self.realizations[-1].state(start)
            if self.realizations
            else ChannelState(np.asarray(self.initial.value, dtype=float), np.asarray(self.initial.velocity, dtype=float), start)
        )
        realization = lmp.activate(state)
        starts = np.append(self.starts, float(start))
        return ChannelTimeline(self.channel, self.initial, (*self.lmps, lmp), (*self.realizations, realization), starts)

    @property
    def warnings(self) -> tuple[str, ...]:
        """Every realization's warnings, in time order."""
        return tuple(w for realization in self.realizations for w in realization.warnings)

    def in_control(self, time: float) -> LMP | None:
        """The LMP controlling the channel at ``time`` (None before the first starts)."""
        index = int(np.searchsorted(self.starts, time, side="right")) - 1
        return self.lmps[index] if index >= 0 else None

    def sample(self, times: np.ndarray) -> np.ndarray:
        """Channel values at ``times``: ``(n, D)`` (``(n, 4)`` quaternions for rotations)."""
        t = np.asarray(times, dtype=float)
        value = np.asarray(self.initial.value, dtype=float)
        out = np.broadcast_to(value, (t.size, value.size)).copy()
        owner = np.searchsorted(self.starts, t, side="right") - 1
        for index, realization in enumerate(self.realizations):
            mask = owner == index
            if np.any(mask):
                out[mask] = realization.sample(t[mask])
        return out

    def state(self, time: float) -> ChannelState:
        """Value and velocity of the channel at ``time``."""
        index = int(np.searchsorted(self.starts, time, side="right")) - 1
        if index < 0:
            return ChannelState(np.asarray(self.initial.value, dtype=float), np.zeros_like(self.initial.velocity), time)
        return self.realizations[index].state(time)
