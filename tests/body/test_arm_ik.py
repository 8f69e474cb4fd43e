"""Arm IK: exact on reachable targets, graceful out of reach, natural swivel, orientation."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from motor import quaternion as quat
from motor.arm.hand_orientation import hand_rotation
from motor.arm.chain import REACH_EASE
from motor.arm.ik import ArmSolution, solve_arm
from motor.body.avatar import Avatar
from motor.body.kinematics import Pose, forward_kinematics, identity_rotations
from mura.murml_vocabulary import parse_direction, parse_palm_orientation
from mura.values import Direction, PalmOrientation

SIDES = ["l", "r"]


def _signing_space(avatar: Avatar) -> np.ndarray:
    """10 × 10 × 6 targets spanning the grid from extreme periphery to extreme periphery,
    stomach to above the head, contact to stretched distance."""
    grid = avatar.grid
    lateral = np.linspace(grid.laterals["LocExtremePeripheryRight"], grid.laterals["LocExtremePeripheryLeft"], 10)
    height = np.linspace(grid.heights["LocStomach"], grid.heights["LocAboveHead"], 10)
    distance = grid.front + np.linspace(grid.distances["LocContact"], grid.distances["LocStreched"], 6)
    return np.stack(np.meshgrid(lateral, height, distance, indexing="ij"), axis=-1).reshape(-1, 3)


def _pose(avatar: Avatar, side: str, solution: ArmSolution) -> Pose:
    rotations = identity_rotations(avatar, solution.rotations.shape[0])
    rotations[:, avatar.arm_joints(side)] = solution.rotations
    return forward_kinematics(avatar, rotations)


def _inside_torso(avatar: Avatar, start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """Whether the segment start→end (n, 3) passes through the torso's elliptic cylinder."""
    torso = avatar.torso
    points = start[:, None] + np.linspace(0.05, 1.0, 40)[:, None] * (end - start)[:, None]
    radial = ((points[..., 0] - torso.center[0]) / torso.half_width) ** 2 + ((points[..., 2] - torso.center[2]) / torso.half_depth) ** 2
    return ((radial < 1.0) & (points[..., 1] > torso.bottom) & (points[..., 1] < torso.top)).any(axis=1)


@pytest.mark.parametrize("side", SIDES)
def test_reachable_targets_are_met_within_a_millimetre(avatar, side):
    targets = _signing_space(avatar)
    solution = solve_arm(avatar, side, targets)
    pose = _pose(avatar, side, solution)
    shoulder, elbow, wrist = (pose.positions[:, j] for j in avatar.arm_joints(side)[1:])
    reachable = solution.shortfall == 0.0
    assert reachable.sum() > 0.5 * len(targets)  # the last 3 cm before full stretch are eased
    assert np.linalg.norm(wrist - targets, axis=1)[reachable].max() < 1e-3
    assert np.allclose(elbow, solution.elbow) and np.allclose(wrist, solution.wrist)
    low, high = avatar.limit(f"{side}_elbow", "flexion")
    assert np.all((solution.elbow_flexion >= low - 1e-9) & (solution.elbow_flexion <= high + 1e-9))
    # the upper arm stays out of the torso wherever the straight reach does not cross it
    # (reaching through the body would need the trunk to turn); elsewhere the IK says so
    upper_arm_inside = _inside_torso(avatar, shoulder, elbow)
    reach_crosses_body = _inside_torso(avatar, shoulder, targets)
    assert not np.any(upper_arm_inside & reachable & ~reach_crosses_body)
    assert np.all(solution.penetration[upper_arm_inside] > 0)


@pytest.mark.parametrize("side", SIDES)
def test_unreachable_targets_land_on_the_reach_sphere(avatar, side):
    sign = 1.0 if side == "l" else -1.0
    targets = np.array([[sign * 2.0, 0.5, 0.0], [0.0, 2.5, 0.3], [-sign * 1.5, 0.3, 1.5], [0.0, -1.0, 1.0]])
    solution = solve_arm(avatar, side, targets)
    reach = solution.wrist - solution.shoulder
    # the wrist stops short of full stretch by the reach's ease (the elbow never locks)
    assert np.allclose(np.linalg.norm(reach, axis=1), avatar.arm_length(side) - REACH_EASE)
    wanted = targets - solution.shoulder
    cosine = np.sum(reach * wanted, axis=1) / np.linalg.norm(reach, axis=1) / np.linalg.norm(wanted, axis=1)
    assert np.allclose(cosine, 1.0)
    assert np.allclose(solution.shortfall, np.linalg.norm(wanted, axis=1) - avatar.arm_length(side) + REACH_EASE)
    assert np.all(solution.shortfall > 0.3)


