"""Published gesture lexicons (``<gestures>``) and symbol tables (``<hns>``), written for
the test: entries with and without ``<function>``, declared and implicit ``$`` parameters,
variants, ``<keyframing>`` and ``chop``; ``--lexicon`` on check, render and the API BML
uses (:func:`mura.gesture_functions.function_gesture`)."""

from __future__ import annotations

from pathlib import Path

import pytest

from agent.agent import Agent
from agent.cli import main
from mura.constraints import Dynamic, Static, iter_leaves
from mura.errors import SpecError
from mura.gesture_functions import function_gesture
from mura.lexicon import combine_lexicons, load_lexicon, load_lexicons
from mura.model import FunctionCall
from mura.murml import parse_utterance
from mura.values import BetweenLocation, GridLocation

LEXICON = """<?xml version="1.0"?>
<gestures>
  <gesture name="pointing_variant_1">
    <function name="point_at">
      <param name="refloc"/>
      <param name="hand" value="right_arm"/>
    </function>
    <constraints scope="$hand">
      <parallel>
        <static slot="HandShape" value="BSifinger"/>
        <static slot="ExtFingerOrientation" value="$refloc" mode="pointTo"/>
        <static slot="HandLocation" value="$refloc" mode="pointTo"/>
      </parallel>
    </constraints>
  </gesture>
  <gesture name="pointing_variant_2">
    <function name="point_at"><param name="refloc"/></function>
    <constraints><static slot="HandShape" value="BSfist"/></constraints>
  </gesture>
  <gesture name="raise">
    <dynamic slot="HandLocation" scope="right_arm">
      <dynamicElement type="linear">
        <value type="start" name="$height LocCenterRight LocNorm"/>
        <value type="direction" name="DirU"/>
        <value type="distance" name="$size"/>
      </dynamicElement>
    </dynamic>
  </gesture>
  <gesture name="beat">
    <function name="beat"><param name="size" value="DistShort"/></function>
    <murml-description>
      <parallel>
        <static slot="HandShape" value="BSflat"/>
        <dynamic slot="HandLocation">
          <dynamicElement type="chop">
            <value type="start" name="LocChest LocCenterRight LocNorm"/>
            <value type="direction" name="DirD"/>
            <value type="distance" name="$size"/>
          </dynamicElement>
        </dynamic>
      </parallel>
    </murml-description>
  </gesture>
  <gesture name="nod">
    <dynamic slot="Neck" scope="neck">
      <keyframing mode="spline"><phase>
        <frame ftime="0.2"><posture>Humanoid (vc4 3 5 0 0)</posture></frame>
        <frame ftime="0.5"><posture>Humanoid (vc4 3 0 0 0)</posture></frame>
      </phase></keyframing>
    </dynamic>
  </gesture>
</gestures>
"""

SYMBOLS = """<hns><symbols>
  <symbol class="handReferences" name="LocKnee" value="-40"/>
  <symbol class="distances" name="DistTiny" value="5"/>
  <symbol class="palmOrientations" name="PalmAway" value="90"/>
  <symbol class="handShapes" name="BSfist" value=""/>
</symbols></hns>
"""


def _call(function: str, params: str = "", timing: str = '<timing onset="1" end="2"/>') -> str:
    return (
        '<definition><utterance><behaviorspec id="g"><gesture>' + timing
        + f'<function name="{function}">{params}</function></gesture></behaviorspec></utterance></definition>'
    )  # fmt: skip


@pytest.fixture()
def files(tmp_path: Path) -> dict[str, Path]:
    paths = {"lexicon": tmp_path / "gestures.xml", "symbols": tmp_path / "hns.xml"}
    paths["lexicon"].write_text(LEXICON)
    paths["symbols"].write_text(SYMBOLS)
    return paths


def test_entries_functions_and_parameters(files: dict[str, Path]) -> None:
    lexicon = load_lexicon(files["lexicon"])
    assert lexicon.functions == ("beat", "nod", "point_at", "raise")
    assert dict(lexicon.entry("point_at").params) == {"refloc": None, "hand": "right_arm"}
    assert lexicon.entry("point_at").name == "pointing_variant_1"  # the first variant
    assert dict(lexicon.entry("raise").params) == {"height": None, "size": None}  # implicit, required
    assert dict(lexicon.entry("beat").params) == {"size": "DistShort"}
    assert lexicon.unit == "cm"


def test_function_gesture_fills_placeholders_for_any_caller(files: dict[str, Path]) -> None:
    lexicon = load_lexicons([files["lexicon"]])
    call = FunctionCall("raise", {"height": "LocStomach", "size": "20"})
    gesture = function_gesture(lexicon, call)
    (leaf,) = iter_leaves(gesture.constraints)
    (segment,) = leaf.segments
    assert segment.start == GridLocation("LocStomach", "LocCenterRight", "LocNorm")
    assert segment.distance == pytest.approx(0.20)  # the lexicon's unit: cm
    beat = function_gesture(lexicon, FunctionCall("beat", {}))
    (chop,) = [leaf for leaf in iter_leaves(beat.constraints) if isinstance(leaf, Dynamic)]
    assert chop.segments[0].distance == pytest.approx(0.10) and chop.segments[0].modifiers == ("chop",)


