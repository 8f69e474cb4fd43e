"""Small utterances written for the relaxation steps, how to perform them, and the
properties every performed timeline keeps whatever was relaxed.

Gestures come from the lexicon (``specs/lexicon/gestures.xml``) or are written inline;
the texts are tuned to the fake speech's timing so that each case needs its step.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from blackboard import RELAXATION_ORDER, Scheduler, ScheduledUtterance, VirtualClock
from motor.body.avatar import load_avatar
from motor.control import MotorControl
from motor.trajectory.speed_budget import budget
from mura.model import Affiliate, Utterance
from mura.murml import load_utterance, parse_utterance
from tts import FakeSynthesizer, SpeechSynthesizer
from tts.text import split_words

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((REPO / "specs" / "utterances").glob("*.xml"))
PUBLISHED = sorted((REPO.parent / "shared" / "corpora" / "murml").glob("*.us"))
AVATAR = load_avatar("max")
LEAD = 0.2
EPS = 1e-6

POINT = ('<behaviorspec id="{id}"><gesture><affiliate onset="{onset}" end="{end}"/>'
         '<function name="refer_to_loc"><param name="refloc" value="{where}"/></function></gesture></behaviorspec>')
FUNCTION = '<behaviorspec id="{id}"><gesture><affiliate onset="{onset}" end="{end}"/><function name="{function}"/></gesture></behaviorspec>'
HAMMER = """<behaviorspec id="{id}"><gesture><affiliate onset="{onset}" end="{end}"/><constraints><parallel>
  <static slot="HandShape" value="BSfist(ThAcr)"/><static slot="PalmOrientation" value="PalmL"/>
  <static slot="ExtFingerOrientation" value="DirA"/>
  <repetition count="3"><dynamic slot="HandLocation"><segment type="linear">
    <value type="start" name="LocUpperChest LocCenterRight LocNorm"/><value type="direction" name="DirD"/>
    <value type="distance" name="DistShort"/>
  </segment></dynamic></repetition></parallel></constraints></gesture></behaviorspec>"""
SWEEP = """<behaviorspec id="{id}"><gesture><timing onset="{onset}" end="{end}"/><constraints><parallel>
  <static slot="HandShape" value="BSflat"/>
  <dynamic slot="HandLocation"><segment type="linear">
    <value type="start" name="LocShoulder LocPeripheryLeft LocFar"/>
    <value type="end" name="LocStomach LocPeripheryRight LocNorm"/>
  </segment></dynamic></parallel></constraints></gesture></behaviorspec>"""


def point(id: str, onset: str, end: str, where: str) -> str:
    return POINT.format(id=id, onset=onset, end=end, where=where)


def function(id: str, onset: str, end: str, name: str) -> str:
    return FUNCTION.format(id=id, onset=onset, end=end, function=name)


def spec(text: str, *behaviors: str) -> str:
    """An utterance document; ``[tN]`` in ``text`` is a time tag, ``[tN|]`` one at a chunk border."""
    for k in range(1, 10):
        text = text.replace(f"[t{k}|]", f'<time id="t{k}" chunkborder="true"/>').replace(f"[t{k}]", f'<time id="t{k}"/>')
    return f"<definition><utterance><specification>{text}</specification>{''.join(behaviors)}</utterance></definition>"


@dataclass(frozen=True)
class Case:
    """An utterance written for relaxation ``step`` of behaviour ``behavior`` (amount in ``unit``)."""

    name: str
    step: str
    behavior: str
    unit: str
    document: str


CASES = (
    Case("stroke to stroke", "co_articulation", "b", "s", spec(
        "Put [t1] this [t2] right beside the [t3] other [t4] one.",
        point("a", "t1", "t2", "$Loc-Bolt_1"), point("b", "t3", "t4", "$Loc-Cube_1"))),
    Case("a quick preparation", "shorter_preparation", "a", "s", spec(
        "Well now, take [t1] this [t2] one.", point("a", "t1", "t2", "$Loc-Bolt_1"))),
    Case("the second stroke a little late", "later_stroke_onset", "b", "s", spec(
        "Put [t1] this [t2] on [t3] that [t4] one.",
        point("a", "t1", "t2", "$Loc-Bolt_1"), point("b", "t3", "t4", "$Loc-Cube_1"))),
    Case("a beat held rather than repeated", "hold_instead_of_repeat", "a", "repetitions", spec(
        "This is [t1] really very much [t2] important.", function("a", "t1", "t2", "emphasize"))),
    Case("a longer pause at the chunk border", "stretched_pause", "b", "s", spec(
        "Take [t1] this [t2|] [t3] that [t4] one.",
        point("a", "t1", "t2", "$Loc-Bolt_1"), point("b", "t3", "t4", "$Loc-Bar_2"))),
    Case("an absolute sweep too fast for its budget", "longer_stroke", "a", "s", spec(
        "Look.", SWEEP.format(id="a", onset="1.0", end="1.3"))),
    Case("hammering once less", "dropped_repetition", "a", "repetitions", spec(
        "Now [t1] hammer [t2] it in, then [t3] this [t4] one.",
        HAMMER.format(id="a", onset="t1", end="t2"), point("b", "t3", "t4", "$Loc-Bolt_1"))),
)

#: The issue's utterance: two gestures on the right arm in one chunk, affiliates about 0.5 s apart.
TWO_ON_ONE_ARM = spec("Put [t1] this [t2] on top of [t3] that [t4] shelf.",
                      point("point_this", "t1", "t2", "$Loc-Bar_1"), function("point_that", "t3", "t4", "present"))
#: Touching affiliates whose gestures point to opposite sides: no relaxation separates them.
UNSATISFIABLE = spec("Take [t1] this [t2] that [t3] one.",
                     point("a", "t1", "t2", "$Loc-Bar_1"), point("b", "t2", "t3", "$Loc-Bar_2"))


@dataclass
class Performed:
    """A performance with the motor control that made it (its planned wrist channels stay readable)."""

    utterance: Utterance
    result: ScheduledUtterance
    motor: MotorControl

    @property
    def timeline(self) -> dict:
        return self.result.timeline.to_json()


def perform(utterance: Utterance | str | Path, tts: SpeechSynthesizer | None = None) -> Performed:
    """Perform offline on avatar ``max`` at 60 fps (fake speech unless ``tts`` is given)."""
    if isinstance(utterance, Path):
        utterance = load_utterance(utterance)
    elif isinstance(utterance, str):
        utterance = parse_utterance(utterance)
    motor = MotorControl(AVATAR)
    result = Scheduler(tts or FakeSynthesizer(), motor, VirtualClock()).run(utterance, name="case")
    return Performed(utterance, result, motor)


def relaxed(behavior: dict, step: str) -> float:
    """Total amount of ``step`` taken for a behaviour of the timeline JSON (0 when not taken)."""
    return sum(r["amount"] for r in behavior["relaxations"] if r["step"] == step)


def word_onset(performed: Performed, tag: str) -> float:
    """The start of the first word after time tag ``tag``, read from the timeline's words."""
    tags = performed.utterance.time_tags
    chunk = performed.utterance.chunks[tags[tag].chunk]
    spans = split_words(chunk.text)
    words = [w for w in performed.timeline["words"] if w["chunk"] == chunk.index]
    return words[next(k for k, s in enumerate(spans) if s.start >= tags[tag].offset)]["start"]


