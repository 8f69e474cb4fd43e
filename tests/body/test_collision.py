"""Collision volumes: what the avatars state, what is derived, signed distances against
brute force, and the smooth keeping of wrists out of the torso and hands apart."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from motor import quaternion as quat
from motor.body.avatar import load_avatar
from motor.body.conventions import AVATAR_DIR, AvatarError
from motor.body.collision import (
    SOFT_BAND,
    TORSO_MARGIN,
    hand_segments,
    hand_push_out_of_torso,
    inside_torso,
    kept_out_of_torso,
    outside_torso,
    separate_hands,
)
from motor.body.distance import capsule_distance, segment_distance
from motor.body.hands_parting import HAND_BAND
from motor.body.volumes import BODY_NAMES, Capsule, Ellipsoid, EllipticCylinder, derived_volumes, required_volumes

RNG = np.random.default_rng(11)


def test_every_standard_volume_is_stated_with_an_allowed_shape(avatar):
    for name, shapes in required_volumes().items():
        assert isinstance(avatar.collision[name], shapes), name
    assert 0.015 < avatar.collision.palm_thickness < 0.05


def test_stated_volumes_match_the_skeleton(avatar):
    """The volumes in the avatar file are those derived from its skeleton (rounded to the
    millimetre), so either source gives the same body."""
    sites = {name: (site.bone, site.offset) for name, site in avatar.sites.items()}
    derived = derived_volumes(avatar.joint_names, avatar.rest_positions, avatar.torso, sites)
    for volume in derived.volumes:
        stated = avatar.collision[volume.name]
        assert type(stated) is type(volume) and stated.joint == volume.joint, volume.name
        for field in ("a", "b", "center", "radii", "radius", "half_width", "half_depth", "bottom", "top"):
            if hasattr(volume, field):
                np.testing.assert_allclose(getattr(stated, field), getattr(volume, field), atol=6e-4, err_msg=f"{volume.name}.{field}")
    assert avatar.collision.palm_thickness == pytest.approx(derived.palm_thickness, abs=6e-4)


@pytest.mark.parametrize("side", ["l", "r"])
def test_arms_hanging_at_rest_stay_clear_of_the_torso(avatar, side):
    torso = avatar.collision["torso"]
    upper = avatar.collision.arm(side, "upper_arm")
    assert capsule_distance(torso, upper.a, upper.b, upper.radius) >= -1e-9


@pytest.mark.parametrize("name", ["max", "kim", "makehuman"])
def test_no_arm_volume_overlaps_the_body_in_its_own_rest_pose(name):
    """At rest (arms hanging) every arm capsule is clear of every volume of the body and of
    the other arm — the shipped avatars and the default skinned one, whose volumes are
    measured on its skin: a volume inside the body at rest would count every pose of the
    arm as a penetration."""
    collision = load_avatar(name).collision
    arms = [v for v in collision.volumes if v.name[2:] in ("upper_arm", "forearm", "hand")]
    for arm in arms:
        for other in collision.volumes:
            if other.name[:2] == arm.name[:2] and other in arms:
                continue
            if isinstance(other, Capsule):
                gap = float(segment_distance(arm.a, arm.b, other.a, other.b)) - arm.radius - other.radius
            else:
                gap = float(capsule_distance(other, arm.a, arm.b, arm.radius))
            assert gap >= -1e-3, f"{name}: {arm.name} {100 * -gap:.1f} cm into {other.name} at rest"


@pytest.mark.parametrize("name", ["max", "kim", "makehuman"])
def test_hands_placed_palm_to_palm_do_not_overlap(name):
    """Hands placed a palm thickness apart (midline to midline) touch: their capsules are
    no thicker than the palm."""
    collision = load_avatar(name).collision
    for side in "lr":
        assert 2.0 * collision.arm(side, "hand").radius <= collision.palm_thickness + 1e-3


def _edit(tmp_path: Path, edit) -> Path:
    data = json.loads((AVATAR_DIR / "kim.json").read_text())
    edit(data["collision"])
    path = tmp_path / "kim.json"
    path.write_text(json.dumps(data))
    return path


def _volume(name: str):
    def pick(collision: dict) -> dict:
        return next(v for v in collision["volumes"] if v["name"] == name)

    return pick


@pytest.mark.parametrize(
    "edit, message",
    [
        (lambda c: c.update(palm_thickness=-0.01), r"collision\.palm_thickness: must be positive"),
        (lambda c: c.update(volumes=[v for v in c["volumes"] if v["name"] != "head"]), r"collision\.volumes: missing volume 'head'"),
        (lambda c: _volume("torso")(c).update(shape="cube"), r"shape: unknown shape 'cube'"),
        (lambda c: _volume("torso")(c).update(joint="spine"), r"joint: unknown joint 'spine'"),
        (lambda c: _volume("l_forearm")(c).update(shape="ellipsoid", center=[0, 0, 0], radii=[0.1, 0.1, 0.1]), r"volume 'l_forearm' must be a capsule"),
        (lambda c: _volume("r_hand")(c).update(radius=0), r"radius: must be positive"),
        (lambda c: _volume("head")(c).update(radii=[0.1, 0.1]), r"radii: expected a list of 3 numbers"),
        (lambda c: _volume("torso")(c).update(bottom=1.0), r"top .* must be above bottom"),
        (lambda c: c["volumes"].append(dict(c["volumes"][0])), r"volume 'torso' declared twice"),
    ],
)
def test_broken_collision_entries_are_refused_naming_the_field(tmp_path, edit, message):
    with pytest.raises(AvatarError, match=r"kim\.json: " + message if message.startswith("collision") else message):
        load_avatar(_edit(tmp_path, edit))


def test_palm_thickness_defaults_to_the_hands_thickness(tmp_path):
    avatar = load_avatar(_edit(tmp_path, lambda c: c.pop("palm_thickness")))
    assert avatar.collision.palm_thickness == pytest.approx(2.0 * avatar.collision.arm("l", "hand").radius)


def test_an_avatar_without_collision_entry_gets_derived_volumes(tmp_path):
    data = json.loads((AVATAR_DIR / "max.json").read_text())
    data.pop("collision")
    path = tmp_path / "bare.json"
    path.write_text(json.dumps(data))
    bare, stated = load_avatar(path), load_avatar("max")
    assert [v.name for v in bare.collision.volumes] == [v.name for v in stated.collision.volumes]
    assert set(BODY_NAMES) <= {v.name for v in bare.collision.volumes}


def _brute_distance(volume, a: np.ndarray, b: np.ndarray, radius: float) -> float:
    """Signed distance by dense sampling of the segment against the volume's surface."""
    points = a + np.linspace(0.0, 1.0, 801)[:, None] * (b - a)
    if isinstance(volume, Capsule):
        return float(np.min(segment_distance(points, points, volume.a, volume.b))) - volume.radius - radius
    # the sphere case of the ellipsoid: exact distance
    center, r = volume.center, float(volume.radii[0])
    return float(np.min(np.linalg.norm(points - center, axis=1))) - r - radius


