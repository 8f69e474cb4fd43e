"""Signs inside MURML utterances: parsed in both written forms, timed against speech like
gestures, realized by the motor core."""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from agent import Agent
from motor.body.kinematics import forward_kinematics
from mura.errors import SpecError
from mura.model import AbsoluteTiming
from mura.murml import UNTIMED_GAP, UNTIMED_STROKE, load_utterance, parse_utterance

REPO = Path(__file__).resolve().parents[2]
EXAMPLE = REPO / "specs" / "utterances" / "sign_here.xml"

TEMPLATE = """<utterance><specification>Wait <time id="t1"/> here <time id="t2"/></specification>
<behaviorspec id="s"><sign>{body}</sign></behaviorspec></utterance>"""
AFFILIATE = '<affiliate onset="t1" end="t2"/>'


def test_both_written_forms_parse_to_signs():
    utterance = load_utterance(EXAMPLE)
    here, up = utterance.behaviors
    assert (here.kind, here.gesture, here.chunk) == ("sign", None, 0)
    assert here.sign.gloss == "HERE" and here.sign.two_handed
    assert here.moves_arms and up.moves_arms
    assert up.sign.gloss == "UP"
    assert up.sign.symbols == ("hamfinger2", "hamextfingeru", "hampalml", "hamshoulders", "hammoveu")


@pytest.mark.parametrize(
    ("body", "message"),
    [
        (AFFILIATE, "sign 's' needs exactly one of <hamnosys>, <hns_sign>, <hamgestural_sign>"),
        (AFFILIATE + "<hamnosys> </hamnosys>", "sign 's': <hamnosys> is empty"),
        (AFFILIATE + "<hamnosys>&#xE002;&#xE0F9;</hamnosys>", "sign 's'"),
    ],
)
def test_bad_sign_behaviours_are_spec_errors(body, message):
    with pytest.raises(SpecError) as caught:
        parse_utterance(TEMPLATE.format(body=body), file="signs.xml")
    assert message in str(caught.value)
    assert caught.value.file == "signs.xml" and caught.value.line >= 1


def test_a_sign_without_timing_is_performed_from_the_start():
    utterance = parse_utterance(TEMPLATE.format(body="<hamnosys>&#xE002;&#xE020;&#xE03E;&#xE051;</hamnosys>"), file="signs.xml")
    (sign,) = [b for b in utterance.behaviors if b.kind == "sign"]
    assert sign.timing == AbsoluteTiming(UNTIMED_GAP, UNTIMED_GAP + UNTIMED_STROKE)


def test_a_pointing_sign_without_timing_is_performed_from_the_start_too():
    text = ('<utterance><space><place entity="john" arc="0.9"/></space><specification>Look there.</specification>'
            '<behaviorspec id="b1"><sign point="john"/></behaviorspec></utterance>')
    (pointing,) = parse_utterance(text, file="point.xml").behaviors
    assert pointing.spatial is not None and pointing.timing == AbsoluteTiming(UNTIMED_GAP, UNTIMED_GAP + UNTIMED_STROKE)


@pytest.fixture(scope="module")
def performance():
    return Agent(tts="fake", fps=60).render(EXAMPLE)


def test_signs_are_timed_against_their_affiliates(performance):
    for behavior in performance.timeline["behaviors"]:
        phases, affiliate = behavior["phases"], behavior["affiliate"]
        assert phases["stroke_start"] == pytest.approx(affiliate["onset"] - 0.2, abs=1e-3)
        assert phases["relax"] >= affiliate["end"] - 1e-6


def test_the_two_handed_sign_is_mirrored_and_moves_down(performance):
    agent_avatar = Agent(tts="fake").avatar
    pose = forward_kinematics(agent_avatar, performance.motion.rotations, performance.motion.root_translation)
    right = pose.positions[:, agent_avatar.joint_index("r_wrist")]
    left = pose.positions[:, agent_avatar.joint_index("l_wrist")]
    times = performance.motion.times
    phases = performance.timeline["behaviors"][0]["phases"]
    stroke = (times >= phases["stroke_start"]) & (times <= phases["stroke_end"])
    assert np.max(np.abs(right[stroke, 0] + left[stroke, 0])) < 1e-3
    assert np.max(np.abs(right[stroke, 1] - left[stroke, 1])) < 1e-3
    assert np.ptp(right[stroke, 1]) > 0.03  # the small downward movement, repeated
    assert np.all(np.isfinite(performance.motion.rotations))


def test_same_behaviour_id_in_two_utterances_plans_each_sign():
    from motor.body.avatar import load_avatar
    from motor.control import MotorControl

    control = MotorControl(load_avatar("max"))
    one_handed = parse_utterance(TEMPLATE.format(body=AFFILIATE + "<hamnosys>&#xE002;&#xE020;&#xE03E;&#xE051;&#xE080;</hamnosys>"))
    two_handed = load_utterance(EXAMPLE)
    first = control.demands(one_handed.behaviors[0])
    renamed = replace(two_handed.behaviors[0], id="s")
    second = control.demands(renamed)
    assert first.arms == frozenset({"right"})
    assert second.arms == frozenset({"right", "left"})
