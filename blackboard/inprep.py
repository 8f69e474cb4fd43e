"""InPrep: everything planning a chunk contributes to its blackboard (seed 004, section 5).

Speech synthesis and the movement planner's demands contribute concurrently; then the
time tags are anchored on the audio (:mod:`blackboard.anchors`), the chunk's timing is
solved and relaxed where it must give (:mod:`blackboard.chunk_timing`), each gesture is
planned into a motor program with the motor control, and the result is written to the
timeline. Knowing that a chunk follows sets ``final=False`` for the speech and
``next_gesture_follows`` for gestures followed by another on the same arm.

Absolutely timed behaviours of an utterance with speech are planned with the first chunk
whose speech ends after their onset (the last chunk takes the rest). Behaviours of a BML
block are timed by the block's constraints (:mod:`blackboard.synced`); those no motor
module performs are timed and listed, not planned.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from concurrent.futures import Future

from blackboard import synced
from blackboard.anchors import TagAnchor, acoustic_anchors
from blackboard.board import Blackboard, PlannedGesture
from blackboard.chunk import ChunkState
from blackboard.chunk_timing import ChunkTiming, GestureRequest, time_chunk
from blackboard.config import SchedulerConfig
from blackboard.job import Job
from blackboard.planning import PEG_NAMES, MotorControl, TimePegs
from blackboard.repetitions import with_fewer_repetitions
from blackboard.timeline import BehaviorEntry
from motor.trajectory.spline import fitts_duration
from mura.model import Affiliate, BehaviorSpec
from tts import SpeechError, SpeechRequest, SpeechSynthesizer, SpeechTiming, TextMark
from tts.speech import frozen_marks

#: Preparation distances (m) that differ by less than this between two estimates are the same.
_SAME_DISTANCE = 1e-6


def result(value):
    """The value of a contribution: a future's result, or the value itself."""
    return value.result() if isinstance(value, Future) else value


