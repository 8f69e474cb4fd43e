"""The body: the hand stays outside the torso, errors that name the sign (head non-manuals: tests/nonmanual)."""

from __future__ import annotations

import numpy as np
import pytest
from sign_helpers import sign_from

from motor.body.collision import outside_torso
from motor.signing.plan import SignPlanningError
from motor.signing.planning import plan_sign
from motor.signing.sequence import realize_signs
from mura.signs import HandPosture, Sign
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


def test_unknown_site_fails_naming_the_sign(avatar):
    sign = Sign("NOWHERE", HandPosture(location=BodySite("elsewhere")))
    with pytest.raises(SignPlanningError, match="NOWHERE.*elsewhere"):
        plan_sign(avatar, sign)
