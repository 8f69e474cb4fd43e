"""SiGML documents: both sign forms, per-sign failures, nonmanual tiers, document-level errors."""

from __future__ import annotations

import pytest
from signing_helpers import hns_document

from mura.constraints import (
    Arm,
    Dynamic,
    Parallel,
    Repetition,
    Segment,
    SegmentKind,
    Sequence,
)
from mura.errors import SpecError
from mura.limits import Limits
from mura.sigml import parse_sigml
from mura.signs import HandConstellation, NonmanualItem, SignSymmetry
from mura.values import BetweenLocation, BodySite, Direction, HandShape

FIGURE_7 = """<?xml version="1.0" encoding="utf-8"?>
<sigml>
  <hamgestural_sign gloss="here">
    <sign_manual both_hands="true" lr_symm="true">
      <handconfig handshape="finger2" thumbpos="across" mainbend="bent"/>
      <handconfig extfidir="o" palmor="d"/>
      <location_bodyarm location="stomach" side="right_at"/>
      <rpt_motion repetition="fromstart">
        <directedmotion direction="d" size="small"/>
      </rpt_motion>
    </sign_manual>
  </hamgestural_sign>
</sigml>
"""
HERE = "hamsymmlr hamfinger2 hamthumbacrossmod hamfingerbendmod hamextfingero hampalmd hamstomach hamlrat hammoved hamsmallmod hamrepeatfromstart"


def gestural(manual: str, attributes: str = 'both_hands="false"') -> str:
    return f'<sigml><hamgestural_sign gloss="g"><sign_manual {attributes}>{manual}</sign_manual></hamgestural_sign></sigml>'


def only_sign(text: str):  # noqa: ANN201 - a Sign
    result = parse_sigml(text)
    assert result.failures == (), [str(f.error) for f in result.failures]
    (sign,) = result.signs
    return sign


def test_figure_7_gestural_here() -> None:
    sign = only_sign(FIGURE_7)
    assert sign.gloss == "here"
    assert sign.two_handed and sign.dominant is Arm.RIGHT
    assert sign.symmetry == SignSymmetry("lr", frozenset({"S"}))
    assert sign.posture.shape == HandShape("finger2", thumb="across", bending="bent", name="hamfinger2")
    assert sign.posture.ext_finger == Direction((0.0, 0.0, 1.0), "hamextfingero")
    assert sign.posture.palm is not None and sign.posture.palm.direction == (0.0, -1.0, 0.0)
    assert sign.posture.location == BodySite("stomach", side="lrat")
    assert sign.movement == Repetition(
        Dynamic("HandLocation", (Segment(SegmentKind.LINEAR, direction=Direction((0.0, -1.0, 0.0), "hammoved"), manner="targetted", size="small"),)),
        count=2,
        mode="fromstart",
    )
    assert sign.where is not None and (sign.where.line, sign.where.column) == (3, 3)


def test_gestural_and_tag_forms_of_here_agree() -> None:
    gestural_sign = only_sign(FIGURE_7)
    tag_sign = only_sign(hns_document("here", HERE))
    for attribute in ("posture", "symmetry", "movement", "two_handed", "dominant", "nondominant", "constellation"):
        assert getattr(gestural_sign, attribute) == getattr(tag_sign, attribute), attribute


def test_collection_root_and_isolated_failures() -> None:
    text = (
        '<sigml_collection count="3">\n'
        '<hns_sign gloss="one"><hamnosys_manual><hamfist/><hamextfingero/><hampalmd/></hamnosys_manual></hns_sign>\n'
        '<hns_sign gloss="two"><hamnosys_manual><hamfist/><hamnosuch/></hamnosys_manual></hns_sign>\n'
        '<hns_sign gloss="three"><hamnosys_manual><hamflathand/><hamUpperarm/></hamnosys_manual></hns_sign>\n'
        "</sigml_collection>"
    )
    result = parse_sigml(text, file="c.sigml")
    assert [s.gloss for s in result.signs] == ["one", "three"]
    assert result.signs[1].posture.location == BodySite("upperarm")
    (failure,) = result.failures
    assert (failure.gloss, failure.index) == ("two", 2 - 1)
    assert failure.error.message == "sign 'two': unknown HamNoSys symbol 'hamnosuch' at position 1"
    assert (failure.error.file, failure.error.line, failure.error.column) == ("c.sigml", 3, 50)


