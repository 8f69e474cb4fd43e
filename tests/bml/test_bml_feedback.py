"""BML feedback as Python events on ``Agent``: predictions before the block starts, sync
points as they pass at the predicted times, block end with its status; composition
(REPLACE interrupts, MERGE while busy is queued with a warning); a block id in use is refused.

Live runs on a clock eight times faster than real time, fake speech, no audio device."""

from __future__ import annotations

import threading

import pytest

from agent import Agent
from blackboard.feedback import BlockProgress, PredictionFeedback, SyncPointProgress, WarningFeedback
from mura.errors import SpecError

NS = 'xmlns="http://www.bml-initiative.org/bml/bml-1.0"'
TIMEOUT = 60.0
FRAME = 1.0 / 60.0


def block(block_id: str, composition: str = "APPEND", words: str = "Take <sync id=\"tm1\"/> this bar.") -> str:
    return (f'<bml {NS} id="{block_id}" composition="{composition}"><speech id="s1"><text>{words}</text></speech>'
            f'<gesture id="g1" lexeme="BEAT" stroke="s1:tm1"/><faceFacs id="z1" au="1" start="g1:stroke"/></bml>')


class Recorder:
    """Collects BML feedback; ``wait_for`` blocks until a matching event has arrived."""

    def __init__(self) -> None:
        self.events: list = []
        self._changed = threading.Condition()

    def __call__(self, event) -> None:
        if isinstance(event, (BlockProgress, SyncPointProgress, PredictionFeedback, WarningFeedback)):
            with self._changed:
                self.events.append(event)
                self._changed.notify_all()

    def wait_for(self, match) -> None:
        with self._changed:
            assert self._changed.wait_for(lambda: any(match(e) for e in self.events), TIMEOUT)

    def of(self, block_id: str) -> list:
        return [e for e in self.events if e.block == block_id]


@pytest.fixture
def live():
    agent = Agent(tts="fake", speedup=8.0)
    recorder = Recorder()
    agent.subscribe(recorder)
    yield agent, recorder
    agent.interrupt()
    agent.close()


def test_feedback_order_and_predicted_times(live):
    agent, recorder = live
    agent.say(block("b1"), audio=False).wait(TIMEOUT)
    events = recorder.of("b1")
    kinds = [type(e).__name__ for e in events]
    assert kinds[0] == "WarningFeedback" and events[0].kind == "NOT_PERFORMED" and events[0].where.startswith("<utterance>:1:")
    prediction = kinds.index("PredictionFeedback")
    start = next(i for i, e in enumerate(events) if isinstance(e, BlockProgress) and e.point == "start")
    syncs = [i for i, e in enumerate(events) if isinstance(e, SyncPointProgress)]
    assert prediction < start < min(syncs)
    assert isinstance(events[-1], BlockProgress) and events[-1].point == "end" and events[-1].status == "DONE"
    predicted = events[prediction].behaviors
    for event in (events[i] for i in syncs):
        assert event.time == pytest.approx(predicted[event.behavior][event.sync], abs=FRAME), event.id
    assert "z1" in predicted and not any(isinstance(e, SyncPointProgress) and e.behavior == "z1" for e in events)


def test_replace_interrupts_and_starts_after(live):
    agent, recorder = live
    agent.say(block("long", words="A long sentence <sync id=\"tm1\"/> that goes on and on for quite some time yet."), audio=False)
    recorder.wait_for(lambda e: isinstance(e, SyncPointProgress) and e.block == "long")
    agent.say(block("short", "REPLACE"), audio=False).wait(TIMEOUT)
    ends = [e for e in recorder.events if isinstance(e, BlockProgress)]
    order = [(e.block, e.point, e.status) for e in ends]
    assert order == [("long", "start", ""), ("long", "end", "INTERRUPTED"), ("short", "start", ""), ("short", "end", "DONE")]


def test_merge_while_busy_is_queued_with_a_warning(live):
    agent, recorder = live
    agent.say(block("one"), audio=False)
    recorder.wait_for(lambda e: isinstance(e, BlockProgress) and e.block == "one")
    agent.say(block("two", "MERGE"), audio=False).wait(TIMEOUT)
    warning = next(e for e in recorder.of("two") if isinstance(e, WarningFeedback) and e.kind == "MERGE_QUEUED")
    assert "starts after one" in warning.message
    # queued blocks join fluently: the next starts once the speech and strokes are over (its
    # preparation may cut the previous retraction), so "one" ends after its speech and relax
    one_done = max(i for i, e in enumerate(recorder.events) if isinstance(e, SyncPointProgress) and e.block == "one" and (e.behavior, e.sync) in (("s1", "end"), ("g1", "relax")))
    two_start = next(i for i, e in enumerate(recorder.events) if isinstance(e, BlockProgress) and e.id == "two:start")
    assert one_done < two_start
    assert any(isinstance(e, BlockProgress) and e.id == "one:end" and e.status == "DONE" for e in recorder.events)


def test_a_block_id_in_use_is_refused(live):
    agent, _ = live
    agent.say(block("same"), audio=False)
    with pytest.raises(SpecError, match="'same' is still being performed"):
        agent.say(block("same"), audio=False)