@pytest.mark.parametrize("trial", range(20))
def test_capsule_distances_match_brute_force(trial):
    rng = np.random.default_rng(trial)
    a, b = rng.normal(0, 0.2, (2, 3))
    radius = 0.03
    capsule = Capsule("c", "vl5", *rng.normal(0, 0.2, (2, 3)), 0.05)
    sphere = Ellipsoid("s", "vl5", rng.normal(0, 0.2, 3), np.full(3, 0.1))
    for volume in (capsule, sphere):
        assert capsule_distance(volume, a, b, radius) == pytest.approx(_brute_distance(volume, a, b, radius), abs=2e-4)


@pytest.mark.parametrize("trial", range(20))
def test_cylinder_distance_sign_matches_brute_force(trial):
    """Inside or out of an elliptic cylinder, by sampling the segment: the signed distance
    is negative exactly when a sampled point of the capsule's axis is inside, and the
    deepest sampled point is no deeper than the distance says."""
    rng = np.random.default_rng(100 + trial)
    cylinder = EllipticCylinder("t", "vl5", np.zeros(3), 0.14, 0.11, -0.05, 0.5)
    a, b = rng.uniform([-0.3, -0.2, -0.3], [0.3, 0.7, 0.3], (2, 3))
    points = a + np.linspace(0.0, 1.0, 2001)[:, None] * (b - a)
    radial = np.hypot(points[:, 0] / 0.14, points[:, 2] / 0.11)
    inside = (radial < 1.0) & (points[:, 1] > -0.05) & (points[:, 1] < 0.5)
    distance = float(capsule_distance(cylinder, a, b, 0.0))
    assert (distance < 0.0) == bool(np.any(inside))
    if np.any(inside):
        deepest = np.max((1.0 - radial[inside]) * np.hypot(points[inside, 0], points[inside, 2]) / np.maximum(radial[inside], 1e-9))
        # radial depth at the point of least scaled radius: within 10 % of the deepest
        assert -distance >= 0.9 * deepest - 1e-3


