"""A wrist's straight way bowed around the body where it would crowd the arm.

A retraction takes the wrist back to rest along a straight line, and a preparation goes
to the stroke's start along one (:func:`motor.trajectory.spline.approach`). From a hand
held across the body close to the chest, or to one, that line can pass where no elbow
swivel keeps the upper arm out of the chest (``41_tanedila_welle``'s left hand, lowered
from beside the right cheek: 1.6 cm into the chest, whatever the swivel; taken back up
there after a stroke that went lower: 1.3 cm). People bow the hand's way out instead.

:func:`find_bow` looks at a way at :data:`SAMPLES` instants (first at every
:data:`DETECTION_STRIDE`-th; at all of them only where those find it crowded), its points
kept out of the torso as the motor control keeps them
(:func:`motor.body.collision.kept_out_of_torso`), at how deep the arm's least costly
posture goes into the body there
(:func:`motor.arm.ik.arm_reach`'s ``penetration``: :func:`motor.arm.ik.solve_arm`'s, the measure
:func:`motor.arm.wrist_path.uncrowded` places gesture locations with). Where it goes
deeper than :data:`CROWDING_TOLERANCE` and than at either end (which no bow moves), the
way is displaced across its chord — outward (toward the arm's own side), upward or
forward, each made perpendicular to the chord — by a :func:`bow` that is whole over the
crowded stretch and eases to nothing from it to both ends, by the least of
:data:`BOW_STEPS` that clears it (the direction needing the least). None clearing, the
bow that leaves the arm least deep is taken if it spares the arm at least the tolerance
(a way through the body, which no bow of these sizes gets around, stays straight).

The bow is a function of the way's time, C² and rising over at least :data:`BOW_RAMP` of
it: laid along the way's length instead, a bow whole a tenth of the way in rose within a
few frames of the wrist's slow start and stepped its velocity. The wrist still leaves and
arrives as it did, in the same time: the bow and its first two derivatives vanish at
both ends.

Positions are metres in the avatar frame, times seconds.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from motor.arm.ik import arm_reach
from motor.body.avatar import Avatar
from motor.body.collision import kept_out_of_torso
from motor.trajectory.spline import WristTrajectory

#: How deep (m) the arm may enter the body on a way before the way is bowed; a gesture
#: location the arm reaches deeper is moved forward (:func:`motor.arm.wrist_path.uncrowded`).
CROWDING_TOLERANCE = 0.005
#: Instants along a way at which the arm is looked at (ends included), and how many times
#: as densely the chosen bow is checked.
SAMPLES = 65
CHECK_DENSITY = 4
#: Every this many of the samples (17 of 65, ends included) are looked at first; the
#: rest only where those find the way crowding the arm.
DETECTION_STRIDE = 4
#: Sizes of bow tried (m), smallest first.
BOW_STEPS = np.arange(0.01, 0.121, 0.01)
#: Least fraction of the way's time over which a bow grows to whole before the crowded
#: stretch, and fades after it.
BOW_RAMP = 0.25
#: A way shorter than this (m) is not bowed: its chord gives no direction to bow across.
SHORTEST_WAY = 0.01
_UP = np.array([0.0, 1.0, 0.0])
_FORWARD = np.array([0.0, 0.0, 1.0])

Window = tuple[tuple[float, float], tuple[float, float]]


@dataclass(frozen=True)
class Bow:
    """How a way is bowed: ``displacement (3,)`` (m) where the bow is whole, and its
    ``window``, (ramp in, ramp out) in fractions of the way's time (:func:`bow`)."""

    displacement: np.ndarray
    window: Window


def find_bow(avatar: Avatar, side: str, way: np.ndarray) -> Bow | None:
    """The bow of a way of the arm on ``side`` (``"l"``/``"r"``), given by its points
    ``(SAMPLES, 3)`` at even fractions of its time (module docstring); None where the way
    does not crowd the arm, is too short to bow, or no bow makes it less deep."""
    chord = way[-1] - way[0]
    if float(np.linalg.norm(chord)) < SHORTEST_WAY:
        return None
    # a first look at every DETECTION_STRIDE-th point: most ways do not crowd the arm, and
    # each is looked at as it is activated, on the live path
    glance = arm_reach(avatar, side, kept_out_of_torso(avatar, way[::DETECTION_STRIDE])).penetration
    if not np.any(glance > max(CROWDING_TOLERANCE, float(glance[0]), float(glance[-1]))):
        return None
    depth = arm_reach(avatar, side, kept_out_of_torso(avatar, way)).penetration
    floor = max(CROWDING_TOLERANCE, float(depth[0]), float(depth[-1]))
    crowded = np.flatnonzero(depth > floor)
    if crowded.size == 0:
        return None
    along = np.linspace(0.0, 1.0, way.shape[0])
    window = _window(float(along[crowded[0]]), float(along[crowded[-1]]))
    shape = bow(along, window)[0]
    sizes = _directions(side, chord)[:, None, :] * BOW_STEPS[None, :, None]  # (direction, size, 3)
    ways = way[None, None] + shape[None, None, :, None] * sizes[:, :, None, :]
    deepest = arm_reach(avatar, side, kept_out_of_torso(avatar, ways.reshape(-1, 3))).penetration.reshape(ways.shape[:3]).max(axis=2)
    clears = deepest <= floor
    if np.any(clears):
        smallest = np.where(np.any(clears, axis=1), np.argmax(clears, axis=1), len(BOW_STEPS))
        direction = int(np.argmin(smallest))
        chosen = Bow(sizes[direction, smallest[direction]], window)
    else:
        direction, size = np.unravel_index(int(np.argmin(deepest)), deepest.shape)
        if deepest[direction, size] > depth.max() - CROWDING_TOLERANCE:
            return None
        chosen = Bow(sizes[direction, size], window)
    return chosen if _spares_the_arm(avatar, side, way, chosen) else None