def check_timeline(performed: Performed) -> None:
    """The constraints every performed timeline keeps, with its relaxations taken into account."""
    result = performed.result
    assert result.failed_chunk is None, result.error
    data = performed.timeline
    specs = {b.id: b for b in performed.utterance.behaviors}
    for b in data["behaviors"]:
        _check_behavior(performed, b, specs[b["id"]], data["absolute_delay"])
    _check_same_arm(data)
    _check_pauses(data)
    steps = [r["step"] for b in data["behaviors"] for r in b["relaxations"]]
    for step in set(steps):
        assert sum(step in w for w in data["warnings"]) == steps.count(step), f"one warning per {step}"


def _check_behavior(performed: Performed, b: dict, spec, delay: float) -> None:
    phases = b["phases"]
    for r in b["relaxations"]:
        assert r["amount"] > 0 and r["unit"] in ("s", "repetitions") and r["conflict"], r
    ranks = [_RANK[r["step"]] for r in b["relaxations"]]
    assert ranks == sorted(ranks), "relaxations are listed in the relaxation order"
    if isinstance(spec.timing, Affiliate):
        lead = b["affiliate"]["onset"] - phases["stroke_start"]
        assert lead == pytest.approx(LEAD - relaxed(b, "later_stroke_onset"), abs=EPS), b["id"]
        assert b["affiliate"]["onset"] == pytest.approx(word_onset(performed, spec.timing.onset), abs=EPS)
        assert phases["relax"] >= b["affiliate"]["end"] - EPS
    else:
        assert phases["stroke_start"] == pytest.approx(spec.timing.onset + delay, abs=EPS)
        assert phases["relax"] == pytest.approx(spec.timing.end + delay + relaxed(b, "longer_stroke"), abs=EPS)
        demands = performed.motor.demands(spec)
        if demands.dynamic:
            fastest = budget(demands.manner).shortest_duration(demands.stroke_distance)
            assert phases["relax"] - phases["stroke_start"] >= fastest - EPS, "an absolute stroke within its budget"
    _check_preparation_budget(performed, b, spec)


def _check_preparation_budget(performed: Performed, b: dict, spec) -> None:
    """No preparation is faster than its manner's budget for the distance the planned wrist travels."""
    start, onset = b["phases"]["start"], b["phases"]["stroke_start"]
    manner = performed.motor.demands(spec).manner
    for arm in b["arms"]:
        channel = performed.motor.timeline((arm, "wrist_position"))
        here, there = (np.asarray(channel.state(t).value) for t in (start, onset))
        distance = float(np.linalg.norm(there - here))
        assert onset - start >= budget(manner).shortest_duration(distance) - 1e-3, (b["id"], arm, distance, onset - start)


def _check_same_arm(data: dict) -> None:
    for chunk in {b["chunk"] for b in data["behaviors"]}:
        gestures = sorted((b for b in data["behaviors"] if b["chunk"] == chunk), key=lambda b: b["phases"]["stroke_start"])
        for k, later in enumerate(gestures):
            for earlier in gestures[:k]:
                if set(earlier["arms"]) & set(later["arms"]):
                    assert later["phases"]["start"] >= earlier["phases"]["relax"] - EPS, (earlier["id"], later["id"])


def _check_pauses(data: dict) -> None:
    stretched = {s["chunk"]: s["amount"] for s in data["stretches"]}
    chunks = [c for c in data["chunks"] if c["speech_onset"] is not None]
    for previous, chunk in zip(chunks, chunks[1:]):
        if previous["speech_end"] > previous["speech_onset"]:
            gap = chunk["speech_onset"] - previous["speech_end"]
            assert gap == pytest.approx(0.25 + stretched.get(chunk["index"], 0.0), abs=EPS)


_RANK = {step.value: step.rank for step in RELAXATION_ORDER}
