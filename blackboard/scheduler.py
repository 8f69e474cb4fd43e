"""The scheduler: chunk by chunk, planning the next chunk while the current one runs
(seed 004, section 5, Fig. 6).

One loop serves offline rendering (a :class:`VirtualClock`: time jumps to the next thing
to do) and live runs (a :class:`WallClock`: the loop sleeps, and the next chunk is
planned in a worker thread while the current one plays). For each chunk:

1. InPrep (:mod:`blackboard.inprep`): speech synthesis and the movement planner's
   demands contribute concurrently; the time tags are anchored on the audio, the chunk's
   timing is solved, relaxing what must give (:mod:`blackboard.chunk_timing`), and each
   gesture is planned with the motor control.
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

A gesture-only utterance (no text) is one chunk without speech. Other behaviours than gestures (facial,
…) are listed in the timeline's ``other_behaviors`` but not performed; gestures and signs are.
Behaviours of a BML block are timed by the block's sync constraints (:mod:`blackboard.synced`):
those no motor module performs yet are timed and listed (``performed`` false), not performed;
a BML speech reports its start, its sync markers and its end as behaviour feedback. Observers
also hear when a chunk is planned (:class:`ChunkPlanned`) and when an utterance ends
(:class:`UtteranceEnded`), from which :mod:`blackboard.feedback` makes BML's feedback.
"""

from __future__ import annotations

import dataclasses
import math
import threading
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor

from blackboard import synced
from blackboard.agenda import Agenda
from blackboard.anchors import acoustic_anchors
from blackboard.board import Blackboard, PlannedGesture
from blackboard.chunk import ChunkState
from blackboard.clock import Clock, VirtualClock
from blackboard.config import SchedulerConfig
from blackboard.errors import ScheduleError
from blackboard.events import ChunkPlanned, EventBus, FramesReady, Observer, SpeechEnded, SpeechStarted, UtteranceEnded
from blackboard.inprep import ChunkPlanner, result
from blackboard.job import Job, ScheduledUtterance, performed
from blackboard.planning import PEG_NAMES, MotorControl
from blackboard.timeline import ChunkEntry, PlanningSlack, Timeline
from blackboard.validation import validate
from mura.model import AbsoluteTiming, Affiliate, BehaviorSpec, ChunkSpec, Utterance
from tts import SpeechSynthesizer

__all__ = ["LiveHandle", "ScheduledUtterance", "Scheduler", "SchedulerConfig", "validate"]

_EPS = 1e-9


class LiveHandle:
    """A live utterance: ``wait()`` for its result, ``interrupt()`` to end it gracefully."""

    def __init__(self, scheduler: Scheduler, job: Job) -> None:
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

    @property
    def done(self) -> bool:
        """True once the utterance is over (performed, interrupted or failed)."""
        return self._job.done.is_set()


