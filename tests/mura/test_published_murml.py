"""Published MURML constructs, each in a small utterance written for the test.

A ``<dynamic>`` that carries a value, gestures with neither ``<affiliate>`` nor
``<timing>``, a segment with a start and nothing else, values named by id, the ``chop``
segment type, ``<keyframing>``, location names beyond the core grid and the published
realizer's shorter location forms, palm orientations as angles.
"""

from __future__ import annotations

import numpy as np
import pytest

from agent.agent import Agent
from motor.body.avatar import load_avatar
from motor.body.locations import resolve_location
from mura.constraints import Dynamic, Parallel, SegmentKind, iter_leaves
from mura.errors import SpecError
from mura.model import AbsoluteTiming
from mura.murml import UNTIMED_GAP, UNTIMED_STROKE, parse_utterance
from mura.values import BetweenLocation, GridLocation, PalmOrientation

START = '<value type="start" name="LocChest LocCenterRight LocNorm"/>'


def _utterance(*behaviours: str) -> str:
    return "<definition><utterance>" + "".join(behaviours) + "</utterance></definition>"


def _gesture(body: str, timing: str = '<timing onset="1.0" end="2.0"/>', gid: str = "g") -> str:
    return f'<behaviorspec id="{gid}"><gesture scope="right_arm">{timing}<constraints>{body}</constraints></gesture></behaviorspec>'


def _leaves(text: str) -> list:
    utterance = parse_utterance(text, file="test.us")
    return [leaf for b in utterance.behaviors for leaf in iter_leaves(b.gesture.constraints)]


@pytest.fixture(scope="module")
def agent() -> Agent:
    return Agent(avatar="max", tts="fake", fps=30.0)


@pytest.mark.parametrize(
    ("slot", "value"),
    [("PalmOrientation", "PalmU"), ("ExtFingerOrientation", "DirAU"), ("HandShape", "BSflat"), ("HandLocation", "LocStomach LocCenterRight LocNorm")],
)
def test_dynamic_that_carries_a_value_moves_to_it(agent: Agent, slot: str, value: str) -> None:
    text = _utterance(_gesture(f'<parallel><static slot="HandLocation" value="LocChest LocCenterRight LocNorm"/><dynamic slot="{slot}" value="{value}"/></parallel>'))
    (leaf,) = [leaf for leaf in _leaves(text) if isinstance(leaf, Dynamic)]
    (segment,) = leaf.segments
    assert segment.start is None and segment.end is not None
    assert agent.render(text).duration > 0


def test_dynamic_without_segments_value_or_keyframing_is_refused_in_place() -> None:
    with pytest.raises(SpecError, match=r"dynamic PalmOrientation has no segments") as caught:
        parse_utterance(_utterance(_gesture('<dynamic slot="PalmOrientation"/>')), file="test.us")
    assert caught.value.file == "test.us" and caught.value.line == 1 and caught.value.column > 100


def test_untimed_gestures_follow_one_another_from_the_start(agent: Agent) -> None:
    line = f'<dynamic slot="HandLocation"><dynamicElement type="linear">{START}<value type="direction" name="DirU"/><value type="distance" name="15"/></dynamicElement></dynamic>'
    text = _utterance(_gesture(line, timing="", gid="a"), _gesture(line, gid="timed"), _gesture(line, timing="", gid="b"))
    behaviors = {b.id: b for b in parse_utterance(text, file="test.us").behaviors}
    timed, first, second = behaviors["timed"].timing, behaviors["a"].timing, behaviors["b"].timing
    assert isinstance(first, AbsoluteTiming) and isinstance(second, AbsoluteTiming)
    assert timed == AbsoluteTiming(1.0, 2.0)
    strokes = sorted([(timed.onset, timed.end), (first.onset, first.end), (second.onset, second.end)])
    assert all(later[0] - earlier[1] >= UNTIMED_GAP - 1e-9 for earlier, later in zip(strokes, strokes[1:]))
    assert first.end - first.onset == second.end - second.onset == UNTIMED_STROKE
    assert first.onset < second.onset  # in document order
    performance = agent.render(text)
    assert performance.duration >= second.end


def test_segment_with_only_a_start_is_a_hold(agent: Agent) -> None:
    text = _utterance(_gesture(f'<dynamic slot="HandLocation"><dynamicElement type="linear">{START}</dynamicElement></dynamic>'))
    (leaf,) = _leaves(text)
    (segment,) = leaf.segments
    assert segment.start == segment.end == GridLocation("LocChest", "LocCenterRight", "LocNorm")
    assert agent.render(text).duration > 0


def test_values_named_by_id_pass_through_in_order() -> None:
    text = _utterance(_gesture(
        '<dynamic slot="PalmOrientation"><dynamicElement><value type="start" name="PalmL"/>'
        '<value id="s1" name="PalmLU"/><value id="s2" name="PalmU"/><value type="end" name="PalmRU"/></dynamicElement></dynamic>'
    ))  # fmt: skip
    (leaf,) = _leaves(text)
    names = [leaf.segments[0].start.name] + [segment.end.name for segment in leaf.segments]
    assert names == ["PalmL", "PalmLU", "PalmU", "PalmRU"]


