"""The scheduler: chunk by chunk, planning the next chunk while the current one runs
(seed 004, section 5, Fig. 6).

One loop serves offline rendering (a :class:`VirtualClock`: time jumps to the next thing
to do) and live runs (a :class:`WallClock`: the loop sleeps, and the next chunk is
planned in a worker thread while the current one plays). For each chunk:

1. InPrep: speech synthesis and the movement planner's demands contribute concurrently;
   the chunk's timing is solved (:mod:`blackboard.timing`) and each gesture is planned
   with the motor control. Knowing that a chunk follows sets ``final=False`` for the
   speech and ``next_gesture_follows`` for gestures followed by another on the same arm.
2. Pending once planned (the next chunk's planning starts when this one is InExec).
   Lurking as soon as the previous chunk is Subsiding (or
   Completed): its motor programs are activated before any frame at their start is sampled.
3. InExec when its speech or first behaviour starts; Subsiding once the phrase and every
   stroke are over while a retraction is still running, else straight to Completed;
   Completed when the last retraction ends, or when the next gesture on the same arm
   starts preparing (the retraction is skipped: co-articulation).

Frames are sampled window by window (``SchedulerConfig.frame_window`` live,
``offline_frame_window`` on a virtual clock) from the motor control; a window never
crosses the time a program is activated (nor any other agenda event), so the window
length only decides how many frames one motor call makes, never which. In a live run a
frame window is sampled when the clock reaches its end (the viewer buffers one window).

Absolutely timed behaviours of an utterance with speech are planned with the first chunk
whose speech ends after their onset (the last chunk takes the rest); a gesture-only
utterance (no text) is one chunk without speech. Other behaviours than gestures (facial,
…) are listed in the timeline's ``other_behaviors`` but not performed; gestures and signs are.
"""

from __future__ import annotations

import dataclasses
import heapq
import itertools
import math
import threading
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from blackboard.board import Blackboard, PlannedGesture
from blackboard.chunk import ChunkState
from blackboard.clock import Clock, VirtualClock
from blackboard.errors import BehaviorError, OverlappingGestures, ScheduleError
from blackboard.events import (
    EventBus,
    FramesReady,
    Observer,
    SpeechEnded,
    SpeechStarted,
)
from blackboard.planning import PEG_NAMES, MotorControl, TimePegs
from blackboard.timeline import BehaviorEntry, ChunkEntry, PlanningSlack, Timeline
from blackboard.timing import ChunkTiming, GestureRequest, TimingConfig, time_chunk
from motor.motion import Motion
from motor.trajectory.spline import fitts_duration
from mura.model import AbsoluteTiming, Affiliate, BehaviorSpec, ChunkSpec, Utterance
from tts import SpeechError, SpeechRequest, SpeechSynthesizer, SpeechTiming, TextMark

_EPS = 1e-9


@dataclass(frozen=True)
class SchedulerConfig:
    """Scheduler settings.

    ``frame_window``: seconds of frames sampled at a time in a live run;
    ``offline_frame_window`` the same on a virtual clock, where nobody waits for a window
    and longer ones spare the motor control's per-call cost. ``live_margin``: in a live
    run, how far ahead of the moment planning starts the planned chunk may begin, s (the
    time planning may take). ``voice``/``rate``/``with_audio`` go to the speech requests.
    ``keep_output``: collect the frames and audio into the result; when False they reach
    observers only (``FramesReady``, ``SpeechStarted``), each chunk's audio is dropped once
    published, and memory stays flat however long the utterance.
    """

    timing: TimingConfig = TimingConfig()
    frame_window: float = 0.1
    live_margin: float = 0.1
    voice: str | None = None
    rate: float = 1.0
    with_audio: bool = True
    keep_output: bool = True
    offline_frame_window: float = 1.0

    def __post_init__(self) -> None:
        for name in ("frame_window", "offline_frame_window"):
            value = getattr(self, name)
            if not value > 0.0:
                raise ValueError(f"SchedulerConfig.{name} must be a positive number of seconds, got {value}")


@dataclass(frozen=True)
class ScheduledUtterance:
    """A performed utterance: its timeline, the audio (int16 mono, pauses included, None when
    the speech backend gave none), the motion from the utterance start to the end of the last
    retraction, warnings, and, when a chunk failed, its index and the error. Without
    ``SchedulerConfig.keep_output`` the audio and motion are None (``sample_rate`` stays)."""

    timeline: Timeline
    audio: np.ndarray | None
    sample_rate: int | None
    motion: Motion | None
    warnings: tuple[str, ...]
    failed_chunk: int | None = None
    error: Exception | None = None