class Scheduler:
    """Plans and runs utterances chunk by chunk on ``clock`` (see the module docstring)."""

    def __init__(self, tts: SpeechSynthesizer, motor: MotorControl, clock: Clock | None = None,
                 config: SchedulerConfig = SchedulerConfig()) -> None:
        self.tts = tts
        self.motor = motor
        self.clock = clock if clock is not None else VirtualClock()
        self.config = config
        self.bus = EventBus()
        self._agenda = Agenda()
        self._frame_cursor: float | None = None
        self._time = 0.0  # the scheduler's own time: how far frames and events have been processed
        self._arm_last: dict[str, tuple[Blackboard, PlannedGesture]] = {}
        self._queue: list[Job] = []
        self._board_jobs: dict[Blackboard, Job] = {}
        self._active: list[Job] = []
        self._lock = threading.Lock()
        self._thread: threading.Thread | None = None
        self._running = False
        self._interrupts: list[Job] = []
        self._crash: BaseException | None = None
        self._planner = ThreadPoolExecutor(1, thread_name_prefix="chunk-planner") if self.clock.live else None
        self._contributors = ThreadPoolExecutor(2, thread_name_prefix="chunk-contributor") if self.clock.live else None
        self._inprep = ChunkPlanner(tts, motor, config, self._contribute)

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

    def _request_interrupt(self, job: Job) -> None:
        with self._lock:
            self._interrupts.append(job)

    # ----------------------------------------------------------------- validation

    def _job(self, utterance: Utterance, name: str) -> Job:
        validate(utterance, self.motor)
        chunks = utterance.chunks or (ChunkSpec(0, "", ()),)
        absolute = sorted((b for b in utterance.behaviors if isinstance(b.timing, AbsoluteTiming) and b.moves_arms),
                          key=lambda b: b.timing.onset)
        timeline = Timeline(name, self.motor.fps)
        for warning in utterance.warnings:
            timeline.warn(warning)
        for b in utterance.behaviors:
            if not b.moves_arms and not synced.is_synced(b):  # BML's reader says it of its own
                timeline.warn(f"behaviour {b.id!r} ({b.kind}) is listed but not performed: only gestures and signs are scheduled")
        return Job(utterance, name, chunks, timeline, absolute=list(absolute))

    # ----------------------------------------------------------------- the loop

    def _session(self) -> None:
        while True:
            board = self._next_board(None)
            while board is not None:
                board = self._perform_chunk(board)
            while self._agenda:
                self._advance_to(self._agenda.next_time())
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

    def _following(self, current: Blackboard | None) -> tuple[Job | None, int]:
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

    def _job_of(self, board: Blackboard) -> Job:
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
            self._advance_to(max(board.strokes_done, self._time), unless=lambda: job.interrupted)  # REPLACE goes on at once
        following = result(pending)
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
            if board.spec.speech is not None:
                self._schedule_speech_feedback(board)

    def _schedule_speech_feedback(self, board: Blackboard) -> None:
        """A BML speech's progress, on the audio: ``started`` at the first word, ``sync`` at
        the word after each marker, ``finished`` at the end of the last word."""
        speech = board.spec.speech
        anchors = acoustic_anchors(board.speech, board.spec.time_tags)
        for tag in board.spec.time_tags:
            point = tag.id.split(":", 1)[1]
            anchor = anchors[tag.id]
            t = board.speech_onset + (anchor.end if point == "end" else anchor.onset)
            kind = {"start": "started", "end": "finished"}.get(point, "sync")
            board.feedback_entries.append(self._at(t, lambda k=kind, p=point, t=t: board.post(speech, k, p, t)))

    def _start_speech(self, job: Job, board: Blackboard, onset: float) -> None:
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
        board.retire()  # the job keeps the board to the utterance's end: only what is read later stays
        self._check_done(self._job_of(board))

    def _check_done(self, job: Job) -> None:
        if job.finished and not job.done.is_set():
            self._finish(job)

    # ----------------------------------------------------------------- time and frames

    def _at(self, t: float, action: Callable[[], None]) -> int:
        return self._agenda.at(t, action)

    def _cancel(self, key: int) -> None:
        self._agenda.cancel(key)

    def _advance_to(self, t: float, unless: Callable[[], bool] | None = None) -> None:
        """Let time pass until ``t``: sample frames window by window and fire due agenda
        events; return early once ``unless()`` holds (checked after each interrupt check)."""
        while True:
            self._handle_interrupts()
            if unless is not None and unless():
                return
            stop = min(t, self._agenda.next_time(), self._frame_cursor + self._frame_window())
            self.clock.sleep_until(stop)
            self._time = max(self._time, stop)
            self._sample_frames(stop)
            while (action := self._agenda.pop_due(stop + _EPS)) is not None:
                action()
            if stop >= t - _EPS and not self._agenda.next_time() <= t + _EPS:
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

    def _take_interrupt(self, job: Job) -> bool:
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

    def _plan(self, job: Job, index: int, previous: Blackboard | None) -> Blackboard:
        spec = job.chunks[index]
        now = self.clock.now()
        job.timeline.add_chunk(ChunkEntry(index, spec.text))
        behaviors = job.utterance.behaviors_in_chunk(index)
        board = Blackboard(job.name, spec, tuple(b for b in behaviors if b.moves_arms), job.origin, now, self.bus, job.timeline)
        job.boards.append(board)
        with self._lock:
            self._board_jobs[board] = job
        try:
            margin = self.config.live_margin if self.clock.live else 0.0
            self._inprep.fill(board, job, previous, now, margin, self._followed(job, board.index))
        except Exception as error:  # noqa: BLE001 - any failure fails this chunk only; the part performed is kept
            board.error = error
            job.failed = board
            job.timeline.chunk(index).error = f"{type(error).__name__}: {error}"
            board.move(ChunkState.FAILED, self.clock.now(), str(error))
            self._check_done(job)
            return board
        board.move(ChunkState.PENDING, self.clock.now())
        job.timeline.slack.append(PlanningSlack(index, self.clock.now() - job.origin, board.exec_start - job.origin))
        self._announce_plan(board, job)
        return board

    def _announce_plan(self, board: Blackboard, job: Job) -> None:
        """Tell observers the chunk's planned times (BML's prediction feedback is made of them)."""
        tl, entry = job.timeline, job.timeline.chunk(board.index)
        phases = {b.id: dict(b.phases) for b in list(tl.behaviors) if b.chunk == board.index}
        tags = {}
        for tag in board.spec.time_tags:
            anchor = tl.tag_anchors.get(tag.id)
            if anchor is not None:
                tags[tag.id] = anchor["acoustic_end" if tag.id.endswith(":end") and board.spec.speech else "acoustic_onset"]
        self.bus.publish(ChunkPlanned(job.name, board.index, job.origin, entry.speech_onset, entry.speech_end, phases, tags, tuple(tl.warnings)))

    def _contribute(self, function: Callable, *args) -> Future | object:
        if self._contributors is None:
            return function(*args)
        return self._contributors.submit(function, *args)

    def _followed(self, job: Job, index: int) -> tuple[BehaviorSpec, ...] | None:
        """The behaviours of the chunk that follows chunk ``index`` (None when nothing follows yet)."""
        if index + 1 < len(job.chunks):
            return job.utterance.behaviors_in_chunk(index + 1)
        with self._lock:
            queued = self._queue[0] if self._queue else None
        if queued is None:
            return None
        return queued.utterance.behaviors_in_chunk(0) + tuple(queued.absolute)

    # ----------------------------------------------------------------- results

    def _finish(self, job: Job) -> None:
        job.result = performed(job, self.config.keep_output)
        with self._lock:
            (self._active if job in self._active else self._queue).remove(job)
            for board in job.boards:
                self._board_jobs.pop(board, None)
        failed = job.failed
        status = "interrupted" if job.interrupted else "failed" if failed is not None else "done"
        error = f"{type(failed.error).__name__}: {failed.error}" if failed is not None and failed.error is not None else None
        ended = min(job.end, max(self._time, job.origin)) if job.interrupted else job.end  # not the unspoken rest of the audio
        self.bus.publish(UtteranceEnded(job.name, ended - job.origin, job.origin, status, tuple(job.timeline.warnings), error))
        job.done.set()


def _accents(board: Blackboard) -> tuple[tuple[float, float], ...]:
    """The utterance-clock spans of the chunk's affiliates, which its speech emphasizes."""
    marks, onset = board.speech.marks, board.speech_onset
    return tuple(
        (onset + marks[g.behavior.timing.onset], onset + marks[g.behavior.timing.end])
        for g in board.gestures
        if isinstance(g.behavior.timing, Affiliate) and g.behavior.timing.onset in marks and g.behavior.timing.end in marks
    )
