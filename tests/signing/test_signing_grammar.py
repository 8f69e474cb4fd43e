"""The HamNoSys manual-stream grammar: hand-written signs with known structure, and bad input."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from signing_helpers import hns_document, sign_of

from mura.constraints import (
    Arm,
    Dynamic,
    Parallel,
    Repetition,
    Segment,
    SegmentKind,
    Sequence,
    Static,
)
from mura.errors import SpecError
from mura.hamnosys import hamnosys_string, parse_hamnosys
from mura.hamnosys_symbols import vocabulary
from mura.sigml import parse_sigml
from mura.signs import HandConstellation, SignSymmetry
from mura.values import BetweenLocation, BodySite, Direction, FingerBend, HandShape

HERE = "hamsymmlr hamfinger2 hamthumbacrossmod hamfingerbendmod hamextfingero hampalmd hamstomach hamlrat hammoved hamsmallmod hamrepeatfromstart"
DOWN = Direction((0.0, -1.0, 0.0), "hammoved")


def test_here_as_tags_field_by_field() -> None:
    result = parse_sigml(hns_document("here", HERE))
    assert result.failures == ()
    (sign,) = result.signs
    assert sign.gloss == "here"
    assert sign.dominant is Arm.RIGHT
    assert sign.two_handed
    assert sign.symmetry == SignSymmetry("lr", frozenset({"S"}))
    assert sign.posture.shape == HandShape("finger2", thumb="across", bending="bent", name="hamfinger2")
    assert sign.posture.ext_finger == Direction((0.0, 0.0, 1.0), "hamextfingero")
    assert sign.posture.palm is not None and sign.posture.palm.direction == (0.0, -1.0, 0.0)
    assert sign.posture.location == BodySite("stomach", side="lrat")
    assert sign.movement == Repetition(
        Dynamic("HandLocation", (Segment(SegmentKind.LINEAR, direction=DOWN, manner="targetted", size="small"),)),
        count=2,
        mode="fromstart",
    )
    assert sign.symbols == tuple(HERE.split())
    assert sign.where is not None and sign.where.line == 1


def test_unicode_string_equals_tag_stream() -> None:
    from_tags = parse_sigml(hns_document("here", HERE)).signs[0]
    text = hamnosys_string(HERE.split())
    assert all(0xE000 <= ord(c) <= 0xE0F1 for c in text)
    assert parse_hamnosys(text, gloss="here") == from_tags


def test_circle_with_clock_positions_size_and_manner() -> None:
    sign = sign_of("hamflathand hamextfingeru hampalml hamchest hamcircleo hamclocku hamclockd hamlargemod hamfast")
    assert sign.movement == Dynamic(
        "HandLocation",
        (
            Segment(
                SegmentKind.CIRCLE,
                normal=Direction((0.0, 0.0, 1.0), "hamcircleo"),
                manner="fast",
                size="large",
                modifiers=("start=u", "end=d"),
            ),
        ),
    )


def test_replace_changes_shape_and_palm_from_the_current_posture() -> None:
    sign = sign_of("hamfist hamextfingero hampalmd hamchest hamreplace hamflathand hampalmu")
    fist = HandShape("fist", name="hamfist")
    assert sign.posture.shape == fist
    movement = sign.movement
    assert isinstance(movement, Parallel)
    shape, palm = movement.children
    assert isinstance(shape, Dynamic) and isinstance(palm, Dynamic)
    assert shape.slot == "HandShape"
    assert shape.segments[0].start == fist
    assert shape.segments[0].end == HandShape("flathand", name="hamflathand")
    assert palm.slot == "PalmOrientation"
    assert palm.segments[0].start.direction == (0.0, -1.0, 0.0)  # type: ignore[union-attr]
    assert palm.segments[0].end.direction == (0.0, 1.0, 0.0)  # type: ignore[union-attr]


def test_two_handed_constellation() -> None:
    sign = sign_of(
        "hamparbegin hamflathand hamextfingerol hampalmd hamplus hamflathand hamextfingeror hampalmu hamparend "
        "hamparbegin hampalm hamplus hamhandback hamparend hamtouch hamchest hammoved"
    )
    assert sign.two_handed and sign.symmetry is None
    assert sign.posture.shape == HandShape("flathand", name="hamflathand")
    assert sign.nondominant is not None and sign.nondominant.palm is not None
    assert sign.nondominant.palm.direction == (0.0, 1.0, 0.0)
    assert sign.constellation == HandConstellation(BodySite("palm"), BodySite("handback"), "touch", BodySite("chest"))


def test_between_shape_and_finger_bends() -> None:
    sign = sign_of("hamfinger2345 hambetween hamflathand hamfingerstraightmod hamextfingeru hampalml hamchest")
    assert sign.posture.shape == HandShape(
        "finger2345", name="hamfinger2345", between=HandShape("flathand", bending="straight", name="hamflathand")
    )
    bent = sign_of("hamfinger2345 hamthumbacrossmod hamindexfinger hamfingerbendmod hammiddlefinger hamringfinger hamfingerhookmod hamextfingeru hampalml")
    assert bent.posture.shape is not None
    assert bent.posture.shape.finger_bends == (FingerBend(("index",), "bent"), FingerBend(("middle", "ring"), "hooked"))
    assert bent.posture.shape.thumb == "across"


def test_selected_fingers_and_thumb_contact_inside_a_shape() -> None:
    sign = sign_of("hamfinger2 hampinky hamextfingeru hampalml hamshoulders")
    assert sign.posture.shape is not None and sign.posture.shape.extended == ("pinky",)
    fist = sign_of("hamfist hammiddlefinger hambetween hamringfinger hamextfingeru hampalml")
    assert fist.posture.shape is not None and fist.posture.shape.contact == ("middle", "between", "ring")


def test_between_orientation_and_location() -> None:
    sign = sign_of("hamflathand hamextfingeru hampalml hambetween hampalmul hamshoulders hambetween hamchest hamtouch")
    palm = sign.posture.palm
    assert palm is not None and palm.name == "hampalml hambetween hampalmul"
    assert palm.direction == pytest.approx((0.9238795, 0.3826834, 0.0))
    assert sign.posture.location == BetweenLocation(BodySite("shoulders"), BodySite("chest", proximity="touch"))


def test_two_hands_moving_differently_are_scoped_to_each_arm() -> None:
    sign = sign_of("hamflathand hamextfingero hampalmd hamchest hamparbegin hammoved hamplus hammoveu hamsmallmod hamparend")
    movement = sign.movement
    assert isinstance(movement, Parallel)
    dominant, other = movement.children
    assert isinstance(dominant, Dynamic) and dominant.scope is Arm.RIGHT
    assert isinstance(other, Dynamic) and other.scope is Arm.LEFT and other.segments[0].size == "small"


@pytest.mark.parametrize(
    ("symbols", "expected"),
    [
        ("hamrepeatfromstart", ("fromstart", 2, False)),
        ("hamrepeatfromstartseveral", ("fromstart", 3, False)),
        ("hamrepeatcontinue", ("continue", 2, False)),
        ("hamrepeatcontinueseveral", ("continue", 3, False)),
        ("hamrepeatreverse hamalternatingmotion", ("reverse", 2, True)),
    ],
)
def test_repetitions(symbols: str, expected: tuple[str, int, bool]) -> None:
    sign = sign_of(f"hamfist hamextfingero hampalmd hammoveu {symbols}")
    assert isinstance(sign.movement, Repetition)
    assert (sign.movement.mode, sign.movement.count, sign.movement.alternating) == expected


@pytest.mark.parametrize(
    ("symbol", "slot", "kind"),
    [
        ("hamnodding", "ExtFingerOrientation", SegmentKind.LINEAR),
        ("hamswinging", "ExtFingerOrientation", SegmentKind.LINEAR),
        ("hamtwisting", "PalmOrientation", SegmentKind.LINEAR),
        ("hamfingerplay", "HandShape", SegmentKind.LINEAR),
        ("hamstircw", "HandLocation", SegmentKind.CIRCLE),
        ("hamnomotion", "HandLocation", SegmentKind.LINEAR),
    ],
)
def test_local_movements_use_the_documented_slots(symbol: str, slot: str, kind: SegmentKind) -> None:
    sign = sign_of(f"hamfinger2345 hamextfingeru hampalml {symbol} hamslow")
    assert sign.movement == Dynamic(slot, (Segment(kind, shape=symbol[3:], manner="slow"),))


def test_arc_makes_a_curve_and_a_target_location_ends_it() -> None:
    sign = sign_of("hamfinger2 hamextfingeru hampalml hamchest hammoveu hamarcl hamchin hamtouch")
    movement = sign.movement
    assert isinstance(movement, Dynamic)
    segment = movement.segments[0]
    assert segment.kind is SegmentKind.CURVE and segment.shape == "arcl"
    assert segment.end == BodySite("chin", proximity="touch")


def test_sequence_fusion_and_manner_after_a_bracket() -> None:
    sign = sign_of("hamfist hamextfingero hampalmd hamseqbegin hammoveu hammoved hamseqend hamtense")
    movement = sign.movement
    assert isinstance(movement, Sequence) and len(movement.children) == 2
    assert all(isinstance(c, Dynamic) and c.segments[0].manner == "tense" for c in movement.children)


def test_symmetry_modifiers() -> None:
    sign = sign_of("hamsymmlr hamlargemod hamfingerstraightmod hamalternatingmotion hamflathand hamextfingero hampalmd hammoveu")
    assert sign.symmetry == SignSymmetry("lr", frozenset({"S", "T", "F"}), alternating=True)
    par = sign_of("hamsymmpar hamflathand hamextfingero hampalmd hammoveu")
    assert par.symmetry == SignSymmetry("par") and par.symmetry.to_model().planes == frozenset()


def test_nondominant_hand_and_etc() -> None:
    sign = sign_of(
        "hamparbegin hamflathand hamextfingerol hampalmdl hamplus hamnondominant hametc hamextfingeror hampalmd hamparend hamchest hammoved"
    )
    assert sign.nondominant is not None and sign.nondominant.etc and sign.nondominant.shape is None
    assert sign.nondominant.ext_finger is not None and sign.nondominant.ext_finger.name == "hamextfingeror"


def test_first_alternative_is_read_and_annotations_are_skipped() -> None:
    sign = sign_of("hamversion40 hamaltbegin hamfinger2 hammetaalt hamfist hamaltend hamextfingeru hamspace hampalml hamchest")
    assert sign.posture.shape == HandShape("finger2", name="hamfinger2")
    assert sign.symbols[0] == "hamversion40"


def test_location_only_action_is_static() -> None:
    sign = sign_of("hamfinger2 hamextfingeru hampalml hamchest hammoveo hamseqbegin hamtouch hamchin hamseqend")
    assert isinstance(sign.movement, Sequence)
    assert sign.movement.children[1] == Sequence((Static("HandLocation", BodySite("chin", proximity="touch")),))


@pytest.mark.parametrize(
    ("symbols", "message"),
    [
        ("", "sign 'bad': empty manual stream"),
        ("hamsymmlr", "stream ends early at position 1: expected a hand shape, orientation or location"),
        (
            "hamfinger2 hamextfingero hampalmd hamchest hamparbegin hammoved",
            "stream ends early at position 6: expected hamparend to close hamparbegin at position 4",
        ),
        (
            "hamfinger2 hamextfingero hampalmd hamchest hamreplace",
            "stream ends early at position 5: expected the new hand shape, orientation or location after hamreplace",
        ),
        (
            "hamfinger2 hamextfingero hampalmd hamchest hamseqbegin hammoved hamparend",
            "unexpected symbol hamparend at position 6: expected hamseqend to close hamseqbegin at position 4",
        ),
        (
            "hamfinger2 hamextfingero hampalmd hamchest hammoved hamseqend",
            "misplaced symbol hamseqend at position 5: hamseqend without a matching hamseqbegin",
        ),
        (
            "hamfinger2 hamextfingero hampalmd hamchest hamcircleo hamarcl",
            "misplaced symbol hamarcl at position 5: hamarcl cannot modify this movement",
        ),
        ("hammoved hamfinger2", "unexpected symbol hammoved at position 0: expected a hand shape, orientation or location"),
        (
            "hamfinger2 hamextfingero hampalmd hamrepeatfromstart",
            "unexpected symbol hamrepeatfromstart at position 3: expected a movement before the repetition",
        ),
        (
            "hamfinger2 hamaltbegin hamextfingero hampalmd",
            "hamaltbegin at position 1 is never closed by hamaltend",
        ),
        (
            "hamfinger2 hamextfingero hampalmd hamseqbegin hamseqend",
            "empty hamseqbegin … hamseqend at position 3",
        ),
    ],
)
def test_bad_streams_name_sign_symbol_and_position(symbols: str, message: str) -> None:
    with pytest.raises(SpecError) as caught:
        sign_of(symbols, gloss="bad")
    assert message in caught.value.message
    assert "'bad'" in caught.value.message


def test_error_position_is_the_column_of_the_symbol_in_a_string() -> None:
    with pytest.raises(SpecError) as caught:
        sign_of("hamfinger2 hamextfingero hampalmd hamchest hamcircleo hamarcl")
    assert (caught.value.line, caught.value.column) == (1, 6)


def test_character_outside_hamnosys_is_refused() -> None:
    with pytest.raises(SpecError, match=r"character U\+0078 at position 1 is not a HamNoSys symbol"):
        parse_hamnosys("\ue000x", gloss="u")


def test_deep_nesting_is_refused_not_a_recursion_error() -> None:
    with pytest.raises(SpecError, match="nested more than"):
        sign_of("hamfist hamextfingero hampalmd " + "hamseqbegin " * 200 + "hammoved" + " hamseqend" * 200)


VALID_STREAMS = (
    HERE,
    "hamparbegin hamflathand hamextfingerol hampalmd hamplus hamflathand hamextfingeror hampalmu hamparend "
    "hamparbegin hampalm hamplus hamhandback hamparend hamtouch hamchest hammoved",
    "hamfist hamextfingero hampalmd hamchest hamreplace hamflathand hampalmu hamrepeatfromstart",
    "hamsymmpar hamflathand hamextfingero hampalmd hamchest hamparbegin hammoved hamarcl hamreplace hampalmu hamparend",
    "hamfinger2 hamextfingeru hampalml hamchest hamseqbegin hammoveu hamcircleo hamclocku hamseqend hamfast",
)
_NAMES = tuple(s.name for s in vocabulary().symbols)


@settings(max_examples=400, deadline=None, derandomize=True)
@given(
    base=st.sampled_from(VALID_STREAMS),
    edits=st.lists(
        st.tuples(st.sampled_from(("insert", "delete", "replace")), st.integers(0, 40), st.sampled_from(_NAMES)),
        min_size=1,
        max_size=4,
    ),
)
def test_mutated_streams_raise_nothing_but_spec_error(base: str, edits: list[tuple[str, int, str]]) -> None:
    symbols = base.split()
    for operation, index, name in edits:
        index = index % (len(symbols) + 1)
        if operation == "insert":
            symbols.insert(index, name)
        elif symbols and index < len(symbols):
            if operation == "delete":
                del symbols[index]
            else:
                symbols[index] = name
    try:
        sign_of(" ".join(symbols))
    except SpecError:
        pass


def test_sign_made_by_the_nondominant_hand() -> None:
    sign = sign_of("hamnondominant hamflathand hamextfingeru hampalml hamchest hammoved")
    assert sign.dominant is Arm.LEFT and not sign.two_handed


def test_whole_sign_as_one_constraint_tree() -> None:
    from mura.constraints import Symmetrical, Symmetry, iter_leaves

    sign = sign_of(HERE)
    tree = sign.to_constraint()
    assert isinstance(tree, Symmetrical)
    assert tree.dominant is Arm.RIGHT and tree.symmetry == Symmetry(frozenset({"S"}), "SymS")
    assert isinstance(tree.child, Sequence)
    posture, movement = tree.child.children
    assert movement == sign.movement
    assert [leaf.slot for leaf in iter_leaves(posture)] == ["HandShape", "ExtFingerOrientation", "PalmOrientation", "HandLocation"]
    two = sign_of("hamparbegin hamflathand hamextfingerol hampalmd hamplus hamfist hamextfingeror hampalmu hamparend hamchest")
    leaves = list(iter_leaves(two.to_constraint()))
    assert [leaf.scope for leaf in leaves] == [Arm.RIGHT] * 4 + [Arm.LEFT] * 3


@pytest.mark.parametrize(
    ("tail", "message"),
    [
        ("hammoved" + " hamrepeatfromstart" * 40, "more than 32 repetitions of one movement"),
        ("hamchest" + " hambetween hamchest" * 3, "unexpected symbol hambetween at position 6"),
    ],
)
def test_runaway_streams_are_spec_errors(tail: str, message: str) -> None:
    with pytest.raises(SpecError, match=message):
        sign_of("hamfist hamextfingero hampalmd " + tail)


def test_between_opposite_directions_is_an_error() -> None:
    with pytest.raises(SpecError, match="misplaced symbol hamextfingerd at position 3: hamextfingerd is opposite to hamextfingeru"):
        sign_of("hamfist hamextfingeru hambetween hamextfingerd hampalml")