@dataclass
class _Job:
    utterance: Utterance
    name: str
    chunks: tuple[ChunkSpec, ...]
    timeline: Timeline
    origin: float = 0.0
    boards: list[Blackboard] = field(default_factory=list)
    absolute: list[BehaviorSpec] = field(default_factory=list)
    absolute_delay: float = 0.0  # how late the absolute clock starts, seconds (see blackboard.timing)
    frames: list[Motion] = field(default_factory=list)
    audio_end: int = 0  # without keep_output: samples from the utterance start to the end of the last audio
    sample_rate: int | None = None
    failed: Blackboard | None = None
    interrupted: bool = False
    done: threading.Event = field(default_factory=threading.Event)
    result: ScheduledUtterance | None = None
    end: float = 0.0

    @property
    def finished(self) -> bool:
        planned_all = len(self.boards) == len(self.chunks) or self.failed is not None or self.interrupted
        return planned_all and all(b.machine.finished for b in self.boards)


class LiveHandle:
    """A live utterance: ``wait()`` for its result, ``interrupt()`` to end it gracefully."""

    def __init__(self, scheduler: Scheduler, job: _Job) -> None:
        self._scheduler = scheduler
        self._job = job

    def wait(self, timeout: float | None = None) -> ScheduledUtterance:
        """Block until the utterance is over; TimeoutError after ``timeout`` wall seconds."""
        if not self._job.done.wait(timeout):
            raise TimeoutError(f"utterance {self._job.name!r} still running after {timeout} s")
        if self._scheduler._crash is not None:
            raise self._scheduler._crash
        return self._job.result

    def interrupt(self) -> None:
        """Retract from wherever the arms are now and drop the chunks not yet running."""
        self._scheduler._request_interrupt(self._job)

    @property
    def timeline(self) -> Timeline:
        return self._job.timeline


