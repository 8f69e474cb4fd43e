"""Planning constraint trees into motor programs: demands, timing of sequences and
repetitions, symmetry, pointing, retraction, and the rules for impossible constraints."""

from __future__ import annotations

import numpy as np
import pytest

from motor.arm.wrist_position import WristPositionLMP
from motor.arm.wrist_rotation import WristRotationLMP
from motor.control import MotorControl
from motor.hand.lmp import HandShapeLMP
from motor.program.fragment import POINTING_REACH, PlanningError, movement_time
from motor.program.gesture import GestureDemands, rest_handshape
from motor.program.lmp import ChannelState, RetractionLMP
from motor.trajectory.spline import fitts_duration
from mura.constraints import (
    Arm,
    Dynamic,
    Parallel,
    Repetition,
    Segment,
    SegmentKind,
    Sequence,
    Static,
    Symmetrical,
    Symmetry,
)
from mura.values import (
    Direction,
    GridLocation,
    HandShape,
    PalmOrientation,
    PointLocation,
    Symbol,
)
from tests.motor_program.conftest import behavior, pegs

CHEST = GridLocation("LocChest", "LocCenterRight", "LocNorm")
SHOULDER = GridLocation("LocShoulder", "LocCenterRight", "LocNorm")
RIGHT = Direction((-1.0, 0.0, 0.0), "DirR")
DOWN = Direction((0.0, -1.0, 0.0), "DirD")


def line(distance: float, direction: Direction = RIGHT, start=CHEST, arm: Arm = Arm.RIGHT) -> Dynamic:
    return Dynamic("HandLocation", (Segment(SegmentKind.LINEAR, start=start, direction=direction, distance=distance),), scope=arm)


def lmps_of(program, kind, arm="right"):
    return [lmp for lmp in program.lmps if isinstance(lmp, kind) and lmp.channel[0] == arm]


@pytest.fixture
def control(avatar) -> MotorControl:
    return MotorControl(avatar, fps=60.0)


@pytest.mark.parametrize(
    ("constraints", "arms", "duration", "dynamic"),
    [
        (Static("HandShape", HandShape("fist"), scope=Arm.RIGHT), {"right"}, 0.0, False),
        (Static("HandLocation", CHEST, scope=Arm.LEFT), {"left"}, 0.0, False),
        (line(0.1), {"right"}, movement_time(0.1), True),
        (line(0.6), {"right"}, 0.6 / 0.5, True),
        (Symmetrical(line(0.125), Arm.RIGHT, Symmetry(frozenset("S"), "SymMS")), {"right", "left"}, 0.4, True),
        (Sequence((line(0.1), line(0.3, DOWN, start=None))), {"right"}, movement_time(0.1) + movement_time(0.3), True),
        (Repetition(line(0.1), 3), {"right"}, 3 * 0.4 + 2 * movement_time(0.1), True),
        (Static("GazeDirection", PointLocation((0.0, 0.5, 1.0)), scope="head"), set(), 0.0, False),
    ],
)
def test_demands(control, avatar, constraints, arms, duration, dynamic) -> None:
    demands = control.demands(behavior(constraints))
    assert isinstance(demands, GestureDemands)
    assert demands.arms == frozenset(arms)
    assert demands.stroke_duration == pytest.approx(duration)
    assert demands.dynamic is dynamic and demands.repeatable is dynamic
    if "right" in arms and not isinstance(constraints, Static):
        start = np.array([avatar.grid.laterals["LocCenterRight"], avatar.grid.heights["LocChest"], avatar.grid.front + 0.2])
        assert demands.preparation_distance == pytest.approx(np.linalg.norm(start - avatar.postures["rest"]["r"].wrist))


def test_preparation_duration_is_fitts_from_where_the_arm_will_be(control, avatar) -> None:
    spec = behavior(line(0.1))
    rest = avatar.postures["rest"]["r"].wrist
    start = control.planner.fragment(spec).tracks[("right", "location")][0].value
    assert control.preparation_duration(spec, 0.0) == pytest.approx(float(fitts_duration(np.linalg.norm(start - rest))))
    control.activate(control.plan(spec, pegs(0.0, 0.5, 0.6, 1.0, 3.0)))
    assert control.preparation_duration(spec, 2.0) == pytest.approx(float(fitts_duration(0.1)), rel=1e-3)


