"""Wrist paths the arm can follow: in reach and clear of the torso, breakpoints and between.

:func:`placed` moves points out of the torso (:func:`motor.body.collision.outside_torso`)
and into the arm's exact reach (:func:`in_reach`: where the IK follows them as placed, short
of the band in which it eases a stretched arm's reach); a point moved into reach may
land in front of the torso's margin again, so the two moves alternate (a few rounds) until
it is both. The gesture planner places every breakpoint so, but the curve through them
(:mod:`motor.trajectory.power_law`) can still dip into the torso between two breakpoints
on its front surface, or bulge past the reach — and the motor control would then push the
wrist out of the body with a jump, or the arm stop short. So each rest-to-rest phase of the
path (:func:`motor.trajectory.spline.phases`) is sampled every :data:`SPACING` metres along
its curve; if any sample has to be moved, the phase is replaced by the samples, placed and
their corners rounded (:data:`ROUNDING`), as its new breakpoints (timed evenly by arc
length between the phase's own start and end times, which are all the power law keeps of
them). Holds and reversals stay where they were (a reversal next to a replaced phase as a
hold of :data:`STOP`). Positions are metres in the avatar frame, times seconds.

The curve between two breakpoints is not kept from crowding the arm (each breakpoint is,
:func:`uncrowded_placement`): bowed as preparations and retractions are
(:mod:`motor.arm.bowed_way`), then rounded, ``41_tanedila_welle``'s stroke went from 1.3
to 1.15 cm into the chest but its wrist's velocity stepped by 0.5 m/s where the bowed
phase met its hold, and unrounded it broke the acceleration budget (the stroke took 2 s
longer).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.ndimage import gaussian_filter1d

from motor.arm.bowed_way import CROWDING_TOLERANCE
from motor.arm.chain import arm_chain, exact_reach
from motor.arm.ik import arm_reach
from motor.arm.upright_placement import upright_placement
from motor.body.avatar import Avatar
from motor.body.collision import outside_torso
from motor.trajectory.power_law import path_spline
from motor.trajectory.spline import phases

#: Arc length between the samples of a phase checked against the torso, metres.
SPACING = 0.01
#: Arc length (m) over which the corners of a placed path are rounded.
ROUNDING = 0.03
#: Hold (s) that keeps the stop at a reversal between two phases of which one was replaced.
STOP = 1e-3
#: How far (m) the IK may fall short of a point before it is moved into reach (rounding
#: only: a point left just out of reach would make the wrist stop short and jerk).
REACH_TOLERANCE = 1e-6
#: Rounds of alternately clearing the torso and moving into reach (usually one).
_ROUNDS = 4
#: Rounds of moving points forward out of the arm's way (:func:`uncrowded`).
_CROWDING_ROUNDS = 12


@dataclass(frozen=True, eq=False)
class Placement:
    """Points moved into reach and out of the torso, and by how much: ``depth`` the most
    (m) a point was inside the torso, ``shortfall`` the most the arm fell short,
    ``crowding`` the deepest the arm itself would have entered the body to reach a point
    (moved forward), with the counts of points moved for each."""

    points: np.ndarray
    inside: int
    depth: float
    short: int
    shortfall: float
    crowded: int = 0
    crowding: float = 0.0


def uncrowded_placement(avatar: Avatar, side: str, points: np.ndarray, kept: np.ndarray | None = None) -> Placement:
    """:func:`placed`, and then where the arm can reach the points without entering the
    body (:func:`uncrowded`), except those ``kept`` ``(n,)`` (e.g. where the other hand
    touches this one): what a gesture's key locations get (the curves between them are
    placed only, so that their timing is kept)."""
    placement = placed(avatar, side, points)
    free = np.ones(len(points), dtype=bool) if kept is None else ~np.asarray(kept, dtype=bool)
    if not np.any(free):
        return placement
    clear, crowded, crowding = uncrowded(avatar, side, placement.points[free])
    out = placement.points.copy()
    out[free] = clear
    return replace(placement, points=out, crowded=crowded, crowding=crowding)


def uncrowded(avatar: Avatar, side: str, points: np.ndarray) -> tuple[np.ndarray, int, float]:
    """Placed ``points`` where the arm's least costly posture would still enter the body
    by more than :data:`CROWDING_TOLERANCE` (no swivel keeps the upper arm out, e.g. a hand
    reaching across the belly close to it) moved forward by that depth and the tolerance,
    placed again (in reach, which may pull it back), until clear or for
    :data:`_CROWDING_ROUNDS` rounds; how many were moved and the deepest (m)."""
    out = points
    depth = arm_reach(avatar, side, out).penetration
    crowded = depth > CROWDING_TOLERANCE
    if not np.any(crowded):
        return points, 0, 0.0
    count, worst = int(np.sum(crowded)), float(np.max(depth))
    for _ in range(_CROWDING_ROUNDS):
        moved = out.copy()
        step = depth[crowded, None] + CROWDING_TOLERANCE
        moved[crowded] = placed(avatar, side, out[crowded] + np.array([0.0, 0.0, 1.0]) * step).points
        out = moved
        depth = arm_reach(avatar, side, out).penetration
        crowded = depth > CROWDING_TOLERANCE
        if not np.any(crowded):
            break
    return out, count, worst


def placed(avatar: Avatar, side: str, points: np.ndarray) -> Placement:
    """``points`` ``(n, 3)`` of the arm on ``side`` (``"r"``/``"l"``) out of the torso and in
    reach (module docstring)."""
    clear = outside_torso(avatar, points)
    inside = np.any(clear != points, axis=1)
    reached, shortfall = in_reach(avatar, side, clear)
    short = shortfall > REACH_TOLERANCE
    depth = float(np.max(np.abs(clear - points))) if np.any(inside) else 0.0
    if not np.any(short):
        return Placement(clear, int(np.sum(inside)), depth, 0, 0.0)
    worst = float(np.max(shortfall))
    reached = np.where(short[:, None], reached, clear)
    for _ in range(_ROUNDS):
        cleared = outside_torso(avatar, reached)
        again, shortfall = in_reach(avatar, side, cleared)
        reached = np.where((shortfall > REACH_TOLERANCE)[:, None], again, cleared)
        if np.array_equal(reached, cleared):
            break
    return Placement(reached, int(np.sum(inside)), depth, int(np.sum(short)), worst)


def in_reach(avatar: Avatar, side: str, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The nearest points ``(n, 3)`` to ``points`` that the arm reaches exactly — within
    :func:`motor.arm.chain.exact_reach` of its shoulder (pulled in along the line from
    it; the IK eases its reach beyond, so a path placed there would be followed short of
    its plan) and not nearer than its elbow bends (the IK's nearest point) — and how far
    (m) each was moved."""
    circle = upright_placement(avatar, side, points)[0].circle  # the arm's placement is all it reads of the IK
    away = points - circle.shoulder
    distance = np.linalg.norm(away, axis=1)
    limit = exact_reach(arm_chain(avatar, side))
    pulled = circle.shoulder + away * (limit / np.maximum(distance, 1e-12))[:, None]
    reached = np.where((distance > limit)[:, None], pulled, circle.wrist)
    return reached, np.linalg.norm(reached - points, axis=1)