def test_chop_is_a_fast_straight_stroke(agent: Agent) -> None:
    text = _utterance(_gesture(
        f'<dynamic slot="HandLocation"><dynamicElement type="chop">{START}'
        '<value type="end" name="LocStomach LocCenterRight LocNorm"/></dynamicElement></dynamic>'
    ))  # fmt: skip
    (leaf,) = _leaves(text)
    (segment,) = leaf.segments
    assert (segment.kind, segment.manner, segment.modifiers) == (SegmentKind.LINEAR, "fast", ("chop",))
    assert agent.render(text).duration > 0


KEYFRAMES = (
    '<dynamic slot="Neck" scope="neck"><keyframing mode="spline" easescale="7.0" easeturningpoint="0.4">'
    '<phase><frame ftime="0.2"><posture>Humanoid (vc2 3 3 0 0) (vc4 3 2 0 0)</posture></frame>'
    '<frame ftime="0.6"><posture>Humanoid (vc2 3 3 0 0) (vc4 3 4 0 0)</posture></frame></phase>'
    '<phase><frame ftime="0.3"><posture>Humanoid (vc2 3 0 0 0) (dB_Smile 70)</posture></frame></phase>'
    "</keyframing></dynamic>"
)


def test_keyframing_is_read_and_reported_as_not_realized(agent: Agent) -> None:
    text = _utterance(_gesture(f'<parallel>{KEYFRAMES}<static slot="HandShape" value="BSfist (ThExt)"/></parallel>'))
    (leaf,) = [leaf for leaf in _leaves(text) if isinstance(leaf, Dynamic)]
    frames = leaf.keyframes.frames
    assert [frame.time for frame in frames] == pytest.approx([0.2, 0.6, 0.9])  # phases laid end to end
    assert frames[0].joints == (("vc2", (3.0, 0.0, 0.0)), ("vc4", (2.0, 0.0, 0.0)))
    assert frames[2].joints[1] == ("dB_Smile", (70.0,))
    assert (leaf.keyframes.mode, leaf.keyframes.easescale, leaf.keyframes.easeturningpoint) == ("spline", 7.0, 0.4)
    assert any("Neck" in warning and "not realized" in warning for warning in agent.render(text).warnings)


@pytest.mark.parametrize(
    ("posture", "message"),
    [
        ("Humanoid (vc2 3 3 0)", "announces 3 values but gives 2"),
        ("Humanoid (vc2 3 a b c)", "not a number"),
        ("Humanoid", "names no joint"),
    ],
)
def test_bad_keyframes_are_refused_with_place(posture: str, message: str) -> None:
    body = f'<dynamic slot="Neck"><keyframing><phase><frame ftime="0.2"><posture>{posture}</posture></frame></phase></keyframing></dynamic>'
    with pytest.raises(SpecError, match=message) as caught:
        parse_utterance(_utterance(_gesture(body)), file="test.us")
    assert caught.value.file == "test.us" and caught.value.column > 1


def test_location_beyond_the_core_grid_scales_with_the_avatar() -> None:
    text = _utterance(_gesture('<static slot="HandLocation" value="LocBelowHip LocCenterRight LocNorm"/>'))
    (leaf,) = _leaves(text)
    location = leaf.value
    assert isinstance(location, BetweenLocation) and location.fraction < 0
    for name in ("max", "kim"):
        avatar = load_avatar(name)
        below = resolve_location(avatar, location, "r")
        hip = resolve_location(avatar, GridLocation("LocHip", "LocCenterRight", "LocNorm"), "r")
        assert below[1] < hip[1] - 0.05 and np.allclose(below[[0, 2]], hip[[0, 2]])


@pytest.mark.parametrize(
    ("angle", "name"),
    [("0", "PalmR"), ("90", "PalmD"), ("180", "PalmL"), ("-90", "PalmU"), ("-135", "PalmLU"), ("45", "PalmRD")],
)
def test_palm_orientation_as_an_angle_matches_the_published_names(angle: str, name: str) -> None:
    def palm(value: str) -> PalmOrientation:
        (leaf,) = _leaves(_utterance(_gesture(f'<static slot="PalmOrientation" value="{value}"/>')))
        return leaf.value

    assert np.allclose(palm(angle).direction, palm(name).direction, atol=1e-9)


def test_unknown_location_name_is_still_refused_with_its_place() -> None:
    with pytest.raises(SpecError, match="unknown location name 'LocMiddle'") as caught:
        parse_utterance(_utterance(_gesture('<static slot="HandLocation" value="LocMiddle LocNorm"/>')), file="test.us")
    assert caught.value.line == 1 and caught.value.column > 1


def test_parallel_of_published_leaves_keeps_its_scope() -> None:
    text = _utterance(_gesture('<parallel><static scope="left_arm" slot="HandShape" value="ASLa"/><dynamic slot="PalmOrientation" value="PalmU"/></parallel>'))
    utterance = parse_utterance(text, file="test.us")
    tree = utterance.behaviors[0].gesture.constraints
    assert isinstance(tree, Parallel)
    assert [leaf.scope.value for leaf in iter_leaves(tree)] == ["left_arm", "right_arm"]
