"""Every published MURML file of the shared corpus reads, with the values it writes."""

import pytest

from mura.check import check_file
from mura.constraints import Arm, Dynamic, Symmetrical, iter_leaves
from mura.model import AbsoluteTiming
from mura.murml import load_utterance
from mura.values import GridLocation

PUBLISHED = [
    "01_fo_reissverschluss.us",
    "04_lefu_petersilie.us",
    "05_bati_besen.us",
    "08_pewo_foehn.us",
    "12_denule_regal.us",
    "15_boreda_faden.us",
    "19_ruzanego_bruecke.us",
    "21_loeke_blume.us",
    "30_brido_handtuch.us",
    "41_tanedila_welle.us",
]


@pytest.mark.parametrize("name", PUBLISHED)
def test_published_file_checks_ok(shared, name):
    result = check_file(shared / "corpora" / "murml" / name)
    assert result.ok, [str(e) for e in result.errors]


def test_zip_fastener_strokes_are_centimetres(shared):
    utterance = load_utterance(shared / "corpora" / "murml" / "01_fo_reissverschluss.us")
    (behavior,) = utterance.behaviors
    assert behavior.timing == AbsoluteTiming(1.0, 3.0)
    dynamic = next(leaf for leaf in iter_leaves(behavior.gesture.constraints) if isinstance(leaf, Dynamic))
    assert dynamic.scope is Arm.RIGHT
    assert [segment.distance for segment in dynamic.segments] == pytest.approx([0.40] * 4)
    assert dynamic.segments[1].start == GridLocation("LocNeck", "LocCCenter", "LocNear")
    gaze = [leaf for leaf in iter_leaves(behavior.gesture.constraints) if leaf.slot == "GazeDirection"]
    # the published dialect's gaze vectors (x ahead, y up, z right) as directions in the avatar frame
    assert [leaf.value.vector for leaf in gaze] == [(0.0, 0.0, -1.0), (0.0, 0.0, 1.0)]
    assert gaze[1].mode == "pointTo"


def test_plain_sym_with_six_number_center(shared):
    utterance = load_utterance(shared / "corpora" / "murml" / "12_denule_regal.us")
    tree = utterance.behaviors[0].gesture.constraints
    assert isinstance(tree, Symmetrical)
    assert tree.symmetry.name == "Sym" and tree.symmetry.mirrors_sagittal
    assert tree.center == (0.0, 0.0, 0.0, 0.0, -25.0, 0.0)


def test_curve_extension_and_loc_center_alias(shared):
    utterance = load_utterance(shared / "corpora" / "murml" / "05_bati_besen.us")
    curves = [s for leaf in iter_leaves(utterance.behaviors[0].gesture.constraints) if isinstance(leaf, Dynamic) for s in leaf.segments]
    assert {segment.shape for segment in curves} == {"LeftC"}
    assert {segment.extent for segment in curves} == {1.0}
    assert GridLocation("LocHip", "LocCCenter", "LocNorm") in {segment.end for segment in curves}


def test_combined_mirror_planes(shared):
    utterance = load_utterance(shared / "corpora" / "murml" / "30_brido_handtuch.us")
    tree = utterance.behaviors[0].gesture.constraints
    assert tree.symmetry.planes == frozenset("ST")
