"""Head lexemes and the attack–sustain–release envelope, as the constructors a realizer calls."""

from __future__ import annotations

import numpy as np
import pytest
from face_helpers import frame_at, phases
from test_nonmanual import head_angles

from agent.agent import Agent
from motor.neck.lexemes import HEAD_LEXEMES, UnknownHeadLexeme, head_lexeme, lexeme_named, natural_duration
from motor.trajectory.envelope import Envelope
from mura.murml import parse_utterance


@pytest.mark.parametrize(
    ("name", "lexeme"),
    [("NOD", "NOD"), ("nod", "NOD"), ("Nodding", "NOD"), ("SH", "SHAKE"), ("TiltLeft", "TILT_LEFT"), ("tilt_right", "TILT_RIGHT"),
     ("TILT", "TILT_RIGHT"), ("Up", "TILT_BACK"), ("NF", "TILT_FORWARD"), ("PF", "PUSH_FORWARD"), ("turn-left", "TURN_LEFT")],
)  # fmt: skip
def test_names_aliases_and_hamnosys_codes(name, lexeme):
    assert lexeme_named(name).name == lexeme


def test_an_unknown_lexeme_names_the_known_ones():
    with pytest.raises(UnknownHeadLexeme, match="'WOBBLE'.*NOD.*SHAKE"):
        lexeme_named("WOBBLE")


@pytest.mark.parametrize(("name", "repetitions", "one_sided"), [("NOD", None, True), ("NOD", 3, True), ("SHAKE", None, False), ("SHAKE", 2, False)])
def test_swings_count_and_side(name, repetitions, one_sided):
    lmp = head_lexeme(name, 1.0, repetitions=repetitions)
    assert lmp.end - lmp.start == pytest.approx(natural_duration(lmp.lexeme, repetitions))
    times = np.linspace(0.5, lmp.end + 0.5, 4001)
    angle = lmp.sample(times)[:, :3] @ np.asarray(lmp.lexeme.axis)
    peaks = np.flatnonzero((angle[1:-1] > angle[:-2]) & (angle[1:-1] >= angle[2:]) & (angle[1:-1] > 0.3 * lmp.lexeme.angle))
    assert len(peaks) == (repetitions or lmp.lexeme.swings)
    assert (angle.min() >= -1e-12) == one_sided
    assert angle[times < 1.0].max() == 0.0 and angle[times > lmp.end].max() == 0.0


@pytest.mark.parametrize("amount", [0.5, 1.0, 1.6])
def test_a_held_tilt_rises_holds_and_falls(amount):
    lmp = head_lexeme("TILT_LEFT", 1.0, 2.0, amount=amount)
    angle = -lmp.sample(np.array([0.5, 0.9, 1.0, 1.5, 2.0, 2.1, 3.0]))[:, 2]
    peak = amount * HEAD_LEXEMES["TILT_LEFT"].angle
    assert angle[0] == 0.0 and 0.0 < angle[1] < peak and angle[2:5] == pytest.approx([peak] * 3) and 0.0 < angle[5] < peak and angle[6] == 0.0


@pytest.mark.parametrize("manner", ["targetted", "lax", "fast", "tense"])
def test_envelopes_rise_monotonically_and_hold(manner):
    envelope = Envelope.around(1.0, 2.0, 0.3, 0.4, manner)
    times = np.linspace(0.0, 3.0, 3001)
    amount = envelope.sample(times)
    rising, falling = amount[(times >= 0.7) & (times <= 1.0)], amount[(times >= 2.0) & (times <= 2.4)]
    assert np.all(np.diff(rising) >= 0) and np.all(np.diff(falling) <= 0)
    assert amount[(times >= 1.0) & (times <= 2.0)].min() == pytest.approx(1.0)
    assert amount[(times < 0.7) | (times > 2.4)].max() == 0.0


def _murml(neck: str, repetitions: int = 1) -> str:
    leaf = f'<static slot="Neck" value="{neck}" scope="head"/>'
    if repetitions > 1:
        leaf = f'<repetition count="{repetitions}">{leaf}</repetition>'
    return f"""<utterance><specification>Yes <time id="a"/> indeed, that is right. <time id="b"/></specification>
      <behaviorspec id="h"><gesture><affiliate onset="a" end="b"/><constraints>{leaf}</constraints></gesture></behaviorspec></utterance>"""


@pytest.mark.parametrize("repetitions", [1, 3])
def test_a_murml_neck_nod_swings_over_the_stroke(repetitions):
    performance = Agent(avatar="max", tts="fake", fps=60).render(parse_utterance(_murml("Nod", repetitions), file="nod.xml"), name="nod")
    motion = performance.motion
    pitch = head_angles(motion)[:, 0]
    p = phases(performance, "h")
    inside = slice(frame_at(motion, p["stroke_start"]), frame_at(motion, max(p["stroke_end"], p["stroke_start"] + 2.0)))
    stroke = pitch[inside]
    dips = np.flatnonzero((stroke[1:-1] > stroke[:-2]) & (stroke[1:-1] >= stroke[2:]) & (stroke[1:-1] > 5.0))
    assert len(dips) == 2 * repetitions


def test_an_unknown_neck_lexeme_warns_where_and_leaves_the_head():
    performance = Agent(avatar="max", tts="fake", fps=60).render(parse_utterance(_murml("Wobble"), file="nod.xml"), name="nod")
    (warning,) = [w for w in performance.warnings if "Wobble" in w]
    assert "nod.xml:2:" in warning and "does not move" in warning
