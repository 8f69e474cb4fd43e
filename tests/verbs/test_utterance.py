"""Placed entities, pointing and indicating verbs inside MURML utterances: the markup, its
errors, and the utterance performed with speech by the same motor core."""

import numpy as np
import pytest

from agent.agent import Agent
from agent.export.bvh import bvh_text
from motor.verbs.capture import global_transforms
from mura.bvh import parse_bvh
from mura.errors import SpecError
from mura.murml import parse_utterance
from mura.space import IndicatingVerbSign, PointingSign

EXAMPLE = "specs/utterances/indicating_verbs.xml"


def _utterance(space: str, sign: str, definition_space: str = "") -> str:
    body = f"""<utterance>
  {space}
  <specification> John <time id="t1"/> asks <time id="t2"/> Mary. <time id="t3"/> </specification>
  <behaviorspec id="b1">
    {sign}
  </behaviorspec>
</utterance>"""
    return f"<definition>{definition_space}{body}</definition>" if definition_space else body


SPACE = '<space><place entity="john" arc="0.9"/><place entity="mary" arc="-0.6"/></space>'


@pytest.mark.parametrize(
    ("sign", "verb", "subject", "obj", "model"),
    [
        ('<sign verb="ASK" subject="john" object="mary"><affiliate onset="t1" end="t2"/></sign>', "ASK", 0.9, -0.6, "point"),
        ('<sign verb="give" subject="-0.2" object="mary" model="vector"><affiliate onset="t1" end="t3"/></sign>', "GIVE", -0.2, -0.6, "vector"),
        ('<sign verb="TELL" object="john" model="uninflected"><timing onset="0.5" end="1.0"/></sign>', "TELL", None, 0.9, "uninflected"),
    ],
)
def test_verb_markup(sign, verb, subject, obj, model):
    utterance = parse_utterance(_utterance(SPACE, sign))
    behavior = utterance.behaviors[0]
    assert behavior.kind == "sign" and behavior.sign is None and behavior.moves_arms
    spatial = behavior.spatial
    assert isinstance(spatial, IndicatingVerbSign)
    assert (spatial.verb, spatial.model, spatial.object.arc) == (verb, model, obj)
    assert (spatial.subject.arc if spatial.subject else None) == subject
    assert {r.entity: r.arc for r in utterance.space} == {"john": 0.9, "mary": -0.6}


@pytest.mark.parametrize(("target", "arc", "entity"), [("john", 0.9, "john"), ("0.25", 0.25, None)])
def test_pointing_markup(target, arc, entity):
    utterance = parse_utterance(_utterance(SPACE, f'<sign point="{target}"><affiliate onset="t1" end="t2"/></sign>'))
    spatial = utterance.behaviors[0].spatial
    assert isinstance(spatial, PointingSign) and spatial.target.arc == arc and spatial.target.entity == entity


def test_space_of_a_definition_serves_its_utterances():
    text = _utterance("", '<sign point="mary"><affiliate onset="t1" end="t2"/></sign>', definition_space=SPACE)
    utterance = parse_utterance(text)
    assert utterance.behaviors[0].spatial.target.arc == -0.6


@pytest.mark.parametrize(
    ("space", "sign", "message", "line"),
    [
        (SPACE, '<sign verb="ASK" subject="bob" object="mary"><affiliate onset="t1" end="t2"/></sign>', "neither an arc position", 5),
        (SPACE, '<sign verb="ASK" subject="john" object="1.4"><affiliate onset="t1" end="t2"/></sign>', "outside [-1, 1]", 5),
        (SPACE, '<sign verb="HUG" subject="john" object="mary"><affiliate onset="t1" end="t2"/></sign>', "unknown indicating verb 'HUG'", 5),
        (SPACE, '<sign verb="TELL" subject="john" object="mary"><affiliate onset="t1" end="t2"/></sign>', "takes no subject", 5),
        (SPACE, '<sign verb="GIVE" object="mary"><affiliate onset="t1" end="t2"/></sign>', "needs a subject", 5),
        (SPACE, '<sign verb="GIVE" subject="john"><affiliate onset="t1" end="t2"/></sign>', "needs an object", 5),
        (SPACE, '<sign verb="GIVE" subject="john" object="mary" model="spline"><affiliate onset="t1" end="t2"/></sign>', "model 'spline'", 5),
        (SPACE, '<sign point="john" verb="ASK"><affiliate onset="t1" end="t2"/></sign>', "either point or verb", 5),
        ('<space><place entity="john" arc="2"/></space>', '<sign point="john"><affiliate onset="t1" end="t2"/></sign>', "outside [-1, 1]", 2),
        ('<space><place entity="john" arc="0.1"/><place entity="john" arc="0.2"/></space>', '<sign point="john"><affiliate onset="t1" end="t2"/></sign>', "placed twice", 2),
    ],
)
def test_bad_markup_names_the_place(space, sign, message, line):
    with pytest.raises(SpecError, match=message.replace("[", r"\[").replace("]", r"\]").replace("(", r"\(")) as caught:
        parse_utterance(_utterance(space, sign), file="bad.xml")
    assert caught.value.file == "bad.xml" and caught.value.line == line and caught.value.column > 0


@pytest.fixture(scope="module")
def performed():
    agent = Agent(avatar="max", tts="fake", fps=30)
    return agent, agent.render(EXAMPLE)


def test_utterance_with_placed_entities_renders_with_speech(performed):
    agent, performance = performed
    assert performance.audio.size > 0 and not np.isnan(performance.motion.rotations).any()
    ids = {b["id"] for b in performance.timeline["behaviors"]}
    assert {"point_john", "ask", "point_mary", "give"} <= ids


def test_ask_moves_from_johns_place_to_marys(performed):
    agent, performance = performed
    behavior = next(b for b in performance.timeline["behaviors"] if b["id"] == "ask")
    phases = behavior["phases"]
    motion = performance.motion
    frames = np.round((np.array([phases["stroke_start"], phases["stroke_end"]]) - motion.start_time) * motion.fps).astype(int)
    clip = parse_bvh(bvh_text(motion))  # the exported frames, through the BVH's own kinematics
    _, positions = global_transforms(clip, frames)
    wrist = positions[:, clip.names.index("r_wrist")]
    # John is on the signer's right (−x), Mary on the left (+x): the wrist travels leftward
    assert wrist[1, 0] - wrist[0, 0] > 15.0  # centimetres
