"""The agent-facing API: give it an utterance, get speech and motion.

``Agent.render(xml)`` performs an utterance offline on a virtual clock and returns a
:class:`Performance` (deterministic with the fake speech backend); ``Agent.render_files``
writes the same performance straight to files in bounded memory, for any length. ``Agent.say(xml)``
performs it live on the wall clock: speech plays through the audio device when one is
there, frames go to whoever subscribed (the browser page of ``mura play``), utterances
said while one plays are queued and join it fluently, and ``interrupt()`` ends the
current gesture gracefully.

A BML 1.0 block given to ``say`` follows its ``composition``: ``APPEND`` and ``MERGE``
queue it (mura performs one block at a time, so a ``MERGE`` arriving while another block
plays waits for it, with a warning), ``REPLACE`` interrupts every block playing or queued
(the arms retract from where they are) and then starts. Observers receive the BML
feedback of :mod:`blackboard.feedback` (predictions, block and sync-point progress,
warnings) beside the scheduler's events.

Faults: every input is checked against the agent's :class:`~mura.limits.Limits` where it
is read; a chunk that fails (speech, planning, whatever the exception) ends its utterance
there, and ``wait()`` raises :class:`PerformanceError` carrying the part performed.
Live speech runs through :class:`~tts.interruptible.InterruptibleSynthesizer`, so an
interrupt ends even a hung speech backend's chunk at once, and ``close()`` stops every
thread the agent started.
"""

from __future__ import annotations

import itertools
import os
import queue
import sys
import threading
from collections.abc import Callable

import numpy as np

from agent.export.names import check_stem
from agent.performance import Performance, PerformanceError, SavedFiles, rest_motion
from agent.sources import UtteranceSource, read_spec, read_utterance
from agent.streaming import render_to_files
from blackboard.clock import VirtualClock, WallClock
from blackboard.events import Event, SpeechStarted
from blackboard.feedback import BmlFeedback, FeedbackTranslator, WarningFeedback
from blackboard.scheduler import (
    LiveHandle,
    ScheduledUtterance,
    Scheduler,
    SchedulerConfig,
)
from motor.body.avatar import Avatar, load_avatar
from motor.compiled import warm_up
from motor.control import MotorControl
from mura.bml import BmlBlock
from mura.errors import SourceLocation, SpecError
from mura.lexicon import GestureLexicon
from mura.limits import DEFAULT_LIMITS, Limits
from tts import SpeechSynthesizer, make_synthesizer
from tts.interruptible import CheckedSynthesizer, InterruptibleSynthesizer
from tts.playback import PlaybackUnavailable, make_player

#: Longest wait for the speech player to finish the chunk it is playing on close, seconds.
PLAYER_CLOSE_TIMEOUT = 10.0


