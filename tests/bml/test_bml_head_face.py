"""BML head, gaze and face behaviours performed by the neck and face modules: measured on
the rendered motion with :mod:`bench.head_face`'s own forward kinematics, never the
motor's."""

from __future__ import annotations

import numpy as np
import pytest

from agent import Agent
from bench.head_face import gaze_errors, joint_frames
from mura.lexicon import load_lexicon

NS = 'xmlns="http://www.bml-initiative.org/bml/bml-1.0"'
SPEECH = '<speech id="s1"><text>Take <sync id="tm1"/> this bar and put it <sync id="tm2"/> over there, <sync id="tm3"/> please.</text></speech>'
PLACES = {name: np.array([float(v) for v in place.text.split()]) for name, place in load_lexicon().scene.items() if place.is_position}


@pytest.fixture(scope="module")
def agent() -> Agent:
    return Agent(avatar="max", tts="fake", fps=60.0)


def _render(agent: Agent, body: str):
    performance = agent.render(f'<bml {NS} id="block">{SPEECH}{body}</bml>')
    return performance, {b["id"]: b for b in performance.timeline["behaviors"]}


def _frame(motion, time: float) -> int:
    return int(round((time - motion.start_time) * motion.fps))


def _head_turn(motion, start: float, end: float) -> float:
    """The largest angle (°) the skull turns from where it is at ``start`` until ``end``."""
    frames = np.arange(_frame(motion, start), _frame(motion, end) + 1)
    _, orientations = joint_frames(motion, frames)
    skull = orientations[motion.joint_names.index("skullbase")]
    return float(np.degrees(np.max((skull[0].inv() * skull).magnitude())))


@pytest.mark.parametrize("lexeme", ["NOD", "SHAKE", "TILT"])
def test_a_head_lexeme_moves_the_head_at_its_stroke(agent, lexeme):
    """Still until shortly before the stroke (a held tilt is reached by then), turned by
    more than 5° from there until after its end."""
    performance, behaviors = _render(agent, f'<head id="h1" lexeme="{lexeme}" stroke="s1:tm2"/>')
    phases = behaviors["h1"]["phases"]
    assert behaviors["h1"]["performed"]
    before = _head_turn(performance.motion, phases["start"], phases["stroke_start"] - 0.5)
    during = _head_turn(performance.motion, phases["stroke_start"] - 0.5, phases["end"] + 0.6)
    assert before < 1.0 and during > 5.0, (before, during)


def _yaw_reversals(agent, count: int) -> int:
    performance, behaviors = _render(agent, f'<head id="h1" lexeme="SHAKE" repetition="{count}" stroke="s1:tm1"/>')
    phases = behaviors["h1"]["phases"]
    motion = performance.motion
    frames = np.arange(_frame(motion, phases["stroke_start"]), min(_frame(motion, phases["end"] + 3.0), motion.frame_count))
    _, orientations = joint_frames(motion, frames)
    yaw = orientations[motion.joint_names.index("skullbase")].as_rotvec()[:, 1]
    turning = np.sign(np.diff(yaw))
    turning = turning[turning != 0]
    return int(np.sum(turning[1:] != turning[:-1]))


def test_head_repetitions_make_more_swings(agent):
    once, thrice = _yaw_reversals(agent, 1), _yaw_reversals(agent, 3)
    assert thrice >= once + 4, (once, thrice)


@pytest.mark.parametrize("place", ["Loc-Bar_1", "Loc-Bar_2"])
def test_gaze_puts_the_eyes_on_the_target(agent, place):
    performance, behaviors = _render(agent, f'<gaze id="z1" target="{place}" ready="s1:tm2" relax="s1:tm3"/>')
    ready = behaviors["z1"]["phases"]["ready"]
    assert max(gaze_errors(performance.motion, ready + 0.05, place, PLACES).values()) < 5.0


def test_face_lexeme_raises_its_weights_between_attack_peak_and_relax(agent):
    performance, behaviors = _render(agent, '<faceLexeme id="f1" lexeme="RAISE_BROWS" attackPeak="s1:tm1" relax="s1:tm3"/>')
    phases = behaviors["f1"]["phases"]
    motion = performance.motion
    brows = np.asarray(motion.face_weights)[:, list(motion.face_names).index("browInnerUp")]
    assert brows[_frame(motion, phases["start"])] < 0.05
    assert brows[_frame(motion, 0.5 * (phases["ready"] + phases["relax"]))] > 0.5
