"""BML blocks written for these tests, rendered offline with the fake speech: the rendered
timeline satisfies every constraint of each block within one frame, behaviours appear by
id with their sync-point times, speech sync markers as time tags, and what mura leaves out
is warned about while the rest runs."""

from __future__ import annotations

from pathlib import Path

import pytest

from agent import Agent
from mura.bml import load_bml
from mura.model import BML_SYNC_PEGS, SyncConstraint, SyncRef

FPS = 60.0
FRAME = 1.0 / FPS
NS = 'xmlns="http://www.bml-initiative.org/bml/bml-1.0"'
SPEECH = '<speech id="s1"><text>Take <sync id="tm1"/> this bar and put it <sync id="tm2"/> over there, <sync id="tm3"/> please.</text></speech>'

#: name → (block body, the behaviours it must list performed, timed only, the warnings' kinds of words)
CASES: dict[str, tuple[str, set[str], set[str], tuple[str, ...]]] = {
    "speech_sync_markers": (SPEECH.replace('id="s1"', 'id="s1" start="0.3"', 1), set(), set(), ()),
    "beat_on_sync": (SPEECH + '<gesture id="g1" lexeme="BEAT" stroke="s1:tm1"/>', {"g1"}, set(), ()),
    "nod_at_stroke_end": (
        SPEECH + '<gesture id="g1" lexeme="BEAT" stroke="s1:tm1"/><head id="h1" lexeme="NOD" stroke="g1:strokeEnd"/>',
        {"g1", "h1"}, set(), (),
    ),
    "offsets_and_chains": (
        SPEECH + '<gesture id="g1" lexeme="BEAT" stroke="s1:tm1+0.3"/>'
        '<head id="h1" lexeme="SHAKE" start="g1:strokeEnd-0.1"/>'
        '<gaze id="z1" target="Loc-User" start="h1:end+0.2" end="s1:end - 0.05"/>',
        {"g1", "h1", "z1"}, set(), (),
    ),
    "before_and_after": (
        SPEECH + '<gesture id="g1" lexeme="BEAT" stroke="s1:tm1"/>'
        '<pointing id="p1" target="Loc-Bar_2" mode="LEFT_HAND" stroke="s1:tm2"/>'
        '<constraint id="c1"><after ref="g1:strokeEnd+0.1"><sync ref="p1:start"/></after></constraint>'
        '<constraint id="c2"><before ref="s1:end+1.5"><sync ref="p1:relax"/><sync ref="g1:end"/></before></constraint>',
        {"g1", "p1"}, set(), (),
    ),
    "synchronize": (
        SPEECH + '<gesture id="g1" lexeme="BEAT"/><head id="h1" lexeme="NOD"/>'
        '<constraint id="c1"><synchronize><sync ref="g1:stroke"/><sync ref="h1:stroke"/><sync ref="s1:tm2"/></synchronize></constraint>',
        {"g1", "h1"}, set(), (),
    ),
    "required_block": (
        '<required>' + SPEECH + '<gesture id="g1" lexeme="BEAT" stroke="s1:tm2"/></required>'
        '<faceLexeme id="f1" lexeme="RAISE_BROWS" attackPeak="g1:stroke" relax="s1:end"/>',
        {"g1", "f1"}, set(), (),
    ),
    "absolute_timings": (
        '<speech id="s1" start="1.0"><text>Here <sync id="tm1"/> it is.</text></speech>'
        '<gesture id="g1" lexeme="BEAT" start="0.2"/><head id="h1" lexeme="NOD" stroke="2.5"/>',
        {"g1", "h1"}, set(), (),
    ),
    "gesture_only": ('<gesture id="g1" lexeme="NEGATE" start="0.5" end="2.5"/>', {"g1"}, set(), ()),
    "both_hands_and_murml": (
        SPEECH + '<gesture id="g1" lexeme="BEAT" mode="BOTH_HANDS" stroke="s1:tm1"/>'
        '<murml:murmlgesture xmlns:murml="http://www.techfak.uni-bielefeld.de/ags/soa/murml" id="m1" strokeStart="s1:tm2" strokeEnd="s1:tm3">'
        '<murml:murml-description><murml:parallel>'
        '<murml:static slot="HandShape" value="BSflat"/><murml:static slot="PalmOrientation" value="PalmD"/>'
        '<murml:dynamic slot="HandLocation"><murml:segment type="linear">'
        '<murml:value type="start" name="LocStomach LocCCenter LocNorm"/><murml:value type="end" name="LocStomach LocPeripheryRight LocNorm"/>'
        '</murml:segment></murml:dynamic></murml:parallel></murml:murml-description></murml:murmlgesture>',
        {"g1", "m1"}, set(), (),
    ),
    "unknown_behaviours_and_attributes": (
        SPEECH + '<gesture id="g1" lexeme="BEAT" stroke="s1:tm1" wobble="3"/>'
        '<locomotion id="l1" target="door"/><juggle id="j1" balls="3"/>'
        '<x:sparkle xmlns:x="http://example.org/ext" id="x1"/>'
        '<gesture id="g2" lexeme="MOONWALK" start="g1:end"/>'
        '<head id="h1" lexeme="NOD" start="l1:end"/>',
        {"g1", "h1"}, set(),
        ("unknown attribute 'wobble'", "<locomotion> 'l1' is not supported", "unknown behaviour <juggle>",
         "namespace http://example.org/ext", "unknown lexeme 'MOONWALK'", "names l1, which is left out"),
    ),
    "two_speeches": (
        SPEECH + '<gesture id="g1" lexeme="BEAT" stroke="s1:tm3"/>'
        '<speech id="s2" start="g1:end+0.3"><text>And then <sync id="a"/> we are done.</text></speech>'
        '<head id="h1" lexeme="NOD" stroke="s2:a"/>',
        {"g1", "h1"}, set(), (),
    ),
    "timed_only": (
        SPEECH + '<gesture id="g1" lexeme="BEAT" stroke="s1:tm1"/>'
        '<faceFacs id="a1" au="2" start="g1:stroke" end="s1:end"/><posture id="p1" start="g1:end" end="s1:end"/>',
        {"g1"}, {"a1", "p1"}, ("timed but not performed",),
    ),
    "amount_and_influence": (
        SPEECH + '<gesture id="g1" lexeme="BEAT" stroke="s1:tm1"/>'
        '<head id="h1" lexeme="NOD" amount="2" stroke="g1:strokeEnd"/><gaze id="z1" target="Loc-Bar_2" influence="EYES" start="s1:tm2"/>',
        {"g1", "h1", "z1"}, set(), ("amount 2 is not performed", "influence EYES is not performed"),
    ),
    "optional_constraint_dropped": (
        SPEECH + '<gesture id="g1" lexeme="BEAT" stroke="s1:tm1"/>'
        '<constraint id="c1"><before ref="s1:start"><sync ref="g1:end"/></before></constraint>',
        {"g1"}, set(), ("dropped",),
    ),
}