def test_sequence_splits_the_stroke_in_proportion_to_natural_durations(control) -> None:
    spec = behavior(Sequence((line(0.1), line(0.3, DOWN, start=None))))
    program = control.plan(spec, pegs(0.0, 0.5, 1.0, 3.0))
    (wrist,) = lmps_of(program, WristPositionLMP)
    first, second = movement_time(0.1), movement_time(0.3)
    corner = 1.0 + 2.0 * first / (first + second)
    assert wrist.breakpoint_times[0] == pytest.approx(1.0) and wrist.breakpoint_times[-1] == pytest.approx(3.0)
    index = int(np.argmin(abs(wrist.breakpoint_times - corner)))
    assert wrist.breakpoint_times[index] == pytest.approx(corner)
    np.testing.assert_allclose(wrist.breakpoints[index] - wrist.breakpoints[0], [-0.1, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(wrist.breakpoints[-1] - wrist.breakpoints[index], [0.0, -0.3, 0.0], atol=1e-12)


def test_static_locations_in_a_sequence_are_successive_targets(control, avatar) -> None:
    places = [GridLocation("LocChest", lateral, "LocNorm") for lateral in ("LocCenterRight", "LocCCenter", "LocCCenterRight")]
    spec = behavior(Sequence(tuple(Static("HandLocation", place, scope=Arm.RIGHT) for place in places)))
    program = control.plan(spec, pegs(0.0, 0.5, 1.0, 2.0))
    (wrist,) = lmps_of(program, WristPositionLMP)
    assert wrist.breakpoints.shape == (3, 3)
    np.testing.assert_allclose(wrist.breakpoints[:, 0], [avatar.grid.laterals[p.lateral] for p in places])
    assert control.demands(spec).stroke_duration == pytest.approx(movement_time(0.25) + movement_time(0.15))


@pytest.mark.parametrize(("mode", "expected_x"), [("fromstart", [0, -0.1, 0, -0.1]), ("reverse", [0, -0.1, 0]), ("continue", [0, -0.1, -0.2])])
def test_repetition_modes(control, mode, expected_x) -> None:
    program = control.plan(behavior(Repetition(line(0.1), 2, mode=mode)), pegs(0.0, 0.5, 1.0, 2.0))
    (wrist,) = lmps_of(program, WristPositionLMP)
    np.testing.assert_allclose(wrist.breakpoints[:, 0] - wrist.breakpoints[0, 0], expected_x, atol=1e-12)


def test_repetitions_argument_repeats_the_whole_stroke_evenly(control) -> None:
    program = control.plan(behavior(line(0.1)), pegs(0.0, 0.5, 1.0, 2.0), repetitions=3)
    (wrist,) = lmps_of(program, WristPositionLMP)
    assert wrist.breakpoints.shape[0] == 6
    np.testing.assert_allclose(np.diff(wrist.breakpoint_times), 0.2)  # stroke and return take 0.4 s each, scaled by 1/2


def test_symmetry_in_the_transversal_plane_through_the_spec_center(control, avatar) -> None:
    center = (0.0, 1200.0, 0.0)  # millimetres, height from the floor
    spec = behavior(Symmetrical(Parallel((line(0.1, DOWN),)), Arm.RIGHT, Symmetry(frozenset("ST"), "SymMST"), center))
    program = control.plan(spec, pegs(0.0, 0.5, 1.0, 2.0))
    (right,), (left,) = lmps_of(program, WristPositionLMP), lmps_of(program, WristPositionLMP, "left")
    plane = 1.2 - avatar.root_height
    np.testing.assert_allclose(left.breakpoints[:, 1], 2 * plane - right.breakpoints[:, 1])
    np.testing.assert_allclose(left.breakpoints[:, [0, 2]], right.breakpoints[:, [0, 2]] * [-1.0, 1.0])


def test_symmetry_keeps_the_other_arms_own_constraints(control) -> None:
    child = Parallel((line(0.1), Static("HandShape", HandShape("fist"), scope=Arm.RIGHT), Static("HandShape", HandShape("flathand"), scope=Arm.LEFT)))
    program = control.plan(behavior(Symmetrical(child, Arm.RIGHT, Symmetry(frozenset("S"), "SymMS"))), pegs(0.0, 0.5, 1.0, 2.0))
    (right,), (left,) = lmps_of(program, HandShapeLMP), lmps_of(program, HandShapeLMP, "left")
    assert not np.allclose(right.keys, left.keys)
    (left_wrist,) = lmps_of(program, WristPositionLMP, "left")
    assert left_wrist.breakpoints[-1, 0] - left_wrist.breakpoints[0, 0] == pytest.approx(0.1)


def test_pointing_places_the_hand_toward_the_target_and_points_the_fingers(control, avatar) -> None:
    target = PointLocation((-0.35, 0.05, 0.55))
    spec = behavior(Parallel((
        Static("HandLocation", target, scope=Arm.RIGHT, mode="pointTo"),
        Static("ExtFingerOrientation", target, scope=Arm.RIGHT, mode="pointTo"),
    )))  # fmt: skip
    program = control.plan(spec, pegs(0.0, 0.5, 1.0, 2.0))
    (wrist,) = lmps_of(program, WristPositionLMP)
    shoulder = avatar.rest_positions[avatar.joint_index("r_shoulder")]
    offset = wrist.breakpoints[0] - shoulder
    assert np.linalg.norm(offset) == pytest.approx(POINTING_REACH * avatar.arm_length("r"))
    toward = np.array(target.position) - shoulder
    assert np.cross(offset, toward) == pytest.approx(np.zeros(3), abs=1e-12)
    (rotation,) = lmps_of(program, WristRotationLMP)
    from motor import quaternion as quat

    fingers = quat.rotate(rotation.keys[-1], avatar.hand_frames["r"].finger_axis)
    np.testing.assert_allclose(fingers, toward / np.linalg.norm(toward), atol=1e-9)


@pytest.mark.parametrize(("follows", "posture"), [(False, "rest"), (True, "interim_rest")])
def test_retraction_goes_to_rest_or_interim_rest(control, avatar, follows, posture) -> None:
    spec = behavior(Parallel((line(0.1), Static("HandShape", HandShape("fist"), scope=Arm.RIGHT))))
    program = control.plan(spec, pegs(0.0, 0.5, 1.0, 1.5, 2.0), next_gesture_follows=follows)
    retractions = {lmp.channel[1]: lmp for lmp in program.lmps if isinstance(lmp, RetractionLMP)}
    assert set(retractions) == {"wrist_position", "hand_rotation", "handshape"}
    rest = avatar.postures[posture]["r"]
    np.testing.assert_allclose(retractions["wrist_position"].rest, rest.wrist)
    np.testing.assert_allclose(retractions["hand_rotation"].rest, rest.hand_rotation)
    np.testing.assert_allclose(retractions["handshape"].rest, rest_handshape())
    assert all(lmp.pegs.start == 2.0 for lmp in retractions.values())
    assert program.pegs.end == retractions["wrist_position"].pegs.ready > 2.0


def test_busy_until_and_interrupt(control, avatar) -> None:
    assert control.busy_until("right") == 0.0
    first = control.plan(behavior(line(0.1), "first"), pegs(0.0, 0.5, 1.0, 1.5, 2.0))
    second = control.plan(behavior(line(0.2, DOWN, start=SHOULDER), "second"), pegs(2.5, 3.0, 3.2, 3.8, 4.0))
    control.activate(first)
    control.activate(second)
    assert control.busy_until("right") == second.pegs.end and control.busy_until("left") == 0.0
    control.interrupt(1.2)
    assert control.busy_until("right") < second.pegs.start
    motion = control.frames(0.0, 5.0)
    assert np.all(np.isfinite(motion.rotations))
    wrist = control.timeline(("right", "wrist_position")).sample(np.array([control.busy_until("right") + 0.01]))
    np.testing.assert_allclose(wrist[0], avatar.postures["rest"]["r"].wrist, atol=1e-9)
    with pytest.raises(ValueError, match="arm must be"):
        control.busy_until("middle")


@pytest.mark.parametrize(
    ("constraints", "message"),
    [
        (Dynamic("HandLocation", (Segment(SegmentKind.LINEAR, start=CHEST, direction=Direction((0.0, 0.0, 0.0)), distance=0.1),), scope=Arm.RIGHT), "direction has zero length"),
        (Dynamic("HandLocation", (Segment(SegmentKind.LINEAR, start=CHEST),), scope=Arm.RIGHT), "needs an end"),
        (Static("HandLocation", GridLocation("LocNowhere", "LocCCenter", "LocNorm"), scope=Arm.RIGHT), "unknown grid height"),
        (Static("HandShape", PalmOrientation((0.0, 1.0, 0.0)), scope=Arm.RIGHT), "HandShape needs a hand shape"),
        (Static("ExtFingerOrientation", Direction((0.0, 0.0, 0.0)), scope=Arm.RIGHT), "ExtFingerOrientation has zero length"),
        (Static("HandLocation", PointLocation((-0.18, 0.49, -0.015)), scope=Arm.RIGHT, mode="pointTo"), "pointTo target lies at the shoulder"),
        (Dynamic("HandLocation", (), scope=Arm.RIGHT), "has no segments"),
    ],
)
def test_impossible_constraints_raise_errors_naming_the_behaviour(control, constraints, message) -> None:
    with pytest.raises(PlanningError, match=rf"behaviour 'broken'.*{message}"):
        control.plan(behavior(constraints, "broken"), pegs(0.0, 0.5, 1.0, 2.0))


@pytest.mark.parametrize(
    ("constraints", "timing", "warning"),
    [
        (line(0.6), pegs(0.0, 0.5, 1.0, 1.05), "the stroke needs"),
        (line(0.6), pegs(0.0, 0.5, 1.0, 1.4), "the stroke peaks at"),
        (Static("HandLocation", GridLocation("LocAboveHead", "LocRight", "LocStreched"), scope=Arm.RIGHT), pegs(0.0, 0.5, 1.0, 1.5), "out of reach"),
        (line(0.1), pegs(1.0, 1.0, 1.0, 1.5), "no time for the preparation"),
        (line(0.1), pegs(0.0, 0.5, 1.0, 1.0), "stroke interval"),
        (Dynamic("HandLocation", (Segment(SegmentKind.LINEAR, end=CHEST),), scope=Arm.RIGHT), pegs(0.0, 0.5, 1.0, 1.5), "without a start"),
        (Static("GazeDirection", Symbol("Nowhere"), scope="head"), pegs(0.0, 0.5, 1.0, 1.5), "unknown gaze target 'Nowhere'"),
        (Repetition(Static("HandShape", HandShape("fist"), scope=Arm.RIGHT), 2), pegs(0.0, 0.5, 1.0, 1.5), "cannot be repeated"),
    ],
)
def test_impossible_timing_and_places_are_resolved_with_warnings(control, constraints, timing, warning) -> None:
    program = control.plan(behavior(constraints, "odd"), timing)
    assert any(warning in note and note.startswith("odd") for note in program.warnings), program.warnings
    control.activate(program)
    motion = control.frames(0.0, program.pegs.end + 0.1)
    assert np.all(np.isfinite(motion.rotations))


def test_activation_warnings_are_collected(control, avatar) -> None:
    """A program planned for an arm already at its stroke (no preparation) but activated
    with the arm at rest cannot prepare in time: its stroke starts late, and says so."""
    start = control.planner.fragment(behavior(line(0.1))).first(("right", "location"))
    program = control.planner.plan(behavior(line(0.1)), pegs(0.0, 0.05, 0.1, 0.6), start_states={"right": ChannelState.at_rest(start)})
    control.activate(program)
    assert any("late" in note for note in control.warnings())


def test_rotation_and_shape_lmps_reach_their_first_key_at_ready(control) -> None:
    spec = behavior(Parallel((
        Static("HandShape", HandShape("fist"), scope=Arm.RIGHT),
        Static("PalmOrientation", PalmOrientation((0.0, -1.0, 0.0)), scope=Arm.RIGHT),
        Dynamic("HandShape", (Segment(SegmentKind.LINEAR, start=HandShape("fist"), end=HandShape("flathand")),), scope=Arm.LEFT),
    )))  # fmt: skip
    program = control.plan(spec, pegs(0.0, 0.4, 0.6, 1.4))
    for lmp in lmps_of(program, HandShapeLMP) + lmps_of(program, WristRotationLMP) + lmps_of(program, HandShapeLMP, "left"):
        assert lmp.key_times[0] == pytest.approx(0.4)
        assert lmp.key_times[-1] <= 1.4 + 1e-12
    (left,) = lmps_of(program, HandShapeLMP, "left")
    assert not np.allclose(left.keys[0], left.keys[-1])
    assert not lmps_of(program, WristPositionLMP, "left")