def test_wrists_are_kept_out_of_the_torso_smoothly(avatar):
    """Along a path straight through the torso the pushed wrist never ends inside, and
    its position changes continuously with a continuous first derivative (no speed step);
    points the planners placed out of the torso stay out of it."""
    front = avatar.torso.center[2] + avatar.torso.half_depth
    z = np.linspace(front + 0.2, -0.2, 4001)
    path = np.stack([np.full_like(z, 0.05), np.full_like(z, 0.3), z], axis=1)
    pushed = kept_out_of_torso(avatar, path)
    assert not np.any(inside_torso(avatar, pushed))
    velocity = np.diff(pushed[:, 2]) / np.diff(z)
    # a continuous derivative: from sample to sample it changes by at most its curvature
    # (the ease's, below 1 / SOFT_BAND) times the step
    assert np.max(np.abs(np.diff(velocity))) < 2.0 * abs(z[1] - z[0]) / SOFT_BAND
    far = path[:10]
    assert np.array_equal(kept_out_of_torso(avatar, far), far)
    placed = outside_torso(avatar, path)
    assert not np.any(inside_torso(avatar, placed))
    assert np.array_equal(outside_torso(avatar, placed), placed)
    assert not np.any(inside_torso(avatar, kept_out_of_torso(avatar, placed)))


#: Hands turned so that they point back into the body (the direction the hand's capsule
#: runs from the wrist), as a hand turns on its way down to rest.
HAND_WAYS = {"back": (0.0, 0.0, -1.0), "down and back": (0.0, -0.7, -0.7), "across and back": (1.0, 0.0, -1.0), "up and back": (0.0, 0.5, -1.0)}