def test_scene_places_pass_through_parameters(files: dict[str, Path]) -> None:
    utterance = parse_utterance(_call("point_at", '<param name="refloc" value="$Loc-Bar_1"/>'), lexicon=load_lexicons([files["lexicon"]]))
    leaves = list(iter_leaves(utterance.behaviors[0].gesture.constraints))
    assert {leaf.slot for leaf in leaves} == {"HandShape", "ExtFingerOrientation", "HandLocation"}
    assert all(isinstance(leaf, Static) for leaf in leaves)


@pytest.mark.parametrize(
    ("function", "params", "message"),
    [
        ("raise", '<param name="height" value="LocStomach"/>', "function 'raise' needs parameter 'size'"),
        ("beat", '<param name="colour" value="red"/>', "function 'beat' has no parameter 'colour'"),
        ("raise", '<param name="height" value="LocMoon"/><param name="size" value="20"/>', "unknown location name 'LocMoon'"),
        ("juggle", "", "unknown gesture function 'juggle' (the lexicon has: beat, emphasize, negate, nod, point_at"),
    ],
)
def test_bad_calls_are_reported_at_the_call(files: dict[str, Path], function: str, params: str, message: str) -> None:
    with pytest.raises(SpecError) as caught:
        parse_utterance(_call(function, params), file="call.us", lexicon=load_lexicons([files["lexicon"]]))
    assert message in caught.value.message
    assert caught.value.file == "call.us" and caught.value.line == 1 and caught.value.column > 1
    if "LocMoon" in message:
        assert f"in the lexicon at {files['lexicon']}:" in caught.value.message


def test_symbol_table_adds_names(files: dict[str, Path]) -> None:
    lexicon = load_lexicons([files["symbols"]])
    text = (
        '<definition><utterance><behaviorspec id="g"><gesture><timing onset="1" end="2"/><constraints><parallel>'
        '<static slot="PalmOrientation" value="PalmAway"/><dynamic slot="HandLocation"><dynamicElement type="linear">'
        '<value type="start" name="LocKnee LocCenterRight"/><value type="direction" name="DirU"/><value type="distance" name="DistTiny"/>'
        "</dynamicElement></dynamic></parallel></constraints></gesture></behaviorspec></utterance></definition>"
    )  # fmt: skip
    leaves = list(iter_leaves(parse_utterance(text, lexicon=lexicon).behaviors[0].gesture.constraints))
    palm, move = leaves
    assert palm.value.direction == pytest.approx((0.0, -1.0, 0.0), abs=1e-9)
    segment = move.segments[0]
    assert isinstance(segment.start, BetweenLocation) and segment.distance == pytest.approx(0.05)
    with pytest.raises(SpecError, match="unknown palm orientation 'PalmAway'"):
        parse_utterance(text)


def test_later_lexicons_win(files: dict[str, Path], tmp_path: Path) -> None:
    other = tmp_path / "other.xml"
    other.write_text('<gestures><gesture name="beat"><static slot="HandShape" value="ASL5"/></gesture></gestures>')
    combined = combine_lexicons([load_lexicon(), load_lexicon(files["lexicon"]), load_lexicon(other)])
    assert combined.entry("beat").source.file == str(other.resolve())
    assert combined.entry("refer_to_loc") is not None  # the bundled lexicon's functions stay


def test_check_and_render_take_repeated_lexicons(files: dict[str, Path], tmp_path: Path, capsys) -> None:
    utterance = tmp_path / "u.xml"
    utterance.write_text(_call("raise", '<param name="height" value="LocKnee"/><param name="size" value="DistTiny"/>'))
    assert main(["check", str(utterance)]) == 1
    assert "unknown gesture function 'raise'" in capsys.readouterr().out
    options = ["--lexicon", str(files["lexicon"]), "--lexicon", str(files["symbols"])]
    assert main(["check", *options, str(utterance), str(files["lexicon"]), str(files["symbols"])]) == 0
    out = capsys.readouterr().out
    assert "lexicon of 4 function(s)" in out and "3 symbol(s)" in out
    assert main(["render", *options, str(utterance), "-o", str(tmp_path / "out"), "--no-glb", "--avatar", "max"]) == 0
    assert (tmp_path / "out" / "u.bvh").is_file()


def test_keyframed_entry_renders_with_a_warning(files: dict[str, Path]) -> None:
    agent = Agent(avatar="max", fps=30.0, lexicon=load_lexicons([files["lexicon"]]))
    performance = agent.render(_call("nod", timing=""))
    assert any("Neck" in warning for warning in performance.warnings)


@pytest.mark.parametrize(
    ("document", "message"),
    [
        ('<gestures><gesture name="x"><static slot="HandShape" value="BSclaw"/></gesture></gestures>', "unknown hand shape 'BSclaw'"),
        ('<gestures><gesture name="x"/></gestures>', "needs one form"),
        ('<gestures><wobble/></gestures>', "unexpected <wobble> in <gestures>"),
        ('<gestures><gesture><static slot="HandShape" value="ASL5"/></gesture></gestures>', "<gesture> needs a name"),
        ('<hns><symbols><symbol class="handReferences" name="LocX" value="high"/></symbols></hns>', "not a number"),
    ],
)
def test_check_reports_broken_lexicons_in_place(tmp_path: Path, capsys, document: str, message: str) -> None:
    path = tmp_path / "bad.xml"
    path.write_text(document)
    assert main(["check", str(path)]) == 1
    line = capsys.readouterr().out.strip()
    assert line.startswith(f"{path}:1:") and message in line
