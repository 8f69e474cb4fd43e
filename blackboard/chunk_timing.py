"""Within-chunk timing: the chunk's speech and gestures as a temporal network that relaxes
before it refuses (seed 004, section 5; :mod:`blackboard.timing`, :mod:`blackboard.relaxation`).

Time points: the utterance start, the chunk's speech onset, the absolute clock start,
the acoustic anchors of the affiliates (:mod:`blackboard.anchors`) and, per gesture, its
preparation start, stroke onset and stroke span end. The constraints of a gesture with an
affiliate:

* stroke onset = affiliate onset − ``stroke_lead`` (about one syllable, 0.2 s), the
  affiliate onset being the acoustic onset of its first word; a gesture that follows
  another on the same arm may start its stroke later, down to no lead
  (``later_stroke_onset``);
* stroke span end ≥ the acoustic end of the affiliate's last word, and ≥ stroke onset +
  the natural stroke duration (fewer written repetitions shorten it: ``dropped_repetition``);
* stroke onset − preparation start ≥ the preparation time: Fitts' law on the distance
  from where the arm is expected to be, never faster than the speed budget of the
  gesture's manner (``motor.trajectory.speed_budget``); it may go stroke to stroke from an
  earlier gesture on the same arm (``co_articulation``) and shrink to the budget's
  shortest movement (``shorter_preparation``);
* preparation start ≥ the time the arm is free; a later gesture on the same arm prepares
  after the earlier one's stroke span ends (its retraction is then cut, or skipped).

The speech onset is the earliest allowed (the previous speech end plus a minimal pause);
the pause grows only when nothing inside the chunk can give (``stretched_pause``), and the
stretch is reported with the constraints that forced it. An absolutely timed gesture's
stroke spans ``[onset, end]`` of the absolute clock, which runs with the utterance clock
but may start late: when an absolute stroke comes sooner than its preparation allows,
every absolute time of the utterance is delayed alike (``stretched_pause`` of the
absolute clock; later chunks keep the delay). An absolute stroke must last at least the
shortest movement of its path within the speed budget; when its timing asks for more
speed its end moves later (``longer_stroke``). How each stroke then fills its span:
:mod:`blackboard.stroke_fill`.

A behaviour timed by sync constraints (BML) has a point for each of its seven pegs
(``start``, ``ready``, ``stroke_start``, ``stroke``, ``stroke_end``, ``relax``, ``end``)
and the block's constraints between them (:class:`SyncLink`: equal, before, after, with
offsets; times on the block clock are counted from the absolute clock start). Its phases
keep their natural lengths unless the block names the pegs that bound them: the
preparation takes at least its duration, with the same gives as above (a gesture starts
it as soon as the arm is free, as for MURML; another behaviour keeps its nominal length
unless its ``start`` is named), ``ready`` is the stroke onset unless ``ready`` is named
(then a pre-stroke hold), the stroke point lies ``lead`` into the stroke unless both are
named, the stroke lasts at least its natural duration and goes on ``lead`` past its
stroke point, ``relax`` is the stroke end unless named (then a post-stroke hold), and the
retraction keeps its duration unless both ``relax`` and ``end`` are named. When no
relaxation satisfies the constraints, the one stated last among the block's constraints
that are not required and take part in the conflict is dropped, and solving starts again
(named in :attr:`ChunkTiming.dropped`); points of earlier chunks enter as fixed times.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from blackboard.anchors import TagAnchor
from blackboard.errors import TimingConflict
from blackboard.planning import PEG_NAMES, GestureDemands
from blackboard.relaxation import Relaxation, RelaxationStep, merged
from blackboard.stroke_fill import fill_stroke
from blackboard.timing import ZERO, Give, TemporalNetwork
from motor.trajectory.speed_budget import budget
from motor.trajectory.spline import fitts_duration

#: The absolute clock's start, a time point of every chunk's network.
ABSOLUTE = "absolute clock start"
_EPS = 1e-9


@dataclass(frozen=True)
class TimingConfig:
    """Constants of the timing rules, seconds (``max_slowdown`` is a factor)."""

    stroke_lead: float = 0.2
    min_pause: float = 0.25
    max_slowdown: float = 1.5


@dataclass(frozen=True)
class SyncedPhases:
    """How a behaviour timed by sync constraints keeps its phases (module docstring).

    ``named``: the pegs some constraint names; ``arm_bound``: a gesture, whose preparation
    starts once the arm is free; ``lead``: seconds from the stroke onset to the stroke point
    (and at least as long after it); ``retraction``: seconds from relax to end;
    ``preparation``: the nominal preparation of a behaviour no motor module performs
    (None: from the arms' distances, as for every gesture).
    """

    named: frozenset[str]
    arm_bound: bool
    lead: float
    retraction: float
    preparation: float | None = None


@dataclass(frozen=True)
class SyncLink:
    """A constraint between two points of the network: ``t[point] − t[anchor]`` is
    ``offset`` (``relation`` ``=``), at most (``<=``) or at least (``>=``) that, seconds.
    ``name`` says it in the spec's words; a link that is not ``required`` may be dropped."""

    point: str
    anchor: str
    relation: str
    offset: float
    name: str
    behavior: str | None = None
    required: bool = True


@dataclass(frozen=True)
class GestureRequest:
    """One gesture to time in a chunk: exactly one of ``affiliate`` (onset tag, end tag),
    ``absolute`` (onset, end, s on the absolute clock) and ``synced`` (timed by
    :class:`SyncLink` constraints).

    ``distances``: metres each arm travels to the stroke's start from where it is expected
    to be when the preparation starts (the motor's estimate, previous chunks included).
    ``fewer_repetitions``: the demands with one, two, … of the gesture's written
    repetitions dropped (empty when it has none).
    """

    behavior: str
    demands: GestureDemands
    distances: Mapping[str, float]
    affiliate: tuple[str, str] | None = None
    absolute: tuple[float, float] | None = None
    fewer_repetitions: tuple[GestureDemands, ...] = ()
    synced: SyncedPhases | None = None


@dataclass(frozen=True)
class GestureTiming:
    """Where a gesture's phases fall, seconds on the utterance clock.

    ``mode`` is how the stroke fills its span: ``static``, ``slowed``, ``repeated`` or
    ``held``; ``slowdown`` the factor applied to the natural stroke duration;
    ``relaxations`` what gave way for it; ``dropped_repetitions`` how many written
    repetitions were dropped.
    """

    behavior: str
    prep_start: float
    stroke_start: float
    stroke: float
    stroke_end: float
    relax: float
    repetitions: int
    mode: str
    slowdown: float
    relaxations: tuple[Relaxation, ...] = ()
    dropped_repetitions: int = 0
    ready: float | None = None
    end: float | None = None


@dataclass(frozen=True)
class PauseStretch:
    """The vocal pause before ``chunk`` grew by ``amount`` seconds; ``reason`` lists the constraints that forced it."""

    chunk: int
    amount: float
    reason: str
    behavior: str | None


@dataclass(frozen=True)
class ChunkTiming:
    """The solved timing of one chunk; ``absolute_delay`` is how late the absolute clock
    starts (seconds after the utterance start), ``absolute_stretch`` says why when this
    chunk made it later than asked."""

    speech_onset: float
    gestures: tuple[GestureTiming, ...]
    stretch: PauseStretch | None
    absolute_delay: float = 0.0
    absolute_stretch: PauseStretch | None = None
    dropped: tuple[str, ...] = ()


def speech_point(chunk: int) -> str:
    return f"speech onset of chunk {chunk + 1}"


def onset_point(tag: str) -> str:
    return f"acoustic onset at {tag}"


def end_point(tag: str) -> str:
    return f"acoustic end at {tag}"


def peg_point(behavior: str, peg: str) -> str:
    """The network point of ``behavior``'s peg (one of ``PEG_NAMES``)."""
    prep, onset, span_end = _points(behavior)
    return {"start": prep, "stroke_start": onset, "relax": span_end}.get(peg, f"{peg.replace('_', ' ')} of {behavior}")


def preparation_times(distances: Mapping[str, float], manner: str | None) -> tuple[float, float]:
    """``(comfortable, shortest)`` seconds to bring the arms ``distances`` metres: Fitts'
    law but never faster than the manner's speed budget, and the budget's shortest
    minimum-jerk movement; the farthest arm counts."""
    limit = budget(manner)
    comfortable = shortest = 0.0
    for distance in distances.values():
        fastest = limit.shortest_duration(distance)
        comfortable = max(comfortable, float(fitts_duration(distance)), fastest)
        shortest = max(shortest, fastest)
    return comfortable, shortest


def time_chunk(
    chunk: int,
    earliest_onset: float,
    onset_reason: str,
    arm_free: float,
    arm_free_reason: str,
    anchors: Mapping[str, TagAnchor],
    gestures: Sequence[GestureRequest],
    config: TimingConfig = TimingConfig(),
    absolute_delay: float = 0.0,
    links: Sequence[SyncLink] = (),
    fixed: Mapping[str, float] | None = None,
) -> ChunkTiming:
    """Solve chunk ``chunk``'s timing, relaxing what must give (module docstring).

    ``earliest_onset`` is the earliest speech onset on the utterance clock (the previous
    speech end plus the pause, or the utterance start) and ``onset_reason`` says so in
    words; ``arm_free`` is when this chunk's gestures may start preparing. ``anchors``
    are the time tags' acoustic anchors, seconds from the chunk's speech onset. Gestures
    on the same arm are ordered by their stroke onset as the spec asks for it. Absolute
    times are counted from the absolute clock start, at least ``absolute_delay`` after
    the utterance start (the delay earlier chunks needed). ``links`` are sync constraints
    between points (:func:`peg_point`, :func:`onset_point`, :data:`ABSOLUTE` …); ``fixed``
    the times of points already timed with earlier chunks. Raises
    :class:`~blackboard.errors.TimingConflict` when no relaxation satisfies the constraints
    (and dropping the optional links in conflict does not help).
    """
    speech = speech_point(chunk)
    at_earliest = f"speech of chunk {chunk + 1} at its earliest, {earliest_onset:.3f} s"
    absolute_start = f"absolute timings start {absolute_delay:.3f} s after the utterance start"

    def network(active: Sequence[SyncLink], hints: Mapping[str, float] | None) -> TemporalNetwork:
        net = TemporalNetwork()
        stretch = (Give(RelaxationStep.STRETCHED_PAUSE, float("inf")),)
        net.at_least(speech, ZERO, earliest_onset, onset_reason)
        net.at_most(speech, ZERO, earliest_onset, at_earliest, gives=stretch)
        net.at_least(ABSOLUTE, ZERO, absolute_delay, f"absolute timings run {absolute_delay:.3f} s late")
        net.at_most(ABSOLUTE, ZERO, absolute_delay, absolute_start, gives=stretch)
        for tag, anchor in anchors.items():
            net.exactly(onset_point(tag), speech, anchor.onset, f"time tag {tag}: word onset {anchor.onset:.3f} s into the speech of chunk {chunk + 1}")
            net.exactly(end_point(tag), speech, anchor.end, f"time tag {tag}: word end {anchor.end:.3f} s into the speech of chunk {chunk + 1}")
        for point, time in (fixed or {}).items():
            net.exactly(point, ZERO, time, f"{point} at {time:.3f} s, timed with an earlier chunk")
        previous = _previous_on_arm(gestures, anchors, earliest_onset, absolute_delay, hints)
        for g in gestures:
            _add_gesture(net, g, previous[g.behavior] if hints is not None else {}, arm_free, arm_free_reason, config)
        for link in active:
            _add_link(net, link)
        return net

    active, dropped = list(links), []
    hints = _synced_onsets(network, active, gestures, chunk)
    while True:
        try:
            times, taken = network(active, hints).solve(f"chunk {chunk + 1}")
            break
        except TimingConflict as conflict:
            optional = [link for link in active if not link.required and link.name in conflict.constraints]
            if not optional:
                raise
            active.remove(optional[-1])  # the one stated last yields: what came first is kept
            dropped.append(optional[-1].name)
    by_behavior: dict[str | None, list[Relaxation]] = {}
    for r in taken:
        by_behavior.setdefault(r.behavior, []).append(r)
    timed = tuple(_timed(g, times, by_behavior.get(g.behavior, []), config) for g in gestures)
    onset, delay = times[speech], times[ABSOLUTE]
    return ChunkTiming(
        onset, timed, _stretch(chunk, taken, at_earliest, onset - earliest_onset),
        delay, _stretch(chunk, taken, absolute_start, delay - absolute_delay), tuple(dropped),
    )


def _synced_onsets(network, links: Sequence[SyncLink], gestures: Sequence[GestureRequest], chunk: int) -> dict[str, float]:
    """Stroke onsets of the synced gestures solved without the same-arm order, to order them by."""
    if not any(g.synced is not None for g in gestures):
        return {}
    try:
        times, _ = network(links, None).solve(f"chunk {chunk + 1} (order)")
    except TimingConflict:
        return {}
    return {g.behavior: times[_points(g.behavior)[1]] for g in gestures if g.synced is not None}


def _add_link(net: TemporalNetwork, link: SyncLink) -> None:
    if link.relation in ("=", ">="):
        net.at_least(link.point, link.anchor, link.offset, link.name, link.behavior)
    if link.relation in ("=", "<="):
        net.at_most(link.point, link.anchor, link.offset, link.name, link.behavior)


def _stretch(chunk: int, taken: Sequence[Relaxation], constraint: str, amount: float) -> PauseStretch | None:
    """The stretch of the pause that relaxing ``constraint`` by ``amount`` seconds made, with the constraints that forced it."""
    causes = [r for r in taken if r.constraint == constraint]
    if amount <= _EPS or not causes:
        return None
    reason = "; ".join(dict.fromkeys(name for r in causes for name in r.conflict if name != constraint))
    return PauseStretch(chunk, amount, reason, causes[0].behavior)


def _points(behavior: str) -> tuple[str, str, str]:
    return f"preparation start of {behavior}", f"stroke onset of {behavior}", f"stroke end of {behavior}"


def _requested_onset(g: GestureRequest, anchors: Mapping[str, TagAnchor], earliest: float, delay: float,
                     hints: Mapping[str, float] | None = None) -> float:
    if g.synced is not None:
        return (hints or {}).get(g.behavior, math.inf)
    if g.absolute is not None:
        return delay + g.absolute[0]
    return earliest + anchors[g.affiliate[0]].onset


def _previous_on_arm(gestures: Sequence[GestureRequest], anchors, earliest: float, delay: float,
                    hints: Mapping[str, float] | None = None) -> dict[str, dict[str, GestureRequest]]:
    """Per gesture, per arm it shares with an earlier gesture of the chunk: that gesture."""
    ordered = sorted(gestures, key=lambda g: _requested_onset(g, anchors, earliest, delay, hints))
    last: dict[str, GestureRequest] = {}
    out = {}
    for g in ordered:
        out[g.behavior] = {arm: last[arm] for arm in sorted(g.demands.arms) if arm in last}
        for arm in g.demands.arms:
            last[arm] = g
    return out


def _add_gesture(net: TemporalNetwork, g: GestureRequest, previous: Mapping[str, GestureRequest],
                 arm_free: float, arm_free_reason: str, config: TimingConfig) -> None:
    b = g.behavior
    prep, onset, span_end = _points(b)
    if g.synced is not None:
        _add_synced(net, g, previous, arm_free, arm_free_reason)
        return
    if g.absolute is not None:
        start, end = g.absolute
        net.exactly(onset, ABSOLUTE, start, f"{b}: stroke onset at absolute {start:.3f} s", b)
        net.at_least(span_end, ABSOLUTE, end, f"{b}: stroke end at absolute {end:.3f} s", b)
        net.at_most(span_end, ABSOLUTE, end, f"{b}: stroke ends at absolute {end:.3f} s", b,
                    gives=(Give(RelaxationStep.LONGER_STROKE, float("inf")),))
        shortest = [budget(d.manner).shortest_duration(d.stroke_distance) for d in (g.demands,) + g.fewer_repetitions]
        _stroke_lasts(net, g, shortest, f"{b}: stroke of {g.demands.stroke_distance:.3f} m within its speed budget "
                                        f"takes at least {shortest[0]:.3f} s")
    else:
        first, last = g.affiliate
        lead = config.stroke_lead
        net.at_least(onset, onset_point(first), -lead, f"{b}: stroke onset not earlier than {lead:.3f} s before affiliate onset {first}", b)
        later = (Give(RelaxationStep.LATER_STROKE_ONSET, lead),) if previous else ()
        net.at_most(onset, onset_point(first), -lead, f"{b}: stroke onset {lead:.3f} s before affiliate onset {first}", b, later)
        net.at_least(span_end, end_point(last), 0.0, f"{b}: stroke spans its affiliate up to {last}", b)
        natural = [d.stroke_duration for d in (g.demands,) + g.fewer_repetitions]
        _stroke_lasts(net, g, natural, f"{b}: stroke lasts at least its natural {natural[0]:.3f} s")
    _add_preparation(net, g, previous, onset, arm_free, arm_free_reason)


def _add_preparation(net: TemporalNetwork, g: GestureRequest, previous: Mapping[str, GestureRequest], ready: str,
                     arm_free: float, arm_free_reason: str) -> None:
    """Preparation start to ``ready``: at least its time, with the gives of co-articulation
    and of a shorter preparation; the arm free; after the strokes of earlier gestures on it."""
    b = g.behavior
    prep = _points(b)[0]
    comfortable, shortest = preparation_times(g.distances, g.demands.manner)
    gives = []
    floor = shortest
    if previous:
        joined, joined_shortest = preparation_times(_stroke_to_stroke(g, previous), g.demands.manner)
        if joined < comfortable - _EPS:
            gives.append(Give(RelaxationStep.CO_ARTICULATION, comfortable - joined, whole=True, amount=comfortable - joined))
            floor = joined_shortest
    gives.append(Give(RelaxationStep.SHORTER_PREPARATION, comfortable - sum(give.seconds for give in gives) - floor))
    net.at_least(ready, prep, comfortable, f"{b}: preparation takes {comfortable:.3f} s", b, tuple(gives))
    net.at_least(prep, ZERO, arm_free, f"{b}: {arm_free_reason}", b)
    for arm, earlier in sorted(previous.items()):
        net.at_least(prep, _points(earlier.behavior)[2], 0.0, f"{b} prepares after the stroke of {earlier.behavior} on the {arm} arm", b)


def _add_synced(net: TemporalNetwork, g: GestureRequest, previous: Mapping[str, GestureRequest],
                arm_free: float, arm_free_reason: str) -> None:
    """The points of a synced behaviour and how its phases hold together (module docstring)."""
    b, phases, named = g.behavior, g.synced, g.synced.named
    start, ready, onset, stroke, stroke_end, relax, end = (peg_point(b, peg) for peg in PEG_NAMES)
    natural = g.demands.stroke_duration if g.demands.dynamic else 0.0
    if phases.preparation is None:
        _add_preparation(net, g, previous, ready, arm_free, arm_free_reason)
    else:
        net.at_least(ready, start, phases.preparation, f"{b}: preparation takes {phases.preparation:.3f} s", b)
        if "start" not in named:
            net.at_most(ready, start, phases.preparation, f"{b}: preparation keeps its {phases.preparation:.3f} s", b)
    net.at_least(onset, ready, 0.0, f"{b}: stroke starts once ready", b)
    if "ready" not in named:
        net.at_most(onset, ready, 0.0, f"{b}: stroke starts when ready (no pre-stroke hold asked for)", b)
    if {"stroke", "stroke_start"} <= named:
        net.at_least(stroke, onset, 0.0, f"{b}: stroke point within the stroke", b)
    else:
        net.exactly(stroke, onset, phases.lead, f"{b}: stroke point {phases.lead:.3f} s into the stroke", b)
    net.at_least(stroke_end, stroke, phases.lead, f"{b}: stroke goes on {phases.lead:.3f} s past its stroke point", b)
    if natural > 0.0:
        net.at_least(stroke_end, onset, natural, f"{b}: stroke lasts at least its natural {natural:.3f} s", b)
    net.at_least(relax, stroke_end, 0.0, f"{b}: relax after the stroke", b)
    if "relax" not in named:
        net.at_most(relax, stroke_end, 0.0, f"{b}: relax when the stroke ends (no post-stroke hold asked for)", b)
    net.at_least(end, relax, phases.retraction, f"{b}: retraction takes {phases.retraction:.3f} s", b)
    if not {"relax", "end"} <= named:
        net.at_most(end, relax, phases.retraction, f"{b}: retraction keeps its {phases.retraction:.3f} s", b)


def _stroke_lasts(net: TemporalNetwork, g: GestureRequest, minimum: list[float], name: str) -> None:
    """Stroke span ≥ ``minimum[0]``; ``minimum[k]`` is the minimum with ``k`` written
    repetitions dropped, each drop that shortens it a whole give (of as many repetitions as
    it takes to shorten it)."""
    if not g.demands.dynamic or minimum[0] <= 0:
        return
    gives, kept, count = [], minimum[0], 0
    for shorter in minimum[1:]:
        count += 1
        if kept - shorter > _EPS:
            gives.append(Give(RelaxationStep.DROPPED_REPETITION, kept - shorter, whole=True, amount=float(count), unit="repetitions"))
            kept, count = shorter, 0
    _, onset, span_end = _points(g.behavior)
    net.at_least(span_end, onset, minimum[0], name, g.behavior, tuple(gives))


def _stroke_to_stroke(g: GestureRequest, previous: Mapping[str, GestureRequest]) -> dict[str, float]:
    """Per arm, metres from where the earlier gesture's stroke ends to where this one's starts."""
    distances = dict(g.distances)
    for arm, earlier in previous.items():
        start, end = g.demands.first_wrists.get(arm), earlier.demands.last_wrists.get(arm)
        if start is not None and end is not None:
            distances[arm] = float(np.linalg.norm(np.subtract(start, end)))
    return distances


def _timed_synced(g: GestureRequest, times: Mapping[str, float], relaxations: list[Relaxation], config: TimingConfig) -> GestureTiming:
    """A synced behaviour's pegs as solved; the stroke fills its span as any stroke does
    (:mod:`blackboard.stroke_fill`), a held stroke only when its stroke end is not named."""
    start, ready, onset, stroke, stroke_end, relax, end = (times[peg_point(g.behavior, peg)] for peg in PEG_NAMES)
    named_end = "stroke_end" in g.synced.named
    fill = fill_stroke(g.behavior, g.demands, onset, stroke_end if named_end else relax, config.max_slowdown)
    mode, count, slowdown, filled_end = fill.mode, fill.repetitions, fill.slowdown, max(fill.stroke_end, stroke)
    if named_end and fill.mode == "held":
        mode, slowdown, filled_end = "slowed", (stroke_end - onset) / g.demands.stroke_duration, stroke_end
    if fill.relaxation is not None:
        relaxations = relaxations + [fill.relaxation]
    return GestureTiming(g.behavior, start, onset, stroke, filled_end, relax, count, mode, slowdown,
                         merged(sorted(relaxations, key=lambda r: r.step.rank)), 0, ready, end)


def _timed(g: GestureRequest, times: Mapping[str, float], relaxations: list[Relaxation], config: TimingConfig) -> GestureTiming:
    if g.synced is not None:
        return _timed_synced(g, times, relaxations, config)
    prep, onset, span_end = (times[p] for p in _points(g.behavior))
    dropped = int(sum(r.amount for r in relaxations if r.step is RelaxationStep.DROPPED_REPETITION))
    demands = g.fewer_repetitions[dropped - 1] if dropped else g.demands
    fill = fill_stroke(g.behavior, demands, onset, span_end, config.max_slowdown)
    accent = times[onset_point(g.affiliate[0])] if g.affiliate is not None else onset
    accent = min(max(accent, onset), fill.stroke_end)
    if fill.relaxation is not None:
        relaxations = relaxations + [fill.relaxation]
    return GestureTiming(g.behavior, prep, onset, accent, fill.stroke_end, span_end, fill.repetitions, fill.mode,
                         fill.slowdown, merged(sorted(relaxations, key=lambda r: r.step.rank)), dropped)