class ChunkPlanner:
    """Fills a chunk's blackboard in InPrep; ``contribute(function, *args)`` runs a
    contribution (in a worker when live, at once offline) and returns a future or the value."""

    def __init__(self, tts: SpeechSynthesizer, motor: MotorControl, config: SchedulerConfig,
                 contribute: Callable[..., object]) -> None:
        self.tts = tts
        self.motor = motor
        self.config = config
        self.contribute = contribute

    def fill(self, board: Blackboard, job: Job, previous: Blackboard | None, now: float, margin: float,
             follows: tuple[BehaviorSpec, ...] | None) -> None:
        """Speech and demands concurrently, then anchors, timing, motor programs and the timeline."""
        speech_future = self.contribute(self._speak, board, follows)
        demand_futures = {b.id: self.contribute(self.motor.demands, b) for b in board.behaviors}
        board.speech = result(speech_future)
        board.demands = {k: result(f) for k, f in demand_futures.items()}
        anchors = acoustic_anchors(board.speech, board.spec.time_tags) if board.has_speech else {}
        last_word = board.speech.words[-1].end if board.has_speech else 0.0
        pause = self.config.timing.min_pause
        if previous is not None and previous.state is not ChunkState.FAILED:
            # never before the utterance's own start (a queued utterance after an interrupted one)
            earliest = max(previous.speech_end + (pause if previous.has_speech else 0.0), now + margin, job.origin)
            onset_reason = f"speech onset of chunk {board.index + 1} at least {pause:.3f} s after the previous speech end"
            arm_free = max(previous.strokes_done, now + margin, job.origin)
            arm_reason = "arm free once the previous chunk's strokes are done"
            board.lurk_allowed = previous.strokes_done
        else:
            earliest = arm_free = max(job.origin, now + margin)
            onset_reason = f"speech onset of chunk {board.index + 1} not before the utterance starts"
            arm_reason = "arm free from the utterance start"
            board.lurk_allowed = job.origin
        absolute = _take_absolute(job, board, earliest + last_word)
        board.behaviors = board.behaviors + tuple(absolute)
        for b in absolute:
            board.demands[b.id] = self.motor.demands(b)
        unperformed = synced.unperformed(job.utterance, board.index)
        board.demands.update({b.id: synced.nominal_demands(b) for b in unperformed})
        retractions: dict[str, float] = {}
        timing = self._solve(board, job, anchors, earliest, onset_reason, arm_free, arm_reason, unperformed, retractions)
        board.timing = timing
        board.speech_end = timing.speech_onset + last_word
        board.gestures = self._program(board, job, timing, follows)
        if _retime_ends(board, timing, retractions):  # a named end: time it with the motor's own retraction
            timing = self._solve(board, job, anchors, earliest, onset_reason, arm_free, arm_reason, unperformed, retractions)
            board.timing = timing
            board.speech_end = timing.speech_onset + last_word
            board.gestures = self._program(board, job, timing, follows)
        end = max([board.speech_end] + [g.program.pegs.end for g in board.gestures])
        self.config.limits.check_performance(end - job.origin, self.motor.fps, f"the utterance, up to chunk {board.index + 1},")
        _record(board, job, timing, anchors, unperformed)

    def _speak(self, board: Blackboard, follows) -> SpeechTiming | None:
        spec = board.spec
        if not spec.text.strip():
            return None
        tags = {t.id: t for t in spec.time_tags}
        emphasis = [(tags[b.timing.onset].offset, tags[b.timing.end].offset) for b in board.behaviors
                    if isinstance(b.timing, Affiliate) and b.timing.onset in tags and b.timing.end in tags]
        names = {f"mark{n}" if ":" in t.id else t.id: t.id for n, t in enumerate(spec.time_tags)}  # SSML names have no colon
        request = SpeechRequest(
            text=spec.text,
            marks=tuple(TextMark(name, t.offset) for name, t in zip(names, spec.time_tags)),
            emphasis=tuple(sorted(emphasis)),
            final=follows is None,
            voice=self.config.voice,
            rate=self.config.rate,
            with_audio=self.config.with_audio,
        )
        try:
            speech = self.tts.synthesize(request)
        except SpeechError as error:
            raise SpeechError(f"speech of chunk {spec.index + 1} ({spec.text!r}) failed: {error}") from error
        if all(name == tag for name, tag in names.items()):
            return speech
        return dataclasses.replace(speech, marks=frozen_marks({names[name]: t for name, t in speech.marks.items()}))

    def _solve(self, board: Blackboard, job: Job, anchors: Mapping[str, TagAnchor], earliest: float,
               onset_reason: str, arm_free: float, arm_reason: str, unperformed: tuple[BehaviorSpec, ...] = (),
               retractions: dict[str, float] | None = None) -> ChunkTiming:
        """Two passes: preparation distances from where the arms are at a first guess of
        each preparation start, then at the solved starts when they differ."""
        lead = self.config.timing.stroke_lead
        fewer = {b.id: tuple(self.motor.demands(x) for x in with_fewer_repetitions(b)) for b in board.behaviors}
        links, foreign = synced.links(job.utterance, board.index)
        fixed = synced.fixed_times(foreign, job.utterance, job.timeline, job.origin)
        guesses = {}
        for b in board.behaviors:
            if synced.is_synced(b):
                guesses[b.id] = arm_free  # not known before solving: prepare from where the arm is when free
                continue
            if isinstance(b.timing, Affiliate):
                stroke = earliest + anchors[b.timing.onset].onset - lead
            else:
                stroke = job.origin + job.absolute_delay + b.timing.onset
            guesses[b.id] = max(arm_free, stroke - float(fitts_duration(board.demands[b.id].preparation_distance)))

        def solve(starts: Mapping[str, float]) -> tuple[ChunkTiming, dict[str, Mapping[str, float]]]:
            distances = {b.id: self.motor.preparation_distances(b, starts[b.id]) for b in board.behaviors}
            requests = [_request(b, board.demands[b.id], distances[b.id], fewer[b.id], job, self.config, retractions)
                        for b in board.behaviors]
            requests += [_request(b, board.demands[b.id], {}, (), job, self.config) for b in unperformed]
            timing = time_chunk(board.index, earliest, onset_reason, arm_free, arm_reason, anchors, requests,
                                self.config.timing, job.absolute_delay, links, fixed)
            return timing, distances

        timing, distances = solve(guesses)
        solved = {g.behavior: g.prep_start for g in timing.gestures}
        again = {b.id: self.motor.preparation_distances(b, solved[b.id]) for b in board.behaviors}
        if all(_same(again[k], distances[k]) for k in again):
            return timing
        return solve(solved)[0]

    def _program(self, board: Blackboard, job: Job, timing: ChunkTiming, follows) -> tuple[PlannedGesture, ...]:
        later_arms = self._arms_following(board, timing, follows)
        planned = []
        for g, b in zip(timing.gestures, board.behaviors):
            if g.dropped_repetitions:
                b = with_fewer_repetitions(b)[g.dropped_repetitions - 1]
                board.demands[b.id] = self.motor.demands(b)
            d = board.demands[b.id]
            retraction = float(fitts_duration(d.preparation_distance))
            ready = g.ready if g.ready is not None else g.stroke_start
            end = g.end if g.end is not None else g.relax + retraction
            pegs = TimePegs(g.prep_start, ready, g.stroke_start, g.stroke, g.stroke_end, g.relax, end)
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