def test_too_close_and_degenerate_targets_do_not_raise(avatar):
    shoulder = avatar.rest_positions[avatar.joint_index("r_shoulder")]
    solution = solve_arm(avatar, "r", np.array([shoulder, shoulder + [0.0, 0.0, 0.01]]))
    assert np.all(np.isfinite(solution.rotations)) and np.all(solution.shortfall > 0.0)
    high = avatar.limit("r_elbow", "flexion")[1]
    assert np.allclose(solution.elbow_flexion, high)


@pytest.mark.parametrize("side", SIDES)
def test_swivel_grows_from_the_side_to_across_the_body(avatar, side):
    sign = 1.0 if side == "l" else -1.0
    grid = avatar.grid
    lateral = sign * np.array([0.45, 0.3, 0.15, 0.0, -0.1]) * avatar.arm_length(side) / 0.58
    targets = np.stack(
        (lateral, np.full(5, grid.heights["LocChest"]), np.full(5, grid.front + grid.distances["LocNorm"])), axis=-1
    )
    swivel = solve_arm(avatar, side, targets).swivel
    assert abs(swivel[0]) < np.radians(20)
    assert np.all(np.diff(swivel) > 0)
    assert swivel[-1] > np.radians(25)


def test_left_arm_mirrors_right(avatar):
    targets = _signing_space(avatar)[::7]
    left = solve_arm(avatar, "l", targets * [-1, 1, 1])
    right = solve_arm(avatar, "r", targets)
    assert np.allclose(left.elbow * [-1, 1, 1], right.elbow, atol=1e-9)
    assert np.allclose(left.swivel, right.swivel)


def test_swivel_override_is_used(avatar):
    target = np.tile(avatar.grid.front + np.array([0.0, 0.0, 0.1]) + [-0.1, avatar.grid.heights["LocChest"], 0.0], (3, 1))
    swivels = np.array([0.0, 0.5, 1.0])
    solution = solve_arm(avatar, "r", target, swivel=swivels)
    assert np.allclose(solution.swivel, swivels)
    assert np.allclose(solution.wrist, target, atol=1e-9)
    outward = -solution.elbow[:, 0]  # the right arm's outside is -x
    assert outward[0] < outward[1] < outward[2]


def test_clavicle_follows_only_far_reaches(avatar):
    grid = avatar.grid
    near = [-0.1, grid.heights["LocChest"], grid.front + grid.distances["LocContact"]]
    far = [-0.3, grid.heights["LocShoulder"], grid.front + grid.distances["LocStreched"]]
    solution = solve_arm(avatar, "r", np.array([near, far]))
    clavicle_angle = quat.angle_between(solution.rotations[:, 0], quat.IDENTITY)
    assert clavicle_angle[0] < 0.02
    assert 0.1 < clavicle_angle[1] <= avatar.limit("r_sternoclavicular", "swing")[1] + 1e-9


#: Extended-finger direction and palm orientation of a right hand, at places a right hand
#: reaches them comfortably; the left hand does the mirror image.
ORIENTATIONS = [("DirA", "PalmD"), ("DirA", "PalmL"), ("DirAL", "PalmD"), ("DirL", "PalmT"), ("DirAU", "PalmD")]
PLACES = [
    ("LocCenterRight", "LocChest", "LocNorm"),
    ("LocCCenterRight", "LocShoulder", "LocFar"),
    ("LocPeripheryRight", "LocAbdomen", "LocNorm"),
]


@pytest.mark.parametrize("side", SIDES)
def test_natural_hand_orientations_are_met_within_a_degree(avatar, side):
    grid = avatar.grid
    mirror = np.array([-1.0 if side == "l" else 1.0, 1.0, 1.0])
    targets, hands = [], []
    for direction, palm in ORIENTATIONS:
        finger = Direction(tuple(np.array(parse_direction(direction).vector) * mirror))
        facing = PalmOrientation(tuple(np.array(parse_palm_orientation(palm).direction) * mirror))
        for lateral, height, distance in PLACES:
            targets.append(np.array([grid.laterals[lateral], grid.heights[height], grid.front + grid.distances[distance]]) * mirror)
            hands.append(hand_rotation(avatar, side, finger, facing))
    targets, hands = np.array(targets), np.array(hands)
    solution = solve_arm(avatar, side, targets, hands)
    pose = _pose(avatar, side, solution)
    reached = pose.orientations[:, avatar.arm_joints(side)[3]]
    error = np.degrees(quat.angle_between(reached, hands))
    assert np.allclose(error, np.degrees(solution.orientation_error), atol=1e-4)
    assert error.max() < 1.0
    assert np.linalg.norm(pose.positions[:, avatar.arm_joints(side)[3]] - targets, axis=1).max() < 1e-3