class Agent:
    """A speaking, gesturing agent on one avatar with one speech backend.

    Args:
        avatar: an avatar name from ``specs/avatars`` or a loaded :class:`Avatar`.
        tts: ``"fake"``, ``"espeak"``, ``"pyttsx3"``, ``"default"`` or a synthesizer.
        fps: frame rate of the motion, frames per second (within ``limits``).
        voice, rate: passed to the speech backend (``rate`` within ``limits``).
        speedup: how much faster than real time the live clock runs (1: real time; more
            for previews and tests).
        limits: the input limits every utterance is read and performed against.
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
        speedup: float = 1.0,
        limits: Limits = DEFAULT_LIMITS,
        lexicon: GestureLexicon | None = None,
    ) -> None:
        self.limits = limits
        self.lexicon = lexicon
        self.fps = limits.check_fps(fps)
        self.config = SchedulerConfig(voice=voice, rate=limits.check_rate(rate), limits=limits)
        self.avatar = load_avatar(avatar) if isinstance(avatar, str) else avatar
        self.tts = make_synthesizer(tts) if isinstance(tts, str) else tts
        self._live: Scheduler | None = None
        self._live_tts: InterruptibleSynthesizer | None = None
        self._player: SpeechPlayer | None = None
        self._live_lock = threading.Lock()
        self._observers: list[Callable[[Event | BmlFeedback], None]] = []
        self._speedup = float(speedup)
        self._feedback = FeedbackTranslator(self._tell)
        self._handles: dict[str, LiveHandle] = {}

    def render(self, utterance: UtteranceSource, name: str | None = None) -> Performance:
        """Perform ``utterance`` offline; raises :class:`SpecError` for a bad spec and
        :class:`PerformanceError` (with the part performed) when a chunk fails. ``name``
        (the saved files' stem) must be a plain file name."""
        model, default_name = read_utterance(utterance, self.limits, self.lexicon)
        name = check_stem(name) if name is not None else default_name
        scheduler = Scheduler(CheckedSynthesizer(self.tts), MotorControl(self.avatar, self.fps), VirtualClock(), self.config)
        try:
            result = scheduler.run(model, name)
        finally:
            scheduler.close()
        return _performance(result, name, self.avatar, self.fps)

    def render_files(
        self, utterance: UtteranceSource, directory: str | os.PathLike[str], name: str | None = None, glb: bool = False
    ) -> SavedFiles:
        """Perform ``utterance`` offline straight into NAME.wav, .bvh, .timeline.json and .html
        (and NAME.glb with ``glb``) in ``directory``, in memory that does not grow with its
        length; the files equal ``render(...).save(directory)``'s. Raises as :meth:`render`
        does (``partial`` None). ``name`` must be a plain file name: nothing is ever written
        outside ``directory``."""
        model, default_name = read_utterance(utterance, self.limits, self.lexicon)
        name = check_stem(name) if name is not None else default_name
        return render_to_files(model, directory, CheckedSynthesizer(self.tts), self.avatar, self.fps, self.config, name, glb=glb)

    def subscribe(self, observer: Callable[[Event | BmlFeedback], None]) -> None:
        """Receive every event of live utterances (chunk states, feedback, frames) and the
        BML feedback of live blocks."""
        self._observers.append(observer)
        if self._live is not None:
            self._live.subscribe(observer)

    def say(self, utterance: UtteranceSource, name: str | None = None, audio: bool = True) -> LiveUtterance:
        """Perform ``utterance`` (MURML, or a BML block with its composition) live; returns
        at once with a handle to wait on or interrupt. A BML block keeps its id as its name
        (used once at a time); a MURML utterance whose name is still playing or queued is
        named ``NAME-2``, ``NAME-3`` …"""
        model, default_name, block = read_spec(utterance, self.limits, self.lexicon)
        name = block.id if block is not None else check_stem(name) if name is not None else default_name
        scheduler, speech = self._live_scheduler(audio)
        with self._live_lock:
            self._handles = {n: h for n, h in self._handles.items() if not h.done}
            if name in self._handles and block is not None:
                raise SpecError(f"{name!r} is still being performed: a block id is used once at a time", SourceLocation(model.source, 1, 1))
            name = _free_name(name, self._handles)
        self._feedback.register(name, _sync_points(model, block), _kinds(model, block), block.character if block else None, model.warnings)
        if block is not None:
            self._compose(block)
        handle = scheduler.start(model, name)
        with self._live_lock:
            self._handles[name] = handle
        return LiveUtterance(handle, name, self.avatar, self.fps, speech)

    def interrupt(self, name: str | None = None) -> list[str]:
        """End the live utterance or block ``name`` (every one playing or queued when None)
        gracefully; returns the names interrupted."""
        with self._live_lock:
            handles = {n: h for n, h in self._handles.items() if not h.done and (name is None or n == name)}
        for handle in handles.values():
            handle.interrupt()
        return sorted(handles)

    def _compose(self, block: BmlBlock) -> None:
        for warning in block.warnings:
            self._tell(WarningFeedback(block.id, warning.kind, warning.message, str(warning.where)))
        if block.composition == "REPLACE":
            self.interrupt()
            return
        with self._live_lock:
            busy = sorted(n for n, h in self._handles.items() if not h.done)
        if block.composition == "MERGE" and busy:
            self._tell(WarningFeedback(block.id, "MERGE_QUEUED", f"mura performs one block at a time: {block.id!r} starts after {', '.join(busy)}"))

    def _tell(self, event: Event | BmlFeedback) -> None:
        for observer in list(self._observers):
            observer(event)

    def close(self) -> None:
        """Wait for live utterances to end, then stop the live scheduler, the speech
        workers and the speech player: no thread the agent started outlives this call."""
        with self._live_lock:
            live, speech, player = self._live, self._live_tts, self._player
            self._live = self._live_tts = self._player = None
        if live is not None:
            live.close()
        if speech is not None:
            for stuck in speech.close():
                print(f"mura: the speech backend still has not returned ({stuck}); abandoned", file=sys.stderr)
        if player is not None:
            player.close(PLAYER_CLOSE_TIMEOUT)

    def _live_scheduler(self, audio: bool) -> tuple[Scheduler, InterruptibleSynthesizer]:
        with self._live_lock:
            if self._live is None:
                warm_up()
                self._live_tts = InterruptibleSynthesizer(self.tts)
                self._live = Scheduler(self._live_tts, MotorControl(self.avatar, self.fps), WallClock(self._speedup), self.config)
                for observer in self._observers:
                    self._live.subscribe(observer)
                self._live.subscribe(self._feedback)
            if audio and self._player is None:
                self._player = SpeechPlayer()
                self._live.subscribe(self._player)
            assert self._live_tts is not None
            return self._live, self._live_tts


def _free_name(name: str, taken: dict[str, LiveHandle]) -> str:
    """``name``, or the first ``name-k`` (k = 2, 3 …) not in ``taken``."""
    if name not in taken:
        return name
    return next(f"{name}-{k}" for k in itertools.count(2) if f"{name}-{k}" not in taken)


def _sync_points(model, block: BmlBlock | None) -> dict[str, tuple[str, ...]]:
    """The sync points feedback reports: a block's own, or the seven pegs of each MURML gesture."""
    if block is not None:
        return dict(block.sync_points)
    return {b.id: ("start", "ready", "strokeStart", "stroke", "strokeEnd", "relax", "end") for b in model.behaviors if b.moves_arms}


def _kinds(model, block: BmlBlock | None) -> dict[str, str]:
    return dict(block.kinds) if block is not None else {b.id: b.kind for b in model.behaviors}


class LiveUtterance:
    """A live utterance: ``wait()`` gives its :class:`Performance`, ``interrupt()`` ends it."""

    def __init__(self, handle: LiveHandle, name: str, avatar: Avatar, fps: float,
                 speech: InterruptibleSynthesizer | None = None) -> None:
        self._handle = handle
        self.name = name
        self._avatar = avatar
        self._fps = fps
        self._speech = speech
        self.interrupted = False

    def wait(self, timeout: float | None = None) -> Performance:
        """Block until the utterance has been performed (or interrupted) and return it.

        Raises :class:`PerformanceError` with the part performed (``partial``) when a chunk
        failed — unless the failure is the interrupt's doing — and TimeoutError after
        ``timeout`` wall seconds.
        """
        return _performance(self._handle.wait(timeout), self.name, self._avatar, self._fps, allow_partial=self.interrupted)

    def interrupt(self) -> None:
        """Retract from where the arms are and drop the chunks not yet begun; speech being
        synthesized is abandoned at once, even when the backend hangs."""
        self.interrupted = True
        self._handle.interrupt()
        if self._speech is not None:
            self._speech.cancel()


class SpeechPlayer:
    """An observer that plays each chunk's speech when the scheduler starts it.

    Playback blocks for as long as the audio lasts, so it runs in a worker thread of its
    own and the scheduler never waits on it. The first time no audio device can play, it
    says so once on stderr and stays silent; the schedule runs on regardless.
    """

    def __init__(self, backend: str | None = None) -> None:
        self.problem: str | None = None
        self._backend = backend
        self._queue: queue.Queue[tuple[np.ndarray, int] | None] = queue.Queue()
        self._worker = threading.Thread(target=self._play_queued, name="speech-player", daemon=True)
        self._worker.start()

    def __call__(self, event: Event) -> None:
        if isinstance(event, SpeechStarted) and event.audio is not None and self.problem is None:
            self._queue.put((event.audio, event.sample_rate))

    def close(self, timeout: float | None = None) -> None:
        """Play what is queued, then end the worker thread (waiting at most ``timeout`` s)."""
        self._queue.put(None)
        self._worker.join(timeout)

    def _play_queued(self) -> None:
        player = None
        while True:
            item = self._queue.get()
            if item is None:
                return
            samples, rate = item
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
        raise PerformanceError(f"chunk {result.failed_chunk + 1} failed: {result.error}", performance)
    return performance


__all__ = ["Agent", "LiveUtterance", "Performance", "PerformanceError", "SpeechPlayer", "read_utterance", "rest_motion"]
