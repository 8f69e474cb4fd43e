"""MURML names map onto the shared HamNoSys feature values."""

import math

import pytest

from mura.murml import parse_utterance
from mura.murml_vocabulary import (
    parse_direction,
    parse_grid_location,
    parse_handshape,
    parse_palm_orientation,
)
from mura.values import FingerBend, GridLocation

R = 1 / math.sqrt(2)


@pytest.mark.parametrize(
    ("name", "vector"),
    [
        ("DirA", (0, 0, 1)),
        ("DirT", (0, 0, -1)),
        ("DirU", (0, 1, 0)),
        ("DirD", (0, -1, 0)),
        ("DirL", (1, 0, 0)),
        ("DirR", (-1, 0, 0)),
        ("DirUL", (R, R, 0)),
        ("DirDA", (0, -R, R)),
        ("DirAR", (-R, 0, R)),
    ],
)
def test_directions_in_the_avatar_frame(name, vector):
    assert parse_direction(name).vector == pytest.approx(vector)


@pytest.mark.parametrize("bad", ["Dir", "DirX", "DirUD", "Up"])
def test_bad_directions(bad):
    with pytest.raises(ValueError):
        parse_direction(bad)


@pytest.mark.parametrize(
    ("name", "normal"),
    [("PalmL", (1, 0, 0)), ("PalmR", (-1, 0, 0)), ("PalmU", (0, 1, 0)), ("PalmLD", (R, -R, 0)), ("DirAL", (R, 0, R))],
)
def test_palm_orientations(name, normal):
    assert parse_palm_orientation(name).direction == pytest.approx(normal)


@pytest.mark.parametrize(
    ("text", "basic", "thumb", "opening", "bends"),
    [
        ("BSfist", "fist", None, None, ()),
        ("ASLb", "flathand", "across", None, ()),
        ("ASL5", "finger2345", "out", None, ()),
        ("ASLcsmall", "ceeall", None, "narrow", ()),
        ("ASLo", "pinchall", None, None, ()),
        ("BSifinger(ThAcr)", "finger2", "across", None, ()),
        ("BSflat(FBround all o)(ThCpart o)", "flathand", "open", "normal",
         (FingerBend(("index", "middle", "ring", "pinky"), "round"),)),
        ("BSflat(FB2angle)(FB5roll)", "flathand", None, None,
         (FingerBend(("index",), "bent"), FingerBend(("pinky",), "dblhooked"))),
        ("BSimcfinger(FAbd)", "finger23spread", None, None, ()),
    ],
)
def test_handshapes(text, basic, thumb, opening, bends):
    shape = parse_handshape(text)
    assert (shape.basic, shape.thumb, shape.opening, shape.finger_bends) == (basic, thumb, opening, bends)
    assert shape.name == text


@pytest.mark.parametrize("bad", ["BSclaw", "BSflat(FBwiggle)", "BSflat(Zz)", "BSflat(FBround all xx)", "BSflat()", "BSflat(FB7round)"])
def test_bad_handshapes(bad):
    with pytest.raises(ValueError):
        parse_handshape(bad)


def test_grid_location_names_in_any_order_and_aliases():
    assert parse_grid_location("LocNorm LocCenter LocHip") == GridLocation("LocHip", "LocCCenter", "LocNorm")
    with pytest.raises(ValueError, match="same axis"):
        parse_grid_location("LocHip LocChest LocNorm")
    with pytest.raises(ValueError, match="names no height"):
        parse_grid_location("LocCenter LocNorm")
    with pytest.raises(ValueError, match="three names at most"):
        parse_grid_location("LocHip LocCenter LocNorm LocFar")


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("LocHip LocNorm", GridLocation("LocHip", "LocCCenter", "LocNorm")),  # the published realizer's two-name form
        ("LocChest LocCenterRight", GridLocation("LocChest", "LocCenterRight", "LocNorm")),
        ("LocShoulder", GridLocation("LocShoulder", "LocCCenter", "LocNorm")),
    ],
)
def test_grid_location_axes_left_out_take_their_defaults(text, expected):
    assert parse_grid_location(text) == expected


SEGMENT = """<utterance {unit}><specification>Take <time id="t1"/> this <time id="t2"/></specification>
<behaviorspec id="g"><gesture><affiliate onset="t1" end="t2"/><constraints><dynamic slot="HandLocation">
<{element} type="linear"><value type="start" name="LocChest LocCCenter LocNorm"/><value type="direction" name="DirR"/>
<value type="distance" name="{distance}"/></{element}></dynamic></constraints></gesture></behaviorspec></utterance>"""


@pytest.mark.parametrize(
    ("element", "unit", "distance", "metres"),
    [
        ("segment", "", "125.0", 0.125),  # the seed's dialect: millimetres
        ("dynamicElement", "", "40", 0.40),  # the published dialect: centimetres
        ("segment", 'unit="cm"', "12.5", 0.125),  # an explicit document unit wins
        ("dynamicElement", 'unit="m"', "0.4", 0.40),
        ("segment", "", "30cm", 0.30),  # a unit suffix wins over everything
        ("segment", "", "DistNorm", 0.20),
    ],
)
def test_length_unit_rule(element, unit, distance, metres):
    text = SEGMENT.format(element=element, unit=unit, distance=distance)
    utterance = parse_utterance(text)
    segment = utterance.behaviors[0].gesture.constraints.segments[0]
    assert segment.distance == pytest.approx(metres)