@pytest.fixture(scope="module")
def agent() -> Agent:
    return Agent(tts="fake", fps=FPS)


@pytest.fixture(scope="module", params=sorted(CASES))
def rendered(request, agent, tmp_path_factory):
    name = request.param
    body = CASES[name][0]
    path = tmp_path_factory.mktemp("bml") / f"{name}.bml"
    path.write_text(f'<bml {NS} id="{name}">{body}</bml>', encoding="utf-8")
    block = load_bml(path)
    performance = agent.render(path)
    return name, block, performance.timeline, performance


def _time(ref: SyncRef, timeline: dict, speeches: set[str]) -> float:
    if ref.behavior is None:
        return ref.offset + timeline["absolute_delay"]
    if ref.behavior in speeches:  # anchored on the audio: the next word's onset, the last word's end
        anchor = timeline["tag_anchors"][f"{ref.behavior}:{ref.point}"]
        return anchor["acoustic_end" if ref.point == "end" else "acoustic_onset"] + ref.offset
    entry = next(b for b in timeline["behaviors"] if b["id"] == ref.behavior)
    return entry["phases"][BML_SYNC_PEGS[ref.point]] + ref.offset


def _holds(constraint: SyncConstraint, timeline: dict, speeches: set[str]) -> bool:
    point, anchor = _time(constraint.point, timeline, speeches), _time(constraint.anchor, timeline, speeches)
    if constraint.relation == "=":
        return abs(point - anchor) <= FRAME
    if constraint.relation == "<=":
        return point <= anchor + FRAME
    return point >= anchor - FRAME


def test_every_constraint_holds_on_the_rendered_timeline(rendered):
    name, block, timeline, _ = rendered
    speeches = {c.speech for c in block.utterance.chunks}
    kept = [c for c in block.utterance.constraints if not any(w.startswith(f"constraint {c} dropped") for w in timeline["warnings"])]
    assert kept, f"{name}: no constraint left to check"
    broken = [str(c) for c in kept if not _holds(c, timeline, speeches)]
    assert not broken, f"{name}: constraints broken on the timeline: {broken}"


