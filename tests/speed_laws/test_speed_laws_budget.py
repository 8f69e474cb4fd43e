"""Wrist speed: never above the absolute ceiling, strokes within their manner's budget
unless the behaviour reports that the time given was too short, and what had to give
reported once per behaviour."""

from __future__ import annotations

from collections import Counter

import numpy as np

from bench.speed_laws import derivatives
from motor.body.avatar import Avatar
from motor.program.gesture import GESTURE_MANNER
from motor.trajectory.speed_budget import ABSOLUTE_PEAK_SPEED, CEILING, budget
from tests.speed_laws.conftest import Rendered

#: Finite differences at 60 fps read a peak a little high or low.
TOLERANCE = 1.02
#: How the motor program's budget warning begins, after the behaviour's name.
_OVER = f": over the {GESTURE_MANNER} speed budget"


def test_peak_wrist_speed_stays_below_the_ceiling(viewed: Rendered) -> None:
    for arm, x in viewed.wrists.items():
        speed = np.linalg.norm(derivatives(x, viewed.fps)[0], axis=1)
        assert speed.max() <= ABSOLUTE_PEAK_SPEED, f"{arm} wrist at {speed.max():.2f} m/s, {viewed.times[speed.argmax()]:.3f} s"


def test_gesture_strokes_stay_within_their_budget_or_say_why(viewed: Rendered, avatar: Avatar) -> None:
    """Away from contact between the hands: where the rendered palms touch, the motor
    control keeps them a palm thickness apart whatever the planned paths do (hands a spec
    drives through each other are pushed apart frame by frame), so there the wrist moves
    as the body demands, not as the planned stroke."""
    reported = {w.split(":", 1)[0] for w in viewed.warnings if _OVER in w}
    free = ~viewed.hands_in_contact(avatar.collision.palm_thickness)
    for behavior in viewed.behaviors("gesture"):
        first, last = viewed.frame(behavior["phases"]["stroke_start"]), viewed.frame(behavior["phases"]["stroke_end"])
        limit = (CEILING if behavior["id"] in reported else budget(GESTURE_MANNER)).peak_speed * TOLERANCE
        for arm in behavior["arms"]:
            speed = np.linalg.norm(derivatives(viewed.wrists[arm], viewed.fps)[0][first : last + 1], axis=1)[free[first : last + 1]]
            assert speed.max(initial=0.0) <= limit, f"{behavior['id']} ({arm}) stroke at {speed.max():.2f} m/s"


def test_the_budget_warning_comes_once_per_behaviour_with_its_amount(viewed: Rendered) -> None:
    notes = [w for w in viewed.warnings if _OVER in w]
    counts = Counter(w.split(":", 1)[0] for w in notes)
    assert all(count == 1 for count in counts.values()), counts
    assert all(" s later" in w or " m/s and " in w for w in notes)