def test_empty_manual_stream_fails_alone() -> None:
    result = parse_sigml(hns_document("blank", ""), file="e.sigml")
    (failure,) = result.failures
    assert failure.error.message == "sign 'blank': empty manual stream"
    assert failure.error.line == 1


def test_misplaced_tag_reports_line_and_column_of_the_tag() -> None:
    text = '<sigml>\n<hns_sign gloss="m"><hamnosys_manual>\n  <hamfist/><hamextfingero/><hampalmd/>\n  <hamcircleo/> <hamarcl/>\n</hamnosys_manual></hns_sign></sigml>'
    (failure,) = parse_sigml(text).failures
    assert failure.error.message == "sign 'm': misplaced symbol hamarcl at position 4: hamarcl cannot modify this movement"
    assert (failure.error.line, failure.error.column) == (4, 17)


def test_nonmanual_tiers_are_kept_raw() -> None:
    sign = only_sign(hns_document("hello", "hamflathand hamextfingeru hampalmd hamforehead hammoveo", '<hnm_mouthpicture picture="hVlU"/>'))
    assert sign.nonmanual == {"mouthpicture": (NonmanualItem("hnm_mouthpicture", (("picture", "hVlU"),)),)}


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("<sigml><hns_sign>", "malformed XML: Premature end of data"),
        ("<signs/>", "root element <signs> is not <sigml> or <sigml_collection>"),
        ('<!DOCTYPE sigml [<!ENTITY x "y">]><sigml/>', "entity declarations are not allowed"),
    ],
)
def test_document_errors(text: str, message: str) -> None:
    with pytest.raises(SpecError, match=message):
        parse_sigml(text, file="d.sigml")


def test_oversized_document_is_refused() -> None:
    with pytest.raises(SpecError, match="more than the limit of 100"):
        parse_sigml("<sigml>" + " " * 200 + "</sigml>", limits=Limits(max_input_bytes=100))


def test_unknown_element_in_document_is_a_sign_failure() -> None:
    result = parse_sigml("<sigml><hns_sign gloss='a'><hamnosys_manual><hamfist/></hamnosys_manual></hns_sign><oops/></sigml>")
    assert len(result.signs) == 1
    assert "unexpected element <oops>" in result.failures[0].error.message


def test_gestural_circle_with_size_and_start() -> None:
    sign = only_sign(gestural('<handconfig handshape="flathand" extfidir="u" palmor="l"/><circularmotion axis="o" start="u" size="big" manner="slow"/>'))
    assert sign.movement == Dynamic(
        "HandLocation",
        (Segment(SegmentKind.CIRCLE, normal=Direction((0.0, 0.0, 1.0), "hamcircleo"), manner="slow", size="large", modifiers=("start=u",)),),
    )
    assert not sign.two_handed


def test_gestural_between_values_and_curve() -> None:
    sign = only_sign(
        gestural(
            '<handconfig handshape="finger2345" second_handshape="flathand" extfidir="u" palmor="l" second_palmor="ul"/>'
            '<location_bodyarm location="shoulders" second_location="chest" contact="touch"/>'
            '<directedmotion direction="u" curve="l"/>'
        )
    )
    assert sign.posture.shape == HandShape("finger2345", name="hamfinger2345", between=HandShape("flathand", name="hamflathand"))
    assert sign.posture.palm is not None and sign.posture.palm.name == "hampalml hambetween hampalmul"
    assert sign.posture.location == BetweenLocation(BodySite("shoulders", proximity="touch"), BodySite("chest", proximity="touch"))
    assert isinstance(sign.movement, Dynamic)
    assert sign.movement.segments[0].kind is SegmentKind.CURVE and sign.movement.segments[0].shape == "arcl"


def test_gestural_split_motion_constellation_and_sequence() -> None:
    sign = only_sign(
        gestural(
            '<split_handconfig><handconfig handshape="flathand" extfidir="ol" palmor="d"/>'
            '<handconfig handshape="fist" extfidir="or" palmor="u"/></split_handconfig>'
            '<handconstellation contact="touch"><location_hand location="palm"/><location_hand location="handback"/>'
            '<location_bodyarm location="chest"/></handconstellation>'
            '<seq_motion><split_motion><directedmotion direction="d"/><nomotion/></split_motion>'
            '<wristmotion motion="twisting" size="small"/></seq_motion>',
            'both_hands="true"',
        )
    )
    assert sign.nondominant is not None and sign.nondominant.shape == HandShape("fist", name="hamfist")
    assert sign.constellation == HandConstellation(BodySite("palm"), BodySite("handback"), "touch", BodySite("chest"))
    assert isinstance(sign.movement, Sequence)
    split, twist = sign.movement.children
    assert isinstance(split, Parallel)
    assert [leaf.scope for leaf in split.children] == [Arm.RIGHT, Arm.LEFT]  # type: ignore[union-attr]
    assert twist == Dynamic("PalmOrientation", (Segment(SegmentKind.LINEAR, shape="twisting", manner="targetted", size="small"),))
    assert sign.symmetry is None


