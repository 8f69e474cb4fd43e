"""The arm's clearance from the body, as the swivel search sees it (synthetic tables of
wrist targets across the chest, trunk turns and hand rotations).

* Where the trunk turns toward a reach, the trunk's volumes that do not turn with all of
  it (the torso, carried by the lowest lumbar joint in every avatar file, and a chest on
  the thoracic spine) are measured where their joint carries them, not turned with the
  arm: checked against the motion audit's exact distances.
* Where some candidate swivel keeps the arm out of the body, the cheapest one goes in
  little further than the swivel cost tolerates, whatever the hand asks of the wrist.
"""

from __future__ import annotations

import numpy as np
import pytest

import motor.arm.clearance as clearance_module
from bench.motion_audit.distance import EllipticCylinder, capsule_depth
from motor import quaternion as quat
from motor.arm.chain import place_arm
from motor.arm.clearance import TOLERATED_DEPTH, arm_capsules, body_obstacles, clearance, upright_obstacles
from motor.arm.ik import CANDIDATES, solve_arm
from motor.arm.reach_turn import TURN_JOINTS, turned
from motor.body.avatar import load_avatar
from motor.body.kinematics import forward_kinematics
from motor.body.volumes import TRUNK_NAMES
from motor.body.volumes import EllipticCylinder as MotorCylinder

AVATARS = ("max", "makehuman")
YAWS = (-0.35, -0.15, 0.2)
SHALLOW = 0.02
#: How far (m) the motor's depth may part from the audit's: the motor measures a segment
#: inside an elliptic cylinder at its point nearest the axis in the ellipse's own scale,
#: not at its deepest point. Where the arm crosses the face between the torso and the
#: chest, the two part by up to about a millimetre (1.02 mm on max).
AGREEMENT = 0.0015


@pytest.fixture(scope="module", params=AVATARS)
def avatar(request):
    return load_avatar(request.param)


def _across_the_chest(avatar, side: str) -> np.ndarray:
    """Wrist targets from the midline to the far side at chest height, close to the chest."""
    torso = avatar.torso
    far = -1.0 if side == "l" else 1.0
    xs = far * np.linspace(0.0, 0.15, 4)
    ys = torso.bottom + np.array([0.6, 0.8]) * (torso.top - torso.bottom)
    zs = torso.center[2] + torso.half_depth + np.array([0.05, 0.12])
    return np.array([[x, y, z] for x in xs for y in ys for z in zs])


def _audit_cylinder(volume) -> EllipticCylinder:
    assert isinstance(volume, MotorCylinder)
    return EllipticCylinder(volume.center, volume.half_width, volume.half_depth, volume.bottom, volume.top)


def _turned_pose(avatar, turn):
    """Every joint's global pose with the trunk turned, by forward kinematics of the
    turning spine joints' local rotations (not the frames the clearance uses)."""
    local = np.broadcast_to(quat.IDENTITY, (len(turn.yaw), len(avatar.joint_names), 4)).copy()
    local[:, [avatar.joint_index(name) for name in TURN_JOINTS]] = turn.local_rotations()
    return forward_kinematics(avatar, local)


@pytest.mark.parametrize("yaw", YAWS)
@pytest.mark.parametrize("side", ["l", "r"])
@pytest.mark.parametrize("trunk", TRUNK_NAMES)
def test_trunk_volumes_are_measured_where_their_joint_carries_them(avatar, trunk, side, yaw, monkeypatch):
    """The arm solved in the turned trunk's frame, carried back into the avatar's and
    from there into the rest frame of the trunk volume's own joint (the torso on the
    lowest lumbar joint stays with the hips; the chest on the thoracic spine turns with
    the part of it below its joint): its depth in the volume is the audit's within
    :data:`AGREEMENT`, wherever it is shallower than :data:`SHALLOW` (deeper, the motor's
    depth along the ray from the axis parts from the exact one; the swivel search avoids
    such depths anyway)."""
    if trunk not in avatar.collision:
        pytest.skip(f"{avatar.name} has no {trunk} volume")
    (obstacle,) = (o for o in body_obstacles(avatar) if o.volume.name == trunk)
    assert obstacle.carriers < len(TURN_JOINTS)
    targets = _across_the_chest(avatar, side)
    yaws = np.full(len(targets), yaw)
    placement = place_arm(avatar, side, targets, trunk_yaw=yaws)
    circle = placement.circle
    swivels = CANDIDATES[::3]
    radial = [circle.down[:, i : i + 1] * np.cos(swivels) + circle.out[:, i : i + 1] * np.sin(swivels) for i in range(3)]
    elbow = tuple(circle.center[:, i : i + 1] + circle.radius[:, None] * radial[i] for i in range(3))
    alone = tuple((obstacle,) if count == obstacle.carriers else () for count in range(len(TURN_JOINTS) + 1))
    monkeypatch.setattr(clearance_module, "_by_carriers", lambda _avatar: alone)
    measured = clearance(avatar, side, circle.shoulder, circle.wrist, elbow, carried_frames=placement.carried_frames)[1]
    turn = turned(avatar, yaws)
    pose = _turned_pose(avatar, turn)
    carrier = avatar.joint_index(obstacle.volume.joint)
    inverse = quat.conjugate(pose.orientations[:, carrier])
    into_volume = lambda p: quat.rotate(inverse, turn.from_trunk(p) - pose.positions[:, carrier]) + avatar.rest_positions[carrier]
    capsules = arm_capsules(avatar, side)
    shape = _audit_cylinder(obstacle.volume)
    for k in range(len(swivels)):
        joints = [into_volume(p) for p in (circle.shoulder, np.stack([c[:, k] for c in elbow], axis=1), circle.wrist)]
        upper = _depth(joints[0], joints[1], capsules.upper_ends, capsules.upper_radius, shape)
        fore = _depth(joints[1], joints[2], capsules.fore_ends, capsules.fore_radius, shape)
        expected = np.maximum(np.maximum(upper, fore), 0.0)
        shallow = expected < SHALLOW
        assert measured[shallow, k] == pytest.approx(expected[shallow], abs=AGREEMENT)


