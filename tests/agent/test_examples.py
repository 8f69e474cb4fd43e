"""The example agent scripts run offline and produce what they say."""

import pytest

from agent.examples import assembly_expert, describe_objects
from mura.constraints import iter_leaves
from mura.murml import parse_utterance


def test_assembly_expert_writes_every_turn(tmp_path, capsys):
    assert assembly_expert.main(["-o", str(tmp_path)]) == 0
    for turn in range(1, len(assembly_expert.DIALOGUE) + 1):
        for suffix in (".wav", ".bvh", ".timeline.json", ".html"):
            assert (tmp_path / f"turn{turn}{suffix}").is_file()
    out = capsys.readouterr().out
    assert "agent: You need this bar and that one." in out


def test_descriptions_follow_the_data():
    items = (describe_objects.Item("a box", 0.3), describe_objects.Item("a pin & a nut", 0.05))
    utterance = parse_utterance(describe_objects.describe(items))
    assert [chunk.text for chunk in utterance.chunks] == ["A box is this wide", "A pin & a nut is this wide"]
    distances = [
        segment.distance
        for behavior in utterance.behaviors
        for leaf in iter_leaves(behavior.gesture.constraints)
        if leaf.slot == "HandLocation"
        for segment in leaf.segments
    ]
    assert distances == pytest.approx([0.3, 0.05])


def test_describe_objects_renders(tmp_path, capsys):
    assert describe_objects.main(["-o", str(tmp_path)]) == 0
    assert (tmp_path / "inventory.html").is_file()
    assert capsys.readouterr().out.startswith("3 chunks")


def test_nothing_to_describe_is_an_error():
    with pytest.raises(ValueError, match="nothing to describe"):
        describe_objects.describe(())