def test_gestural_target_motion_changes_posture() -> None:
    sign = only_sign(gestural('<handconfig handshape="fist" extfidir="o" palmor="d"/><tgt_motion><directedmotion direction="u"/><handconfig handshape="flathand"/></tgt_motion>'))
    assert isinstance(sign.movement, Parallel)
    move, change = sign.movement.children
    assert isinstance(change, Dynamic) and change.slot == "HandShape"
    assert change.segments[0].end == HandShape("flathand", name="hamflathand")


@pytest.mark.parametrize(
    ("manual", "message"),
    [
        ("", "<sign_manual>: empty sign"),
        ('<handconfig handshape="blob"/>', "<handconfig>: unknown handshape 'blob'"),
        ('<handconfig handshape="fist" colour="red"/>', "<handconfig>: unknown attribute 'colour'"),
        ('<handconfig handshape="fist" extfidir="q"/>', "extfidir='q': unknown direction letter 'q'"),
        ('<handconfig handshape="fist"/><teleport/>', "<teleport>: unknown element in <sign_manual>"),
        ('<handconfig handshape="fist"/><rpt_motion repetition="forever"><nomotion/></rpt_motion>', "unknown repetition 'forever'"),
        ('<handconfig handshape="fist"/><directedmotion direction="u"/><handconfig handshape="fist"/>', "a posture after the movement"),
        ('<handconfig handshape="fist"/><seq_motion/>', "<seq_motion>: has no motion inside"),
    ],
)
def test_gestural_errors(manual: str, message: str) -> None:
    result = parse_sigml(gestural(manual))
    (failure,) = result.failures
    assert failure.gloss == "g"
    assert message in failure.error.message
    assert failure.error.line == 1


def test_bad_boolean_attribute() -> None:
    result = parse_sigml(gestural('<handconfig handshape="fist"/>', 'both_hands="yes"'))
    assert "both_hands='yes' (expected true or false)" in result.failures[0].error.message


def test_gestural_nonmanual_tiers_and_nonmanual_motion() -> None:
    sign = only_sign(
        '<sigml><hamgestural_sign gloss="g"><sign_nonmanual><head_tier><head_movement movement="NO"/></head_tier></sign_nonmanual>'
        '<sign_manual><handconfig handshape="fist" extfidir="o" palmor="d"/>'
        '<seq_motion><directedmotion direction="u"/><nonman_motion><mouth_picture picture="pa"/></nonman_motion></seq_motion>'
        "</sign_manual></hamgestural_sign></sigml>"
    )
    assert set(sign.nonmanual) == {"head_tier", "mouth_picture"}
    assert sign.nonmanual["head_tier"] == (NonmanualItem("head_movement", (("movement", "NO"),)),)
    assert sign.nonmanual["mouth_picture"] == (NonmanualItem("mouth_picture", (("picture", "pa"),)),)
    assert isinstance(sign.movement, Sequence) and len(sign.movement.children) == 1


@pytest.mark.parametrize(
    ("manual", "message"),
    [
        ('<handconfig handshape="fist"/><directedmotion direction="u" speed="9"/>', "<directedmotion>: unknown attribute 'speed'"),
        ('<handconfig handshape="fist"/><location_bodyarm location="chest" height="2"/>', "<location_bodyarm>: unknown attribute 'height'"),
        ('<handconfig handshape="fist"/><directedmotion direction="u" size="huge"/>', "unknown size 'huge'"),
        ('<handconfig handshape="fist"/><wristmotion motion="flapping"/>', "unknown motion 'flapping'"),
        ('<handconfig handshape="fist"/><split_motion><nomotion/></split_motion>', "has 1 parts (expected two"),
    ],
)
def test_gestural_motion_errors(manual: str, message: str) -> None:
    (failure,) = parse_sigml(gestural(manual)).failures
    assert message in failure.error.message
