"""The wrist position LMP: guiding strokes realized as a Hermite spline when activated.

Starting from wherever the wrist is (value and velocity of the channel at activation), a
preparatory guiding stroke leads to the first breakpoint, arriving at ``ready``; from
rest it waits and takes the Fitts'-law duration ``0.24 ln(100 A + 1)`` when the plan
leaves more time than that. Positions are metres in the avatar frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from motor.program.lmp import Channel, ChannelState, TimePegs, check_activation
from motor.trajectory.spline import (
    Accent,
    WristTrajectory,
    fitts_duration,
    plan_wrist_trajectory,
    time_breakpoints,
)

#: Step of the backward difference that ends a one-point path, seconds.
_DIFFERENCE_STEP = 1e-4
#: Below this distance (m) or speed (m/s) the wrist counts as still.
_AT_REST = 1e-6

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
    """Guiding strokes of the wrist, realized as a Hermite spline at activation.

    Attributes:
        side: ``"right"`` or ``"left"``.
        pegs: time pegs; the preparation arrives at the first breakpoint at ``ready``,
            the stroke runs through the breakpoints over ``[stroke_start, stroke_end]``.
        breakpoints: ``(n, 3)`` positions, metres; one breakpoint is a static target.
        breakpoint_times: ``(n,)`` explicit times, or None to time the stroke by the
            power-law rule of :func:`motor.trajectory.spline.time_breakpoints`.
        curved: per-stroke curve flags (``n − 1``), for the 0.8 breakpoint gain.
        accents: accents on strokes, indexed over ``breakpoints``.
        warnings: notes from planning the breakpoints (e.g. a curve's default normal),
            carried into the realization.
    """

    side: str
    pegs: TimePegs
    breakpoints: np.ndarray
    breakpoint_times: np.ndarray | None = None
    curved: tuple[bool, ...] | None = None
    accents: tuple[Accent, ...] = ()
    warnings: tuple[str, ...] = ()

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
        if self.curved is not None and len(self.curved) != points.shape[0] - 1:
            raise ValueError(f"{self.channel}: curved needs one flag per stroke ({points.shape[0] - 1})")
        object.__setattr__(self, "breakpoints", points)
        object.__setattr__(self, "breakpoint_times", times)

    @property
    def channel(self) -> Channel:
        return (self.side, "wrist_position")

    def activate(self, state: ChannelState) -> SplineRealization:
        check_activation(self.channel, state, self.pegs.ready)
        here = np.asarray(state.value, dtype=float)
        velocity = np.asarray(state.velocity, dtype=float)
        first, arrival = self.breakpoints[0], self.pegs.ready
        amplitude = float(np.linalg.norm(first - here))
        moving = float(np.linalg.norm(velocity)) > _AT_REST
        warnings = list(self.warnings)
        points, times = [here], [state.time]
        if amplitude > _AT_REST or moving:
            natural = float(fitts_duration(amplitude))
            window = arrival - state.time
            if natural > window:
                warnings.append(
                    f"{self.channel}: preparation of {amplitude:.3f} m squeezed into {window:.3f} s "
                    f"(Fitts' law asks {natural:.3f} s)"
                )
            elif not moving and natural > 0.0 and arrival - natural > state.time:
                points.append(here)
                times.append(arrival - natural)
            points.append(first)
            times.append(arrival)
        if self.breakpoint_times[0] > times[-1]:
            points.append(first)
            times.append(float(self.breakpoint_times[0]))
        prefix = len(points) - 1
        points.extend(self.breakpoints[1:])
        times.extend(self.breakpoint_times[1:])
        if len(points) == 1:
            points.append(here)
            times.append(max(self.pegs.end, state.time + _DIFFERENCE_STEP))
        curved = None if self.curved is None else (False,) * prefix + tuple(self.curved)
        accents = tuple(Accent(a.stroke + prefix, a.fraction) for a in self.accents)
        trajectory = plan_wrist_trajectory(
            np.array(points), np.array(times), start_velocity=velocity, curved=curved, accents=accents,
            warnings=tuple(warnings),
        )
        return SplineRealization(trajectory)