@pytest.mark.parametrize("side", SIDES)
def test_any_feasible_hand_rotation_is_met(avatar, side):
    """Hand rotations made by posing the arm within its limits are reached again."""
    rng = np.random.default_rng(7)
    frames = 200
    sign = 1.0 if side == "l" else -1.0
    grid = avatar.grid
    targets = np.stack(
        (
            sign * rng.uniform(-0.1, 0.35, frames) * avatar.arm_length(side) / 0.58,
            rng.uniform(grid.heights["LocStomach"], grid.heights["LocShoulder"], frames),
            grid.front + rng.uniform(grid.distances["LocNear"], grid.distances["LocFFar"], frames),
        ),
        axis=-1,
    )
    posed = solve_arm(avatar, side, targets, swivel=rng.uniform(-0.2, 1.0, frames))
    frame = avatar.hand_frames[side]
    shrink = lambda kind, joint: np.array(avatar.limit(f"{side}_{joint}", kind)) * 0.6
    twist = rng.uniform(*shrink("twist", "elbow"), frames)
    flexion = rng.uniform(*shrink("flexion", "wrist"), frames)
    deviation = rng.uniform(*shrink("deviation", "wrist"), frames)
    rotations = posed.rotations.copy()
    rotations[:, 2] = quat.multiply(rotations[:, 2], quat.from_axis_angle(frame.twist_axis, twist))
    rotations[:, 3] = quat.from_rotation_vector(flexion[:, None] * frame.bend_axis + deviation[:, None] * frame.splay_axis)
    feasible = (posed.shortfall == 0) & (posed.penetration == 0)
    posed_pose = _pose(avatar, side, replace(posed, rotations=rotations))
    hands = posed_pose.orientations[:, avatar.arm_joints(side)[3]]
    solution = solve_arm(avatar, side, targets[feasible], hands[feasible])
    assert feasible.sum() > frames // 2
    assert np.degrees(solution.orientation_error).max() < 1.0


def test_wrist_and_twist_stay_in_limits(avatar):
    rng = np.random.default_rng(3)
    targets = _signing_space(avatar)
    hands = quat.normalize(rng.normal(size=(len(targets), 4)))
    solution = solve_arm(avatar, "r", targets, hands)
    frame = avatar.hand_frames["r"]
    wrist = quat.to_rotation_vector(solution.rotations[:, 3])
    flexion, deviation = wrist @ frame.bend_axis, wrist @ frame.splay_axis
    assert np.allclose(wrist @ frame.twist_axis, 0.0, atol=1e-9)
    low, high = avatar.limit("r_wrist", "flexion")
    assert np.all((flexion >= low - 1e-9) & (flexion <= high + 1e-9))
    low, high = avatar.limit("r_wrist", "deviation")
    assert np.all((deviation >= low - 1e-9) & (deviation <= high + 1e-9))
    pose = _pose(avatar, "r", solution)
    reached = pose.orientations[:, avatar.arm_joints("r")[3]]
    assert np.allclose(quat.angle_between(reached, hands), solution.orientation_error, atol=1e-6)


@pytest.mark.parametrize("posture", ["rest", "interim_rest"])
@pytest.mark.parametrize("side", SIDES)
def test_named_postures_are_reachable(avatar, posture, side):
    named = avatar.postures[posture][side]
    solution = solve_arm(avatar, side, named.wrist[None], named.hand_rotation[None])
    assert solution.shortfall[0] == 0.0
    assert np.degrees(solution.orientation_error[0]) < 1.0
    assert solution.penetration[0] == 0.0


def test_turning_the_torso_turns_the_solution_with_it(avatar):
    targets = _signing_space(avatar)[::11]
    frames = len(targets)
    turn = quat.from_axis_angle(np.array([0.0, 1.0, 0.0]), 0.4)
    pivot = avatar.rest_positions[avatar.joint_index("vt1")]
    moved = quat.rotate(turn, targets)
    upright = solve_arm(avatar, "r", targets)
    turned = solve_arm(
        avatar, "r", moved, torso_rotations=np.tile(turn, (frames, 1)), torso_positions=np.tile(quat.rotate(turn, pivot), (frames, 1))
    )
    assert np.allclose(turned.wrist, quat.rotate(turn, upright.wrist), atol=1e-9)
    assert np.allclose(np.abs(np.sum(turned.rotations * upright.rotations, axis=-1)), 1.0, atol=1e-9)
    assert np.allclose(turned.shortfall, upright.shortfall, atol=1e-9)
