"""The agent-facing API: give it an utterance, get speech and motion.

``Agent.render(xml)`` performs an utterance offline on a virtual clock and returns a
:class:`Performance` (deterministic with the fake speech backend); ``Agent.render_files``
writes the same performance straight to files in bounded memory, for any length. ``Agent.say(xml)``
performs it live on the wall clock: speech plays through the audio device when one is
there, frames go to whoever subscribed (the browser page of ``mura play``), utterances
said while one plays are queued and join it fluently, and ``interrupt()`` ends the
current gesture gracefully.
"""

from __future__ import annotations

import os
import queue
import sys
import threading
from collections.abc import Callable

import numpy as np

from agent.performance import Performance, PerformanceError, SavedFiles, rest_motion
from agent.sources import UtteranceSource, read_utterance
from agent.streaming import render_to_files
from blackboard.clock import VirtualClock, WallClock
from blackboard.events import Event, SpeechStarted
from blackboard.scheduler import (
    LiveHandle,
    ScheduledUtterance,
    Scheduler,
    SchedulerConfig,
)
from motor.body.avatar import Avatar, load_avatar
from motor.control import MotorControl
from mura.lexicon import GestureLexicon
from tts import SpeechSynthesizer, make_synthesizer
from tts.playback import PlaybackUnavailable, make_player


class Agent:
    """A speaking, gesturing agent on one avatar with one speech backend.

    Args:
        avatar: an avatar name from ``specs/avatars`` or a loaded :class:`Avatar`.
        tts: ``"fake"``, ``"espeak"``, ``"pyttsx3"``, ``"default"`` or a synthesizer.
        fps: frame rate of the motion, frames per second.
        voice, rate: passed to the speech backend.
        lexicon: the gesture lexicon functions are looked up in (the bundled one when None;
            see :func:`mura.lexicon.load_lexicons`).
    """

    def __init__(
        self,
        avatar: str | Avatar = "max",
        tts: str | SpeechSynthesizer = "fake",
        fps: float = 60.0,
        voice: str | None = None,
        rate: float = 1.0,
        lexicon: GestureLexicon | None = None,
    ) -> None:
        self.lexicon = lexicon
        self.avatar = load_avatar(avatar) if isinstance(avatar, str) else avatar
        self.tts = make_synthesizer(tts) if isinstance(tts, str) else tts
        self.fps = float(fps)
        self.config = SchedulerConfig(voice=voice, rate=rate)
        self._live: Scheduler | None = None
        self._live_lock = threading.Lock()
        self._observers: list[Callable[[Event], None]] = []

    def render(self, utterance: UtteranceSource, name: str | None = None) -> Performance:
        """Perform ``utterance`` offline; raises :class:`SpecError` for a bad spec and
        :class:`PerformanceError` (with the part performed) when a chunk fails."""
        model, default_name = read_utterance(utterance, self.lexicon)
        scheduler = Scheduler(self.tts, MotorControl(self.avatar, self.fps), VirtualClock(), self.config)
        try:
            result = scheduler.run(model, name or default_name)
        finally:
            scheduler.close()
        return _performance(result, name or default_name, self.avatar, self.fps)

    def render_files(
        self, utterance: UtteranceSource, directory: str | os.PathLike[str], name: str | None = None, glb: bool = False
    ) -> SavedFiles:
        """Perform ``utterance`` offline straight into NAME.wav, .bvh, .timeline.json and .html
        (and NAME.glb with ``glb``) in ``directory``, in memory that does not grow with its
        length; the files equal ``render(...).save(directory)``'s. Raises as :meth:`render`
        does (``partial`` None)."""
        model, default_name = read_utterance(utterance, self.lexicon)
        return render_to_files(model, directory, self.tts, self.avatar, self.fps, self.config, name or default_name, glb=glb)

    def subscribe(self, observer: Callable[[Event], None]) -> None:
        """Receive every event of live utterances (chunk states, feedback, frames)."""
        self._observers.append(observer)
        if self._live is not None:
            self._live.subscribe(observer)

    def say(self, utterance: UtteranceSource, name: str | None = None, audio: bool = True) -> LiveUtterance:
        """Perform ``utterance`` live; returns at once with a handle to wait on or interrupt."""
        model, default_name = read_utterance(utterance, self.lexicon)
        scheduler = self._live_scheduler(audio)
        handle = scheduler.start(model, name or default_name)
        return LiveUtterance(handle, name or default_name, self.avatar, self.fps)

    def close(self) -> None:
        """Wait for live utterances to end and release the live scheduler."""
        with self._live_lock:
            if self._live is not None:
                self._live.close()
                self._live = None

    def _live_scheduler(self, audio: bool) -> Scheduler:
        with self._live_lock:
            if self._live is None:
                self._live = Scheduler(self.tts, MotorControl(self.avatar, self.fps), WallClock(), self.config)
                for observer in self._observers:
                    self._live.subscribe(observer)
                if audio:
                    self._live.subscribe(SpeechPlayer())
            return self._live


class LiveUtterance:
    """A live utterance: ``wait()`` gives its :class:`Performance`, ``interrupt()`` ends it."""

    def __init__(self, handle: LiveHandle, name: str, avatar: Avatar, fps: float) -> None:
        self._handle = handle
        self.name = name
        self._avatar = avatar
        self._fps = fps

    def wait(self, timeout: float | None = None) -> Performance:
        """Block until the utterance has been performed (or interrupted)."""
        return _performance(self._handle.wait(timeout), self.name, self._avatar, self._fps, allow_partial=True)

    def interrupt(self) -> None:
        """Retract from where the arms are and drop the chunks not yet begun."""
        self._handle.interrupt()


class SpeechPlayer:
    """An observer that plays each chunk's speech when the scheduler starts it.

    Playback blocks for as long as the audio lasts, so it runs in a worker thread of its
    own and the scheduler never waits on it. The first time no audio device can play, it
    says so once on stderr and stays silent; the schedule runs on regardless.
    """

    def __init__(self, backend: str | None = None) -> None:
        self.problem: str | None = None
        self._backend = backend
        self._queue: queue.Queue[tuple[np.ndarray, int]] = queue.Queue()
        self._worker = threading.Thread(target=self._play_queued, name="speech-player", daemon=True)
        self._worker.start()

    def __call__(self, event: Event) -> None:
        if isinstance(event, SpeechStarted) and event.audio is not None and self.problem is None:
            self._queue.put((event.audio, event.sample_rate))

    def _play_queued(self) -> None:
        player = None
        while True:
            samples, rate = self._queue.get()
            if self.problem is not None:
                continue
            try:
                player = player or make_player(self._backend)
                player.play(samples, rate)
            except PlaybackUnavailable as error:
                self.problem = str(error)
                print(f"mura: speech not played: {error}", file=sys.stderr)


def _performance(result: ScheduledUtterance, name: str, avatar: Avatar, fps: float, allow_partial: bool = False) -> Performance:
    motion = result.motion if result.motion is not None else rest_motion(avatar, fps)
    audio = result.audio
    performance = Performance(
        name=name,
        timeline=result.timeline.to_json(),
        motion=motion,
        audio=audio.astype(np.int16) if audio is not None else None,
        sample_rate=int(result.sample_rate or 22050),
        warnings=tuple(result.warnings),
        avatar=avatar,
    )
    if result.error is not None and not allow_partial:
        raise PerformanceError(f"chunk {result.failed_chunk} failed: {result.error}", performance)
    return performance


__all__ = ["Agent", "LiveUtterance", "Performance", "PerformanceError", "SpeechPlayer", "read_utterance", "rest_motion"]