def test_behaviours_listed_by_id_with_their_phases(rendered):
    name, block, timeline, _ = rendered
    _, performed, timed, _ = CASES[name]
    entries = {b["id"]: b for b in timeline["behaviors"]}
    assert {i for i, b in entries.items() if b["performed"]} == performed
    assert {i for i, b in entries.items() if not b["performed"]} == timed
    for entry in entries.values():
        phases = [entry["phases"][peg] for peg in ("start", "ready", "stroke_start", "stroke", "stroke_end", "relax", "end")]
        assert phases == sorted(phases), f"{name}: {entry['id']} phases out of order: {phases}"


def test_speech_syncs_are_time_tags_in_order(rendered):
    name, block, timeline, _ = rendered
    for chunk in block.utterance.chunks:
        tags = [timeline["time_tags"][tag.id] for tag in chunk.time_tags]
        assert tags == sorted(tags), f"{name}: {chunk.speech} markers out of order"
        assert tags[0] >= timeline["chunks"][chunk.index]["speech_onset"] - FRAME
        assert tags[-1] <= timeline["chunks"][chunk.index]["speech_end"] + FRAME


def test_left_out_parts_are_warned_and_the_rest_runs(rendered):
    name, block, timeline, performance = rendered
    for words in CASES[name][3]:
        assert any(words in w for w in timeline["warnings"]), f"{name}: no warning with {words!r} in {timeline['warnings']}"
    assert performance.motion.frame_count > 0


def test_two_speeches_speak_in_order_and_refer_back():
    agent = Agent(tts="fake", fps=FPS)
    body = CASES["two_speeches"][0]
    timeline = agent.render(f'<bml {NS} id="two">{body}</bml>').timeline
    first, second = timeline["chunks"]
    gesture = next(b for b in timeline["behaviors"] if b["id"] == "g1")
    assert second["speech_onset"] >= first["speech_end"]
    assert timeline["tag_anchors"]["s2:start"]["acoustic_onset"] == pytest.approx(gesture["phases"]["end"] + 0.3, abs=FRAME)


def test_both_hands_mirror_a_one_handed_lexeme(agent):
    timeline = agent.render(f'<bml {NS} id="both">{CASES["both_hands_and_murml"][0]}</bml>').timeline
    arms = {b["id"]: set(b["arms"]) for b in timeline["behaviors"]}
    assert arms["g1"] == {"left", "right"}
    assert arms["m1"] == {"right"}


def test_left_hand_pointing_uses_the_left_arm(agent):
    timeline = agent.render(f'<bml {NS} id="left">{CASES["before_and_after"][0]}</bml>').timeline
    assert {b["id"]: b["arms"] for b in timeline["behaviors"]}["p1"] == ["left"]


@pytest.mark.parametrize("relation", ["synchronize", "before"])
def test_required_constraints_that_conflict_are_named(agent, relation):
    constraint = {
        "synchronize": '<synchronize><sync ref="g1:stroke"/><sync ref="s1:start"/></synchronize>',
        "before": '<before ref="s1:start"><sync ref="g1:end"/></before>',
    }[relation]
    xml = f'<bml {NS} id="conflict"><required>{SPEECH}<gesture id="g1" lexeme="BEAT" stroke="s1:tm3"/><constraint id="c">{constraint}</constraint></required></bml>'
    with pytest.raises(Exception) as caught:
        agent.render(xml)
    assert "timing constraints conflict" in str(caught.value)
    assert "g1:" in str(caught.value) and "<utterance>:1:" in str(caught.value)


def test_example_block_renders_with_every_constraint(agent, repo: Path):
    path = repo / "specs" / "bml" / "take_this_bar.bml"
    block, timeline = load_bml(path), agent.render(path).timeline
    assert {b["id"] for b in timeline["behaviors"]} == {"beat", "point", "nod"}
    assert not any(w.startswith("constraint ") and " dropped: " in w for w in timeline["warnings"])
    speeches = {c.speech for c in block.utterance.chunks}
    assert all(_holds(c, timeline, speeches) for c in block.utterance.constraints)


def test_a_conflict_drops_the_later_optional_constraint(agent):
    """Two strokes on one arm too close for the second preparation: the later one yields."""
    body = (SPEECH + '<gesture id="g1" lexeme="BEAT" stroke="s1:tm1"/><gesture id="g2" lexeme="NEGATE" stroke="s1:tm1+0.3"/>')
    timeline = agent.render(f'<bml {NS} id="close">{body}</bml>').timeline
    dropped = [w for w in timeline["warnings"] if w.startswith("constraint ") and " dropped: " in w]
    assert len(dropped) == 1 and dropped[0].startswith("constraint g2:stroke = s1:tm1+0.3")
    g1 = next(b for b in timeline["behaviors"] if b["id"] == "g1")
    assert g1["phases"]["stroke"] == pytest.approx(timeline["tag_anchors"]["s1:tm1"]["acoustic_onset"], abs=FRAME)
