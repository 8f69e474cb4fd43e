"""The stroke starts at a landmark a viewer can see, exactly where the timeline says."""

from __future__ import annotations

import numpy as np
import pytest

from bench.speed_laws import DIP_RATIO, DYNAMIC_PATH, PEAK_REACH, landmark, still_pairs
from motor.body.avatar import Avatar
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


def _low_between_peaks(x: np.ndarray, frame: int, fps: float) -> bool:
    """The wrist's speed at ``frame`` lies in a valley: at most :data:`DIP_RATIO` of its
    peaks within :data:`PEAK_REACH` before and after."""
    speed = np.linalg.norm(np.gradient(x, 1.0 / fps, axis=0), axis=1)
    reach = int(PEAK_REACH * fps)
    before, after = speed[max(frame - reach, 0) : frame + 1].max(), speed[frame : frame + reach + 1].max()
    return bool(speed[frame] <= DIP_RATIO * min(before, after))


def test_every_dynamic_stroke_starts_at_a_hold_or_a_speed_valley(fine: Rendered, avatar: Avatar) -> None:
    """A hold or a speed minimum at stroke_start (±1 frame). Where the palms touch there,
    the motor control keeps the hands a palm thickness apart as the arms turn them: the
    wrist then follows its hand's turn (a few cm/s) while its planned path rests, so the
    speed minimum may lie a few frames off the peg; the onset must still lie in a valley
    (well below the speed on either side)."""
    strokes = _dynamic_strokes(fine)
    if not strokes:
        pytest.skip("no dynamic stroke")
    contact = fine.hands_in_contact(avatar.collision.palm_thickness)
    for behavior, arm in strokes:
        frame = fine.frame(behavior["phases"]["stroke_start"])
        what = f"{behavior['id']} ({arm})"
        if contact[frame]:
            assert _low_between_peaks(fine.wrists[arm], frame, fine.fps), f"{what}: hands in contact, stroke_start not in a speed valley"
        else:
            assert landmark(fine.wrists[arm], frame, fine.fps) is not None, f"{what}: no landmark at stroke_start"


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
