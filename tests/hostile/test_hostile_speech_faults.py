"""Item 10: speech faults during live utterances.

Before: a SpeechError on chunk 2 during ``Agent.say`` made ``wait()`` return the partial
performance without saying so; another exception type lost the partial; a hung backend
could not be interrupted (``wait(10)`` timed out); a missing espeak-ng data folder was a
RuntimeError traceback even with ``--tts default``; one ``speech-player`` thread leaked
per Agent with audio.
"""

from __future__ import annotations

import os
import threading
from pathlib import Path

import numpy as np
import pytest
from hostile_helpers import REPO, run_mura, utterance

from agent.agent import Agent, PerformanceError
from tts import FakeSynthesizer, SpeechError

FIG2 = REPO / "specs" / "utterances" / "fig2_take_this_bar.xml"
#: Two short chunks with a gesture on the first: quick on the wall clock.
TWO_CHUNKS = utterance(
    'Take <time id="t1"/> this <time id="t2" chunkborder="true"/> and go.',
    '<behaviorspec id="point"><gesture><affiliate onset="t1" end="t2"/><function name="refer_to_loc">'
    '<param name="refloc" value="$Loc-Bar_1"/></function></gesture></behaviorspec>',
)


class FailingOn(FakeSynthesizer):
    """The fake speech, raising ``error`` on call ``call``."""

    def __init__(self, call: int, error: BaseException) -> None:
        self.call, self.error, self.calls = call, error, 0

    def synthesize(self, request):
        self.calls += 1
        if self.calls == self.call:
            raise self.error
        return super().synthesize(request)


class HangingOn(FakeSynthesizer):
    """The fake speech, hanging on call ``call`` until ``release`` is set."""

    def __init__(self, call: int) -> None:
        self.call, self.calls = call, 0
        self.entered, self.release = threading.Event(), threading.Event()

    def synthesize(self, request):
        self.calls += 1
        if self.calls == self.call:
            self.entered.set()
            self.release.wait()
        return super().synthesize(request)


ERRORS = [SpeechError("the voice went away"), RuntimeError("driver crashed"), KeyError("phoneme"), ZeroDivisionError("rate"), MemoryError()]


@pytest.mark.timeout(60)
@pytest.mark.parametrize("error", ERRORS, ids=lambda e: type(e).__name__)
@pytest.mark.parametrize("mode", ["live", "offline"])
def test_a_failed_chunk_is_raised_with_the_part_performed(error, mode):
    agent = Agent(tts=FailingOn(2, error), fps=30)
    try:
        with pytest.raises(PerformanceError) as caught:
            agent.say(TWO_CHUNKS, audio=False).wait(timeout=30) if mode == "live" else agent.render(TWO_CHUNKS)
    finally:
        agent.close()
    message = str(caught.value)
    assert message.startswith("chunk 2 failed: speech of chunk 2 ('and go.') failed")
    if not isinstance(error, SpeechError):
        assert f"the fake speech backend failed: {type(error).__name__}" in message
    partial = caught.value.partial
    assert partial is not None and partial.motion.frame_count > 0 and np.all(np.isfinite(partial.motion.rotations))
    assert [chunk["index"] for chunk in partial.timeline["chunks"]] == [0, 1]
    assert partial.timeline["chunks"][1]["error"] is not None


@pytest.mark.timeout(60)
@pytest.mark.parametrize("hung_call", [1, 2])
def test_interrupt_ends_an_utterance_whose_backend_hangs(hung_call):
    baseline = set(threading.enumerate())
    backend = HangingOn(hung_call)
    agent = Agent(tts=backend, fps=30)
    live = agent.say(TWO_CHUNKS, audio=False)
    assert backend.entered.wait(timeout=30)
    live.interrupt()
    performance = live.wait(timeout=30)  # within the bound: before, wait(10) timed out
    assert live.interrupted and np.all(np.isfinite(performance.motion.rotations))
    backend.release.set()  # the backend returns at last; its abandoned worker ends
    agent.close()
    assert set(threading.enumerate()) <= baseline


@pytest.mark.timeout(60)
def test_no_thread_outlives_close():
    baseline = set(threading.enumerate())
    for _ in range(2):
        agent = Agent(tts="fake", fps=30)
        first, second = agent.say(utterance("Hi."), audio=True), agent.say(utterance("Bye."), audio=True)
        first.wait(timeout=30), second.wait(timeout=30)
        agent.close()
    assert set(threading.enumerate()) <= baseline


@pytest.fixture
def espeak_without_data(tmp_path) -> Path:
    """A copy of the installed ``espeakng_loader`` module beside its library but without
    its ``espeak-ng-data`` folder: the wheel as a broken install leaves it."""
    import espeakng_loader

    installed = Path(espeakng_loader.__file__).parent
    shim = tmp_path / "shim" / "espeakng_loader"
    shim.mkdir(parents=True)
    (shim / "__init__.py").write_text((installed / "__init__.py").read_text())
    for library in installed.glob("libespeak-ng.so*"):
        os.symlink(library.resolve(), shim / library.name)
    return shim.parent


@pytest.mark.timeout(60)
def test_missing_espeak_data_falls_back_to_the_fake_and_says_so(espeak_without_data, tmp_path):
    env = {"PYTHONPATH": f"{espeak_without_data}{os.pathsep}{REPO}"}
    said = run_mura("say", "hi", "--tts", "default", env=env)
    assert said.status == 0 and said.out.startswith("fake: 1 words")
    assert "mura say: espeak-ng unavailable (espeak-ng's data folder is missing" in said.err
    named = run_mura("say", "hi", "--tts", "espeak", env=env)
    assert named.status == 2 and named.err.startswith("mura say: espeak-ng's data folder is missing")
