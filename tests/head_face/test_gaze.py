"""Gaze: eyes and head turned toward the target at the stroke, the eye–head split, eyes first."""

from __future__ import annotations

import numpy as np
import pytest
from face_helpers import EXAMPLES, frame_at, phases, rendered

from agent.agent import Agent
from bench.head_face import GAZE_CASES, gaze_errors, joint_frames
from motor.body.avatar import load_avatar
from motor.neck.gaze import EYE_LIMIT, GAIN, HEAD_LIMIT, gaze, head_direction, point, saccade_duration
from motor.program.lmp import ChannelState
from mura.lexicon import load_lexicon
from mura.murml import parse_utterance

PLACES = {name: np.array([float(v) for v in place.text.split()]) for name, place in load_lexicon().scene.items() if place.is_position}


@pytest.mark.parametrize("avatar", ["max", "kim", "makehuman"])
@pytest.mark.parametrize("case", GAZE_CASES, ids=lambda c: f"{c.utterance}-{c.behavior}")
def test_eyes_are_on_the_target_at_the_stroke(avatar, case):
    performance = rendered(case.utterance, avatar)
    stroke = phases(performance, case.behavior)["stroke"]
    errors = gaze_errors(performance.motion, stroke, case.target, PLACES)
    assert max(errors.values()) < 5.0, errors


@pytest.mark.parametrize(("utterance", "behavior", "place"), [("look_and_nod", "look_at_bar", "Loc-Bar_2"), ("fig2_take_this_bar", "gesture_1", "Loc-Bar_1")])
def test_the_head_turns_toward_the_target(utterance, behavior, place):
    """The face's forward direction comes within 25° of the target, from far more at rest."""
    motion = rendered(utterance).motion
    stroke = frame_at(motion, phases(rendered(utterance), behavior)["stroke"])
    positions, orientations = joint_frames(motion, np.array([0, stroke]))
    head = motion.joint_names.index("skullbase")
    angles = []
    for k in range(2):
        facing = orientations[head][k].apply([0.0, 0.0, 1.0])
        wanted = PLACES[place] - positions[k, head]
        angles.append(np.degrees(np.arccos(facing @ wanted / np.linalg.norm(wanted))))
    assert angles[0] > 40.0 and angles[1] < 25.0, angles


def test_the_gaze_follows_the_moving_hand():
    performance = rendered("circle_wheel")
    p = phases(performance, "draw_wheel")
    for time in np.linspace(p["stroke_start"], p["stroke_end"], 7):
        assert max(gaze_errors(performance.motion, time, "right_palm", PLACES).values()) < 5.0, time


@pytest.mark.parametrize(
    ("degrees", "head"),
    [(10.0, 0.0), (15.0, 0.0), (30.0, GAIN * 15.0), (60.0, GAIN * 45.0), (100.0, 100.0 - np.degrees(EYE_LIMIT)), (150.0, np.degrees(HEAD_LIMIT))],
)
def test_eye_head_split(degrees, head):
    """Eyes alone up to 15°, the head takes 0.65 of the excess and whatever the eyes cannot
    reach (35°), up to 70°; the direction stays on the great circle toward the target."""
    angle = np.radians(degrees)
    target = np.array([np.sin(angle) * np.cos(0.3), np.sin(angle) * np.sin(0.3), np.cos(angle)])
    facing = head_direction(target[None, :])[0]
    assert np.degrees(np.arccos(np.clip(facing[2], -1, 1))) == pytest.approx(head, abs=1e-6)
    if head > 0:
        assert np.cross(facing, target) @ np.cross([0.0, 0.0, 1.0], target) > 0.0


def test_the_eyes_arrive_before_the_head():
    avatar = load_avatar("max")
    target = point(np.array([0.6, 0.3, 0.8]))
    lmp = gaze(avatar, target, 0.0)
    rest = np.concatenate([lmp.origin + np.array([0.0, 0.0, 10.0]), [0.0, 0.0, 1.0]])
    shift = lmp.activate(ChannelState.at_rest(rest))
    times = np.linspace(0.0, 1.0, 1001)
    values = shift.sample(times)
    eyes_on = times[np.argmax(np.linalg.norm(values[:, :3] - target.points(times[:1])[0], axis=1) < 1e-3)]
    final = values[-1, 3:]
    head_on = times[np.argmax(np.degrees(np.arccos(np.clip(values[:, 3:] @ final, -1, 1))) < 0.5)]
    assert eyes_on <= saccade_duration(shift.amplitudes[0]) + 1e-3
    assert eyes_on < head_on - 0.1


def test_an_unknown_gaze_target_warns_where_and_looks_at_the_listener():
    document = """<utterance><specification>Look <time id="a"/> here now. <time id="b"/></specification>
      <behaviorspec id="look"><gesture><affiliate onset="a" end="b"/><constraints>
        <static slot="GazeDirection" value="Nowhere" scope="head"/></constraints></gesture></behaviorspec></utterance>"""
    performance = Agent(avatar="max", tts="fake", fps=60).render(parse_utterance(document, file="look.xml"), name="look")
    warning = next(w for w in performance.warnings if "Nowhere" in w)
    assert "look.xml:3:" in warning and "listener instead" in warning
    stroke = phases(performance, "look")["stroke"]
    assert max(gaze_errors(performance.motion, stroke, "listener", PLACES).values()) < 5.0


def test_published_gaze_vectors_look_ahead_and_down():
    """``1000 -500 0`` in the published dialect (x ahead, y up): 26.6° below straight ahead."""
    document = """<definition><utterance><behaviorspec><gesture id="g" scope="head"><timing onset="1.0" end="2.0"/>
      <constraints><static slot="GazeDirection" value="1000 -500 0" scope="head"/></constraints></gesture>
      </behaviorspec></utterance></definition>"""
    performance = Agent(avatar="max", tts="fake", fps=60).render(parse_utterance(document, file="pub.us"), name="pub")
    motion = performance.motion
    stroke = frame_at(motion, phases(performance, "behavior_1")["stroke"])
    _, orientations = joint_frames(motion, np.array([stroke]))
    for eye in ("l_eyeball_joint", "r_eyeball_joint"):
        sight = orientations[motion.joint_names.index(eye)][0].apply([0.0, 0.0, 1.0])
        assert np.degrees(np.arccos(sight @ np.array([0.0, -0.5, 1.0]) / np.sqrt(1.25))) < 1.0


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.xml")), ids=lambda p: p.stem)
def test_no_head_or_face_slot_is_left_unrealized(path):
    assert not [w for w in rendered(path.stem).warnings if "not realized" in w]


def test_published_files_realize_their_gaze(shared):
    agent = Agent(avatar="max", tts="fake", fps=30)
    for path in sorted((shared / "corpora" / "murml").glob("*.us")):
        performance = agent.render(path)
        assert not [w for w in performance.warnings if "not realized" in w], path.name
