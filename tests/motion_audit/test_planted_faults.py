"""Each per-frame metric finds a fault planted in synthetic motion of the ``max`` skeleton,
and reports nothing on clean synthetic motion."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from bench.motion_audit import continuity, penetration, twist
from bench.motion_audit.avatar_file import read_avatar
from bench.motion_audit.bvh_reader import parse_bvh
from bench.motion_audit.kinematics import forward_kinematics
from bench.motion_audit.volumes import audit_volumes

from .synthetic import FPS, SyntheticMotion, minimum_jerk, raise_arm

FRAMES = 120
FAULT_FRAME = 60
AVATAR = read_avatar("max")
UPPER_ARM, FOREARM = 0.31, 0.27


def kinematics_of(motion: SyntheticMotion):
    return forward_kinematics(parse_bvh(motion.bvh(), "synthetic.bvh"), scale=0.01)


def step_profile(frames: int, at: int) -> np.ndarray:
    """0 before frame ``at``, 1 from it on: a change within one frame."""
    return (np.arange(frames) >= at).astype(float)


def smooth_profile(frames: int, start: int = 20, duration: int = 60) -> np.ndarray:
    profile = np.zeros(frames)
    profile[start : start + duration] = minimum_jerk(duration)
    profile[start + duration :] = 1.0
    return profile


def about(axis, degrees: np.ndarray) -> Rotation:
    return Rotation.from_rotvec(np.outer(np.radians(degrees), np.asarray(axis, float)))


def bent_arm(frames: int) -> tuple[Rotation, Rotation]:
    """Shoulder flexed 60° forward and elbow bent 80°: the hand in front of the chest."""
    return about([1, 0, 0], np.full(frames, -60.0)), about([1, 0, 0], np.full(frames, -80.0))


def swivel(frames: int, profile: np.ndarray, degrees: float, side: str = "r") -> SyntheticMotion:
    """The bent arm turned about its shoulder–wrist axis by ``degrees × profile``: the elbow
    moves, the wrist stays."""
    shoulder, elbow = bent_arm(frames)
    wrist_from_shoulder = shoulder[0].apply([0, -UPPER_ARM, 0]) + (shoulder[0] * elbow[0]).apply([0, -FOREARM, 0])
    axis = wrist_from_shoulder / np.linalg.norm(wrist_from_shoulder)
    turn = about(axis, degrees * profile)
    return SyntheticMotion(frames).set(f"{side}_shoulder", turn * shoulder).set(f"{side}_elbow", elbow)


CLEAN = {
    "rest": lambda: SyntheticMotion(FRAMES),
    "right arm raised": lambda: SyntheticMotion(FRAMES).set("r_shoulder", raise_arm(FRAMES, "r")),
    "both arms raised": lambda: SyntheticMotion(FRAMES).set("r_shoulder", raise_arm(FRAMES, "r")).set("l_shoulder", raise_arm(FRAMES, "l", 50)),
    "arm swung out sideways": lambda: SyntheticMotion(FRAMES).set("l_shoulder", about([0, 0, 1], 60 * smooth_profile(FRAMES))),
    "slow swivel outward": lambda: swivel(FRAMES, smooth_profile(FRAMES), -90.0),
    "slow forearm twist": lambda: SyntheticMotion(FRAMES).set("r_shoulder", raise_arm(FRAMES)).set("r_elbow", about([0, 1, 0], 80 * smooth_profile(FRAMES))),
}


@pytest.mark.parametrize("name", CLEAN)
def test_clean_motion_reports_nothing(name):
    kinematics = kinematics_of(CLEAN[name]())
    for side in ("l", "r"):
        assert continuity.elbow_pops(kinematics, side).events == 0
        assert continuity.wrist_steps(kinematics, side).events == 0
    assert continuity.joint_turns(kinematics).frames_over == 0
    found = penetration.penetrations(kinematics, audit_volumes(AVATAR, kinematics))
    assert all(group.frames_over == 0 for group in found.values()), found


@pytest.mark.parametrize("degrees", [40.0, 90.0, 150.0])
@pytest.mark.parametrize("side", ["l", "r"])
def test_one_frame_swivel_is_one_elbow_pop(degrees, side):
    kinematics = kinematics_of(swivel(FRAMES, step_profile(FRAMES, FAULT_FRAME), degrees, side))
    pops = continuity.elbow_pops(kinematics, side)
    assert (pops.events, pops.frames) == (1, 1)
    assert pops.worst.time == pytest.approx(FAULT_FRAME / FPS)
    assert pops.worst.value > 3.0 and pops.worst.what.startswith(f"{side}_elbow")
    assert continuity.elbow_pops(kinematics, "l" if side == "r" else "r").events == 0
    assert continuity.wrist_steps(kinematics, side).events == 0  # the hand stays where it is


@pytest.mark.parametrize("degrees", [30.0, 90.0, 170.0])
def test_forearm_twist_wrap_is_the_largest_turn(degrees):
    twist_profile = 85.0 - degrees * step_profile(FRAMES, FAULT_FRAME)  # e.g. +85° to −85°: the wrap
    motion = SyntheticMotion(FRAMES).set("r_shoulder", about([1, 0, 0], np.full(FRAMES, -60.0))).set("r_elbow", about([0, 1, 0], twist_profile))
    turns = continuity.joint_turns(kinematics_of(motion))
    assert turns.largest.what == "r_elbow"
    assert turns.largest.value == pytest.approx(degrees, abs=1e-3)
    assert turns.largest.time == pytest.approx(FAULT_FRAME / FPS)
    assert turns.frames_over == (1 if degrees > continuity.TURN_LIMIT else 0)


@pytest.mark.parametrize("speed, detected", [(0.3, False), (0.8, True), (1.5, True)])
def test_wrist_stopping_dead_is_a_speed_step(speed, detected):
    """The straight arm swings forward at constant angular speed and stops within one frame."""
    reach = UPPER_ARM + FOREARM
    rate = np.degrees(speed / reach) / FPS  # degrees per frame
    angle = -rate * np.clip(np.arange(FRAMES) - 20, 0, FAULT_FRAME - 20)
    kinematics = kinematics_of(SyntheticMotion(FRAMES).set("r_shoulder", about([1, 0, 0], angle)))
    steps = continuity.wrist_steps(kinematics, "r")
    assert steps.events == (2 if detected else 0)  # starting and stopping dead
    if detected:
        assert steps.worst.value == pytest.approx(speed, rel=0.02)
        assert steps.worst.time in (pytest.approx(20 / FPS), pytest.approx(FAULT_FRAME / FPS))


@pytest.mark.parametrize("degrees, deep", [(-40.0, False), (-5.0, False), (40.0, True), (60.0, True)])
def test_arm_swung_into_the_torso_penetrates(degrees, deep):
    """The right arm swung about the forward axis: positive angles bring it across the body."""
    motion = SyntheticMotion(FRAMES).set("r_shoulder", about([0, 0, 1], degrees * smooth_profile(FRAMES)))
    kinematics = kinematics_of(motion)
    found = penetration.penetrations(kinematics, audit_volumes(AVATAR, kinematics))
    assert (found["torso"].frames_over > 0) == deep
    if deep:
        assert found["torso"].worst.value > 5.0 and found["torso"].worst.what.endswith("in torso")
        assert found["torso"].worst.what.startswith("r_")


def arms_forward_turned_in(yaw: float) -> SyntheticMotion:
    """Both arms straight forward, each turned inward by ``yaw`` degrees."""
    forward = about([1, 0, 0], np.full(FRAMES, -90.0))
    return SyntheticMotion(FRAMES).set("r_shoulder", about([0, 1, 0], np.full(FRAMES, yaw)) * forward).set("l_shoulder", about([0, 1, 0], np.full(FRAMES, -yaw)) * forward)


def test_hands_on_one_point_overlap_by_the_palms_thickness():
    meet = np.degrees(np.arcsin(0.18 / (UPPER_ARM + FOREARM)))  # the wrists meet on the midline
    kinematics = kinematics_of(arms_forward_turned_in(meet))
    volumes = audit_volumes(AVATAR, kinematics)
    found = penetration.penetrations(kinematics, volumes)
    palm = volumes["l_hand"].shape.radius + volumes["r_hand"].shape.radius
    assert found["hands"].worst.value == pytest.approx(100 * palm, rel=0.05)
    assert found["hands"].frames_over == FRAMES and found["forearms"].frames_over == FRAMES


def test_hands_apart_do_not_overlap():
    found = penetration.penetrations(kinematics := kinematics_of(arms_forward_turned_in(10.0)), audit_volumes(AVATAR, kinematics))
    assert found["hands"].frames_over == 0 and found["forearms"].frames_over == 0


@pytest.mark.parametrize("held, pinned", [(40.0, False), (84.0, True), (-84.0, True), (95.0, True)])
def test_twist_held_at_its_limit_is_pinned(held, pinned):
    motion = SyntheticMotion(FRAMES).set("r_shoulder", raise_arm(FRAMES, "r", 70.0, start=0, duration=10)).set("r_elbow", about([0, 1, 0], np.full(FRAMES, held)))
    result = twist.twist_pinning(kinematics_of(motion), "r", AVATAR.twist_limit("r"))
    assert result.gesture_frames > FRAMES // 2
    assert result.pinned_frames == (result.gesture_frames if pinned else 0)


def test_turn_angles_agree_with_rotation_algebra():
    rng = np.random.default_rng(7)
    rotations = Rotation.random(40 * 5, random_state=rng)
    quaternions = rotations.as_quat().reshape(40, 5, 4)
    expected = np.degrees((Rotation.from_quat(quaternions[:-1].reshape(-1, 4)).inv() * Rotation.from_quat(quaternions[1:].reshape(-1, 4))).magnitude())
    np.testing.assert_allclose(continuity.turn_angles(quaternions).ravel(), expected, atol=1e-9)
