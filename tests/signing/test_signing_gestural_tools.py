"""Gestural SiGML as public tools write it: signs written for the test, and bad variants.

Hand shapes and thumb positions by their gestural names (``flat``, ``cee12open``,
``opposed``), features split over several ``<handconfig>``, targets wrapping
``<changeposture/>``, hand constellations and split locations as targets, the part of the
hand at a location (``<location_hand>`` inside a location), finger parts without
``finger`` (``midjoint``), ``armextended`` and ``second_side``.
"""

from __future__ import annotations

import pytest

from motor.signing.plan import SignPlan
from motor.signing.planning import plan_signs
from mura.constraints import Arm, Dynamic, Parallel, iter_leaves
from mura.sigml import parse_sigml
from mura.values import BetweenLocation, BodySite, HandShape


def _document(manual: str, attributes: str = "") -> str:
    return f'<sigml><hamgestural_sign gloss="test"><sign_manual {attributes}>{manual}</sign_manual></hamgestural_sign></sigml>'


def _sign(manual: str, attributes: str = ""):
    result = parse_sigml(_document(manual, attributes), file="test.sigml")
    assert result.failures == (), [str(f.error) for f in result.failures]
    return result.signs[0]


def _renders(avatar, sign) -> SignPlan:
    (plan,) = plan_signs(avatar, [sign])
    assert isinstance(plan, SignPlan), plan
    return plan


@pytest.mark.parametrize(
    ("attributes", "shape"),
    [
        ('handshape="flat"', HandShape("flathand", name="hamflathand")),
        ('handshape="flat" thumbpos="opposed"', HandShape("flathand", thumb="open", name="hamflathand")),
        ('handshape="cee12open"', HandShape("ceeopen", name="hamceeopen")),
        ('handshape="finger2" mainbend="hooked" thumbpos="across"', HandShape("finger2", thumb="across", bending="hooked", name="hamfinger2")),
    ],
)
def test_gestural_hand_shape_names(attributes: str, shape: HandShape) -> None:
    sign = _sign(f'<handconfig {attributes}/><handconfig extfidir="u"/><handconfig palmor="l"/><location_bodyarm location="chest"/>')
    assert sign.posture.shape == shape


def test_features_split_over_several_handconfigs_and_second_shape(avatar) -> None:
    sign = _sign(
        '<handconfig handshape="fist" second_handshape="finger2345" second_thumbpos="out"/>'
        '<handconfig extfidir="ul" second_extfidir="u"/><handconfig palmor="d" second_palmor="l"/>'
        '<location_bodyarm contact="close" location="shoulders" side="left_at"/><wristmotion motion="nodding" size="small"/>'
    )
    assert sign.posture.shape is not None and sign.posture.shape.between is not None
    assert sign.posture.shape.between.thumb == "out"
    assert sign.posture.location == BodySite("shoulders", side="lrat", proximity="close")
    _renders(avatar, sign)


def test_target_wrapping_changeposture(avatar) -> None:
    sign = _sign(
        '<handconfig handshape="finger23" thumbpos="across"/><handconfig extfidir="il" palmor="dr"/>'
        '<location_bodyarm contact="close" location="neck" side="right_at"/>'
        '<par_motion><directedmotion direction="do" size="small"/>'
        '<tgt_motion><changeposture/><handconfig extfidir="ol" palmor="d" second_palmor="dl"/></tgt_motion></par_motion>'
    )
    slots = sorted(leaf.slot for leaf in iter_leaves(sign.movement))
    assert slots == ["ExtFingerOrientation", "HandLocation", "PalmOrientation"]
    _renders(avatar, sign)


