"""The wrist position LMP: a preparation from wherever the wrist is, then the stroke's strokes.

The stroke (the breakpoints from ``stroke_start`` on) is formed once, by the gesture
planner or when the LMP is made (:func:`motor.trajectory.spline.plan_wrist_trajectory`,
which never exceeds :data:`motor.trajectory.spline.MAX_WRIST_SPEED`): it starts and ends at
rest and follows the power law.
At activation the LMP takes the channel's value and velocity and prepends the
*preparation*: the minimum-jerk movement from that state to rest at the first breakpoint
(:func:`motor.trajectory.spline.approach`), bowed around the body where its straight way
would crowd the arm (:mod:`motor.arm.bowed_way`).

**The stroke onset is visible** (Kendon's pre-stroke hold, as Greta does). The preparation
always arrives at rest, by the ``ready`` peg — a speed minimum of zero at the
preparation–stroke breakpoint — and the wrist holds there until the stroke starts from a
standstill exactly at its first breakpoint time (the program's ``stroke_start``). The rule
(:func:`preparation_timing`; the gesture planner applies it to set ``ready``, the same
for both arms): the preparation takes its natural duration, the longer of Fitts' law
``0.24 ln(100 A + 1)`` and the shortest duration the speed budget allows
(:mod:`motor.trajectory.speed_budget`); the pre-stroke hold takes what the window from
``start`` to ``stroke_start`` leaves beyond that, up to :data:`PRE_STROKE_HOLD`; from rest
the wrist waits before it starts moving with what is left. A window shorter than the
natural duration is used whole (the scheduler keeps it within the manner's budget
beforehand); one that would go beyond the absolute ceiling
(:data:`motor.trajectory.speed_budget.CEILING`) makes the stroke start late, with a
warning.

Positions are metres in the avatar frame, times seconds on the utterance clock.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from motor.arm.bowed_way import SAMPLES, bowed_trajectory, find_bow
from motor.body.avatar import Avatar
from motor.body.conventions import AVATAR_SIDE
from motor.program.lmp import Channel, ChannelState, TimePegs, check_activation
from motor.trajectory.speed_budget import CEILING, budget
from motor.trajectory.spline import (
    WristTrajectory,
    approach,
    fitts_duration,
    held,
    joined,
    plan_wrist_trajectory,
    stretch_factor,
    time_breakpoints,
)

#: Longest pre-stroke hold (s): the hand waits this long at the stroke's start when the
#: preparation leaves the time.
PRE_STROKE_HOLD = 0.15
#: Below this distance (m) or speed (m/s) the wrist counts as still.
_AT_REST = 1e-6
#: Shortest time (s) an LMP holds a single target, when its pegs give none.
_DIFFERENCE_STEP = 1e-4


def preparation_timing(amplitude: float, window: float, manner: str | None = None) -> tuple[float, float]:
    """Duration of the preparation and of the pre-stroke hold (s) for a preparation of
    ``amplitude`` metres in a ``window`` of seconds (module docstring)."""
    if amplitude <= _AT_REST:
        return 0.0, 0.0
    natural = max(float(fitts_duration(amplitude)), budget(manner).shortest_duration(amplitude))
    if window <= natural + _AT_REST:
        return min(window, natural), 0.0
    return natural, min(PRE_STROKE_HOLD, window - natural)


@dataclass(frozen=True, eq=False)
class SplineRealization:
    """A wrist position following a :class:`WristTrajectory`."""

    trajectory: WristTrajectory

    @property
    def warnings(self) -> tuple[str, ...]:
        return self.trajectory.warnings

    def sample(self, times: np.ndarray) -> np.ndarray:
        return self.trajectory.position(times)

    def state(self, time: float) -> ChannelState:
        t = np.array([time])
        return ChannelState(self.trajectory.position(t)[0], self.trajectory.velocity(t)[0], float(time))


@dataclass(frozen=True, eq=False)
class WristPositionLMP:
    """The wrist through guiding-stroke breakpoints, after a preparation into the first.

    Attributes:
        side: ``"right"`` or ``"left"``.
        pegs: time pegs; the preparation arrives at the first breakpoint by ``ready``, the
            stroke runs through the breakpoints over ``[stroke_start, stroke_end]``.
        breakpoints: ``(n, 3)`` positions, metres; one breakpoint is a static target.
        breakpoint_times: ``(n,)`` times, from ``ready`` on, or None to time the stroke by
            :func:`motor.trajectory.spline.time_breakpoints`. They fix where the stroke
            starts and stops (its first and last breakpoints, holds, reversals); the
            breakpoints in between are passed as the power law times them.
        warnings: notes from planning the breakpoints (e.g. a curve's default normal),
            carried into the realization.
        stroke: the stroke's trajectory through the breakpoints at their times, when the
            planner has formed it already; otherwise it is formed here.
        avatar: the body whose arm this is: the preparation bows around it where its
            straight way would crowd the arm (:mod:`motor.arm.bowed_way`); None: straight.
    """

    side: str
    pegs: TimePegs
    breakpoints: np.ndarray
    breakpoint_times: np.ndarray | None = None
    warnings: tuple[str, ...] = ()
    stroke: WristTrajectory | None = None
    avatar: Avatar | None = None

    def __post_init__(self) -> None:
        points = np.atleast_2d(np.asarray(self.breakpoints, dtype=float))
        if points.ndim != 2 or points.shape[1] != 3 or not np.all(np.isfinite(points)):
            raise ValueError(f"{self.channel}: breakpoints must be finite (n, 3) positions, got {np.shape(self.breakpoints)}")
        if self.pegs.ready <= self.pegs.start:
            raise ValueError(f"{self.channel}: ready {self.pegs.ready} must follow start {self.pegs.start}")
        if self.breakpoint_times is not None:
            times = np.asarray(self.breakpoint_times, dtype=float)
            if times.shape != (points.shape[0],) or times[0] < self.pegs.ready or np.any(np.diff(times) <= 0):
                raise ValueError(f"{self.channel}: breakpoint times must increase from ready, one per breakpoint")
        elif points.shape[0] > 1:
            times = time_breakpoints(points, self.pegs.stroke_start, self.pegs.stroke_end)
        else:
            times = np.array([self.pegs.ready])
        object.__setattr__(self, "breakpoints", points)
        object.__setattr__(self, "breakpoint_times", times)
        if self.stroke is not None:
            if abs(self.stroke.start - times[0]) > 1e-9 or abs(self.stroke.end - times[-1]) > 1e-9:
                raise ValueError(f"{self.channel}: the given stroke spans [{self.stroke.start}, {self.stroke.end}], not its breakpoint times")
        elif points.shape[0] > 1:
            object.__setattr__(self, "stroke", plan_wrist_trajectory(points, times))

    @property
    def channel(self) -> Channel:
        return (self.side, "wrist_position")

    def activate(self, state: ChannelState) -> SplineRealization:
        check_activation(self.channel, state, self.pegs.ready)
        here = np.asarray(state.value, dtype=float)
        velocity = np.asarray(state.velocity, dtype=float)
        first, onset = self.breakpoints[0], float(self.breakpoint_times[0])
        amplitude = float(np.linalg.norm(first - here))
        moving = float(np.linalg.norm(velocity)) > _AT_REST
        notes = list(self.warnings)
        pieces: list[WristTrajectory] = []
        arrival = state.time
        if amplitude > _AT_REST or moving:
            arrival = self.pegs.ready
            duration, _ = preparation_timing(max(amplitude, _AT_REST * 2.0), arrival - state.time)
            begin = state.time if moving else arrival - duration
            if begin > state.time:
                pieces.append(held(here, state.time, begin))
            preparation = approach(here, velocity, begin, first, arrival)
            factor = stretch_factor(preparation, CEILING.peak_speed, CEILING.peak_acceleration)
            if factor > 1.0:
                arrival = begin + factor * (arrival - begin)
                notes.append(
                    f"{self.channel}: preparation of {amplitude:.3f} m in {onset - begin:.3f} s would exceed "
                    f"{CEILING.peak_speed} m/s or {CEILING.peak_acceleration} m/s²; the stroke starts {arrival - onset:.3f} s late"
                )
                preparation = approach(here, velocity, begin, first, arrival)
            pieces.append(self._bowed(preparation))
        stroke = self._stroke_from(max(arrival, onset), max(0.0, arrival - onset))
        still_from = pieces[-1].end if pieces else state.time
        if stroke.start > still_from:
            pieces.append(held(first, still_from, stroke.start))
        pieces.append(stroke)
        return SplineRealization(joined(pieces).with_warnings(notes))

    def _bowed(self, preparation: WristTrajectory) -> WristTrajectory:
        """The preparation bowed around the body where it would crowd the arm."""
        if self.avatar is None:
            return preparation
        way = preparation.position(np.linspace(preparation.start, preparation.end, SAMPLES))
        found = find_bow(self.avatar, AVATAR_SIDE[self.side], way)
        return preparation if found is None else bowed_trajectory(preparation, found)

    def _stroke_from(self, onset: float, late: float) -> WristTrajectory:
        """The stroke from rest at ``onset`` (late by ``late`` seconds when the preparation
        could not arrive in time); a single target holds until the pegs' end."""
        if self.stroke is None:
            return held(self.breakpoints[0], onset, max(self.pegs.end, onset + _DIFFERENCE_STEP))
        return self.stroke.shifted(late) if late > 0.0 else self.stroke