class Scheduler:
    """Plans and runs utterances chunk by chunk on ``clock`` (see the module docstring)."""

    def __init__(self, tts: SpeechSynthesizer, motor: MotorControl, clock: Clock | None = None,
                 config: SchedulerConfig = SchedulerConfig()) -> None:
        self.tts = tts
        self.motor = motor
        self.clock = clock if clock is not None else VirtualClock()
        self.config = config
        self.bus = EventBus()
        self._agenda: list[tuple[float, int, Callable[[], None]]] = []
        self._cancelled: set[int] = set()
        self._counter = itertools.count()
        self._frame_cursor: float | None = None
        self._time = 0.0  # the scheduler's own time: how far frames and events have been processed
        self._arm_last: dict[str, tuple[Blackboard, PlannedGesture]] = {}
        self._queue: list[_Job] = []
        self._board_jobs: dict[Blackboard, _Job] = {}
        self._active: list[_Job] = []
        self._lock = threading.Lock()
        self._thread: threading.Thread | None = None
        self._running = False
        self._interrupts: list[_Job] = []
        self._crash: BaseException | None = None
        self._planner = ThreadPoolExecutor(1, thread_name_prefix="chunk-planner") if self.clock.live else None
        self._contributors = ThreadPoolExecutor(2, thread_name_prefix="chunk-contributor") if self.clock.live else None

    def subscribe(self, observer: Observer) -> Callable[[], None]:
        """Call ``observer`` with every event; returns the unsubscribe function."""
        return self.bus.subscribe(observer)

    # ----------------------------------------------------------------- entry points

    def run(self, utterance: Utterance, name: str = "utterance") -> ScheduledUtterance:
        """Plan and perform ``utterance`` to the end on this scheduler's clock (offline with a virtual clock)."""
        job = self._job(utterance, name)
        with self._lock:
            if self._running:
                raise ScheduleError("run() while a live session plays; use start() to queue the utterance")
            self._queue.append(job)
            self._running = True
        try:
            self._session()
        finally:
            with self._lock:
                self._running = False
        return job.result

    def start(self, utterance: Utterance, name: str = "utterance") -> LiveHandle:
        """Perform ``utterance`` in a background thread; it joins fluently after any utterance still playing."""
        job = self._job(utterance, name)
        with self._lock:
            self._queue.append(job)
            if not self._running:
                self._running = True
                self._thread = threading.Thread(target=self._guarded_session, name="scheduler", daemon=True)
                self._thread.start()
        return LiveHandle(self, job)

    def close(self) -> None:
        """Wait for the live session to end and stop the planning workers."""
        if self._thread is not None:
            self._thread.join()
        for pool in (self._planner, self._contributors):
            if pool is not None:
                pool.shutdown()

    def _guarded_session(self) -> None:
        try:
            self._session()
        except BaseException as crash:  # surfaced by LiveHandle.wait, never lost in the thread
            self._crash = crash
            with self._lock:
                jobs = self._active + self._queue
            for job in jobs:
                job.done.set()

    def _request_interrupt(self, job: _Job) -> None:
        with self._lock:
            self._interrupts.append(job)

    # ----------------------------------------------------------------- validation

    def _job(self, utterance: Utterance, name: str) -> _Job:
        validate(utterance, self.motor)
        chunks = utterance.chunks or (ChunkSpec(0, "", ()),)
        absolute = sorted((b for b in utterance.behaviors if isinstance(b.timing, AbsoluteTiming) and b.moves_arms),
                          key=lambda b: b.timing.onset)
        timeline = Timeline(name, self.motor.fps)
        for b in utterance.behaviors:
            if not b.moves_arms:
                timeline.warn(f"behaviour {b.id!r} ({b.kind}) is listed but not performed: only gestures and signs are scheduled")
        return _Job(utterance, name, chunks, timeline, absolute=list(absolute))

    # ----------------------------------------------------------------- the loop

    def _session(self) -> None:
        while True:
            board = self._next_board(None)
            while board is not None:
                board = self._perform_chunk(board)
            while self._agenda:
                self._advance_to(self._agenda[0][0])
            with self._lock:
                leftover = [j for j in self._active if not j.done.is_set()]
            for job in leftover:
                self._finish(job)
            with self._lock:
                if not self._queue:
                    self._running = False
                    return

    def _next_board(self, current: Blackboard | None) -> Blackboard | None:
        """Plan the chunk after ``current`` (the next of its utterance, or the first of the next queued one)."""
        job, index = self._following(current)
        if job is None:
            return None
        return self._plan(job, index, current)

    def _following(self, current: Blackboard | None) -> tuple[_Job | None, int]:
        with self._lock:
            job = self._board_jobs.get(current) if current is not None else None
        if job is not None:
            if not job.interrupted and job.failed is None and current.index + 1 < len(job.chunks):
                return job, current.index + 1
        with self._lock:
            if not self._queue:
                return None, 0
            job = self._queue.pop(0)
            self._active.append(job)
        start = self.clock.now() + (self.config.live_margin if self.clock.live else 0.0)
        if current is not None and current.timing is not None and current.state is not ChunkState.FAILED:
            start = max(start, current.strokes_done)
        job.origin = math.ceil(start * self.motor.fps - _EPS) / self.motor.fps
        job.timeline.origin = job.origin
        with self._lock:
            alone = len(self._active) == 1
        if self._frame_cursor is None or alone:
            self._frame_cursor = max(self._frame_cursor or job.origin, job.origin)
            self._time = max(self._time, job.origin)
        return job, 0

    def _job_of(self, board: Blackboard) -> _Job:
        with self._lock:
            return self._board_jobs[board]

    def _perform_chunk(self, board: Blackboard) -> Blackboard | None:
        if board.state is ChunkState.FAILED:
            return self._next_board(None)  # its utterance ends here; the next queued one, if any, goes on
        job = self._job_of(board)
        self._advance_to(max(self._time, board.lurk_allowed))
        if self._take_interrupt(job):
            board.move(ChunkState.FAILED, self._time, "interrupted before it ran")
            self._check_done(job)
            return self._next_board(board)
        self._lurk(board)
        self._advance_to(max(board.exec_start, self._time))
        if board.state is ChunkState.LURKING:
            board.move(ChunkState.IN_EXEC, self._time)
        pending = self._submit_next(board)  # Fig. 6: the next chunk is prepared while this one executes
        if not job.interrupted:
            self._advance_to(max(board.strokes_done, self._time))
        following = _result(pending)
        if job.interrupted:
            return following
        if following is not None and following.state is ChunkState.PENDING:
            self._cut_retractions(following.gestures)
        if board.state is ChunkState.IN_EXEC:
            self._subside(board)
        return following

    def _submit_next(self, board: Blackboard) -> Future | Blackboard | None:
        if self._planner is None:
            return self._next_board(board)
        return self._planner.submit(self._next_board, board)

    def _lurk(self, board: Blackboard) -> None:
        now = self._time
        board.move(ChunkState.LURKING, now)
        job = self._job_of(board)
        for gesture in sorted(board.gestures, key=lambda g: g.program.pegs.start):
            self._cut_retractions((gesture,))
            self.motor.activate(gesture.program)
            late = self._frame_cursor - gesture.program.pegs.start
            if late > _EPS:  # frames after its start were sampled without it
                job.timeline.warn(f"{gesture.behavior.id}: activated {late:.3f} s late (planning too slow)")
            for arm in gesture.demands.arms:
                self._arm_last[arm] = (board, gesture)
            self._schedule_feedback(board, gesture)
        if board.has_speech:
            onset, end = board.speech_onset, board.speech_end
            for warning in self.motor.speak(board.speech, onset, _accents(board)):
                job.timeline.warn(warning)
            self._at(onset, lambda: self._start_speech(job, board, onset))
            board.speech_end_entry = self._at(end, lambda: self.bus.publish(SpeechEnded(job.name, board.index, end - job.origin)))

    def _start_speech(self, job: _Job, board: Blackboard, onset: float) -> None:
        speech = board.speech
        self.bus.publish(SpeechStarted(job.name, board.index, board.spec.text, onset - job.origin, speech.audio, speech.sample_rate))
        if self.config.keep_output or speech.audio is None:
            return
        if job.sample_rate is not None and speech.sample_rate != job.sample_rate:
            raise ScheduleError(f"{job.name}: chunks came back at different sample rates")
        job.sample_rate = speech.sample_rate
        job.audio_end = max(job.audio_end, int(round((onset - job.origin) * speech.sample_rate)) + len(speech.audio))
        board.speech = dataclasses.replace(speech, audio=None)

    def _schedule_feedback(self, board: Blackboard, gesture: PlannedGesture) -> None:
        pegs = gesture.program.pegs
        behavior = gesture.behavior.id
        entries = []
        for name in PEG_NAMES[:-1]:
            kind = "started" if name == "start" else "sync"
            t = getattr(pegs, name)
            entries.append(self._at(t, lambda n=name, k=kind, t=t: board.post(behavior, k, n, t)))
        board.effective_ends[behavior] = pegs.end
        board.finish_entries[behavior] = self._at(pegs.end, lambda: board.post(behavior, "finished", "end", pegs.end))
        board.feedback_entries.extend(entries)

    def _cut_retractions(self, gestures: tuple[PlannedGesture, ...]) -> None:
        """A following gesture that starts preparing before an earlier one's retraction ends cuts it there."""
        for gesture in gestures:
            start = gesture.program.pegs.start
            for arm in gesture.demands.arms:
                earlier = self._arm_last.get(arm)
                if earlier is None:
                    continue
                board, previous = earlier
                behavior = previous.behavior.id
                if start < board.effective_ends[behavior] - _EPS:
                    board.effective_ends[behavior] = max(start, previous.program.pegs.relax)
                    entry = board.timeline.behavior(behavior)
                    entry.phases["end"] = board.effective_ends[behavior] - board.origin
                    entry.retraction_skipped = True
                    self._cancel(board.finish_entries[behavior])
                    cut = board.effective_ends[behavior]
                    board.finish_entries[behavior] = self._at(cut, lambda b=board, n=behavior, t=cut: b.post(n, "finished", "end", t))
                    if board.state is ChunkState.SUBSIDING:
                        self._cancel(board.completed_entry)
                        board.completed_entry = self._at(board.effective_end, lambda b=board: self._complete(b))

    def _subside(self, board: Blackboard) -> None:
        now = self._time
        if board.effective_end > now + _EPS:
            board.move(ChunkState.SUBSIDING, now)
            board.completed_entry = self._at(board.effective_end, lambda: self._complete(board))
        else:
            self._complete(board, "no retraction active (skipped by the next gesture, or none planned)")

    def _complete(self, board: Blackboard, reason: str = "") -> None:
        board.move(ChunkState.COMPLETED, self._time, reason)
        self._check_done(self._job_of(board))

    def _check_done(self, job: _Job) -> None:
        if job.finished and not job.done.is_set():
            self._finish(job)

    # ----------------------------------------------------------------- time and frames

    def _at(self, t: float, action: Callable[[], None]) -> int:
        key = next(self._counter)
        heapq.heappush(self._agenda, (t, key, action))
        return key

    def _cancel(self, key: int) -> None:
        self._cancelled.add(key)

    def _advance_to(self, t: float) -> None:
        """Let time pass until ``t``: sample frames window by window and fire due agenda events."""
        while True:
            self._handle_interrupts()
            next_event = self._agenda[0][0] if self._agenda else math.inf
            stop = min(t, next_event, self._frame_cursor + self._frame_window())
            self.clock.sleep_until(stop)
            self._time = max(self._time, stop)
            self._sample_frames(stop)
            while self._agenda and self._agenda[0][0] <= stop + _EPS:
                _, key, action = heapq.heappop(self._agenda)
                if key in self._cancelled:
                    self._cancelled.discard(key)
                    continue
                action()
            if stop >= t - _EPS and not (self._agenda and self._agenda[0][0] <= t + _EPS):
                return

    def _frame_window(self) -> float:
        return self.config.frame_window if self.clock.live else self.config.offline_frame_window

    def _sample_frames(self, until: float) -> None:
        start = self._frame_cursor
        if until <= start + _EPS:
            return
        motion = self.motor.frames(start, until)
        self._frame_cursor = until
        if motion.frame_count == 0:
            return
        with self._lock:
            jobs = [j for j in self._active if not j.done.is_set()]
        for job in jobs:
            if self.config.keep_output:
                job.frames.append(motion)
            self.bus.publish(FramesReady(job.name, start - job.origin, until - job.origin, motion))

    # ----------------------------------------------------------------- interrupts

    def _take_interrupt(self, job: _Job) -> bool:
        self._handle_interrupts()
        return job.interrupted

    def _handle_interrupts(self) -> None:
        with self._lock:
            requests, self._interrupts = self._interrupts, []
        for job in requests:
            if job.interrupted or job.done.is_set():
                continue
            job.interrupted = True
            now = self.clock.now()
            self.motor.interrupt(now)
            for board in job.boards:
                self._stop_board(board, now)
            self._check_done(job)

    def _stop_board(self, board: Blackboard, now: float) -> None:
        state = board.state
        if state is ChunkState.IN_PREP:
            return  # the loop fails it once its planning is over
        for key in board.feedback_entries + list(board.finish_entries.values()):
            self._cancel(key)
        if board.speech_end_entry is not None and board.speech_onset <= now < board.speech_end:
            self._cancel(board.speech_end_entry)
            self.bus.publish(SpeechEnded(board.utterance, board.index, now - board.origin))
        if state in (ChunkState.PENDING, ChunkState.LURKING):
            board.move(ChunkState.FAILED, now, "interrupted before it ran")
            return
        if state is ChunkState.IN_EXEC or state is ChunkState.SUBSIDING:
            retracted = max([now] + [self.motor.busy_until(arm) for g in board.gestures for arm in g.demands.arms])
            for g in board.gestures:
                board.effective_ends[g.behavior.id] = min(board.effective_ends[g.behavior.id], retracted)
                board.timeline.behavior(g.behavior.id).phases["end"] = retracted - board.origin
            board.speech_end = min(board.speech_end, now)
            board.cutoff = retracted
            if state is ChunkState.IN_EXEC:
                board.move(ChunkState.SUBSIDING, now, "interrupted")
            else:
                self._cancel(board.completed_entry)
            board.completed_entry = self._at(retracted, lambda: self._complete(board))

    # ----------------------------------------------------------------- planning (InPrep)

    def _plan(self, job: _Job, index: int, previous: Blackboard | None) -> Blackboard:
        spec = job.chunks[index]
        now = self.clock.now()
        job.timeline.add_chunk(ChunkEntry(index, spec.text))
        behaviors = job.utterance.behaviors_in_chunk(index) if job.utterance.chunks else ()
        board = Blackboard(job.name, spec, tuple(b for b in behaviors if b.moves_arms), job.origin, now, self.bus, job.timeline)
        job.boards.append(board)
        with self._lock:
            self._board_jobs[board] = job
        try:
            self._fill(board, job, previous, now)
        except (SpeechError, ScheduleError, ValueError) as error:
            board.error = error
            job.failed = board
            job.timeline.chunk(index).error = f"{type(error).__name__}: {error}"
            board.move(ChunkState.FAILED, self.clock.now(), str(error))
            self._check_done(job)
            return board
        board.move(ChunkState.PENDING, self.clock.now())
        job.timeline.slack.append(PlanningSlack(index, self.clock.now() - job.origin, board.exec_start - job.origin))
        return board

    def _fill(self, board: Blackboard, job: _Job, previous: Blackboard | None, now: float) -> None:
        """Everything InPrep does: speech and demands concurrently, then timing, then motor programs."""
        margin = self.config.live_margin if self.clock.live else 0.0
        follows = self._followed(job, board.index)
        speech_future = self._contribute(self._speak, board, follows)
        demand_futures = {b.id: self._contribute(self.motor.demands, b) for b in board.behaviors}
        board.speech = _result(speech_future)
        board.demands = {k: _result(f) for k, f in demand_futures.items()}
        last_word = board.speech.words[-1].end if board.has_speech else 0.0

        if previous is not None and previous.state is not ChunkState.FAILED:
            earliest = max(previous.speech_end + (self.config.timing.min_pause if previous.has_speech else 0.0), now + margin)
            onset_reason = f"speech onset of chunk {board.index + 1} at least {self.config.timing.min_pause:.3f} s after the previous speech end"
            arm_free = max(previous.strokes_done, now + margin)
            arm_reason = "arm free once the previous chunk's strokes are done"
        else:
            earliest = arm_free = max(job.origin, now + margin)
            onset_reason = f"speech onset of chunk {board.index + 1} not before the utterance starts"
            arm_reason = "arm free from the utterance start"
        board.lurk_allowed = previous.strokes_done if previous is not None and previous.state is not ChunkState.FAILED else job.origin

        absolute = self._take_absolute(job, board, earliest + last_word)
        board.behaviors = board.behaviors + tuple(absolute)
        for b in absolute:
            board.demands[b.id] = self.motor.demands(b)
        marks = dict(board.speech.marks) if board.speech is not None else {}
        self._check_marks(board, marks)
        timing = self._solve(board, job, marks, earliest, onset_reason, arm_free, arm_reason)
        board.timing = timing
        board.speech_end = timing.speech_onset + last_word
        board.gestures = self._program(board, job, timing, follows)
        self._record(board, job, timing)

    def _contribute(self, function: Callable, *args) -> Future | object:
        if self._contributors is None:
            return function(*args)
        return self._contributors.submit(function, *args)

    def _followed(self, job: _Job, index: int) -> Blackboard | tuple[BehaviorSpec, ...] | None:
        """The behaviours of the chunk that follows chunk ``index`` (None when nothing follows yet)."""
        if index + 1 < len(job.chunks):
            return job.utterance.behaviors_in_chunk(index + 1)
        with self._lock:
            queued = self._queue[0] if self._queue else None
        if queued is None:
            return None
        return queued.utterance.behaviors_in_chunk(0) + tuple(queued.absolute)

    def _speak(self, board: Blackboard, follows) -> SpeechTiming | None:
        spec = board.spec
        if not spec.text.strip():
            return None
        emphasis = []
        tags = {t.id: t for t in spec.time_tags}
        for b in board.behaviors:
            if isinstance(b.timing, Affiliate) and b.timing.onset in tags and b.timing.end in tags:
                emphasis.append((tags[b.timing.onset].offset, tags[b.timing.end].offset))
        request = SpeechRequest(
            text=spec.text,
            marks=tuple(TextMark(t.id, t.offset) for t in spec.time_tags),
            emphasis=tuple(sorted(emphasis)),
            final=follows is None,
            voice=self.config.voice,
            rate=self.config.rate,
            with_audio=self.config.with_audio,
        )
        try:
            return self.tts.synthesize(request)
        except SpeechError as error:
            raise SpeechError(f"speech of chunk {spec.index + 1} ({spec.text!r}) failed: {error}") from error

    def _take_absolute(self, job: _Job, board: Blackboard, speech_end: float) -> list[BehaviorSpec]:
        last = board.index == len(job.chunks) - 1
        taken = [b for b in job.absolute if last or job.origin + b.timing.onset < speech_end]
        job.absolute = [b for b in job.absolute if b not in taken]
        return taken

    def _check_marks(self, board: Blackboard, marks: dict[str, float]) -> None:
        for b in board.behaviors:
            if isinstance(b.timing, Affiliate):
                missing = [t for t in (b.timing.onset, b.timing.end) if t not in marks]
                if missing:
                    raise BehaviorError(f"behaviour {b.id!r}: the speech of chunk {board.index + 1} gave no time for tag(s) {missing}")

    def _requests(self, board: Blackboard, job: _Job, prep: dict[str, float]) -> list[GestureRequest]:
        out = []
        for b in board.behaviors:
            d = board.demands[b.id]
            if isinstance(b.timing, Affiliate):
                out.append(GestureRequest(b.id, d, prep[b.id], affiliate=(b.timing.onset, b.timing.end)))
            else:
                out.append(GestureRequest(b.id, d, prep[b.id], absolute=(job.origin + b.timing.onset, job.origin + b.timing.end)))
        return out

    def _solve(self, board, job, marks, earliest, onset_reason, arm_free, arm_reason) -> ChunkTiming:
        """Two passes: preparation times from where the arms are at the naive start, then at the solved start."""
        cfg = self.config.timing
        naive = {}
        for b in board.behaviors:
            stroke = (earliest + marks[b.timing.onset] - cfg.stroke_lead) if isinstance(b.timing, Affiliate) else job.origin + b.timing.onset
            guess = float(fitts_duration(board.demands[b.id].preparation_distance))
            naive[b.id] = self.motor.preparation_duration(b, max(arm_free, stroke - guess))
        delay = job.absolute_delay
        timing = time_chunk(board.index, earliest, onset_reason, arm_free, arm_reason, marks, self._requests(board, job, naive), cfg, delay)
        solved = {g.behavior: self.motor.preparation_duration(b, g.prep_start) for g, b in zip(timing.gestures, board.behaviors)}
        if all(abs(solved[k] - naive[k]) < 1e-6 for k in solved):
            return timing
        return time_chunk(board.index, earliest, onset_reason, arm_free, arm_reason, marks, self._requests(board, job, solved), cfg, delay)

    def _program(self, board: Blackboard, job: _Job, timing: ChunkTiming, follows) -> tuple[PlannedGesture, ...]:
        later_arms = self._arms_following(board, timing, follows)
        planned = []
        for g, b in zip(timing.gestures, board.behaviors):
            d = board.demands[b.id]
            retraction = float(fitts_duration(d.preparation_distance))
            pegs = TimePegs(g.prep_start, g.stroke_start, g.stroke_start, g.stroke, g.stroke_end, g.relax, g.relax + retraction)
            next_follows = bool(d.arms & later_arms[b.id])
            program = self.motor.plan(b, pegs, repetitions=g.repetitions, next_gesture_follows=next_follows)
            for warning in program.warnings:
                job.timeline.warn(warning)  # the motor names the behaviour in its warnings
            planned.append(PlannedGesture(b, d, g, program, next_follows))
        return tuple(planned)

    def _arms_following(self, board: Blackboard, timing: ChunkTiming, follows) -> dict[str, frozenset[str]]:
        """Per gesture, the arms another gesture uses after it (later in this chunk, or in the next chunk)."""
        next_arms: frozenset[str] = frozenset()
        for b in follows or ():
            if b.moves_arms:
                next_arms |= self.motor.demands(b).arms
        out = {}
        for g in timing.gestures:
            arms = set(next_arms)
            for other in timing.gestures:
                if other.stroke_start > g.stroke_start:
                    arms |= board.demands[other.behavior].arms
            out[g.behavior] = frozenset(arms)
        return out

    def _record(self, board: Blackboard, job: _Job, timing: ChunkTiming) -> None:
        tl, o, i = job.timeline, job.origin, board.index
        entry = tl.chunk(i)
        entry.speech_onset = timing.speech_onset - o
        entry.speech_end = board.speech_end - o
        if timing.stretch is not None:
            tl.stretches.append(timing.stretch)
        if timing.absolute_stretch is not None:
            tl.warn(f"absolute timings delayed by {timing.absolute_stretch.amount:.3f} s: {timing.absolute_stretch.reason}")
        job.absolute_delay = timing.absolute_delay
        tl.absolute_delay = timing.absolute_delay
        if board.speech is not None:
            onset = timing.speech_onset - o
            tl.words.extend({"text": w.text, "start": onset + w.start, "end": onset + w.end, "chunk": i} for w in board.speech.words)
            tl.phonemes.extend({"symbol": p.symbol, "start": onset + p.start, "end": onset + p.end, "chunk": i} for p in board.speech.phonemes)
            tl.time_tags.update({name: onset + t for name, t in board.speech.marks.items()})
        for g in board.gestures:
            b = g.behavior
            pegs = g.program.pegs
            affiliate = None
            if isinstance(b.timing, Affiliate):
                affiliate = {"onset": tl.time_tags[b.timing.onset], "end": tl.time_tags[b.timing.end]}
            else:
                delay = timing.absolute_delay
                affiliate = {"onset": b.timing.onset + delay, "end": b.timing.end + delay, "absolute": True}
            tl.add_behavior(BehaviorEntry(
                b.id, i, b.kind, tuple(sorted(g.demands.arms, reverse=True)),
                {name: getattr(pegs, name) - o for name in PEG_NAMES}, affiliate,
                g.timing.mode, g.timing.repetitions, g.timing.slowdown, False, g.next_gesture_follows,
            ))

    # ----------------------------------------------------------------- results

    def _finish(self, job: _Job) -> None:
        performed = [b for b in job.boards if b.timing is not None and b.state is not ChunkState.FAILED]
        ends = [b.effective_end for b in performed]
        job.end = max(ends + [job.origin])
        audio, rate = self._audio(job, performed) if self.config.keep_output else (None, job.sample_rate)
        if audio is not None:
            job.end = max(job.end, job.origin + len(audio) / rate)
        elif job.audio_end:
            job.end = max(job.end, job.origin + job.audio_end / rate)
        job.timeline.duration = job.end - job.origin
        failed = job.failed
        job.result = ScheduledUtterance(
            timeline=job.timeline,
            audio=audio,
            sample_rate=rate,
            motion=_concatenate(job.frames, job.origin),
            warnings=tuple(job.timeline.warnings),
            failed_chunk=failed.index if failed is not None else None,
            error=failed.error if failed is not None else None,
        )
        with self._lock:
            (self._active if job in self._active else self._queue).remove(job)
            for board in job.boards:
                self._board_jobs.pop(board, None)
        job.done.set()

    def _audio(self, job: _Job, performed: list[Blackboard]) -> tuple[np.ndarray | None, int | None]:
        pieces = [(b.speech_onset - job.origin, b.speech) for b in performed if b.speech is not None and b.speech.audio is not None]
        if not pieces:
            return None, None
        rate = pieces[0][1].sample_rate
        if any(s.sample_rate != rate for _, s in pieces):
            raise ScheduleError(f"{job.name}: chunks came back at different sample rates")
        starts = [int(round(onset * rate)) for onset, _ in pieces]
        length = max(start + len(s.audio) for start, (_, s) in zip(starts, pieces))
        mix = np.zeros(length, dtype=np.int32)
        for start, (_, speech) in zip(starts, pieces):
            mix[start:start + len(speech.audio)] += speech.audio.astype(np.int32)
        return np.clip(mix, -32768, 32767).astype(np.int16), rate


