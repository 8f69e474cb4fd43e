"""Hands placed against each other or against the body by a named part of the hand.

A symmetric sign whose hands change into a constellation (``hamreplace … hampinkyside
hamplus hampinkyside …``) brings both hands together in front of the body, each changing
its shape and orientation; a contact bracket naming a part of the hand (``hamchin
hamseqbegin hamtouch hamthumb hamfingertip hamseqend``) puts that part, not the palm, at
the site. Measured on the planned wrists and, for the contact, on the rendered skeleton.
"""

from __future__ import annotations

import numpy as np
import pytest
from sign_helpers import sign_from

from motor.body.kinematics import forward_kinematics
from motor.body.locations import resolve_location
from motor.signing.plan import SignPlan
from motor.signing.planning import plan_signs
from motor.signing.sequence import realize_signs
from mura.values import BodySite

#: Symmetric signs whose hands change into a constellation, as the DGS and ISL corpora
#: write them (``classroom`` is the Indian corpus's).
MEETINGS = {
    "classroom": "hamsymmlr hamceeall hamextfingeru hampalml hamtouch hamshouldertop hamparbegin hamreplace hamflathand "
    "hampalmu hamparbegin hampinkyside hamplus hampinkyside hamparend hamtouch hamparend",
    "palms together": "hamsymmlr hamflathand hamextfingero hampalml hamshoulders hamlrat hamparbegin hamreplace hamfist "
    "hamparbegin hampalm hamplus hampalm hamparend hamclose hamparend",
}
#: Least distance (m) each hand travels to the meeting (the hands of ``palms together``
#: start 13 cm apart), and the most by which the point halfway between the wrists may
#: miss the body's midline.
TRAVEL = 0.01
MIDLINE = 0.01


def _plan(avatar, symbols: str) -> SignPlan:
    (plan,) = plan_signs(avatar, [sign_from(symbols)])
    assert isinstance(plan, SignPlan), plan
    return plan


def _path(plan: SignPlan, arm: str) -> np.ndarray:
    moves = plan.moves.get((arm, "wrist_position"), ())
    return np.concatenate([plan.first[arm].wrist[None]] + [move.values for move in moves])


@pytest.mark.parametrize("gloss", sorted(MEETINGS))
def test_symmetric_hands_meet_halfway(avatar, gloss):
    plan = _plan(avatar, MEETINGS[gloss])
    right, left = _path(plan, "right"), _path(plan, "left")
    for arm, path in (("right", right), ("left", left)):
        assert np.linalg.norm(path[-1] - path[0]) > TRAVEL, f"{gloss}: the {arm} hand stays where it was"
    assert abs(0.5 * (right[-1, 0] + left[-1, 0])) < MIDLINE, f"{gloss}: the hands meet off the midline"


@pytest.mark.parametrize("gloss", sorted(MEETINGS))
def test_both_hands_change_shape_into_the_constellation(avatar, gloss):
    plan = _plan(avatar, MEETINGS[gloss])
    ends = {arm: plan.moves[(arm, "handshape")][-1].values[-1] for arm in ("right", "left")}
    starts = {arm: plan.first[arm].shape for arm in ("right", "left")}
    assert not np.allclose(ends["right"], starts["right"])
    np.testing.assert_allclose(ends["left"], ends["right"], atol=1e-9)


@pytest.mark.parametrize(
    ("part", "joint"),
    [("hamthumb hamfingertip", "r_thumb3"), ("hamindexfinger hamfingertip", "r_index3")],
)
def test_the_named_part_of_the_hand_makes_the_contact(avatar, part, joint):
    """The joint nearest the named part ends up nearer the chin than the palm does, and
    nearer than it would without the bracket."""
    shape = "hamflathand hamextfingeru hampalml hamchin"
    with_part = realize_signs(avatar, [sign_from(f"{shape} hamseqbegin hamtouch {part} hamseqend")])
    without = realize_signs(avatar, [sign_from(f"{shape} hamtouch")])
    chin = resolve_location(avatar, BodySite("chin"), "r")
    index = avatar.joint_index(joint)

    def distance(signed) -> float:
        (timing,) = signed.timings
        frame = int(np.searchsorted(signed.motion.times, 0.5 * (timing.ready + timing.end)))
        positions = forward_kinematics(avatar, signed.motion.rotations[frame : frame + 1]).positions[0]
        return float(np.linalg.norm(positions[index] - chin))

    assert distance(with_part) < distance(without) - 0.01, f"{joint}: no nearer the chin with the part named"
