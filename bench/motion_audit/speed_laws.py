"""Human speed laws measured on the rendered wrist: speed budget, power law, minimum jerk.

* **Peak speed and acceleration** of each wrist (world frame): speed by central
  differences, acceleration by the second difference ``(x[i+1] − 2x[i] + x[i−1])·fps²``.
* **Power law** ``speed ∝ R^β`` (R the radius of curvature, ``|v|³/|v × a|``), fitted by
  least squares in log–log on each *curved stroke*. A stroke is a behaviour's planned
  stroke phase (timeline ``stroke_start`` to ``stroke_end``) on one arm; it counts as
  curved when, on the rendered path, the wrist travels at least :data:`CURVED_PATH`, its
  direction of motion turns by at least :data:`CURVED_TURN` in total (summed between
  consecutive frames above the speed floor, leaving out single-frame turns above
  :data:`REVERSAL_TURN`, which are reversals through a stop, not curvature) and the
  median radius over those frames is below :data:`CURVED_RADIUS`. The law relates speed
  to curvature *within* a movement: it says nothing about how fast a movement starts
  or stops, and each movement has its own gain (``v = K·R^β``, K set by its size and
  duration). So the fit

  - uses the frames faster than the floor ``max(`` :data:`SPEED_FLOOR` ``,``
    :data:`SPEED_FLOOR_FRACTION` ``× the stroke's peak)`` whose radius is below
    :data:`MAX_RADIUS` and that lie at least :data:`RAMP_TIME` from any frame of the
    track slower than the floor (a start from or a stop at rest, where the speed is set
    by the acceleration from or to rest whatever the curvature, and where the differences
    that estimate R span the rest);
  - gives each *piece* of the stroke — a stretch between two frames slower than the
    floor, i.e. one movement between stops — its own gain: log speed and log R are
    centred on their means within each piece (pieces with fewer than
    :data:`MIN_PIECE_POINTS` frames left out) and β is the slope of the pooled centred
    values, R² their fraction of the centred variance explained.

  It needs :data:`MIN_FIT_POINTS` frames and a spread (standard deviation of the centred
  log R) of at least :data:`MIN_LOG_SPREAD`: a circle traced at any speed has one
  radius and no exponent.
* **Jerk ratio** of a movement unit (:mod:`bench.motion_audit.movement`): the peak jerk
  *along the path* — the third difference ``·fps³`` of the distance travelled, i.e. of
  the speed profile, which is what a start with a step in acceleration spoils — against
  that of the minimum-jerk movement over the same frames: the quintic ``s(t)`` from 0 to
  the unit's path length ``L`` with the unit's speed and acceleration at its two ends —
  zero at rest; at a speed valley the rendered ones (second-order one-sided differences
  inside the unit) — differenced the same way (from rest to rest it is
  ``L(10τ³ − 15τ⁴ + 6τ⁵)``). A unit that starts (ends) at rest is taken with
  :data:`JERK_MARGIN` still frames before (after) it, and so is the reference, so that a
  jump in acceleration at the start counts. A minimum-jerk movement scores 1. (Changes
  of direction are not in this figure: the steps catch kinks, the power law the curves.)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bench.motion_audit.movement import Unit

CURVED_PATH = 0.05
CURVED_TURN = np.pi / 2
REVERSAL_TURN = np.radians(60.0)
CURVED_RADIUS = 0.3
SPEED_FLOOR = 0.05
SPEED_FLOOR_FRACTION = 0.2
MAX_RADIUS = 1.0
MIN_FIT_POINTS = 8
#: Seconds next to a frame slower than the floor that the fit leaves out: the start or the
#: stop of a movement. A minimum-jerk movement spends its first and last 20 % below 41 %
#: of its peak speed, rising or falling whatever the path's curvature: 0.1 s of a 0.5 s
#: stroke.
RAMP_TIME = 0.1
#: Fewest frames of a piece (a movement between two stops) that enters the fit.
MIN_PIECE_POINTS = 3
MIN_LOG_SPREAD = 0.1
#: Units shorter than this path (metres) or this many frames get no jerk ratio.
MIN_UNIT_PATH = 0.02
MIN_UNIT_FRAMES = 4
#: Still frames around a unit included in its jerk (the third difference spans 4 frames).
JERK_MARGIN = 2
#: Distance (m) past which a wrist counts as having left rest when a movement's onset is
#: read to a fraction of a frame (:func:`_onset`): beyond the BVH's rounding.
_MOVED = 1e-6
#: Speed (m/s) below which a unit's end between two movements (a speed valley) counts as
#: a stop for its reference: the wrist turned back through it, or paused too briefly for a
#: hold, and its reference leaves or reaches rest there, to a fraction of a frame.
STILL_SPEED = 0.02


def peak_speed(path: np.ndarray, fps: float) -> tuple[float, int]:
    """The highest central-difference speed (m/s) and its frame."""
    speed = np.linalg.norm(np.gradient(path, 1.0 / fps, axis=0), axis=1) if path.shape[0] > 1 else np.zeros(1)
    frame = int(np.argmax(speed))
    return float(speed[frame]), frame


def peak_acceleration(path: np.ndarray, fps: float) -> tuple[float, int]:
    """The highest second-difference acceleration (m/s²) and its (middle) frame."""
    if path.shape[0] < 3:
        return 0.0, 0
    acceleration = np.linalg.norm(np.diff(path, n=2, axis=0), axis=1) * fps * fps
    frame = int(np.argmax(acceleration))
    return float(acceleration[frame]), frame + 1


@dataclass(frozen=True)
class PowerLawFit:
    """β of ``speed ∝ R^β`` on one curved stroke, with R² and the frames used; ``beta``
    is None when the stroke is curved but its curvature too uniform to fit."""

    what: str
    time: float
    beta: float | None
    r_squared: float | None
    points: int
    turn_degrees: float
    file: str = ""

    def as_json(self) -> dict:
        return {
            "file": self.file,
            "what": self.what,
            "time": round(self.time, 4),
            "beta": None if self.beta is None else round(self.beta, 4),
            "r_squared": None if self.r_squared is None else round(self.r_squared, 4),
            "points": self.points,
            "turn_degrees": round(self.turn_degrees, 1),
        }


def curvature(path: np.ndarray, fps: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Velocity ``(n, 3)``, speed ``(n,)`` and radius of curvature ``(n,)`` (inf where straight)."""
    velocity = np.gradient(path, 1.0 / fps, axis=0)
    acceleration = np.gradient(velocity, 1.0 / fps, axis=0)
    speed = np.linalg.norm(velocity, axis=1)
    bend = np.linalg.norm(np.cross(velocity, acceleration), axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        radius = np.where(bend > 0, speed**3 / bend, np.inf)
    return velocity, speed, radius


def _frames_from_rest(slow: np.ndarray) -> np.ndarray:
    """Per frame, the number of frames to the nearest ``slow`` one (a large number if none)."""
    index = np.arange(slow.size)
    rest = np.flatnonzero(slow)
    if rest.size == 0:
        return np.full(slow.size, slow.size)
    after = np.clip(np.searchsorted(rest, index), 0, rest.size - 1)
    before = np.clip(after - 1, 0, rest.size - 1)
    return np.minimum(np.abs(rest[after] - index), np.abs(rest[before] - index))


def _centred(values: np.ndarray, pieces: np.ndarray) -> np.ndarray:
    """``values`` less the mean of their piece."""
    counts = np.bincount(pieces)
    means = np.bincount(pieces, weights=values) / np.maximum(counts, 1)
    return values - means[pieces]


def power_law(track: np.ndarray, fps: float, first: int, last: int, what: str, time: float) -> PowerLawFit | None:
    """β on the stroke from frame ``first`` to ``last`` of the wrist ``track`` ``(n, 3)``;
    None if the stroke is not curved by the rule above. Derivatives are central
    differences on the whole track, so frames within two of its ends are left out."""
    velocity, speed, radius = curvature(track, fps)
    frames = np.arange(max(first, 2), min(last, track.shape[0] - 3) + 1)
    path = track[first : last + 1]
    if frames.size < 5 or np.linalg.norm(np.diff(path, axis=0), axis=1).sum() < CURVED_PATH:
        return None
    floor = max(SPEED_FLOOR, SPEED_FLOOR_FRACTION * float(speed[frames].max()))
    slow = speed <= floor
    away = _frames_from_rest(slow)[frames] >= RAMP_TIME * fps
    pieces = np.cumsum(slow)[frames]
    velocity, speed, radius = velocity[frames], speed[frames], radius[frames]
    fast = ~slow[frames]
    pairs = fast[:-1] & fast[1:]
    unit = velocity / np.maximum(speed, 1e-12)[:, None]
    turns = np.arccos(np.clip(np.sum(unit[:-1] * unit[1:], axis=1), -1.0, 1.0))
    turn = float(np.sum(turns[pairs & (turns < REVERSAL_TURN)]))
    if turn < CURVED_TURN or not fast.any() or np.median(radius[fast]) >= CURVED_RADIUS:
        return None
    keep = fast & away & np.isfinite(radius) & (radius < MAX_RADIUS)
    _, piece, counts = np.unique(pieces[keep], return_inverse=True, return_counts=True)
    keep[np.flatnonzero(keep)[counts[piece] < MIN_PIECE_POINTS]] = False
    _, piece = np.unique(pieces[keep], return_inverse=True)
    log_radius, log_speed = _centred(np.log(radius[keep]), piece), _centred(np.log(speed[keep]), piece)
    if keep.sum() < MIN_FIT_POINTS or np.sqrt(np.mean(log_radius**2)) < MIN_LOG_SPREAD:
        return PowerLawFit(what, time, None, None, int(keep.sum()), float(np.degrees(turn)))
    slope = float(log_radius @ log_speed) / float(log_radius @ log_radius)
    residual = log_speed - slope * log_radius
    variance = float(log_speed @ log_speed)
    r_squared = 1.0 - float(residual @ residual) / variance if variance > 0 else 1.0
    return PowerLawFit(what, time, slope, r_squared, int(keep.sum()), float(np.degrees(turn)))


@dataclass(frozen=True)
class Boundary:
    """Speed (m/s) and acceleration (m/s²) along the path at one end of a movement."""

    speed: float = 0.0
    acceleration: float = 0.0


REST = Boundary()


def minimum_jerk_distance(length: float, duration: float, start: Boundary, end: Boundary, times: np.ndarray) -> np.ndarray:
    """The minimum-jerk distance ``s(t)`` (the quintic) from 0 to ``length`` in
    ``duration`` seconds with the ``start`` and ``end`` speed and acceleration, at
    ``times`` (seconds from the start)."""
    t, d = np.asarray(times, dtype=float), duration
    v0, v1, a0, a1 = start.speed, end.speed, start.acceleration, end.acceleration
    c3 = (20.0 * length - (8.0 * v1 + 12.0 * v0) * d - (3.0 * a0 - a1) * d * d) / (2.0 * d**3)
    c4 = (-30.0 * length + (14.0 * v1 + 16.0 * v0) * d + (3.0 * a0 - 2.0 * a1) * d * d) / (2.0 * d**4)
    c5 = (12.0 * length - 6.0 * (v1 + v0) * d + (a1 - a0) * d * d) / (2.0 * d**5)
    return v0 * t + 0.5 * a0 * t * t + c3 * t**3 + c4 * t**4 + c5 * t**5


def _boundary(distance: np.ndarray, fps: float) -> Boundary:
    """Speed and acceleration at the first sample of ``distance`` (≥ 4 samples), by
    second-order one-sided differences."""
    s0, s1, s2, s3 = distance[:4]
    return Boundary((-3.0 * s0 + 4.0 * s1 - s2) * fps / 2.0, (2.0 * s0 - 5.0 * s1 + 4.0 * s2 - s3) * fps * fps)


def _peak_third_difference(distance: np.ndarray, fps: float) -> float:
    return float(np.abs(np.diff(distance, n=3)).max() * fps**3) if distance.size >= 4 else 0.0


def jerk_ratio(path: np.ndarray, unit: Unit, fps: float) -> float | None:
    """Peak jerk along the path of ``unit`` over the minimum-jerk reference's; None for a
    unit too short (:data:`MIN_UNIT_PATH`, :data:`MIN_UNIT_FRAMES`)."""
    frames = unit.last - unit.first + 1
    before = min(JERK_MARGIN, unit.first) if unit.from_rest else 0
    after = min(JERK_MARGIN, path.shape[0] - 1 - unit.last) if unit.to_rest else 0
    piece = path[unit.first - before : unit.last + after + 1]
    distance = np.concatenate(([0.0], np.cumsum(np.linalg.norm(np.diff(piece, axis=0), axis=1))))
    length = distance[before + frames - 1] - distance[before]
    if frames < MIN_UNIT_FRAMES or length < MIN_UNIT_PATH:
        return None
    inside = distance[before : before + frames]
    start = _boundary(inside, fps)
    backwards = _boundary(inside[::-1], fps)
    leaves = unit.from_rest or abs(start.speed) < STILL_SPEED
    arrives = unit.to_rest or abs(backwards.speed) < STILL_SPEED
    start = REST if leaves else start
    end = REST if arrives else Boundary(-backwards.speed, backwards.acceleration)
    reference = _fitted_reference(distance - distance[before], length, frames, before, start, end, (leaves, arrives), fps)
    peak = _peak_third_difference(reference, fps)
    return _peak_third_difference(distance, fps) / peak if peak > 0 else None


def _fitted_reference(
    distance: np.ndarray, length: float, frames: int, before: int, start: Boundary, end: Boundary, at_rest: tuple[bool, bool], fps: float
) -> np.ndarray:
    """The minimum-jerk reference for a unit's ``distance`` (m, from the unit's first
    frame, with ``before`` still frames ahead of it). A movement leaves or reaches rest
    — a hold, or a valley where the wrist all but stops (:data:`STILL_SPEED`), as where it
    turns back: ``at_rest`` says which ends do — between frames, not on the unit's end
    frame, so there the reference starts or ends where the movement does, to a fraction
    of a frame (:func:`_onset`); spanning whole frames, a 0.4 s minimum-jerk movement that
    started between frames scored 1.2 against itself, and one that turned back 1.7."""
    leaves, arrives = at_rest
    onset = _onset(distance[before:]) if leaves else 0.0
    finish = _onset(length - distance[before : before + frames][::-1]) if arrives else 0.0
    times = (np.arange(distance.size) - before - onset) / fps
    duration = (frames - 1 - onset - finish) / fps
    inside = minimum_jerk_distance(length, duration, start, end, np.clip(times, 0.0, duration))
    return np.where(times < 0.0, 0.0, inside) if leaves else inside


def _onset(distance: np.ndarray) -> float:
    """Frames after the first sample of ``distance`` (m, 0 there, at rest) at which the
    movement starts: a start from rest with neither speed nor acceleration travels
    as the cube of the time since its onset, so the first two samples past it, ``s₁`` and
    ``s₂`` at frames ``i`` and ``i + 1``, put it ``1 / ((s₂ / s₁)^⅓ − 1)`` frames before
    ``i``; 0 where that cannot be read."""
    moving = np.flatnonzero(distance > _MOVED)
    if moving.size == 0 or moving[0] + 1 >= distance.size:
        return 0.0
    first = int(moving[0])
    ratio = np.cbrt(distance[first + 1] / distance[first])
    if ratio <= 1.0:
        return 0.0
    return float(np.clip(first - 1.0 / (ratio - 1.0), max(first - 1.0, 0.0), float(first)))
