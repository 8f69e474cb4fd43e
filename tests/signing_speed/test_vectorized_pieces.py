"""Each vectorized piece of sign planning equals the plain computation row by row.

Tables of synthetic wrist positions and hand postures (labelled synthetic: random points
around the avatar's signing space, random rotations and hand parameters, seeded), with
repeated rows, one-point paths and points out of reach or inside the torso.
"""

from __future__ import annotations

import numpy as np
import pytest

from motor.body.kinematics import forward_kinematics, identity_rotations
from motor.body.locations import resolve_location, site_points
from motor.hand.shape import PARAMETER_COUNT
from motor.signing.hand_geometry import GeometryPending, HandGeometry
from motor.signing.reach import (
    arc_fractions,
    arc_fractions_of_paths,
    clear_paths,
    rotations_along,
    rotations_along_paths,
    within_reach,
)
from mura.values import BodySite

SEEDS = (1, 2, 3)


def synthetic_paths(seed: int, count: int = 24) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Synthetic wrist paths (1–10 points, metres) spread over and beyond the signing
    space, some standing still, with unit rotations along them."""
    rng = np.random.default_rng(seed)
    paths = [rng.normal([0.0, 1.15, 0.25], [0.3, 0.25, 0.3], (n, 3)) for n in rng.integers(1, 11, count)]
    paths[0] = np.repeat(paths[0][:1], 4, axis=0)  # a path that does not move
    turns = [rng.normal(size=(len(path), 4)) for path in paths]
    return paths, [turn / np.linalg.norm(turn, axis=1, keepdims=True) for turn in turns]


def same(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and a.tobytes() == b.tobytes()


@pytest.mark.parametrize("arm", ["right", "left"])
@pytest.mark.parametrize("seed", SEEDS)
def test_within_reach_of_distinct_rows_equals_every_row(avatar, arm, seed):
    paths, turns = synthetic_paths(seed)
    points, rotations = np.concatenate(paths), np.concatenate(turns)
    points, rotations = np.concatenate([points, points[::3]]), np.concatenate([rotations, rotations[::3]])  # repeats
    fixed, moved, worst = within_reach(avatar, arm, points, rotations)
    plain = within_reach(avatar, arm, points, rotations, unique=False)
    assert same(fixed, plain[0]) and (moved, worst) == plain[1:]
    assert moved > 0  # the table reaches past the arm


@pytest.mark.parametrize("keep_ends", [False, True])
@pytest.mark.parametrize("seed", SEEDS)
def test_clear_paths_of_a_collection_equals_path_by_path(avatar, seed, keep_ends):
    paths, turns = synthetic_paths(seed)
    together, moved = clear_paths(avatar, "right", paths, turns, keep_ends=keep_ends)
    alone = [clear_paths(avatar, "right", [path], [turn], keep_ends=keep_ends) for path, turn in zip(paths, turns)]
    assert all(same(a, b[0][0]) for a, b in zip(together, alone))
    assert moved == sum(b[1] for b in alone) and moved > 0
    if keep_ends:
        assert all(same(a[[0, -1]], p[[0, -1]]) for a, p in zip(together, paths))


@pytest.mark.parametrize("seed", SEEDS)
def test_rotations_and_fractions_along_all_paths_equal_each_path(seed):
    paths, turns = synthetic_paths(seed)
    keys = [turn if len(turn) > 1 else turn[:1] for turn in turns]
    fractions = np.split(arc_fractions_of_paths(paths), np.cumsum([len(p) for p in paths])[:-1])
    assert all(same(f, arc_fractions(p)) for f, p in zip(fractions, paths))
    along = np.split(rotations_along_paths(keys, paths), np.cumsum([len(p) for p in paths])[:-1])
    for rotations, key, path in zip(along, keys, paths):
        assert same(rotations, key if len(key) == 1 else rotations_along(key, arc_fractions(path)))


@pytest.mark.parametrize("site", [BodySite("palm", proximity="touch"), BodySite("fingertip", finger="middle"), BodySite("elbow", side="lrat")])
@pytest.mark.parametrize("side", ["r", "l"])
def test_site_points_of_many_frames_equal_each_frame(avatar, site, side):
    rng = np.random.default_rng(7)
    rotations = identity_rotations(avatar, 12)
    rotations[:, avatar.arm_joints("l" if side == "r" else "r")] = rng.normal(size=(12, 4, 4))
    rotations /= np.linalg.norm(rotations, axis=-1, keepdims=True)
    pose = forward_kinematics(avatar, rotations)
    points = site_points(avatar, site, side, pose)
    for frame in range(12):
        one = forward_kinematics(avatar, rotations[frame : frame + 1])
        assert same(points[frame], resolve_location(avatar, site, side, one))


@pytest.mark.parametrize("side", ["r", "l"])
def test_prefetched_and_pending_geometry_equals_one_by_one(avatar, side):
    """Site offsets and arm poses computed together for many postures (synthetic) equal
    those computed alone, and a memoizing geometry hands back what a plain one computes."""
    rng = np.random.default_rng(11)
    rotations = rng.normal(size=(16, 4))
    rotations /= np.linalg.norm(rotations, axis=1, keepdims=True)
    params = rng.uniform(0.0, 1.0, (16, PARAMETER_COUNT))
    wrists = rng.normal([0.0, 1.15, 0.3], 0.15, (16, 3))
    palm = BodySite("palm", proximity="touch")
    plain, batched = HandGeometry(avatar, memoize=False), HandGeometry(avatar)
    batched.prefetch_site_offsets([(side, palm, q, p) for q, p in zip(rotations, params)])
    batched.deferring = True
    for wrist, q, p in zip(wrists, rotations, params):
        with pytest.raises(GeometryPending):
            batched.arm_pose(side, wrist, q, p)
    batched.resolve_pending()
    batched.deferring = False
    for wrist, q, p in zip(wrists, rotations, params):
        assert same(batched.site_offset(side, palm, q, p), plain.site_offset(side, palm, q, p))
        fast, slow = batched.arm_pose(side, wrist, q, p), plain.arm_pose(side, wrist, q, p)
        assert same(fast.positions, slow.positions) and same(fast.orientations, slow.orientations)


def test_a_failing_pose_pass_leaves_each_request_to_fail_alone(avatar):
    """One bad request (hand parameters of the wrong length) in a pass of pending arm
    poses: the good ones are still answered, as one by one; the bad one raises alone."""
    geometry, plain = HandGeometry(avatar), HandGeometry(avatar, memoize=False)
    rotation, wrist = np.array([0.0, 0.0, 0.0, 1.0]), np.array([-0.2, 1.2, 0.35])
    good, bad = np.zeros(PARAMETER_COUNT), np.zeros(PARAMETER_COUNT + 1)
    geometry.deferring = True
    for params in (good, bad):
        with pytest.raises(GeometryPending):
            geometry.arm_pose("r", wrist, rotation, params)
    assert geometry.resolve_pending()
    fast, slow = geometry.arm_pose("r", wrist, rotation, good), plain.arm_pose("r", wrist, rotation, good)
    assert same(fast.positions, slow.positions)
    with pytest.raises(ValueError, match="columns"):
        geometry.arm_pose("r", wrist, rotation, bad)