def _spares_the_arm(avatar: Avatar, side: str, way: np.ndarray, found: Bow) -> bool:
    """Whether the bowed way, looked at :data:`CHECK_DENSITY` times as densely (between
    the samples, along their chords), crowds the arm less than the straight one there: a
    way whose points the torso pushes out crowds the arm in narrow spikes, which the
    samples may straddle."""
    along = np.linspace(0.0, 1.0, CHECK_DENSITY * (way.shape[0] - 1) + 1)
    sampled = np.linspace(0.0, 1.0, way.shape[0])
    dense = np.stack([np.interp(along, sampled, way[:, axis]) for axis in range(3)], axis=1)
    bowed = dense + bow(along, found.window)[0][:, None] * found.displacement
    depth = arm_reach(avatar, side, kept_out_of_torso(avatar, np.concatenate([dense, bowed]))).penetration
    return float(depth[along.size :].max()) < float(depth[: along.size].max())


def bowed_trajectory(trajectory: WristTrajectory, found: Bow) -> WristTrajectory:
    """A one-piece wrist trajectory (a preparation) with ``found``'s bow added over its
    time: exactly, as knots at the bow's ramps' edges (between two of them the bow is a
    quintic in time, or constant, as the piece is a quintic; at each edge its slope and
    curvature vanish, so the knots keep the piece's velocity and acceleration)."""
    start, end = trajectory.start, trajectory.end
    fractions = np.unique(np.clip([0.0, *found.window[0], *found.window[1], 1.0], 0.0, 1.0))
    times = start + fractions * (end - start)
    positions = trajectory.position(times) + bow(fractions, found.window)[0][:, None] * found.displacement
    return WristTrajectory(times, positions, trajectory.velocity(times), trajectory.acceleration(times), trajectory.warnings)


def bow(fractions: np.ndarray, window: Window) -> tuple[np.ndarray, np.ndarray]:
    """The bow ``(n,)`` at ``fractions`` of the way's time and its slope: 0 at both ends,
    growing (C², :func:`_smootherstep`) to 1 over ``window[0]``, 1 until ``window[1]``,
    fading to 0 over it."""
    rise, rise_slope = _smootherstep(fractions, window[0])
    fall, fall_slope = _smootherstep(fractions, window[1])
    return rise * (1.0 - fall), rise_slope * (1.0 - fall) - rise * fall_slope


def _window(first: float, last: float) -> Window:
    """The bow's ramps around the crowded stretch ``[first, last]`` (fractions of the
    time): from the start to the stretch and from the stretch to the end, the gentlest a
    bow can be, each at least :data:`BOW_RAMP` long."""
    ramp_in = (0.0, max(first, BOW_RAMP))
    ramp_out = (min(last, 1.0 - BOW_RAMP), 1.0)
    if ramp_out[0] < ramp_in[1]:
        middle = 0.5 * (ramp_in[1] + ramp_out[0])
        ramp_in, ramp_out = (0.0, middle), (middle, 1.0)
    return ramp_in, ramp_out


def _smootherstep(x: np.ndarray, edges: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """0 before ``edges[0]``, rising to 1 at ``edges[1]`` with zero slope and curvature at
    both (C²: the wrist's acceleration does not step where a bow starts or ends), and its
    slope."""
    width = edges[1] - edges[0]
    u = np.clip((x - edges[0]) / width, 0.0, 1.0)
    return u * u * u * (10.0 + u * (6.0 * u - 15.0)), 30.0 * u * u * (1.0 - u) ** 2 / width


def _directions(side: str, chord: np.ndarray) -> np.ndarray:
    """Unit directions ``(3, 3)`` across the chord: outward (toward the arm's own side),
    upward and forward, each made perpendicular to it."""
    unit = chord / float(np.linalg.norm(chord))
    outward = np.array([1.0 if side == "l" else -1.0, 0.0, 0.0])
    directions = np.stack([outward, _UP, _FORWARD])
    directions = directions - (directions @ unit)[:, None] * unit
    return directions / np.maximum(np.linalg.norm(directions, axis=1, keepdims=True), 1e-12)