@pytest.mark.parametrize("way", sorted(HAND_WAYS))
@pytest.mark.parametrize("side", ["l", "r"])
def test_hands_are_kept_out_of_the_torso_smoothly(avatar, side, way):
    """A wrist sweeping down past the chest and hip with its hand turned into the body:
    the pushed hand's capsule axis stays the capsule's radius out of the torso, and the
    push changes continuously along the sweep (no more than a few times the wrist's own
    step from sample to sample)."""
    y = np.linspace(avatar.torso.top + 0.15, avatar.torso.bottom - 0.15, 2001)
    front = avatar.torso.center[2] + avatar.torso.half_depth + TORSO_MARGIN + 0.005
    wrists = np.stack([np.full_like(y, 0.02), y, np.full_like(y, front)], axis=1)
    rest_axis = avatar.collision.arm(side, "hand").b - avatar.collision.arm(side, "hand").a
    turn = quat.between_vectors(rest_axis / np.linalg.norm(rest_axis), np.asarray(HAND_WAYS[way]) / np.linalg.norm(HAND_WAYS[way]))
    hands = np.repeat(np.asarray(turn, dtype=float).reshape(1, 4), y.size, axis=0)
    pushed = kept_out_of_torso(avatar, wrists) + hand_push_out_of_torso(avatar, side, wrists, hands)
    start, end = hand_segments(avatar, side, pushed, hands)
    radius = avatar.collision.arm(side, "hand").radius
    for fraction in np.linspace(0.0, 1.0, 9):
        points = start + fraction * (end - start)
        assert not np.any(inside_torso(avatar, points, radius - 1e-3)), f"{way}: the hand's axis within its radius of the torso"
    step = np.linalg.norm(np.diff(pushed - wrists, axis=0), axis=1)
    assert step.max() < 5.0 * abs(y[1] - y[0]), f"{way}: the push jumps by {1000 * step.max():.1f} mm between samples"
    assert np.any(pushed != wrists), f"{way}: the sweep never needs a push"


def test_hands_are_kept_a_palm_thickness_apart_symmetrically(avatar):
    """Both wrists at one point (the join_hands case) end a palm thickness apart (less the
    band into which hands asked to overlap are eased), mirrored about the midline; hands
    in contact and hands far apart are left alone."""
    wrist = np.array([[0.0, 0.3, 0.3]])
    facing = quat.from_axis_angle(np.array([[1.0, 0.0, 0.0]]), np.array([-np.pi / 2]))
    left, right = separate_hands(avatar, wrist, wrist.copy(), facing, facing)
    assert np.linalg.norm(left - right) == pytest.approx(avatar.collision.palm_thickness - HAND_BAND, abs=1e-4)
    np.testing.assert_allclose(left * [-1, 1, 1], right, atol=1e-12)
    half = np.array([0.5 * avatar.collision.palm_thickness, 0.0, 0.0])
    for pair in ((wrist + half, wrist - half), (np.array([[0.3, 0.3, 0.3]]), np.array([[-0.3, 0.3, 0.3]]))):
        kept = separate_hands(avatar, *pair, facing, facing)
        assert all(np.array_equal(k, a) for k, a in zip(kept, pair))


def test_hands_meet_without_a_speed_step(avatar):
    """Hands approaching head-on slow into contact: the separated wrists' path has a
    continuous first derivative."""
    x = np.linspace(0.15, 0.0, 3001)
    left = np.stack([x, np.full_like(x, 0.3), np.full_like(x, 0.3)], axis=1)
    right = left * [-1, 1, 1]
    down = np.broadcast_to(quat.from_axis_angle(np.array([1.0, 0.0, 0.0]), -np.pi / 2), (len(x), 4))
    kept, _ = separate_hands(avatar, left, right, down, down)
    velocity = np.diff(kept[:, 0]) / np.diff(x)
    assert np.max(np.abs(np.diff(velocity))) < 2.0 * abs(x[1] - x[0]) / HAND_BAND
    assert np.min(kept[:, 0]) > 0.0


@pytest.mark.parametrize("depth", [0.3, 0.6, 0.9])
def test_wrists_meeting_the_torso_side_bend_around_it_smoothly(avatar, depth):
    """A wrist path that runs in from beside the torso, in front of its axis (``depth``:
    how far, in the grown torso's half depths), bends around the side: never inside, no
    speed step, and never pushed farther than straight forward onto the front would."""
    torso = avatar.torso
    a, b = torso.half_width + TORSO_MARGIN, torso.half_depth + TORSO_MARGIN
    x = np.linspace(torso.center[0] - 1.6 * a, torso.center[0] - 0.2 * a, 4001)
    z = torso.center[2] + depth * b
    path = np.stack([x, np.full_like(x, 0.5 * (torso.bottom + torso.top)), np.full_like(x, z)], axis=1)
    pushed = kept_out_of_torso(avatar, path)
    assert not np.any(inside_torso(avatar, pushed))
    velocity = np.diff(pushed, axis=0) / np.diff(x)[:, None]
    assert np.max(np.linalg.norm(np.diff(velocity, axis=0), axis=1)) < 2.0 * abs(x[1] - x[0]) / SOFT_BAND
    forward = torso.center[2] + b * np.sqrt(np.clip(1.0 - ((x - torso.center[0]) / a) ** 2, 0.0, 1.0)) - z
    assert np.all(np.linalg.norm(pushed - path, axis=1) <= np.maximum(forward, 0.0) + SOFT_BAND)


