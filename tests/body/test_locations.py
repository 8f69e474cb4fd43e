"""Named locations land at the same body-relative place on avatars of different sizes."""

from __future__ import annotations

import numpy as np
import pytest

from motor.body.avatar import Avatar
from motor.body.locations import (
    ARM_SITES,
    CENTRAL_SITES,
    FINGER_SITES,
    PAIRED_SITES,
    resolve_location,
)
from mura.errors import SpecError
from mura.murml_vocabulary import (
    GRID_DISTANCES,
    GRID_HEIGHTS,
    GRID_LATERALS,
    parse_grid_location,
)
from mura.values import FINGERS, BetweenLocation, BodySite, GridLocation, PointLocation


def _joint(avatar: Avatar, name: str) -> np.ndarray:
    return avatar.rest_positions[avatar.joint_index(name)]


@pytest.mark.parametrize("side", ["l", "r"])
def test_loc_shoulder_is_at_shoulder_height(avatar, side):
    point = resolve_location(avatar, parse_grid_location("LocShoulder LocCCenter LocNorm"), side)
    assert point[1] == pytest.approx(_joint(avatar, f"{side}_shoulder")[1], abs=0.005)
    assert point[0] == 0.0
    assert point[2] > avatar.sites["chest"].offset[2]


def test_grid_is_ordered_and_scaled_to_the_avatar(avatars):
    for avatar in avatars.values():
        heights = [avatar.grid.heights[name] for name in GRID_HEIGHTS]
        assert heights == sorted(heights)
        laterals = avatar.grid.laterals
        assert laterals["LocLeft"] > laterals["LocCenterLeft"] > 0 > laterals["LocCenterRight"] > laterals["LocRight"]
        distances = [avatar.grid.distances[name] for name in GRID_DISTANCES]
        assert distances == sorted(distances)
    big, small = avatars["max"], avatars["kim"]
    assert small.grid.heights["LocShoulder"] < big.grid.heights["LocShoulder"]
    assert small.grid.laterals["LocLeft"] < big.grid.laterals["LocLeft"]
    assert set(big.grid.laterals) == set(GRID_LATERALS)


@pytest.mark.parametrize("site, joint", [("nose", "skullbase"), ("chin", "skullbase"), ("chest", "vt6")])
def test_sites_near_their_joints_on_both_avatars(avatars, site, joint):
    for avatar in avatars.values():
        point = resolve_location(avatar, BodySite(site, proximity="touch"), "r")
        assert np.linalg.norm(point - _joint(avatar, joint)) < 0.2 * avatar.stature / 1.8


def test_nose_is_between_eyes_and_lips_and_in_front(avatar):
    at = lambda s: resolve_location(avatar, BodySite(s, proximity="touch"), "r")
    assert at("lips")[1] < at("nose")[1] < at("eyes")[1] < at("forehead")[1] < at("headtop")[1]
    assert at("nose")[2] > _joint(avatar, "skullbase")[2] + 0.05
    assert at("chest")[1] < at("shoulders")[1] < at("neck")[1] < at("chin")[1]


def test_every_hamnosys_site_resolves_on_both_sides(avatar):
    for side in ("l", "r"):
        for site in CENTRAL_SITES + PAIRED_SITES + ARM_SITES:
            assert np.all(np.isfinite(resolve_location(avatar, BodySite(site), side)))
        for site in FINGER_SITES:
            for finger in FINGERS:
                assert np.all(np.isfinite(resolve_location(avatar, BodySite(site, finger=finger), side)))


def test_paired_sites_follow_the_hand_and_arm_sites_the_other_arm(avatar):
    right_ear = resolve_location(avatar, BodySite("ear", proximity="touch"), "r")
    left_ear = resolve_location(avatar, BodySite("ear", proximity="touch"), "l")
    assert right_ear[0] < 0 < left_ear[0]
    palm_for_right_hand = resolve_location(avatar, BodySite("palm", proximity="touch"), "r")
    assert palm_for_right_hand[0] > 0


def test_proximity_moves_out_along_the_normal_in_arm_lengths(avatars):
    for avatar in avatars.values():
        touch = resolve_location(avatar, BodySite("chest", proximity="touch"), "r")
        far = resolve_location(avatar, BodySite("chest", proximity="far"), "r")
        assert far[2] - touch[2] == pytest.approx(0.3 * avatar.arm_length("r"))
        close = resolve_location(avatar, BodySite("chest", proximity="close"), "r")
        assert touch[2] < close[2] < far[2]
    beside = resolve_location(avatar, BodySite("chest", side="lrbeside", proximity="touch"), "r")
    at = resolve_location(avatar, BodySite("chest", side="lrat", proximity="touch"), "r")
    assert beside[0] < at[0] < touch[0]


def test_between_and_point(avatar):
    a, b = PointLocation((0.0, 0.1, 0.2)), PointLocation((0.2, 0.3, 0.4))
    assert np.allclose(resolve_location(avatar, BetweenLocation(a, b), "r"), [0.1, 0.2, 0.3])
    assert np.allclose(resolve_location(avatar, BetweenLocation(a, b, 0.25), "r"), [0.05, 0.15, 0.25])


@pytest.mark.parametrize(
    "location, symbol",
    [
        (GridLocation("LocKnee", "LocCCenter", "LocNorm"), "LocKnee"),
        (GridLocation("LocChest", "LocMoon", "LocNorm"), "LocMoon"),
        (GridLocation("LocChest", "LocCCenter", "LocAway"), "LocAway"),
        (BodySite("elbowpit"), "elbowpit"),
        (BodySite("chest", proximity="inside"), "inside"),
        (BodySite("chest", side="lrunder"), "lrunder"),
        (BodySite("fingertip", finger="toe"), "toe"),
    ],
)
def test_unknown_names_are_spec_errors(avatar, location, symbol):
    with pytest.raises(SpecError, match=symbol):
        resolve_location(avatar, location, "r")
