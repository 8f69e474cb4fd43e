"""The compiled head, neck and eyes (:func:`motor.neck.posing.pose_head_and_eyes`) give
the very numbers of the numpy steps they replaced (``plain_neck.py``), over a table of
bodies, gazes and head movements — NaN rows, a gaze straight behind the head, a point
looked at from the eye itself, no frame and no eyes among them."""

from __future__ import annotations

import numpy as np
import pytest
from plain_neck import pose as plain_pose

from motor import quaternion as quat
from motor.body.avatar import load_avatar
from motor.neck.control import EYES, _path
from motor.neck.posing import pose_head_and_eyes

RNG = np.random.default_rng(20261202)


def _joints(avatar) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    index = avatar.joint_index
    neck = np.array([index("vc7"), index("vc4"), index("skullbase")])
    return np.array(_path(avatar, int(neck[0])), dtype=np.int64), neck, np.array([index(n) for n in EYES], dtype=np.int64)


def _case(avatar, name: str, count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rotations ``(n, J, 4)`` (the trunk bent and turned a little), gaze rows ``(n, 6)``
    and head movements ``(n, 4)`` of one case of the table."""
    rotations = np.zeros((count, avatar.joint_count, 4))
    rotations[..., 3] = 1.0
    rotations[:] = quat.normalize(rotations + 0.15 * RNG.normal(size=rotations.shape))
    eyes = avatar.rest_positions[avatar.joint_index("l_eyeball_joint")]
    looked = eyes + np.array([0.0, 0.0, 1.2]) + 0.6 * RNG.normal(size=(count, 3))
    facing = np.array([0.0, 0.0, 1.0]) + 0.5 * RNG.normal(size=(count, 3))
    head = np.column_stack([0.3 * RNG.normal(size=(count, 3)), 0.1 * RNG.normal(size=count)])
    if name == "at rest":
        rotations[:] = quat.IDENTITY
        facing[:] = [0.0, 0.0, 1.0]
        head[:] = 0.0
    elif name == "facing straight back":
        facing[:] = [0.0, 0.0, -1.0]
    elif name == "looking far behind":
        looked = eyes + np.array([0.0, 0.0, -50.0]) + RNG.normal(size=(count, 3))
    elif name == "a point at the eye":
        looked[:] = eyes
        rotations[:] = quat.IDENTITY
        head[:] = 0.0
    elif name == "NaN rows":
        looked[::3] = np.nan
        facing[1::3] = np.nan
        head[2::3, 0] = np.nan
    return rotations, np.column_stack([looked, facing]), head


CASES = ["random", "at rest", "facing straight back", "looking far behind", "a point at the eye", "NaN rows"]


@pytest.mark.parametrize("count", [0, 1, 257])
@pytest.mark.parametrize("name", CASES)
@pytest.mark.parametrize("avatar_name", ["max", "kim", "makehuman"])
@pytest.mark.parametrize("with_eyes", [True, False])
def test_head_neck_and_eyes_as_numpy_did(avatar_name, name, count, with_eyes):
    avatar = load_avatar(avatar_name)
    path, neck, eyes = _joints(avatar)
    if not with_eyes:
        eyes = eyes[:0]
    rotations, gaze, head = _case(avatar, name, count)
    expected = plain_pose(avatar, tuple(path.tolist()), tuple(neck.tolist()), tuple(eyes.tolist()), rotations.copy(), gaze, head)
    offsets = np.ascontiguousarray(avatar.offsets, dtype=float)
    eye_offsets = np.array([avatar.rest_positions[e] - avatar.rest_positions[neck[2]] for e in eyes]).reshape(-1, 3)
    got = rotations.copy()
    pose_head_and_eyes(got, path, neck, eyes, offsets, eye_offsets, gaze, head)
    np.testing.assert_array_equal(got, expected)
    if count and name not in ("at rest", "a point at the eye"):  # the case moves what it sets: the comparison can fail
        assert not np.allclose(got[:, neck[2]], quat.IDENTITY)
