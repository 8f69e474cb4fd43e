"""Cost per frame of the body: forward kinematics, arm IK and hand rotations.

Not a test: prints figures. ``run(quick)`` poses the full skeleton of the ``max`` avatar
(53 joints) for 10,000 frames (2,000 when ``quick``): both arms solved by IK toward wrist
targets moving through signing space, with and without hand-rotation targets, both hands
shaped by interpolating between two hand shapes, then forward kinematics of everything.
Each stage is the median of several runs, reported in microseconds per frame, with the
frames per second of the whole pipeline.
"""

from __future__ import annotations

import json
import sys

import numpy as np

from bench.timing import median_seconds
from motor.arm.hand_orientation import hand_rotations_from_vectors
from motor.arm.ik import solve_arm
from motor.body.avatar import load_avatar
from motor.body.kinematics import forward_kinematics, identity_rotations
from motor.hand.shape import hand_rotations, handshape_params
from mura.values import HandShape


def run(quick: bool) -> dict:
    """Microseconds per frame of each stage and frames per second of the whole body."""
    frames = 2_000 if quick else 10_000
    repeats = 3 if quick else 7
    avatar = load_avatar("max")
    grid = avatar.grid
    phase = np.linspace(0.0, 6.0 * np.pi, frames)
    targets = {
        side: np.stack(
            (
                sign * (0.15 + 0.15 * np.sin(phase)),
                grid.heights["LocChest"] + 0.1 * np.cos(0.5 * phase),
                grid.front + grid.distances["LocNorm"] + 0.05 * np.sin(0.3 * phase),
            ),
            axis=-1,
        )
        for side, sign in (("l", 1.0), ("r", -1.0))
    }
    fingers = np.stack((-0.3 * np.sin(phase), 0.3 * np.cos(phase), np.ones(frames)), axis=-1)
    palms = np.tile([0.0, -1.0, 0.0], (frames, 1))
    hands = {side: hand_rotations_from_vectors(avatar, side, fingers * [1.0 if side == "l" else -1.0, 1, 1], palms) for side in "lr"}
    weight = (0.5 + 0.5 * np.sin(phase))[:, None]
    params = (1.0 - weight) * handshape_params(HandShape("flathand")) + weight * handshape_params(HandShape("pinch12"))

    def pose_body(with_orientation: bool) -> np.ndarray:
        rotations = identity_rotations(avatar, frames)
        for side in "lr":
            arm = solve_arm(avatar, side, targets[side], hands[side] if with_orientation else None)
            rotations[:, avatar.arm_joints(side)] = arm.rotations
            rotations[:, avatar.hand_joints(side)] = hand_rotations(avatar, side, params)
        return forward_kinematics(avatar, rotations).positions

    rotations = identity_rotations(avatar, frames)
    per_frame = lambda seconds: 1e6 * seconds / frames
    fk = median_seconds(lambda: forward_kinematics(avatar, rotations), repeats)
    ik = median_seconds(lambda: solve_arm(avatar, "r", targets["r"]), repeats)
    ik_oriented = median_seconds(lambda: solve_arm(avatar, "r", targets["r"], hands["r"]), repeats)
    ik_fixed = median_seconds(lambda: solve_arm(avatar, "r", targets["r"], hands["r"], swivel=np.zeros(frames)), repeats)
    hand = median_seconds(lambda: hand_rotations(avatar, "r", params), repeats)
    body = median_seconds(lambda: pose_body(False), repeats)
    body_oriented = median_seconds(lambda: pose_body(True), repeats)
    return {
        "frames": frames,
        "joints": avatar.joint_count,
        "fk_us_per_frame": per_frame(fk),
        "arm_ik_us_per_frame": per_frame(ik),
        "arm_ik_with_hand_rotation_us_per_frame": per_frame(ik_oriented),
        "arm_ik_given_swivel_us_per_frame": per_frame(ik_fixed),
        "hand_us_per_frame": per_frame(hand),
        "body_us_per_frame": per_frame(body),
        "body_with_hand_rotations_us_per_frame": per_frame(body_oriented),
        "body_frames_per_s": frames / body,
        "body_with_hand_rotations_frames_per_s": frames / body_oriented,
    }


if __name__ == "__main__":
    print(json.dumps(run(quick="--quick" in sys.argv), indent=2))
