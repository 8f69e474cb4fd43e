"""Two gestures close together on one arm: the second takes over from the first (its
retraction skipped, stroke to stroke), continuous in value and velocity, within the speed
budget, and its stroke still starts from rest at its peg."""

from __future__ import annotations

import numpy as np
import pytest

from bench.speed_laws import derivatives, joint_positions, landmark, still_pairs
from motor.control import MotorControl
from motor.program.gesture import GESTURE_MANNER
from motor.program.lmp import TimePegs
from motor.trajectory.speed_budget import budget
from mura.constraints import Arm, Dynamic, Segment, SegmentKind
from mura.values import Direction, GridLocation
from tests.motor_program.conftest import behavior

FPS = 240.0
FIRST = Dynamic(
    "HandLocation",
    (Segment(SegmentKind.LINEAR, start=GridLocation("LocChest", "LocCenterRight", "LocNorm"), direction=Direction((-1.0, 0.0, 0.0), "DirR"), distance=0.2),),
    scope=Arm.RIGHT,
)
SECOND = Dynamic(
    "HandLocation",
    (Segment(SegmentKind.LINEAR, start=GridLocation("LocShoulder", "LocCenterRight", "LocFar"), direction=Direction((0.0, -1.0, 0.0), "DirD"), distance=0.15),),
    scope=Arm.RIGHT,
)
#: First gesture: stroke 0.8–1.4 s, held until relax at 1.5 s, then its retraction.
FIRST_PEGS = TimePegs(0.0, 0.8, 0.8, 1.0, 1.4, 1.5, 2.3)
#: Finite differences read a peak a little off; the limit is on the motion.
TOLERANCE = 1.05


def _perform(avatar, second_start: float, window: float):
    control = MotorControl(avatar, FPS)
    first = control.plan(behavior(FIRST, "first"), FIRST_PEGS, next_gesture_follows=True)
    control.activate(first)
    onset = second_start + window
    second = control.plan(behavior(SECOND, "second"), TimePegs(second_start, onset, onset, onset + 0.2, onset + 0.6, onset + 0.8, onset + 1.6))
    control.activate(second)
    motion = control.frames(0.0, second.pegs.end + 0.2)
    wrist = joint_positions(motion, ("r_wrist",))["r_wrist"] - motion.root_translation
    return first, second, wrist


@pytest.mark.parametrize(
    ("second_start", "window"),
    [(1.45, 0.7), (1.5, 0.7), (1.7, 0.6), (1.9, 0.5), (1.5, 0.15)],
    ids=["during the hold", "at relax", "early in the retraction", "late in the retraction", "too little time"],
)
def test_stroke_to_stroke_hand_over(avatar, second_start: float, window: float) -> None:
    first, second, wrist = _perform(avatar, second_start, window)
    limits = budget(GESTURE_MANNER)
    velocity, acceleration = derivatives(wrist, FPS)
    assert np.linalg.norm(velocity, axis=1).max() <= limits.peak_speed * TOLERANCE
    assert np.linalg.norm(acceleration, axis=1).max() <= limits.peak_acceleration * TOLERANCE
    onset = second.pegs.stroke_start
    if second.pegs.stroke_start > second_start + window + 1e-9:
        assert any("second: kept within" in w and "s later" in w for w in second.warnings)
    frame = int(round(onset * FPS))
    assert still_pairs(wrist, FPS)[frame - 1], "the second stroke starts from rest"
    assert landmark(wrist, frame, FPS) is not None
    rest = avatar.postures["interim_rest"]["r"].wrist
    between = wrist[int(round(first.pegs.stroke_end * FPS)) : frame]
    assert np.linalg.norm(between - rest, axis=1).min() > 0.05, "the first gesture's retraction is skipped"