def _result(value):
    return value.result() if isinstance(value, Future) else value


def _concatenate(frames: list[Motion], origin: float) -> Motion | None:
    if not frames:
        return None
    first = frames[0]
    faces = [m.face_weights for m in frames if m.face_weights is not None]
    return Motion(
        fps=first.fps,
        joint_names=first.joint_names,
        parents=first.parents,
        offsets=first.offsets,
        rotations=np.concatenate([m.rotations for m in frames]),
        root_translation=np.concatenate([m.root_translation for m in frames]),
        start_time=first.start_time - origin,
        face_names=first.face_names,
        face_weights=np.concatenate(faces) if first.face_names and len(faces) == len(frames) else None,
    )


def _accents(board: Blackboard) -> tuple[tuple[float, float], ...]:
    """The utterance-clock spans of the chunk's affiliates, which its speech emphasizes."""
    marks, onset = board.speech.marks, board.speech_onset
    return tuple(
        (onset + marks[g.behavior.timing.onset], onset + marks[g.behavior.timing.end])
        for g in board.gestures
        if isinstance(g.behavior.timing, Affiliate) and g.behavior.timing.onset in marks and g.behavior.timing.end in marks
    )


def validate(utterance: Utterance, motor: MotorControl) -> None:
    """Refuse an utterance the scheduler cannot perform, naming the behaviour at fault.

    Checks: something to say or do; every affiliate names time tags of its own chunk,
    onset not after end; gestures have timing; two gestures on one arm in one chunk do
    not have affiliates that overlap or touch (their strokes, which start 0.2 s before the
    affiliate and span it, would overlap).
    """
    if not utterance.chunks and not utterance.behaviors:
        raise ScheduleError(f"{utterance.source}: the utterance has neither text nor behaviours")
    if not utterance.chunks and not any(b.moves_arms for b in utterance.behaviors):
        raise ScheduleError(f"{utterance.source}: the utterance has no text and no gesture to perform")
    tags = utterance.time_tags
    for b in utterance.behaviors:
        if b.moves_arms and b.timing is None:
            raise BehaviorError(f"behaviour {b.id!r}: a gesture needs an affiliate or an absolute timing")
        if isinstance(b.timing, Affiliate):
            _check_affiliate(b, tags, utterance)
    for chunk in utterance.chunks:
        _check_same_arm(utterance.behaviors_in_chunk(chunk.index), tags, motor)