@pytest.mark.parametrize(("height", "way"), [(0.0, -1.0), (-0.005, -1.0), (0.005, 1.0)], ids=["level", "below", "above"])
def test_hands_passing_through_each_other_part_one_way(avatar, height, way):
    """The left hand runs across the right one (palms down, its wrist ``height`` m above
    the right's): it passes on the side it is on (``way``: +1 above, -1 below), below where
    the hands are level, and moves continuously — the way they part never flips."""
    x = np.linspace(0.15, -0.15, 3001)
    left = np.stack([x, np.full_like(x, 0.3 + height), np.full_like(x, 0.3)], axis=1)
    right = np.tile([0.0, 0.3, 0.3], (len(x), 1))
    kept_left, kept_right = separate_hands(avatar, left, right, *(_palm_down(avatar, side, len(x)) for side in "lr"))
    rise = kept_left[:, 1] - kept_right[:, 1]
    assert np.all(way * rise >= -1e-12)
    assert np.max(way * rise) >= 0.5 * avatar.collision.palm_thickness
    assert np.max(np.linalg.norm(np.diff(kept_left, axis=0), axis=1)) < 20.0 * abs(x[1] - x[0])


def _palm_down(avatar, side: str, count: int) -> np.ndarray:
    """``count`` global hand rotations with the fingers forward and the palm down."""
    frame = avatar.hand_frames[side]
    axes = lambda finger, palm: np.stack((finger, palm, np.cross(finger, palm)), axis=-1)
    rotation = quat.from_frames(axes(frame.finger_axis, frame.palm_normal), axes(np.array([0.0, 0.0, 1.0]), np.array([0.0, -1.0, 0.0])))
    return np.broadcast_to(rotation, (count, 4))


def _sampled_outside_distance(cylinder: EllipticCylinder, a: np.ndarray, b: np.ndarray) -> float:
    """Least distance of a segment's sampled points (none inside the cylinder) from it: the
    vertical gap and the radial gap along the ray from the axis, combined."""
    points = a + np.linspace(0.0, 1.0, 4001)[:, None] * (b - a)
    sx, sz = points[:, 0] / cylinder.half_width, points[:, 2] / cylinder.half_depth
    rho = np.hypot(sx, sz)
    radial = np.maximum(np.hypot(points[:, 0], points[:, 2]) * (1.0 - 1.0 / np.maximum(rho, 1e-9)), 0.0)
    vertical = np.maximum(np.maximum(cylinder.bottom - points[:, 1], points[:, 1] - cylinder.top), 0.0)
    return float(np.min(np.hypot(radial, vertical)))


ACROSS_THE_TOP = [
    # (segment start, end): an upper arm lying across the top of the chest, its ends beyond the rim
    ((0.137, 0.512, 0.059), (0.040, 0.508, 0.200)),
    ((0.20, 0.53, 0.0), (-0.20, 0.53, 0.05)),
    ((0.18, -0.08, -0.05), (-0.02, -0.07, 0.16)),
    ((0.0, 0.56, 0.2), (0.0, 0.56, -0.2)),
]


