"""The seed's Fig. 2 utterance, parsed and asserted field by field."""

import pytest

from mura.constraints import Arm, Dynamic, Parallel, SegmentKind, Static, Symmetrical
from mura.model import Affiliate
from mura.murml import load_utterance
from mura.values import (
    Direction,
    FingerBend,
    GridLocation,
    HandShape,
    PalmOrientation,
    PointLocation,
)


@pytest.fixture(scope="module")
def fig2(repo):
    return load_utterance(repo / "specs" / "utterances" / "fig2_take_this_bar.xml")


def test_chunks_and_time_tags(fig2):
    assert [chunk.text for chunk in fig2.chunks] == ["And now take this bar", "and make it this big."]
    first, second = fig2.chunks
    assert [(t.id, t.offset, t.chunkborder) for t in first.time_tags] == [("t1", 13, False), ("t2", 21, True)]
    assert [(t.id, t.offset, t.chunkborder) for t in second.time_tags] == [("t3", 12, False), ("t4", 21, False)]
    assert first.text[13:] == "this bar"
    assert second.text[12:] == "this big."
    assert {tag.chunk for tag in first.time_tags} == {0}
    assert {tag.chunk for tag in second.time_tags} == {1}


def test_deictic_gesture_by_function(fig2):
    behavior = fig2.behaviors[0]
    assert (behavior.id, behavior.kind, behavior.chunk) == ("gesture_1", "gesture", 0)
    assert isinstance(behavior.timing, Affiliate)
    assert (behavior.timing.onset, behavior.timing.end) == ("t1", "t2")
    gesture = behavior.gesture
    assert gesture.function.name == "refer_to_loc"
    assert dict(gesture.function.params) == {"refloc": "$Loc-Bar_1"}
    leaves = {leaf.slot: leaf for leaf in gesture.constraints.children}
    assert leaves["HandShape"].value.basic == "finger2"
    bar = PointLocation((-0.35, 0.05, 0.55))
    assert leaves["HandLocation"].value == bar
    assert (leaves["ExtFingerOrientation"].value, leaves["ExtFingerOrientation"].mode) == (bar, "pointTo")
    assert all(leaf.scope is Arm.RIGHT for leaf in gesture.constraints.children)


def test_iconic_gesture_constraint_tree(fig2):
    behavior = fig2.behaviors[1]
    assert (behavior.id, behavior.chunk) == ("gesture_2", 1)
    assert (behavior.timing.onset, behavior.timing.end) == ("t3", "t4")
    tree = behavior.gesture.constraints
    assert isinstance(tree, Symmetrical)
    assert tree.dominant is Arm.RIGHT
    assert tree.symmetry.name == "SymMS" and tree.symmetry.planes == frozenset("S")
    assert tree.center is None
    assert isinstance(tree.child, Parallel)
    shape, palm, finger, location = tree.child.children
    assert shape == Static(
        "HandShape",
        HandShape(
            basic="flathand",
            thumb="open",
            finger_bends=(FingerBend(("index", "middle", "ring", "pinky"), "round"),),
            opening="normal",
            name="BSflat(FBround all o)(ThCpart o)",
        ),
        Arm.RIGHT,
    )
    assert palm == Static("PalmOrientation", PalmOrientation((1.0, 0.0, 0.0), "PalmL"), Arm.RIGHT, "absolute")
    assert finger == Static("ExtFingerOrientation", Direction((0.0, 0.0, 1.0), "DirA"), Arm.RIGHT)
    assert isinstance(location, Dynamic) and location.slot == "HandLocation"
    (segment,) = location.segments
    assert segment.kind is SegmentKind.LINEAR
    assert segment.start == GridLocation("LocShoulder", "LocCenterRight", "LocNorm")
    assert segment.direction == Direction((-1.0, 0.0, 0.0), "DirR")
    assert segment.distance == pytest.approx(0.125)
    assert segment.end is None and segment.normal is None


def test_source_locations_point_into_the_file(fig2):
    behavior = fig2.behaviors[1]
    assert behavior.where.file.endswith("fig2_take_this_bar.xml")
    assert (behavior.where.line, behavior.where.column) == (17, 5)
    segment = behavior.gesture.constraints.child.children[3].segments[0]
    assert (segment.where.line, segment.where.column) == (27, 17)
