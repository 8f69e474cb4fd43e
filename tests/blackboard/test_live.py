"""The same scheduler on a wall clock running 20× faster than real time (short live runs)."""

from __future__ import annotations

import threading
import time

import pytest
from blackboard_fakes import UTTERANCES, FakeMotor, RecordingSpeech, utterance

from blackboard import (
    ChunkState,
    ChunkStateChanged,
    Scheduler,
    SchedulerConfig,
    WallClock,
)

SPEEDUP = 20.0
CONFIG = SchedulerConfig(live_margin=1.0)  # clock seconds planning may take: 50 ms of wall time at 20×


class SlowSpeech(RecordingSpeech):
    """Fake speech that takes 20 ms of wall time, so that planning visibly overlaps execution."""

    def synthesize(self, request):
        time.sleep(0.02)
        return super().synthesize(request)


def live(speech=None, motor=None):
    return Scheduler(speech or RecordingSpeech(), motor or FakeMotor(), WallClock(SPEEDUP), CONFIG)


def test_the_next_chunk_is_planned_while_the_current_one_executes():
    scheduler = live(SlowSpeech())
    states: dict[int, ChunkState] = {}
    seen = []

    def observe(event):
        if isinstance(event, ChunkStateChanged):
            if event.chunk == 1 and event.state in (ChunkState.IN_PREP, ChunkState.PENDING):
                seen.append((event.state, states.get(0)))
            states[event.chunk] = event.state

    scheduler.subscribe(observe)
    result = scheduler.start(utterance("fig2_take_this_bar.xml"), name="fig2").wait(timeout=10)
    assert seen == [(ChunkState.IN_PREP, ChunkState.IN_EXEC), (ChunkState.PENDING, ChunkState.IN_EXEC)]
    assert result.failed_chunk is None


@pytest.mark.parametrize("path", UTTERANCES, ids=lambda p: p.stem)
def test_playback_never_waits_on_planning(path):
    result = live().start(utterance(path.name), name=path.stem).wait(timeout=10)
    data = result.timeline.to_json()
    assert result.failed_chunk is None, result.error
    assert [s["chunk"] for s in data["slack"]] == [c["index"] for c in data["chunks"]]
    assert all(s["slack"] > 0 for s in data["slack"]), data["slack"]
    assert not [w for w in data["warnings"] if "late" in w]
    for b in data["behaviors"]:
        lead = 0.0 if b["affiliate"].get("absolute") else 0.2
        assert b["affiliate"]["onset"] - b["phases"]["stroke_start"] == pytest.approx(lead, abs=1e-3)


def test_interrupt_retracts_and_drops_the_pending_chunks():
    motor = FakeMotor()
    scheduler = live(motor=motor)
    executing = threading.Event()
    scheduler.subscribe(lambda e: executing.set() if isinstance(e, ChunkStateChanged) and e.state is ChunkState.IN_EXEC else None)
    handle = scheduler.start(utterance("fig2_take_this_bar.xml"), name="fig2")
    assert executing.wait(timeout=5)
    handle.interrupt()
    result = handle.wait(timeout=10)
    chunks = result.timeline.to_json()["chunks"]
    assert motor.interrupts
    assert [s["state"] for s in chunks[0]["states"]][-2:] == ["Subsiding", "Completed"]
    assert chunks[0]["states"][-2]["reason"] == "interrupted"
    assert all(c["states"][-1]["state"] == "Failed" for c in chunks[1:])
    assert result.timeline.to_json()["duration"] < 4.0


def test_queued_utterances_join_like_chunks():
    speech = RecordingSpeech()
    scheduler = live(speech)
    first = scheduler.start(utterance("fig2_take_this_bar.xml"), name="first")
    second = scheduler.start(utterance("circle_wheel.xml"), name="second")
    a, b = first.wait(timeout=10).timeline.to_json(), second.wait(timeout=10).timeline.to_json()
    assert [r.final for r in speech.requests] == [False, False, True]
    a_end = a["origin"] + a["chunks"][-1]["speech_end"]
    b_onset = b["origin"] + b["chunks"][0]["speech_onset"]
    assert b_onset >= a_end + 0.25 - 1e-6
    # planned while the first one still played
    assert b["origin"] + b["chunks"][0]["states"][0]["time"] < a["origin"] + a["chunks"][-1]["states"][-1]["time"]


def test_interrupting_a_queued_utterance_drops_it_before_it_starts():
    scheduler = live()
    first = scheduler.start(utterance("circle_wheel.xml"), name="first")
    second = scheduler.start(utterance("fig2_take_this_bar.xml"), name="second")
    second.interrupt()
    assert first.wait(timeout=10).failed_chunk is None
    dropped = second.wait(timeout=10)
    assert dropped.motion is None and dropped.audio is None
    assert all(c["states"][-1]["state"] == "Failed" for c in dropped.timeline.to_json()["chunks"])
    scheduler.close()
