"""Two gestures close together on one arm: the second takes over from the first (its
retraction skipped, stroke to stroke), continuous in value and velocity, within the speed
budget (or below the ceiling, reported, when the time given is too short), and its stroke
still starts from rest at its peg."""

from __future__ import annotations

import numpy as np
import pytest

from bench.speed_laws import derivatives, joint_positions, landmark
from motor.control import MotorControl
from motor.program.gesture import GESTURE_MANNER
from motor.program.lmp import TimePegs
from motor.trajectory.speed_budget import CEILING, budget
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
#: Wrist speed (m/s) that counts as at rest at a stroke's start frame.
AT_REST = 0.005


def _perform(avatar, second_start: float, window: float, control: MotorControl | None = None):
    control = control or MotorControl(avatar, FPS)
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
    [(1.45, 0.7), (1.5, 0.7), (1.7, 0.6), (1.9, 0.5), (1.5, 0.3)],
    ids=["during the hold", "at relax", "early in the retraction", "late in the retraction", "quick"],
)
def test_stroke_to_stroke_hand_over(avatar, second_start: float, window: float) -> None:
    first, second, wrist = _perform(avatar, second_start, window)
    velocity, acceleration = derivatives(wrist, FPS)
    assert np.linalg.norm(velocity, axis=1).max() <= CEILING.peak_speed * TOLERANCE
    assert np.linalg.norm(acceleration, axis=1).max() <= CEILING.peak_acceleration * TOLERANCE
    onset = second.pegs.stroke_start
    frame = int(round(onset * FPS))
    speed = np.linalg.norm(velocity, axis=1)
    assert speed[frame - 1 : frame + 2].min() < AT_REST, "the second stroke starts from rest"
    assert landmark(wrist, frame, FPS) is not None
    rest = avatar.postures["interim_rest"]["r"].wrist
    between = wrist[int(round(first.pegs.stroke_end * FPS)) : frame]
    assert np.linalg.norm(between - rest, axis=1).min() > 0.05, "the first gesture's retraction is skipped"


@pytest.mark.parametrize("window", [0.6, 0.9])
def test_a_hand_over_with_time_to_spare_keeps_the_budget(avatar, window: float) -> None:
    """Given the time the scheduler gives (at least the budget's shortest preparation), the
    whole motion stays within the manner's budget."""
    *_, wrist = _perform(avatar, 1.5, window)
    limits = budget(GESTURE_MANNER)
    velocity, acceleration = derivatives(wrist, FPS)
    assert np.linalg.norm(velocity, axis=1).max() <= limits.peak_speed * TOLERANCE
    assert np.linalg.norm(acceleration, axis=1).max() <= limits.peak_acceleration * TOLERANCE


def test_too_little_time_starts_the_stroke_late_below_the_ceiling(avatar) -> None:
    """A window no motion below the ceiling can prepare in (a plan the scheduler would
    not make): the stroke starts late, from rest, and says so."""
    control = MotorControl(avatar, FPS)
    _, second, wrist = _perform(avatar, 1.5, 0.05, control)
    (late,) = [w for w in control.warnings() if "starts" in w and "late" in w]
    lateness = float(late.rsplit("starts ", 1)[1].split(" s late")[0])
    velocity, acceleration = derivatives(wrist, FPS)
    assert lateness > 0.0
    assert np.linalg.norm(velocity, axis=1).max() <= CEILING.peak_speed * TOLERANCE
    frame = int(round((second.pegs.stroke_start + lateness) * FPS))
    assert landmark(wrist, frame, FPS) is not None