@pytest.mark.parametrize("ends", ACROSS_THE_TOP)
def test_a_segment_across_the_top_is_as_near_as_its_nearest_point(ends):
    """A segment wholly above (or below) the cylinder whose ends lie beyond its rim passes
    nearest somewhere between them: its distance is that point's, not an end's."""
    cylinder = EllipticCylinder("t", "vl5", np.zeros(3), 0.14, 0.11, -0.05, 0.5)
    a, b = (np.array(end, dtype=float) for end in ends)
    assert float(capsule_distance(cylinder, a, b, 0.0)) == pytest.approx(_sampled_outside_distance(cylinder, a, b), abs=1e-3)


@pytest.mark.parametrize("trial", range(20))
def test_a_segment_above_or_below_is_never_measured_nearer_than_it_is(trial):
    rng = np.random.default_rng(300 + trial)
    cylinder = EllipticCylinder("t", "vl5", np.zeros(3), 0.14, 0.11, -0.05, 0.5)
    low, high = (-0.3, 0.52, -0.3), (0.3, 0.8, 0.3)
    a, b = rng.uniform(low, high, (2, 3))
    if trial % 2:
        a[1], b[1] = -a[1] + 0.45, -b[1] + 0.45
    sampled = _sampled_outside_distance(cylinder, a, b)
    distance = float(capsule_distance(cylinder, a, b, 0.0))
    assert sampled - 1e-6 <= distance <= sampled + 0.01


STRADDLING_THE_TOP = [
    # (segment start, end): partly above the top, partly beside the cylinder, nearest the rim
    # above it; 12_denule_regal's upper arm was measured 2 cm in the chest 7 cm clear
    ((0.15, 0.51, 0.06), (0.05, 0.49, 0.20)),
    ((0.16, 0.53, 0.0), (0.06, 0.47, 0.16)),
    ((-0.16, 0.52, 0.05), (-0.03, 0.48, 0.15)),
    ((0.15, -0.07, 0.05), (0.04, -0.03, 0.15)),
]


@pytest.mark.parametrize("ends", STRADDLING_THE_TOP)
def test_a_segment_leaving_the_height_range_is_as_near_as_its_nearest_point(ends):
    """A segment partly above (or below) the cylinder is as near as its nearest point,
    wherever that is: above the rim as well as beside the side."""
    cylinder = EllipticCylinder("t", "vl5", np.zeros(3), 0.14, 0.11, -0.05, 0.5)
    a, b = (np.array(end, dtype=float) for end in ends)
    assert float(capsule_distance(cylinder, a, b, 0.0)) == pytest.approx(_sampled_outside_distance(cylinder, a, b), abs=1e-3)


@pytest.mark.parametrize("trial", range(20))
def test_a_segment_about_the_rim_is_as_far_as_its_nearest_point(trial):
    """Segments from about the top (or bottom) rim, outside the cylinder: as far as their
    nearest densely sampled point, within a millimetre (the distance is measured at a
    few points along the segment)."""
    rng = np.random.default_rng(500 + trial)
    cylinder = EllipticCylinder("t", "vl5", np.zeros(3), 0.14, 0.11, -0.05, 0.5)
    angle = rng.uniform(0.0, 2.0 * np.pi, 2)
    rho = rng.uniform(1.05, 1.8, 2)
    height = rng.uniform(0.42, 0.58, 2) if trial % 2 else rng.uniform(-0.13, 0.03, 2)
    a, b = (np.array([r * 0.14 * np.cos(t), h, r * 0.11 * np.sin(t)]) for r, t, h in zip(rho, angle, height))
    points = a + np.linspace(0.0, 1.0, 4001)[:, None] * (b - a)
    clear = (np.hypot(points[:, 0] / 0.14, points[:, 2] / 0.11) >= 1.0) | (points[:, 1] > 0.5) | (points[:, 1] < -0.05)
    if not np.all(clear):
        pytest.skip("this segment passes through the cylinder")
    sampled = _sampled_outside_distance(cylinder, a, b)
    distance = float(capsule_distance(cylinder, a, b, 0.0))
    assert distance == pytest.approx(sampled, abs=1e-3)