def _depth(start, end, fractions, radius, shape):
    """The audit's depth in ``shape`` of the capsule over ``fractions`` of ``start``–``end``."""
    a, b = (start + f * (end - start) for f in fractions)
    return capsule_depth(a, b, radius, shape)[0]


def _chest_table(avatar, side: str) -> np.ndarray:
    """Wrist targets from just on the own side across to the far side, from mid-chest to
    shoulder height, 3 to 15 cm in front of the chest."""
    torso = avatar.torso
    far = -1.0 if side == "l" else 1.0
    xs = far * np.linspace(-0.05, 0.2, 6)
    ys = torso.bottom + np.array([0.5, 0.7, 0.85, 1.0]) * (torso.top - torso.bottom)
    zs = torso.center[2] + torso.half_depth + np.array([0.03, 0.08, 0.15])
    return np.array([[x, y, z] for x in xs for y in ys for z in zs])


@pytest.mark.parametrize("seed", range(10))
@pytest.mark.parametrize("side", ["l", "r"])
def test_the_cheapest_swivel_keeps_out_of_the_body_where_one_can(avatar, side, seed):
    """Hands rotated at random across the chest: wherever a candidate swivel keeps the arm
    out of the body, the one the IK picks goes no deeper than the depth the swivel cost
    tolerates and 3 mm (the candidates are 10° apart). Without the penetration's own
    penalty, a hand rotation bought 1.1 cm on max."""
    rng = np.random.default_rng(seed)
    targets = _chest_table(avatar, side)
    hands = quat.normalize(rng.normal(size=(len(targets), 4)))
    chosen = solve_arm(avatar, side, targets, hands)
    free = np.zeros(len(targets), dtype=bool)
    for swivel in CANDIDATES:
        free |= (
            solve_arm(
                avatar, side, targets, hands, swivel=np.full(len(targets), swivel)
            ).penetration
            <= 0.0
        )
    if not np.any(free):
        pytest.skip("no swivel keeps the arm out anywhere in this table")
    depth = chosen.penetration[free]
    assert depth.max() <= TOLERATED_DEPTH + 0.003, (
        f"{100 * depth.max():.2f} cm into the body at {targets[free][np.argmax(depth)]}"
    )


def test_upright_the_trunk_pieces_are_the_cylinder_they_make(avatar):
    """Where no part of the spine turns, the torso and the chest are measured as the one
    cylinder they were cut from."""
    trunk = [o for o in upright_obstacles(avatar) if o.trunk]
    pieces = [o.volume for o in body_obstacles(avatar) if o.trunk]
    assert len(trunk) == 1
    (whole,) = (o.volume for o in trunk)
    assert isinstance(whole, MotorCylinder)
    assert whole.bottom == min(v.bottom for v in pieces) and whole.top == max(v.top for v in pieces)


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("side", ["l", "r"])
def test_a_trunk_cut_in_two_costs_what_the_whole_trunk_costs(avatar, side, seed, monkeypatch):
    """With the trunk turned by a hair, the torso and the chest (each measured in its own
    frame) are the one cylinder they were cut from: an arm near the cut pays the clearance
    penalty once, so the swivel costs and depths of random elbows across the chest are
    those of the uncut trunk (where shallower than :data:`SHALLOW`: deeper, each piece's
    depth along the ray from the axis is taken where its own part of the segment comes
    nearest the axis)."""
    trunk = [o for o in body_obstacles(avatar) if o.trunk]
    if len(trunk) < 2:
        pytest.skip(f"{avatar.name} has one trunk volume")
    rng = np.random.default_rng(seed)
    targets = _chest_table(avatar, side)
    placement = place_arm(avatar, side, targets, trunk_yaw=np.full(len(targets), 1e-9))
    circle = placement.circle
    swivels = rng.uniform(-np.pi, np.pi, size=(len(targets), 12))
    elbow = tuple(circle.center[:, i : i + 1] + circle.radius[:, None] * (circle.down[:, i : i + 1] * np.cos(swivels) + circle.out[:, i : i + 1] * np.sin(swivels)) for i in range(3))
    cut = clearance(avatar, side, circle.shoulder, circle.wrist, elbow, carried_frames=placement.carried_frames)
    whole = next(o for o in upright_obstacles(avatar) if o.trunk)
    groups = [[o for o in body_obstacles(avatar) if not o.trunk and o.carriers == count] for count in range(len(TURN_JOINTS) + 1)]
    groups[whole.carriers].append(whole)
    monkeypatch.setattr(clearance_module, "_by_carriers", lambda _avatar: tuple(tuple(g) for g in groups))
    joined = clearance(avatar, side, circle.shoulder, circle.wrist, elbow, carried_frames=placement.carried_frames)
    shallow = joined[1] < SHALLOW
    assert np.any(shallow & (joined[1] > 0.0)), "the table must put some elbows a little into the trunk"
    np.testing.assert_allclose(cut[1][shallow], joined[1][shallow], atol=1e-6)
    # a segment's distance is taken nearest the axis within each piece's height range:
    # where it crosses the cut, that point moves (up to 4 % of the cost on max, against
    # the 100 % more a segment charged by both pieces would pay)
    np.testing.assert_allclose(cut[0][shallow], joined[0][shallow], rtol=0.05, atol=1e-6)
