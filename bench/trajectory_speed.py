"""Sampling speed of wrist trajectories and channel timelines.

Not a test: prints figures. ``run(quick)`` returns samples per second (median of several
runs) of a :class:`motor.trajectory.spline.WristTrajectory` tracing three laps of an ellipse and
of a :class:`motor.program.lmp.ChannelTimeline` of gestures, retractions and co-articulated
successors, for 100,000 frames each (10,000 when ``quick``), plus the planning time of
the timeline.
"""

from __future__ import annotations

import json
import sys

import numpy as np

from bench.timing import median_seconds
from motor.arm.wrist_position import WristPositionLMP
from motor.program.lmp import ChannelState, ChannelTimeline, RetractionLMP, TimePegs
from motor.trajectory.guiding_strokes import curve_breakpoints, ellipse_breakpoints
from motor.trajectory.spline import plan_wrist_trajectory

REST = np.array([0.2, 0.9, 0.1])


def _timeline(gestures: int) -> ChannelTimeline:
    """``gestures`` curved strokes, each followed by a retraction cut short by the next."""
    lmps = []
    for index in range(gestures):
        t0 = 1.5 * index
        start = np.array([0.05 * (index % 3), 1.2, 0.35])
        points = curve_breakpoints(start, start + [-0.3, 0.05, 0.05], (0.0, 0.0, 1.0), "LeftC", 0.3).points
        lmps.append(WristPositionLMP("right", TimePegs(t0, t0 + 0.5, t0 + 0.5, t0 + 0.7, t0 + 0.9, t0 + 1.0, t0 + 1.0), points))
        lmps.append(RetractionLMP(("right", "wrist_position"), TimePegs.movement(t0 + 1.0, t0 + 1.8), REST))
    return ChannelTimeline.build(("right", "wrist_position"), lmps, ChannelState.at_rest(REST))


def run(quick: bool) -> dict:
    """Samples per second of trajectory and timeline sampling; planning time of a timeline."""
    frames = 10_000 if quick else 100_000
    repeats = 3 if quick else 7
    laps, per_lap = 3, 32
    points = ellipse_breakpoints((0.0, 1.2, 0.3), (0.1, 0.04), (0.0, 0.0, 1.0), count=laps * per_lap, sweep=2 * np.pi * laps)
    trajectory = plan_wrist_trajectory(points, start=0.0, end=3.6)
    times = np.linspace(-0.1, 3.7, frames)
    gestures = 20
    planning = median_seconds(lambda: _timeline(gestures), repeats)
    timeline = _timeline(gestures)
    timeline_times = np.linspace(0.0, 1.5 * gestures + 1.0, frames)
    position = median_seconds(lambda: trajectory.position(times), repeats)
    velocity = median_seconds(lambda: trajectory.velocity(times), repeats)
    sampled = median_seconds(lambda: timeline.sample(timeline_times), repeats)
    return {
        "frames": frames,
        "wrist_trajectory_position_samples_per_s": frames / position,
        "wrist_trajectory_velocity_samples_per_s": frames / velocity,
        "channel_timeline_samples_per_s": frames / sampled,
        "channel_timeline_lmps": len(timeline.lmps),
        "channel_timeline_planning_ms": 1000.0 * planning,
    }


if __name__ == "__main__":
    print(json.dumps(run(quick="--quick" in sys.argv), indent=2))
