"""The hands kept apart over time: a separation eased in before the hands would meet and out after.

:func:`motor.body.collision.hand_separation` says, frame by frame, how far the wrists must
move apart for the hands to keep a palm thickness between them. Applied frame by frame,
that separation switches on within one frame where a path enters the contact (a hand
approaching the other at 0.6 m/s is stopped within one 60 fps frame) and, where the way
the hands part turns over from one frame to the next, flips: the rendered wrist's velocity
steps (up to 2 m/s in one frame on the sign corpus). :func:`eased_separation` turns the
frames' separations into one that is a smooth function of time and at least as large
where it is needed, coordinate by coordinate:

* the positive and the negative part of each coordinate are dilated (the largest value
  within :func:`ramp_frames` frames either side) and then averaged over three boxes whose
  radii add up to that: every frame's value is then at least its own need (each frame
  within its boxes holds at least that after the dilation); the separation grows from 0
  over twice :data:`SEPARATION_RAMP` before a need begins and falls the same way after
  it ends, piecewise cubic and C² (the boxes' convolution);
* where the coordinates keep their signs, the eased separation's projection on each
  frame's own separation is at least that separation's length, so the hands are at least
  as far apart as the frame asked (to first order); where a coordinate's sign turns over
  within the reach, its two parts partly cancel, and another look, with the arms solved
  again, tops it up (:meth:`motor.control.MotorControl._solve_frames`).

A frame's value depends on the separations of the frames :func:`reach_frames` either side
of it, and not on where the array starts: windows computed one after another, each with
that margin, give the values of one call over the whole span. Frames before the array's
first count as needing no separation (the first frame of an utterance has none before it).
"""

from __future__ import annotations

import numpy as np

#: Half the time (s) over which a separation grows from 0 to what a frame needs, before
#: the need begins (and falls after it ends). A separation of 3 cm switched on from one
#: frame to the next (the corpus' largest) then adds at most 0.27 m/s to the wrist's speed
#: and 0.07 m/s of velocity change per frame at 60 fps (a speed step is 0.5 m/s).
SEPARATION_RAMP = 0.1
#: How many boxes smooth the dilated separation: three give a C² (piecewise cubic) ramp.
BOXES = 3


def ramp_frames(fps: float) -> int:
    """The dilation's radius in frames at ``fps``: :data:`SEPARATION_RAMP`, at least one frame per box."""
    return max(BOXES, round(SEPARATION_RAMP * fps))


def reach_frames(fps: float) -> int:
    """How many frames either side of a frame its eased separation depends on, at ``fps``."""
    return 2 * ramp_frames(fps)


def eased_separation(needs: np.ndarray, fps: float) -> np.ndarray:
    """The separations ``needs (n, 3)`` (m) of consecutive frames at ``fps`` eased in and
    out over time (module docstring): ``(n, 3)``, each coordinate at least the need's
    where the need is positive, at most where it is negative, with the other part's
    share subtracted."""
    needs = np.ascontiguousarray(needs, dtype=float)
    if not np.any(needs):
        return np.zeros_like(needs)
    ramp = ramp_frames(fps)
    return _envelope(np.maximum(needs, 0.0), ramp) - _envelope(np.maximum(-needs, 0.0), ramp)


def _envelope(values: np.ndarray, ramp: int) -> np.ndarray:
    """Non-negative ``values (n, 3)`` dilated by ``ramp`` frames, then averaged over
    :data:`BOXES` boxes whose radii add up to ``ramp``: at least ``values`` everywhere."""
    if not np.any(values):
        return values
    out = _window(values, ramp, np.maximum)
    for radius in _box_radii(ramp):
        out = _window(out, radius, np.add) / (2 * radius + 1)
    return out


def _box_radii(ramp: int) -> list[int]:
    """:data:`BOXES` radii (frames, each at least 1) adding up to ``ramp``."""
    share, extra = divmod(ramp, BOXES)
    return [share + (1 if index < extra else 0) for index in range(BOXES)]


def _window(values: np.ndarray, radius: int, combine: np.ufunc) -> np.ndarray:
    """``combine`` (max or sum) of the ``2 radius + 1`` frames around each frame, frames
    past the ends counting as 0, always in the same order (so that the same values give
    the same result wherever the array starts)."""
    count = values.shape[0]
    padded = np.zeros((count + 2 * radius, values.shape[1]))
    padded[radius : radius + count] = values
    out = padded[: count].copy()
    for shift in range(1, 2 * radius + 1):  # over the window's offsets, every frame at once
        combine(out, padded[shift : shift + count], out=out)
    return out