def test_split_location_with_hand_parts_second_side_and_arm_extended(avatar) -> None:
    sign = _sign(
        '<handconfig handshape="finger2"/><handconfig extfidir="u"/>'
        '<split_handconfig><handconfig palmor="d"/><handconfig palmor="u"/></split_handconfig>'
        '<split_location><location_bodyarm contact="close" location="shoulders" second_location="chest" side="right_at">'
        '<location_hand location="palm"/></location_bodyarm>'
        '<location_bodyarm contact="armextended" location="shoulders" second_location="chest" second_side="left_at"/></split_location>',
        'both_hands="true" lr_symm="true"',
    )
    location = sign.posture.location
    assert isinstance(location, BetweenLocation) and isinstance(location.first, BodySite)
    assert location.first.hand_part == BodySite("palm")
    assert sign.nondominant is not None and isinstance(sign.nondominant.location, BetweenLocation)
    assert sign.nondominant.location.first.proximity == "armextended"
    _renders(avatar, sign)


def test_hand_constellation_and_finger_part_as_targets(avatar) -> None:
    sign = _sign(
        '<split_handconfig><handconfig handshape="fist"/><handconfig handshape="flat"/></split_handconfig>'
        '<split_handconfig><handconfig extfidir="ol" palmor="d"/><handconfig extfidir="or" palmor="u"/></split_handconfig>'
        '<location_bodyarm location="chest"/>'
        '<tgt_motion><handconstellation contact="touch"><location_hand digits="3" location="midjoint" side="dorsal"/>'
        '<location_hand location="palm"/></handconstellation></tgt_motion>'
        '<tgt_motion><changeposture/><location_hand digits="2"/></tgt_motion>',
        'both_hands="true"',
    )
    first, second = sign.movement.children
    assert isinstance(first, Dynamic) and first.scope is Arm.RIGHT
    target = first.segments[0].end
    assert target == BodySite("palm", proximity="touch", hand_part=BodySite("fingermidjoint", finger="middle"))
    assert isinstance(second, Dynamic) and second.segments[0].end == BodySite("finger", finger="index")
    _renders(avatar, sign)


def test_split_targets_are_scoped_to_each_arm() -> None:
    sign = _sign(
        '<handconfig handshape="flat"/><handconfig extfidir="o" palmor="d"/><location_bodyarm location="chest"/>'
        '<tgt_motion><split_location><location_bodyarm location="neck"/><location_bodyarm location="stomach"/></split_location></tgt_motion>',
        'both_hands="true" lr_symm="true"',
    )
    assert isinstance(sign.movement, Parallel)
    assert [leaf.scope for leaf in sign.movement.children] == [Arm.RIGHT, Arm.LEFT]


@pytest.mark.parametrize(
    ("manual", "message"),
    [
        ('<handconfig handshape="flatt"/>', "unknown handshape 'flatt'"),
        ('<handconfig handshape="flat" thumbpos="sideways"/>', "unknown thumbpos 'sideways'"),
        ('<handconfig handshape="flat"/><location_bodyarm location="knee"/>', "unknown location 'knee'"),
        ('<handconfig handshape="flat"/><location_bodyarm location="chest" contact="glued"/>', "unknown contact 'glued'"),
        ('<handconfig handshape="flat"/><location_bodyarm location="chest" side="dorsal"/>', "unknown side 'dorsal'"),
        ('<handconfig handshape="flat"/><location_hand location="palm" digits="7"/>', "digits='7'"),
        ('<handconfig handshape="flat"/><location_bodyarm location="chest"><handconfig/></location_bodyarm>', "only <location_hand>"),
        ('<handconfig handshape="flat"/><tgt_motion><changeposture/></tgt_motion>', "has no target or motion inside"),
        ('<handconfig handshape="flat"/><tgt_motion manner="sloppy"><handconfig palmor="u"/></tgt_motion>', "unknown manner 'sloppy'"),
    ],
)
def test_bad_gestural_signs_are_refused_with_place_and_reason(manual: str, message: str) -> None:
    result = parse_sigml(_document(manual), file="bad.sigml")
    (failure,) = result.failures
    assert message in failure.error.message
    assert failure.error.file == "bad.sigml" and failure.error.line == 1 and failure.error.column > 1
