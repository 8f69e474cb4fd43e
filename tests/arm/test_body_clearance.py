"""The arm's clearance from the body, as the swivel search sees it (synthetic tables of
wrist targets across the chest, trunk turns and hand rotations).

* Where the trunk turns toward a reach, the volumes that stay with the hips (the torso,
  carried by the lowest lumbar joint in every avatar file) are measured where they stand,
  not turned with the arm: checked against the motion audit's exact distances.
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
from motor.arm.clearance import TOLERATED_DEPTH, arm_capsules, body_obstacles, clearance
from motor.arm.ik import CANDIDATES, solve_arm
from motor.arm.reach_turn import turned
from motor.body.avatar import load_avatar
from motor.body.volumes import EllipticCylinder as MotorCylinder

AVATARS = ("max", "makehuman")
YAWS = (-0.35, -0.15, 0.2)
SHALLOW = 0.02


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


def _audit_torso(avatar) -> EllipticCylinder:
    (volume,) = (o.volume for o in body_obstacles(avatar) if o.volume.name == "torso")
    assert isinstance(volume, MotorCylinder)
    return EllipticCylinder(
        volume.center, volume.half_width, volume.half_depth, volume.bottom, volume.top
    )


@pytest.mark.parametrize("yaw", YAWS)
@pytest.mark.parametrize("side", ["l", "r"])
def test_volumes_that_stay_with_the_hips_are_measured_where_they_stand(
    avatar, side, yaw, monkeypatch
):
    """The arm solved in the turned trunk's frame, carried back into the avatar's: its
    depth in the torso is the audit's within a millimetre, wherever it is shallower than
    :data:`SHALLOW` (deeper, the motor's depth along the ray from the axis parts from the
    exact one; the swivel search avoids such depths anyway)."""
    (torso,) = (o for o in body_obstacles(avatar) if o.volume.name == "torso")
    assert not torso.turns
    targets = _across_the_chest(avatar, side)
    yaws = np.full(len(targets), yaw)
    placement = place_arm(avatar, side, targets, trunk_yaw=yaws)
    circle = placement.circle
    swivels = CANDIDATES[::3]
    radial = [
        circle.down[:, i : i + 1] * np.cos(swivels)
        + circle.out[:, i : i + 1] * np.sin(swivels)
        for i in range(3)
    ]
    elbow = tuple(
        circle.center[:, i : i + 1] + circle.radius[:, None] * radial[i]
        for i in range(3)
    )
    only_torso = tuple(o for o in body_obstacles(avatar) if o.volume.name == "torso")
    monkeypatch.setattr(clearance_module, "body_obstacles", lambda _avatar: only_torso)
    measured = clearance(
        avatar,
        side,
        circle.shoulder,
        circle.wrist,
        elbow,
        hips_frame=placement.hips_frame,
    )[1]
    turn = turned(avatar, yaws)
    capsules = arm_capsules(avatar, side)
    shape = _audit_torso(avatar)
    for k in range(len(swivels)):
        joints = [
            turn.from_trunk(p)
            for p in (
                circle.shoulder,
                np.stack([c[:, k] for c in elbow], axis=1),
                circle.wrist,
            )
        ]
        upper = _depth(joints[0], joints[1], capsules.upper_ends, capsules.upper_radius, shape)
        fore = _depth(joints[1], joints[2], capsules.fore_ends, capsules.fore_radius, shape)
        expected = np.maximum(np.maximum(upper, fore), 0.0)
        shallow = expected < SHALLOW
        assert measured[shallow, k] == pytest.approx(expected[shallow], abs=1e-3)


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
