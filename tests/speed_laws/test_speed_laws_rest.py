"""Movements start and stop at rest with zero acceleration; single straight ones are
minimum-jerk — measured on the rendered wrists of every example and published file."""

from __future__ import annotations

import numpy as np
import pytest

from bench.speed_laws import derivatives, min_jerk_path, movement_units, squared_jerk
from tests.speed_laws.conftest import Rendered

#: The acceleration at the still frame next to a movement, over the movement's peak: a
#: minimum-jerk start of a 0.25 s stroke reaches about 0.15 within a frame at 240 fps, a
#: cubic (a step in acceleration) about 0.5 and more.
REST_ACCELERATION = 0.25
#: Integrated squared jerk over that of the minimum-jerk movement between the same ends.
JERK_RATIO = 1.5
#: Chord over path length from which a movement counts as a single straight stroke.
STRAIGHT = 0.999
#: Shortest movement measured, frames at 240 fps, and shortest straight stroke, metres.
MIN_FRAMES = 12
MIN_LENGTH = 0.02


def _units(performance: Rendered, arm: str) -> list[tuple[int, int, bool, bool]]:
    return [u for u in movement_units(performance.wrists[arm], performance.fps) if u[1] - u[0] >= MIN_FRAMES]


def _during_sign(performance: Rendered, first: int, last: int) -> bool:
    t0, t1 = performance.times[first], performance.times[last]
    return any(t0 < b["phases"]["end"] and t1 > b["phases"]["start"] for b in performance.behaviors("sign"))


@pytest.mark.parametrize("arm", ["right", "left"])
def test_starts_and_stops_at_rest_have_zero_acceleration(fine: Rendered, arm: str) -> None:
    x = fine.wrists[arm]
    _, acceleration = derivatives(x, fine.fps)
    size = np.linalg.norm(acceleration, axis=1)
    checked = 0
    for first, last, from_rest, to_rest in _units(fine, arm):
        peak = size[first + 1 : last].max()
        if from_rest:
            assert size[first] <= REST_ACCELERATION * peak, f"start at {fine.times[first]:.3f} s: {size[first]:.2f} of {peak:.2f} m/s²"
            checked += 1
        if to_rest:
            assert size[last] <= REST_ACCELERATION * peak, f"stop at {fine.times[last]:.3f} s: {size[last]:.2f} of {peak:.2f} m/s²"
            checked += 1
    if not checked:
        pytest.skip(f"the {arm} wrist never moves from or to rest")


@pytest.mark.parametrize("arm", ["right", "left"])
def test_single_straight_strokes_have_minimum_jerk(fine: Rendered, arm: str) -> None:
    x = fine.wrists[arm]
    checked = 0
    for first, last, from_rest, to_rest in _units(fine, arm):
        length = float(np.sum(np.linalg.norm(np.diff(x[first : last + 1], axis=0), axis=1)))
        chord = float(np.linalg.norm(x[last] - x[first]))
        if not (from_rest and to_rest and length > MIN_LENGTH and chord >= STRAIGHT * length) or _during_sign(fine, first, last):
            continue
        window = slice(first - 1, last + 2)
        reference = np.concatenate([x[first - 1 : first + 1], min_jerk_path(x[first], x[last], last - first + 1)[1:-1], x[last : last + 2]])
        ratio = squared_jerk(x[window], fine.fps) / squared_jerk(reference, fine.fps)
        assert ratio <= JERK_RATIO, f"movement {fine.times[first]:.3f}–{fine.times[last]:.3f} s: jerk {ratio:.2f} × minimum jerk"
        checked += 1
    if not checked:
        pytest.skip(f"no single straight movement of the {arm} wrist from rest to rest")