def _request(b: BehaviorSpec, demands, distances: Mapping[str, float], fewer, job: Job, config: SchedulerConfig | None = None,
             retractions: Mapping[str, float] | None = None) -> GestureRequest:
    if synced.is_synced(b):
        retraction = (retractions or {}).get(b.id, float(fitts_duration(demands.preparation_distance)))
        return GestureRequest(b.id, demands, distances, synced=synced.phases(b, config.timing, retraction))
    if isinstance(b.timing, Affiliate):
        return GestureRequest(b.id, demands, distances, affiliate=(b.timing.onset, b.timing.end), fewer_repetitions=fewer)
    return GestureRequest(b.id, demands, distances, absolute=(job.origin + b.timing.onset, job.origin + b.timing.end),
                          fewer_repetitions=fewer)


def _same(a: Mapping[str, float], b: Mapping[str, float]) -> bool:
    return a.keys() == b.keys() and all(abs(a[k] - b[k]) < _SAME_DISTANCE for k in a)


def _take_absolute(job: Job, board: Blackboard, speech_end: float) -> list[BehaviorSpec]:
    last = board.index == len(job.chunks) - 1
    taken = [b for b in job.absolute if last or job.origin + b.timing.onset < speech_end]
    job.absolute = [b for b in job.absolute if b not in taken]
    return taken


def _retime_ends(board: Blackboard, timing: ChunkTiming, retractions: dict[str, float]) -> bool:
    """For synced gestures whose ``end`` a constraint names: remember the motor's own
    retraction where it differs from the estimate; True when timing must be solved again."""
    named = synced.named_end(board.behaviors)
    solved_end = {g.behavior: g.end for g in timing.gestures}
    again = False
    for planned in board.gestures:
        b = planned.behavior.id
        if b in named and b not in retractions and abs(planned.program.pegs.end - solved_end[b]) > 1e-6:
            retractions[b] = planned.program.pegs.end - planned.program.pegs.relax
            again = True
    return again


def _record(board: Blackboard, job: Job, timing: ChunkTiming, anchors: Mapping[str, TagAnchor],
            unperformed: tuple[BehaviorSpec, ...] = ()) -> None:
    """Write the chunk's speech, anchors, stretches, relaxations and gesture phases to the timeline."""
    tl, o, i = job.timeline, job.origin, board.index
    entry = tl.chunk(i)
    entry.speech_onset = timing.speech_onset - o
    entry.speech_end = board.speech_end - o
    if timing.stretch is not None:
        tl.stretches.append(timing.stretch)  # the absolute clock's delay is in absolute_delay
    job.absolute_delay = timing.absolute_delay
    tl.absolute_delay = timing.absolute_delay
    onset = timing.speech_onset - o
    if board.speech is not None:
        tl.words.extend({"text": w.text, "start": onset + w.start, "end": onset + w.end, "chunk": i} for w in board.speech.words)
        tl.phonemes.extend({"symbol": p.symbol, "start": onset + p.start, "end": onset + p.end, "chunk": i} for p in board.speech.phonemes)
    for name, anchor in anchors.items():
        mark = None if anchor.mark is None else onset + anchor.mark
        if mark is not None:
            tl.time_tags[name] = mark
        tl.tag_anchors[name] = {"mark": mark, "acoustic_onset": onset + anchor.onset, "acoustic_end": onset + anchor.end}
    for g in board.gestures:
        b = g.behavior
        if synced.is_synced(b):
            affiliate = None
        elif isinstance(b.timing, Affiliate):
            first, last = tl.tag_anchors[b.timing.onset], tl.tag_anchors[b.timing.end]
            affiliate = {"onset": first["acoustic_onset"], "end": last["acoustic_end"],
                         "onset_mark": first["mark"], "end_mark": last["mark"]}
        else:
            delay = timing.absolute_delay
            affiliate = {"onset": b.timing.onset + delay, "end": b.timing.end + delay, "absolute": True}
        for relaxation in g.timing.relaxations:
            tl.warn(relaxation.describe())
        tl.add_behavior(BehaviorEntry(
            b.id, i, b.kind, tuple(sorted(g.demands.arms, reverse=True)),
            {name: getattr(g.program.pegs, name) - o for name in PEG_NAMES}, affiliate,
            g.timing.mode, g.timing.repetitions, g.timing.slowdown, False, g.next_gesture_follows,
            [r.to_json() for r in g.timing.relaxations],
        ))
    for dropped in timing.dropped:
        tl.warn(f"constraint {dropped} dropped: it conflicts with the rest of the block and is not required")
    timed = {g.behavior: g for g in timing.gestures}
    for b in unperformed:
        g = timed[b.id]
        phases = dict(zip(PEG_NAMES, (g.prep_start, g.ready, g.stroke_start, g.stroke, g.stroke_end, g.relax, g.end)))
        for relaxation in g.relaxations:
            tl.warn(relaxation.describe())
        tl.add_behavior(BehaviorEntry(b.id, i, b.kind, (), {name: t - o for name, t in phases.items()}, None,
                                      g.mode, g.repetitions, g.slowdown, relaxations=[r.to_json() for r in g.relaxations],
                                      performed=False))
