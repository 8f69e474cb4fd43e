"""The live path: ``Agent.say`` performs on the wall clock, streams frames, can be interrupted."""

import threading

import numpy as np
import pytest

from agent import Agent
from blackboard.events import ChunkStateChanged, FramesReady, SpeechStarted

SHORT = """<utterance><specification>Take <time id="t1"/> this <time id="t2"/></specification>
<behaviorspec id="point"><gesture><affiliate onset="t1" end="t2"/>
<function name="refer_to_loc"><param name="refloc" value="$Loc-Bar_1"/></function></gesture></behaviorspec></utterance>"""


@pytest.fixture
def agent():
    live = Agent(tts="fake", fps=30)
    yield live
    live.close()


def test_say_streams_frames_and_returns_the_performance(agent):
    events = []
    lock = threading.Lock()

    def observe(event):
        with lock:
            events.append(event)

    agent.subscribe(observe)
    performance = agent.say(SHORT, name="short", audio=False).wait(timeout=30)
    frames = [e for e in events if isinstance(e, FramesReady)]
    assert frames and all(np.all(np.isfinite(e.motion.rotations)) for e in frames)
    assert any(isinstance(e, SpeechStarted) and e.audio is not None for e in events)
    states = [e.state.name for e in events if isinstance(e, ChunkStateChanged)]
    assert states[0] == "IN_PREP" and states[-1] == "COMPLETED"
    assert performance.name == "short"
    assert performance.timeline["behaviors"][0]["id"] == "point"
    assert performance.motion.frame_count > 0


def test_interrupt_ends_the_utterance_early(agent):
    live = agent.say(SHORT, name="cut", audio=False)
    live.interrupt()
    performance = live.wait(timeout=30)
    assert performance.duration < 5.0
    assert np.all(np.isfinite(performance.motion.rotations))