def _check_affiliate(b: BehaviorSpec, tags, utterance: Utterance) -> None:
    for which in ("onset", "end"):
        name = getattr(b.timing, which)
        if name not in tags:
            raise BehaviorError(f"behaviour {b.id!r}: affiliate {which} names unknown time tag {name!r} (known: {', '.join(tags) or 'none'})")
        if b.chunk is None or tags[name].chunk != b.chunk:
            raise BehaviorError(
                f"behaviour {b.id!r}: affiliate {which} tag {name!r} lies in chunk {tags[name].chunk + 1}, "
                f"not in the behaviour's chunk {'?' if b.chunk is None else b.chunk + 1}"
            )
    if tags[b.timing.onset].offset >= tags[b.timing.end].offset:
        raise BehaviorError(f"behaviour {b.id!r}: affiliate from {b.timing.onset!r} to {b.timing.end!r} spans no words")


def _check_same_arm(behaviors: tuple[BehaviorSpec, ...], tags, motor: MotorControl) -> None:
    gestures = [b for b in behaviors if b.moves_arms and isinstance(b.timing, Affiliate)]
    arms = {b.id: motor.demands(b).arms for b in gestures}
    gestures.sort(key=lambda b: tags[b.timing.onset].offset)
    for earlier, later in itertools.combinations(gestures, 2):
        shared = arms[earlier.id] & arms[later.id]
        if shared and tags[later.timing.onset].offset <= tags[earlier.timing.end].offset:
            raise OverlappingGestures(
                f"gestures {earlier.id!r} and {later.id!r} both need the {', '.join(sorted(shared))} arm "
                f"and their strokes overlap (affiliates {earlier.timing.onset}–{earlier.timing.end} and "
                f"{later.timing.onset}–{later.timing.end})"
            )
