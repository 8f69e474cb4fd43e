"""The body: the hand stays outside the torso, head non-manuals, errors that name the sign."""

from __future__ import annotations

import numpy as np
import pytest
from sign_helpers import sign_from

from motor.body.collision import outside_torso
from motor.signing.plan import SignPlanningError
from motor.signing.planning import plan_sign
from motor.signing.sequence import head_movement, realize_signs
from mura.sigml import parse_sigml
from mura.signs import HandPosture, NonmanualItem, Sign
from mura.values import BodySite


def inside_torso(avatar, points):
    torso = avatar.torso
    dx = (points[:, 0] - torso.center[0]) / torso.half_width
    dz = (points[:, 2] - torso.center[2]) / torso.half_depth
    return (dx * dx + dz * dz < 1.0) & (points[:, 1] > torso.bottom) & (points[:, 1] < torso.top)


@pytest.mark.parametrize(
    "symbols",
    [
        "hamflathand hamextfingeru hampalmr hamchest hamtouch hammover",  # along the chest
        "hamflathand hamextfingeru hampalmr hamstomach hamtouch hammoveu hamlargemod",
        "hamfist hamextfingero hampalmd hamchest hamclose hammovei",  # into the body
    ],
)
def test_wrist_stays_outside_the_torso(avatar, symbols):
    signed = realize_signs(avatar, [sign_from(symbols)])
    times = np.linspace(0.0, signed.duration, 400)
    for arm in ("right", "left"):
        wrists = signed.control.timeline((arm, "wrist_position")).sample(times)
        assert not np.any(inside_torso(avatar, wrists))


def test_outside_torso_pushes_forward_onto_the_front(avatar):
    torso = avatar.torso
    inside = np.array([[0.0, 0.3, 0.0], [0.05, 0.2, -0.2]])
    pushed = outside_torso(avatar, inside)
    assert np.allclose(pushed[:, :2], inside[:, :2])
    assert np.all(pushed[:, 2] > torso.center[2] + torso.half_depth)
    outside = np.array([[0.0, 0.3, 0.4], [0.0, 0.9, 0.0]])
    assert np.array_equal(outside_torso(avatar, outside), outside)


def test_head_nod_from_the_nonmanual_tier(avatar):
    document = (
        '<sigml><hns_sign gloss="yes"><hamnosys_nonmanual><hnm_head tag="NO"/></hamnosys_nonmanual>'
        "<hamnosys_manual><hamfist/><hamextfingeru/><hampalml/><hamchest/><hammoveo/></hamnosys_manual></hns_sign></sigml>"
    )
    (sign,) = parse_sigml(document).signs
    assert head_movement([item for tier in sign.nonmanual.values() for item in tier]) == "nod"
    signed = realize_signs(avatar, [sign])
    head = avatar.joint_index("skullbase")
    angles = 2.0 * np.arccos(np.clip(np.abs(signed.motion.rotations[:, head, 3]), 0.0, 1.0))
    assert angles.max() > 0.1
    assert angles[0] == pytest.approx(0.0) and angles[-1] == pytest.approx(0.0)


@pytest.mark.parametrize(
    ("items", "movement"),
    [((NonmanualItem("hnm_head", (("tag", "SH"),)),), "shake"), ((NonmanualItem("hnm_mouthpicture", (("picture", "pa"),)),), None)],
)
def test_head_movements(items, movement):
    assert head_movement(items) == movement


def test_unknown_site_fails_naming_the_sign(avatar):
    sign = Sign("NOWHERE", HandPosture(location=BodySite("elsewhere")))
    with pytest.raises(SignPlanningError, match="NOWHERE.*elsewhere"):
        plan_sign(avatar, sign)
