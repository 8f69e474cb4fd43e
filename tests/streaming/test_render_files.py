"""Streaming render: the same bytes as Performance.save, no complete-looking files after a
failure, and a scheduler that keeps no output when asked not to."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

import agent.streaming as streaming
from agent.agent import Agent, PerformanceError
from agent.cli import main
from agent.performance import SILENT_RATE
from blackboard.clock import VirtualClock
from blackboard.events import FramesReady, SpeechStarted
from blackboard.scheduler import Scheduler
from motor.control import MotorControl
from mura.murml import load_utterance
from tts import SpeechError
from tts.fake import FakeSynthesizer
from tts.wav import read_wav

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((REPO / "specs" / "utterances").glob("*.xml"))
SUFFIXES = (".wav", ".bvh", ".timeline.json", ".face.json", ".html")


class FailingSpeech:
    """The fake speech backend, failing on call number ``fail_on`` (1-based)."""

    def __init__(self, fail_on: int) -> None:
        self.fake = FakeSynthesizer()
        self.fail_on = fail_on
        self.calls = 0

    def available(self) -> bool:
        return True

    def synthesize(self, request):
        self.calls += 1
        if self.calls == self.fail_on:
            raise SpeechError("the speech engine went away")
        return self.fake.synthesize(request)


def files_in(folder: Path) -> list[str]:
    return sorted(path.name for path in folder.iterdir())


@pytest.fixture(scope="module")
def agent() -> Agent:
    return Agent(avatar="max", tts="fake", fps=60)


@pytest.mark.parametrize("example", EXAMPLES, ids=[path.stem for path in EXAMPLES])
def test_streamed_files_equal_saved_files(agent, example, tmp_path):
    saved = agent.render(example).save(tmp_path / "saved")
    streamed = agent.render_files(example, tmp_path / "streamed")
    for suffix in SUFFIXES:
        name = f"{example.stem}{suffix}"
        assert (tmp_path / "streamed" / name).read_bytes() == (tmp_path / "saved" / name).read_bytes(), name
    assert files_in(tmp_path / "streamed") == files_in(tmp_path / "saved")
    assert streamed.duration == saved.duration and streamed.warnings == saved.warnings
    assert streamed.html == tmp_path / "streamed" / f"{example.stem}.html"


@pytest.mark.parametrize("fps", [25.0, 30.0])
def test_streamed_files_equal_at_other_frame_rates(fps, tmp_path):
    agent = Agent(fps=fps)
    example = REPO / "specs" / "utterances" / "fig2_take_this_bar.xml"
    agent.render(example).save(tmp_path / "saved")
    agent.render_files(example, tmp_path / "streamed", name="fig2_take_this_bar")
    for suffix in SUFFIXES:
        name = f"fig2_take_this_bar{suffix}"
        assert (tmp_path / "streamed" / name).read_bytes() == (tmp_path / "saved" / name).read_bytes(), name


def test_gesture_only_utterance_gets_a_silent_track(agent, tmp_path):
    xml = """<definition><utterance><behaviorspec id="g1"><gesture>
      <constraints><static slot="HandShape" value="BSifinger"/></constraints></gesture>
      <timing onset="0.2" end="0.8"/></behaviorspec></utterance></definition>"""
    agent.render(xml, name="silent").save(tmp_path / "saved")
    agent.render_files(xml, tmp_path / "streamed", name="silent")
    for suffix in SUFFIXES:
        assert (tmp_path / "streamed" / f"silent{suffix}").read_bytes() == (tmp_path / "saved" / f"silent{suffix}").read_bytes()
    samples, rate = read_wav(tmp_path / "streamed" / "silent.wav")
    assert rate == SILENT_RATE and len(samples) > 0 and not samples.any()


def test_speech_failing_in_chunk_two_leaves_no_files(tmp_path):
    agent = Agent(tts=FailingSpeech(fail_on=2))
    with pytest.raises(PerformanceError, match="chunk 2 failed: .*went away") as caught:
        agent.render_files(REPO / "specs" / "utterances" / "fig2_take_this_bar.xml", tmp_path)
    assert caught.value.partial is None
    assert files_in(tmp_path) == []


@pytest.mark.parametrize("stage", ["frames", "speech", "page"])
def test_write_error_leaves_no_files(agent, monkeypatch, tmp_path, stage):
    def disk_full(*args, **kwargs):
        raise OSError(28, "No space left on device")

    if stage == "frames":
        monkeypatch.setattr(streaming.StreamingBvh, "add", disk_full)
    elif stage == "speech":
        monkeypatch.setattr(streaming.StreamingWav, "add", disk_full)
    else:
        monkeypatch.setattr(streaming, "write_html_stream", disk_full)
    with pytest.raises(OSError, match="No space left"):
        agent.render_files(EXAMPLES[0], tmp_path)
    assert files_in(tmp_path) == []


def test_failure_keeps_earlier_complete_files_untouched(agent, monkeypatch, tmp_path):
    agent.render_files(EXAMPLES[0], tmp_path)
    before = {name: (tmp_path / name).read_bytes() for name in files_in(tmp_path)}

    def disk_full(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(streaming, "write_html_stream", disk_full)
    with pytest.raises(OSError):
        agent.render_files(EXAMPLES[0], tmp_path)
    assert {name: (tmp_path / name).read_bytes() for name in files_in(tmp_path)} == before


def test_bad_spec_writes_nothing(agent, tmp_path):
    from mura.errors import SpecError

    with pytest.raises(SpecError):
        agent.render_files("<definition><utterance><specification>hi <time id=", tmp_path / "out")
    assert not (tmp_path / "out").exists() or files_in(tmp_path / "out") == []


def run_scheduler(keep_output: bool, example: Path):
    agent = Agent()
    events = []
    config = dataclasses.replace(agent.config, keep_output=keep_output)
    scheduler = Scheduler(agent.tts, MotorControl(agent.avatar, agent.fps), VirtualClock(), config)
    scheduler.subscribe(events.append)
    try:
        return scheduler.run(load_utterance(example), example.stem), events
    finally:
        scheduler.close()


@pytest.mark.parametrize("example", EXAMPLES[:3], ids=[path.stem for path in EXAMPLES[:3]])
def test_scheduler_without_output_keeps_no_motion_or_audio(example):
    kept, kept_events = run_scheduler(True, example)
    streamed, events = run_scheduler(False, example)
    assert streamed.motion is None and streamed.audio is None
    assert streamed.sample_rate == kept.sample_rate
    assert streamed.timeline.duration == kept.timeline.duration
    windows = [e.motion.rotations for e in events if isinstance(e, FramesReady)]
    assert np.array_equal(np.concatenate(windows), kept.motion.rotations)
    speech = [e for e in events if isinstance(e, SpeechStarted)]
    assert speech and all(e.audio is not None for e in speech)
    assert len(speech) == len([e for e in kept_events if isinstance(e, SpeechStarted)])


def test_scheduler_without_output_drops_published_audio(monkeypatch):
    boards = []
    original = Scheduler._start_speech

    def remember(self, job, board, onset):
        original(self, job, board, onset)
        boards.append(board)

    monkeypatch.setattr(Scheduler, "_start_speech", remember)
    run_scheduler(False, EXAMPLES[0])
    assert boards and all(board.speech.audio is None and board.speech.words for board in boards)


def test_mura_render_streams_the_same_files(agent, tmp_path, capsys):
    example = EXAMPLES[0]
    assert main(["render", str(example), "-o", str(tmp_path / "cli"), "--fps", "60", "--avatar", "max"]) == 0
    agent.render(example).save(tmp_path / "saved")
    for suffix in SUFFIXES:
        name = f"{example.stem}{suffix}"
        assert (tmp_path / "cli" / name).read_bytes() == (tmp_path / "saved" / name).read_bytes()
    assert f"-> {tmp_path / 'cli' / example.stem}.html" in capsys.readouterr().out


def test_error_while_closing_after_a_failure_does_not_hide_it(agent, monkeypatch, tmp_path):
    def finish_fails(self, duration):
        raise OSError(5, "Input/output error")

    def close_fails(self):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(streaming.StreamingWav, "finish", finish_fails)
    monkeypatch.setattr(streaming.StreamingWav, "close", close_fails)
    with pytest.raises(OSError, match="Input/output error"):
        agent.render_files(EXAMPLES[0], tmp_path)
    assert files_in(tmp_path) == []
