"""The arm placed in compiled passes for the upright body
(:func:`motor.arm.upright_placement.upright_placement`) is the numpy composition's
placement (:func:`motor.arm.chain.place_arm`) and natural swivel bit for bit: over both
avatars and sides, targets in front and across the chest, raised, behind, out of reach,
at the shoulder and too near it, with and without hand rotations, and calls with a target
or hand rotation that is not finite (which take the composition)."""

from __future__ import annotations

import numpy as np
import pytest

from motor.arm.chain import natural_swivel, place_arm
from motor.arm.upright_placement import upright_placement
from motor.body.avatar import load_avatar

RNG = np.random.default_rng(23)
N = 256
#: Where the targets lie, from the shoulder (metres, avatar frame: +x the avatar's left,
#: y up, z forward), and how far they scatter.
PLACES = {
    "front": ((0.0, -0.3, 0.3), 0.1),
    "across the chest": ("across", 0.08),
    "raised": ((0.0, 0.45, 0.2), 0.1),
    "behind": ((0.0, -0.2, -0.3), 0.1),
    "out of reach": ((0.0, 0.0, 0.9), 0.3),
    "anywhere": ((0.0, 0.0, 0.0), 0.6),
    "near the shoulder": ((0.0, 0.0, 0.0), 0.03),
}


def targets(avatar, side: str, place: str) -> np.ndarray:  # noqa: ANN001
    shoulder = avatar.rest_positions[avatar.joint_index(f"{side}_shoulder")]
    toward, spread = PLACES[place]
    offset = np.array([-shoulder[0], -0.15, 0.12]) if toward == "across" else np.array(toward)
    points = shoulder + offset + RNG.normal(0.0, spread, (N, 3))
    points[0] = shoulder  # a target on the shoulder at rest
    return points


def assert_same(got, expected) -> None:  # noqa: ANN001
    (placement, natural), (reference, reference_natural) = got, expected
    assert np.array_equal(natural, reference_natural, equal_nan=True)
    for name in reference.circle.__dataclass_fields__:
        assert np.array_equal(getattr(placement.circle, name), getattr(reference.circle, name), equal_nan=True), name
    for name in ("clavicle_local", "sc_global", "targets", "hands"):
        a, b = getattr(placement, name), getattr(reference, name)
        assert (a is None and b is None) or np.array_equal(a, b, equal_nan=True), name
    assert (placement.torso_q, placement.body_frame, placement.carried_frames) == (None, None, None)
    assert placement.chain is reference.chain


def composed(avatar, side, points, rotations):  # noqa: ANN001, ANN201
    placement = place_arm(avatar, side, points, rotations)
    return placement, natural_swivel(placement.chain, placement.circle, placement.targets, placement.torso_q)


@pytest.mark.parametrize("avatar_name", ["max", "kim"])
@pytest.mark.parametrize("side", ["l", "r"])
@pytest.mark.parametrize("place", sorted(PLACES))
@pytest.mark.parametrize("hands", [True, False], ids=["hand rotations", "no hand rotations"])
def test_the_compiled_placement_is_the_composed_one(avatar_name, side, place, hands):
    avatar = load_avatar(avatar_name)
    points = targets(avatar, side, place)
    rotations = RNG.normal(size=(N, 4)) if hands else None
    assert_same(upright_placement(avatar, side, points, rotations), composed(avatar, side, points, rotations))


@pytest.mark.parametrize("what", ["target", "hand rotation"])
@pytest.mark.parametrize("bad", [np.nan, np.inf], ids=["NaN", "infinite"])
def test_a_call_with_a_value_not_finite_is_the_composed_one(what, bad):
    avatar = load_avatar("max")
    points, rotations = targets(avatar, "r", "front"), RNG.normal(size=(N, 4))
    (points if what == "target" else rotations)[7] = bad
    with np.errstate(all="ignore"):
        assert_same(upright_placement(avatar, "r", points, rotations), composed(avatar, "r", points, rotations))


def test_no_targets_place_no_arm():
    placement, natural = upright_placement(load_avatar("max"), "l", np.zeros((0, 3)))
    assert placement.circle.wrist.shape == (0, 3) and natural.shape == (0,)
