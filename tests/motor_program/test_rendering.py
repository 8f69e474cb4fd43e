"""Rendered motion of planned gestures: speed profiles, hand-overs, the seed's Fig. 2,
every example and corpus utterance, streaming and vectorization."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from motor import control as control_module
from motor.arm import arm_pair
from motor import quaternion as quat
from motor.body.collision import inside_torso, outside_torso
from motor.control import MotorControl
from motor.hand.shape import hand_rotations, handshape_params
from motor.program.lmp import TimePegs
from mura.constraints import Arm, Dynamic, Parallel, Segment, SegmentKind, Static
from mura.lexicon import load_lexicon
from mura.murml import load_utterance, load_utterances
from mura.values import Direction, GridLocation, HandShape, PalmOrientation
from tests.motor_program.conftest import behavior, joint_path, pegs, pose, render

REPO = Path(__file__).resolve().parents[2]
FIG2 = REPO / "specs" / "utterances" / "fig2_take_this_bar.xml"
BAR = np.array([-0.35, 0.05, 0.55])  # Loc-Bar_1 of the lexicon's scene


def _stroke(start: GridLocation, direction: tuple[float, float, float], distance: float, arm: Arm = Arm.RIGHT) -> Dynamic:
    segment = Segment(SegmentKind.LINEAR, start=start, direction=Direction(direction), distance=distance)
    return Dynamic("HandLocation", (segment,), scope=arm)


def _speeds(path: np.ndarray, fps: float) -> np.ndarray:
    """Central-difference speeds at frames 1 … n-2."""
    return np.linalg.norm(path[2:] - path[:-2], axis=1) * fps / 2.0


@pytest.mark.parametrize(
    ("direction", "distance", "stroke"),
    [((-1.0, 0.0, 0.0), 0.2, (1.0, 1.5)), ((0.0, -1.0, 0.0), 0.15, (0.9, 1.3)), ((0.0, 0.0, 1.0), 0.1, (1.0, 1.6))],
)
def test_linear_stroke_has_a_symmetric_bell_shaped_speed_profile(avatar, direction, distance, stroke) -> None:
    start = GridLocation("LocChest", "LocCenterRight", "LocNorm")
    spec = behavior(_stroke(start, direction, distance))
    fps = 240.0
    _, motion = render(avatar, [(spec, pegs(0.1, 0.7, *stroke, relax=2.0))], fps=fps)
    wrist = joint_path(avatar, motion, "r_wrist")
    times = motion.times[1:-1]
    inside = (times >= stroke[0]) & (times <= stroke[1])
    speed = _speeds(wrist, fps)[inside]
    peak = times[inside][np.argmax(speed)]
    duration = stroke[1] - stroke[0]
    assert abs(peak - (stroke[0] + 0.5 * duration)) <= 0.05 * duration
    assert speed[0] < 0.05 * speed.max() and speed[-1] < 0.05 * speed.max()
    travelled = wrist[np.argmin(abs(motion.times - stroke[1]))] - wrist[np.argmin(abs(motion.times - stroke[0]))]
    np.testing.assert_allclose(travelled, distance * np.array(direction), atol=1e-3)


def _two_gestures() -> list:
    beat = behavior(Parallel((
        Static("HandShape", HandShape("flathand"), scope=Arm.RIGHT),
        Static("PalmOrientation", PalmOrientation((0.0, 1.0, 0.0)), scope=Arm.RIGHT),
        _stroke(GridLocation("LocUpperChest", "LocCenterRight", "LocNorm"), (0.0, -1.0, 0.0), 0.12),
    )), "beat")  # fmt: skip
    sweep = behavior(Parallel((
        Static("HandShape", HandShape("finger2"), scope=Arm.RIGHT),
        Static("ExtFingerOrientation", Direction((-0.7071, 0.0, 0.7071)), scope=Arm.RIGHT),
        _stroke(GridLocation("LocShoulder", "LocCCenter", "LocFar"), (-1.0, 0.0, 0.0), 0.25),
    )), "sweep")  # fmt: skip
    # the second gesture starts while the first is retracting: co-articulation
    return [(beat, pegs(0.2, 0.7, 0.8, 1.2, 1.4)), (sweep, pegs(1.6, 2.0, 2.1, 2.6, 2.9))]


def test_positions_and_velocities_are_continuous_at_every_hand_over(avatar) -> None:
    fps = 600.0
    control, motion = render(avatar, _two_gestures(), fps=fps, end=4.5)
    handovers = sorted({lmp.pegs.start for lmps in control.activated().values() for lmp in lmps})
    for joint in ("r_wrist", "r_index3"):
        path = joint_path(avatar, motion, joint)
        step = np.linalg.norm(np.diff(path, axis=0), axis=1)
        velocity = np.diff(path, axis=0) * fps
        peak_speed = float(np.max(np.linalg.norm(velocity, axis=1)))
        for t in handovers:
            k = int(np.searchsorted(motion.times, t))
            around = slice(max(k - 2, 0), k + 2)
            assert np.all(step[around] <= peak_speed / fps * 1.0001), (joint, t)
            jumps = np.linalg.norm(np.diff(velocity[around], axis=0), axis=1)
            assert np.all(jumps <= 0.05 * peak_speed), (joint, t, jumps, peak_speed)


def test_channels_are_continuous_at_hand_overs(avatar) -> None:
    control, _ = render(avatar, _two_gestures(), end=0.1)
    h = 1e-5
    for channel, lmps in control.activated().items():
        timeline = control.timeline(channel)
        for lmp in lmps:
            t = lmp.pegs.start
            before, after = timeline.sample(np.array([t - 2 * h, t - h])), timeline.sample(np.array([t, t + h]))
            np.testing.assert_allclose(before[1], after[0], atol=1e-4, err_msg=f"{channel} at {t}")
            np.testing.assert_allclose((before[1] - before[0]) / h, (after[1] - after[0]) / h, atol=0.05, err_msg=f"{channel} at {t}")


@pytest.fixture(scope="module")
def fig2():
    utterance = load_utterance(FIG2)
    return {spec.id: spec for spec in utterance.behaviors}


FIG2_PEGS = pegs(0.2, 0.8, 1.0, 1.5, 1.8)


def test_fig2_iconic_gesture_is_two_handed_and_mirror_symmetric(avatar, fig2) -> None:
    _, motion = render(avatar, [(fig2["gesture_2"], FIG2_PEGS)], fps=120.0)
    right, left = joint_path(avatar, motion, "r_wrist"), joint_path(avatar, motion, "l_wrist")
    start, end = (int(np.argmin(abs(motion.times - t))) for t in (FIG2_PEGS.stroke_start, FIG2_PEGS.stroke_end))
    moved = right[end] - right[start]
    assert moved[0] == pytest.approx(-0.125, abs=0.005)
    assert np.linalg.norm(moved[1:]) < 0.005
    np.testing.assert_allclose(left, right * np.array([-1.0, 1.0, 1.0]), atol=1e-6)


def test_fig2_hand_shape_and_palm_orientation_hold_during_the_stroke(avatar, fig2) -> None:
    _, motion = render(avatar, [(fig2["gesture_2"], FIG2_PEGS)], fps=120.0)
    stroke = (motion.times >= FIG2_PEGS.stroke_start) & (motion.times <= FIG2_PEGS.relax)
    shape = next(leaf.value for leaf in fig2["gesture_2"].gesture.constraints.child.children if leaf.slot == "HandShape")
    for side in ("r", "l"):
        expected = hand_rotations(avatar, side, handshape_params(shape))[0]
        fingers = motion.rotations[stroke][:, avatar.hand_joints(side)]
        np.testing.assert_allclose(np.abs(np.sum(fingers * expected, axis=-1)), 1.0, atol=1e-9)
    orientation = pose(avatar, motion).orientations[stroke]
    for side, palm_direction in (("r", [1.0, 0.0, 0.0]), ("l", [-1.0, 0.0, 0.0])):
        palm = quat.rotate(orientation[:, avatar.joint_index(f"{side}_wrist")], avatar.hand_frames[side].palm_normal)
        assert np.degrees(np.arccos(np.clip(palm @ palm_direction, -1.0, 1.0))).max() < 3.0
        fingers = quat.rotate(orientation[:, avatar.joint_index(f"{side}_wrist")], avatar.hand_frames[side].finger_axis)
        assert np.degrees(np.arccos(np.clip(fingers @ [0.0, 0.0, 1.0], -1.0, 1.0))).max() < 3.0


def test_fig2_deictic_gesture_points_the_index_finger_at_the_bar(avatar, fig2) -> None:
    _, motion = render(avatar, [(fig2["gesture_1"], FIG2_PEGS)])
    stroke = (motion.times >= FIG2_PEGS.stroke_start) & (motion.times <= FIG2_PEGS.relax)
    base, tip = joint_path(avatar, motion, "r_index1")[stroke], joint_path(avatar, motion, "r_index3")[stroke]
    finger = quat.normalize(tip - base)
    toward = quat.normalize(BAR - base)
    assert np.degrees(np.arccos(np.clip(np.sum(finger * toward, axis=1), -1.0, 1.0))).max() < 6.0


def _corpus_files() -> list[Path]:
    shared = REPO.parent / "shared" / "corpora" / "murml"
    return sorted((REPO / "specs" / "utterances").glob("*.xml")) + sorted(shared.glob("*.us"))


def _utterance_pegs(index: int, spec) -> TimePegs:
    """Absolute timings as given; affiliates laid out one after another (no speech here)."""
    timing = spec.timing
    if hasattr(timing, "onset") and isinstance(timing.onset, float):
        onset, end = timing.onset, max(timing.end, timing.onset + 0.1)
    else:
        onset, end = 1.0 + 2.0 * index, 1.6 + 2.0 * index
    return TimePegs(onset - 0.7, onset - 0.1, onset, 0.5 * (onset + end), end, end + 0.2, end + 0.8)


@pytest.mark.parametrize("path", _corpus_files(), ids=lambda p: p.name)
def test_every_utterance_plans_and_renders_within_reach_without_nan(avatar, path) -> None:
    control = MotorControl(avatar, fps=25.0)
    lexicon = load_lexicon()
    for utterance in load_utterances(path, lexicon):
        for index, spec in enumerate(utterance.behaviors):
            program = control.plan(spec, _utterance_pegs(index, spec))
            assert np.all(np.isfinite(program.pegs.end))
            control.activate(program)
    end = max(control.busy_until(arm) for arm in ("right", "left")) + 0.2
    motion = control.frames(0.0, end)
    assert motion.frame_count > 0 and np.all(np.isfinite(motion.rotations))
    np.testing.assert_allclose(np.linalg.norm(motion.rotations, axis=-1), 1.0, atol=1e-9)
    given = control.wrist_targets(motion.times)
    # the torso turns with the chest where a hand reaches across the body
    chest = avatar.joint_index("vt1")
    posed = pose(avatar, motion)
    in_trunk = lambda points: quat.rotate(quat.conjugate(posed.orientations[:, chest]), points - posed.positions[:, chest]) + avatar.rest_positions[chest]
    for arm, side in (("right", "r"), ("left", "l")):
        planned = outside_torso(avatar, control.timeline((arm, "wrist_position")).sample(motion.times))
        reached = joint_path(avatar, motion, f"{side}_wrist")
        # breakpoints are moved into reach when planned; the smooth path between them may
        # bulge a little beyond it, where the IK takes the nearest reachable point; the path
        # is kept out of the torso before the IK, and the hands a palm thickness apart
        assert not np.any(inside_torso(avatar, in_trunk(reached))), f"{arm} wrist inside the torso"
        assert np.max(np.linalg.norm(reached - given[arm], axis=1)) < 0.02, arm
        assert np.max(np.linalg.norm(given[arm] - planned, axis=1)) < 2.0 * avatar.collision.palm_thickness, arm


@pytest.mark.parametrize("fps", [25.0, 60.0])
def test_streaming_windows_equal_one_call(avatar, fps, monkeypatch) -> None:
    # two gestures leave each channel fewer spent LMPs than the control drops at a time
    monkeypatch.setattr(control_module, "FORGET_BATCH", 2)
    control, whole = render(avatar, _two_gestures(), fps=fps, end=4.0)
    activated = sum(len(lmps) for lmps in control.activated().values())
    edges = [0.0, 0.013, 0.5, 0.51, 1.37, 2.0, 2.0, 3.3, 4.0]
    parts = [control.frames(a, b) for a, b in zip(edges, edges[1:])]
    # streaming forgets LMPs that lost control long ago, without changing any frame
    assert sum(len(lmps) for lmps in control.activated().values()) < activated
    assert sum(p.frame_count for p in parts) == whole.frame_count
    np.testing.assert_array_equal(np.concatenate([p.rotations for p in parts]), whole.rotations)
    np.testing.assert_allclose(np.concatenate([p.times for p in parts]), whole.times, atol=1e-12)
    for part in parts:
        if part.frame_count:
            assert part.start_time == pytest.approx(part.times[0])


def test_frames_are_vectorized_not_looped(avatar, monkeypatch) -> None:
    calls = {"arm_rotations": 0, "hand_rotations": 0}

    def counted(name, function):
        def wrapper(*args, **kwargs):
            calls[name] += 1
            return function(*args, **kwargs)

        return wrapper

    monkeypatch.setattr(arm_pair, "arm_rotations", counted("arm_rotations", arm_pair.arm_rotations))
    monkeypatch.setattr(control_module, "hand_rotations", counted("hand_rotations", control_module.hand_rotations))
    counts = []
    for fps in (30.0, 300.0):
        control, _ = render(avatar, _two_gestures(), fps=fps, end=0.0)
        before = dict(calls)
        motion = control.frames(0.0, 4.0)
        assert motion.frame_count == int(4.0 * fps)
        counts.append({name: calls[name] - before[name] for name in calls})
    assert counts[0] == counts[1]
    assert all(count > 0 for count in counts[0].values())  # the counted functions are the ones the frames call


def test_frames_before_anything_is_activated_hold_the_rest_posture(avatar) -> None:
    control = MotorControl(avatar, fps=30.0)
    motion = control.frames(0.0, 1.0)
    assert motion.frame_count == 30
    for side in ("r", "l"):
        np.testing.assert_allclose(joint_path(avatar, motion, f"{side}_wrist"), np.broadcast_to(avatar.postures["rest"][side].wrist, (30, 3)), atol=1e-6)
    empty = control.frames(1.0, 1.0)
    assert empty.frame_count == 0 and empty.rotations.shape == (0, avatar.joint_count, 4)