def _samples(piece: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Points along the curve through ``piece`` about every :data:`SPACING` metres (its
    ends exact), and their fractions of the arc length."""
    spline = path_spline(piece)
    u = np.linspace(spline.x[0], spline.x[-1], 16 * piece.shape[0] + 1)
    dense = spline(u)
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(dense, axis=0), axis=1))])
    count = max(2, int(np.ceil(arc[-1] / SPACING)) + 1)
    fractions = np.linspace(0.0, 1.0, count)
    samples = spline(np.interp(fractions * arc[-1], arc, u))
    samples[[0, -1]] = piece[[0, -1]]
    return samples, fractions


def _rounded(avatar: Avatar, side: str, samples: np.ndarray) -> np.ndarray:
    """Placed samples with the corners that placing leaves (where the path meets the torso
    or the reach) rounded: smoothed by a Gaussian of :data:`ROUNDING` metres of arc and
    placed again, twice; the ends stay."""
    out = samples
    for _ in range(2):
        smooth = gaussian_filter1d(out, ROUNDING / SPACING, axis=0, mode="nearest")
        smooth[[0, -1]] = samples[[0, -1]]
        out = placed(avatar, side, smooth).points
    return out


def followable(avatar: Avatar, side: str, points: np.ndarray, times: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """The breakpoints ``(n, 3)`` and times ``(n,)`` of a wrist path of the arm on ``side``,
    with every phase that leaves the reach or enters the torso replaced by its samples,
    placed (module docstring); and how many phases were replaced."""
    spans = phases(points)
    if not spans:
        return points, times, 0
    sampled = [_samples(points[first : last + 1]) for first, last in spans]
    every = np.concatenate([samples for samples, _ in sampled])
    placed_all = np.split(placed(avatar, side, every).points, np.cumsum([samples.shape[0] for samples, _ in sampled])[:-1])
    changed = [not np.array_equal(cleared, samples) for (samples, _), cleared in zip(sampled, placed_all)]
    placed_all = [_rounded(avatar, side, cleared) if change else cleared for cleared, change in zip(placed_all, changed)]
    kept_points, kept_times = [points[:1]], [times[:1]]
    previous = 0
    for index, ((first, last), (samples, fractions), cleared) in enumerate(zip(spans, sampled, placed_all)):
        kept_points.append(points[previous + 1 : first + 1])
        kept_times.append(times[previous + 1 : first + 1])
        start = float(times[first])
        if index and spans[index - 1][1] == first and (changed[index - 1] or changed[index]):
            # a reversal between two phases: new samples may no longer turn sharply enough
            # there to be cut, so the stop becomes a hold of STOP seconds
            start += STOP
            kept_points.append(points[first : first + 1])
            kept_times.append(np.array([start]))
        if changed[index]:
            kept_points.append(cleared[1:])
            kept_times.append(start + fractions[1:] * (times[last] - start))
        else:
            kept_points.append(points[first + 1 : last + 1])
            kept_times.append(times[first + 1 : last + 1])
        previous = last
    kept_points.append(points[previous + 1 :])
    kept_times.append(times[previous + 1 :])
    return np.concatenate(kept_points), np.concatenate(kept_times), int(sum(changed))
