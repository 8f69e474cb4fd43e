"""A wrist's path cut into what a viewer sees: holds, speed valleys and movement units.

On a path ``(n, 3)`` sampled at ``fps``:

* the wrist is **still** from frame ``i`` to ``i+1`` when it moves slower than
  :data:`STILL_SPEED` between them (one-sided, so that arriving at frame ``i`` and
  leaving after frame ``j`` are exact frames);
* a **hold** is a run of still transitions lasting at least :data:`HOLD_TIME`; it
  *arrives* at its first frame and *departs* from its last — moved inward by up to
  :data:`EXACT_REFINEMENT` frames to where the wrist is exactly at rest (slower than
  :data:`EXACT_STILL`) when it gets there, because a smooth stop is already slower than
  :data:`STILL_SPEED` a frame or so before it ends (a hold that drifts keeps its ends);
* a **valley** is a local minimum of the (central-difference) speed, not inside a hold,
  at most :data:`VALLEY_RATIO` of the speed peaks within :data:`VALLEY_REACH` on either
  side, both peaks at least :data:`MOVING_SPEED` — a slowing a viewer sees. Its time is
  refined to a fraction of a frame by the parabola through the three speeds around it;
* a **movement unit** runs from one boundary (a hold's departure or a valley) to the next
  (a hold's arrival or a valley), if the wrist reaches :data:`MOVING_SPEED` within it; it
  *starts from rest* when its first boundary is a hold's departure or the first frame
  (a render starts from the rest pose), and *ends at rest* when its last boundary is a
  hold's arrival or the last frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

STILL_SPEED = 0.002
EXACT_STILL = 1e-4
EXACT_REFINEMENT = 3
HOLD_TIME = 0.05
VALLEY_RATIO = 0.5
VALLEY_REACH = 0.3
MOVING_SPEED = 0.05


@dataclass(frozen=True)
class Hold:
    """Frames ``first`` (arrival) to ``last`` (departure), both inclusive."""

    first: int
    last: int


@dataclass(frozen=True)
class Valley:
    """A speed valley at ``frame``, at fractional frame ``at`` after parabolic refinement."""

    frame: int
    at: float


@dataclass(frozen=True)
class Unit:
    """A movement from frame ``first`` to ``last``; ``from_rest`` if it leaves a hold (or
    starts the file), ``to_rest`` if it ends in one (or ends the file)."""

    first: int
    last: int
    from_rest: bool
    to_rest: bool


@dataclass(frozen=True)
class Segmentation:
    holds: tuple[Hold, ...]
    valleys: tuple[Valley, ...]
    units: tuple[Unit, ...]


def central_speed(path: np.ndarray, fps: float) -> np.ndarray:
    """Speed ``(n,)`` in m/s by central differences (one-sided at the ends)."""
    if path.shape[0] < 2:
        return np.zeros(path.shape[0])
    return np.linalg.norm(np.gradient(path, 1.0 / fps, axis=0), axis=1)


def holds(path: np.ndarray, fps: float) -> tuple[Hold, ...]:
    """Runs of still transitions at least :data:`HOLD_TIME` long, their ends refined."""
    step = np.linalg.norm(np.diff(path, axis=0), axis=1) * fps
    still = step < STILL_SPEED
    edges = np.diff(np.concatenate(([0], still.astype(np.int8), [0])))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)  # transitions [start, end)
    minimum = max(1, int(np.ceil(HOLD_TIME * fps - 1e-9)))
    found = []
    for start, end in zip(starts, ends):
        if end - start < minimum:
            continue
        exact = np.flatnonzero(step[start:end] < EXACT_STILL)
        first = start + int(exact[0]) if exact.size and exact[0] <= EXACT_REFINEMENT else start
        last = start + int(exact[-1]) + 1 if exact.size and end - 1 - (start + exact[-1]) <= EXACT_REFINEMENT else end
        found.append(Hold(int(first), int(max(last, first))))
    return tuple(found)


def valleys(speed: np.ndarray, fps: float, still: np.ndarray) -> tuple[Valley, ...]:
    """Deep local minima of ``speed`` outside the frames marked ``still``."""
    n = speed.size
    if n < 3:
        return ()
    middle = np.arange(1, n - 1)
    minimum = (speed[middle] <= speed[middle - 1]) & (speed[middle] < speed[middle + 1]) & ~still[middle]
    candidates = middle[minimum]
    if candidates.size == 0:
        return ()
    reach = max(1, int(round(VALLEY_REACH * fps)))
    padded = np.concatenate((np.full(reach, -np.inf), speed, np.full(reach, -np.inf)))
    windows = np.lib.stride_tricks.sliding_window_view(padded, reach + 1)
    before = windows[candidates].max(axis=1)  # speeds from frame − reach to frame
    after = windows[candidates + reach].max(axis=1)  # speeds from frame to frame + reach
    peaks = np.minimum(before, after)
    deep = (peaks >= MOVING_SPEED) & (speed[candidates] <= VALLEY_RATIO * peaks)
    chosen = candidates[deep]
    left, centre, right = speed[chosen - 1], speed[chosen], speed[chosen + 1]
    curvature = left - 2.0 * centre + right
    with np.errstate(divide="ignore", invalid="ignore"):
        shift = np.where(curvature > 0, 0.5 * (left - right) / curvature, 0.0)
    return tuple(Valley(int(f), float(f + s)) for f, s in zip(chosen, np.clip(shift, -0.5, 0.5)))


def segment(path: np.ndarray, fps: float) -> Segmentation:
    """Holds, valleys and movement units of a wrist path ``(n, 3)``."""
    found = holds(path, fps)
    still = np.zeros(path.shape[0], dtype=bool)
    for hold in found:
        still[hold.first : hold.last + 1] = True
    speed = central_speed(path, fps)
    dips = valleys(speed, fps, still)
    boundaries = sorted(
        [(hold.first, "arrive") for hold in found] + [(hold.last, "depart") for hold in found] + [(dip.frame, "valley") for dip in dips]
    )
    if not found or found[0].first > 0:
        boundaries.insert(0, (0, "begin"))
    if not found or found[-1].last < path.shape[0] - 1:
        boundaries.append((path.shape[0] - 1, "finish"))
    units = []
    for (first, kind), (last, next_kind) in zip(boundaries, boundaries[1:]):
        if kind == "arrive" or next_kind in ("depart",) or last <= first:
            continue
        if speed[first : last + 1].max() < MOVING_SPEED:
            continue
        units.append(Unit(first, last, from_rest=kind in ("depart", "begin"), to_rest=next_kind in ("arrive", "finish")))
    return Segmentation(found, dips, tuple(units))
