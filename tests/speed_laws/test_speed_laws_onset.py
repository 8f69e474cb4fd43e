"""The stroke starts at a landmark a viewer can see, exactly where the timeline says."""

from __future__ import annotations

import numpy as np
import pytest

from bench.speed_laws import DYNAMIC_PATH, landmark, still_pairs
from tests.speed_laws.conftest import Rendered

#: Wrist speed (m/s) that counts as at rest at the stroke_start frame (a minimum-jerk
#: arrival and departure around it move the wrist a few micrometres in the frames beside).
AT_REST = 0.005


def _dynamic_strokes(performance: Rendered) -> list[tuple[dict, str]]:
    out = []
    for behavior in performance.behaviors():
        phases = behavior["phases"]
        for arm in behavior["arms"]:
            first, last = performance.frame(phases["stroke_start"]), performance.frame(phases["stroke_end"])
            path = performance.wrists[arm][first : last + 1]
            if last - first >= 3 and np.sum(np.linalg.norm(np.diff(path, axis=0), axis=1)) > DYNAMIC_PATH:
                out.append((behavior, arm))
    return out


def test_every_dynamic_stroke_starts_at_a_hold_or_a_speed_valley(fine: Rendered) -> None:
    strokes = _dynamic_strokes(fine)
    if not strokes:
        pytest.skip("no dynamic stroke")
    for behavior, arm in strokes:
        frame = fine.frame(behavior["phases"]["stroke_start"])
        assert landmark(fine.wrists[arm], frame, fine.fps) is not None, f"{behavior['id']} ({arm}): no landmark at stroke_start"


def test_a_gesture_stroke_starts_from_rest_at_its_stroke_start_peg(fine: Rendered) -> None:
    """The planned peg is where the rendered motion shows the onset: the preparation has
    brought the wrist to rest by the stroke_start frame (the stroke moves it from there
    on, or first changes the hand while the wrist holds), and the stroke then moves it."""
    strokes = [(b, arm) for b, arm in _dynamic_strokes(fine) if b["kind"] == "gesture"]
    if not strokes:
        pytest.skip("no dynamic gesture stroke")
    for behavior, arm in strokes:
        frame = fine.frame(behavior["phases"]["stroke_start"])
        speed = np.linalg.norm(np.gradient(fine.wrists[arm], 1.0 / fine.fps, axis=0), axis=1)
        assert speed[frame - 1 : frame + 2].min() < AT_REST, f"{behavior['id']} ({arm}): moving at stroke_start"
        assert not np.all(still_pairs(fine.wrists[arm], fine.fps)[frame : fine.frame(behavior["phases"]["stroke_end"])])
