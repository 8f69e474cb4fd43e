"""Within-chunk timing as a simple temporal network (seed 004, section 5).

Time points (the utterance start, the chunk's speech onset, its time tags, and per
gesture the preparation start, stroke onset and stroke span end) are nodes of a
:class:`networkx.DiGraph`; every constraint ``t_v − t_u ≥ l`` is an edge ``u → v`` of
weight ``−l`` (an upper bound ``t_v − t_u ≤ w`` is the edge ``v → u`` of weight ``−w``).
Bellman–Ford from the utterance start then gives minus the earliest consistent time of
every point; a negative cycle is a set of constraints no timing satisfies, reported by
the constraints' own names. Weights are whole nanoseconds, so that tight cycles (a
preparation that fits exactly) sum to exactly zero.

The constraints of a gesture with an affiliate:

* stroke onset = affiliate onset − ``stroke_lead`` (about one syllable, 0.2 s);
* stroke span end ≥ affiliate end, and ≥ stroke onset + the natural stroke duration;
* stroke onset − preparation start ≥ the preparation duration (Fitts' law, from the
  motor planner), preparation start ≥ the time the arm is free;
* a later gesture on the same arm prepares after the earlier one's stroke span ends
  (co-articulation: the earlier retraction is skipped).

The speech onset is bounded below by the previous chunk's speech end plus a minimal
pause. Since the stroke onset is tied to the speech, a preparation that cannot fit pushes
the speech onset later: the vocal pause before the chunk is stretched, and the stretch
is reported with the chain of constraints that caused it. An absolutely timed gesture's
stroke spans ``[onset, end]`` of the absolute clock, which runs with the utterance clock
but may start late: when an absolute stroke comes sooner than its preparation from rest
allows (published MURML asks for strokes at 1.0 s that take longer to prepare), every
absolute time of the utterance is delayed alike, the least that makes them fit; the delay
is reported like a stretched pause, and later chunks keep it.

How a stroke fills its span (``relax − stroke onset``), with ``f`` = span / natural
duration: a static stroke holds its posture; ``f ≤ max_slowdown`` (1.5) slows one
stroke to span it; a repeatable stroke with ``f ≥ 2`` is performed ``⌊f⌋`` times, each
slowed by ``f/⌊f⌋ < 1.5``; otherwise the stroke is slowed by ``max_slowdown`` and its
end posture held until the span ends (a post-stroke hold, ``stroke_end < relax``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import networkx as nx

from blackboard.errors import ScheduleError, TimingConflict
from blackboard.planning import GestureDemands

_NS = 1_000_000_000
ZERO = "utterance start"
ABSOLUTE = "absolute clock start"


@dataclass(frozen=True)
class TimingConfig:
    """Constants of the timing rules, seconds (``max_slowdown`` is a factor)."""

    stroke_lead: float = 0.2
    min_pause: float = 0.25
    max_slowdown: float = 1.5


@dataclass(frozen=True)
class GestureRequest:
    """One gesture to time in a chunk: exactly one of ``affiliate`` (onset tag, end tag) and ``absolute`` (onset, end, s)."""

    behavior: str
    demands: GestureDemands
    preparation: float
    affiliate: tuple[str, str] | None = None
    absolute: tuple[float, float] | None = None


@dataclass(frozen=True)
class GestureTiming:
    """Where a gesture's phases fall, seconds on the utterance clock.

    ``mode`` is how the stroke fills its span: ``static``, ``slowed``, ``repeated`` or
    ``held``; ``slowdown`` the factor applied to the natural stroke duration.
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


#: Largest time the network holds, seconds (about 31 years): beyond it a spec asks for nonsense.
MAX_SECONDS = 1e9


def _ns(seconds: float, name: str = "a time") -> int:
    if not math.isfinite(seconds) or abs(seconds) > MAX_SECONDS:
        raise ScheduleError(f"{name}: {seconds} s is not a time the schedule can hold (at most {MAX_SECONDS:g} s)")
    return int(round(seconds * _NS))


class TemporalNetwork:
    """A simple temporal network of named time points and named difference constraints."""

    def __init__(self) -> None:
        self.graph = nx.DiGraph()
        self.graph.add_node(ZERO)

    def at_least(self, later: str, earlier: str, gap: float, name: str, behavior: str | None = None) -> None:
        """``t[later] − t[earlier] ≥ gap`` seconds."""
        self._edge(earlier, later, -_ns(gap, name), name, behavior)

    def at_most(self, later: str, earlier: str, gap: float, name: str, behavior: str | None = None) -> None:
        """``t[later] − t[earlier] ≤ gap`` seconds."""
        self._edge(later, earlier, _ns(gap, name), name, behavior)

    def exactly(self, later: str, earlier: str, gap: float, name: str, behavior: str | None = None) -> None:
        """``t[later] − t[earlier] = gap`` seconds."""
        self.at_least(later, earlier, gap, name, behavior)
        self.at_most(later, earlier, gap, name, behavior)

    def _edge(self, u: str, v: str, weight: int, name: str, behavior: str | None) -> None:
        for node in (u, v):
            if node not in self.graph:
                self.graph.add_node(node)
                self.graph.add_edge(ZERO, node, weight=0, name=f"{node} is not before the utterance start", behavior=None)
        existing = self.graph.get_edge_data(u, v)
        if existing is None or weight <= existing["weight"]:  # keep the tightest; on a tie, the most specific (latest)
            self.graph.add_edge(u, v, weight=weight, name=name, behavior=behavior)

    def solve(self, label: str) -> tuple[dict[str, float], dict[str, list[str]]]:
        """Earliest time of every point, and Bellman–Ford's predecessors (the binding constraints).

        Raises :class:`TimingConflict` naming the constraints of a negative cycle.
        """
        try:
            pred, dist = nx.bellman_ford_predecessor_and_distance(self.graph, ZERO)
        except nx.NetworkXUnbounded:
            cycle = nx.find_negative_cycle(self.graph, ZERO)
            names = tuple(dict.fromkeys(self.graph.edges[u, v]["name"] for u, v in zip(cycle, cycle[1:])))
            raise TimingConflict(f"{label}: timing constraints conflict: " + "; ".join(names), names) from None
        return {node: -d / _NS for node, d in dist.items()}, pred

    def binding_chain(self, pred: Mapping[str, list[str]], point: str) -> list[tuple[str, str | None]]:
        """The constraints (name, behaviour) along the chain that fixes ``point``'s earliest time, from the start."""
        chain: list[tuple[str, str | None]] = []
        seen = {point}
        node = point
        while node != ZERO:
            options = [p for p in pred.get(node, []) if p not in seen] or [ZERO]
            previous = options[0]
            data = self.graph.get_edge_data(previous, node) or {"name": "", "behavior": None}
            chain.append((data["name"], data["behavior"]))
            seen.add(previous)
            node = previous
        return chain[::-1]


def speech_point(chunk: int) -> str:
    return f"speech onset of chunk {chunk + 1}"


def tag_point(tag: str) -> str:
    return f"time tag {tag}"


def time_chunk(
    chunk: int,
    earliest_onset: float,
    onset_reason: str,
    arm_free: float,
    arm_free_reason: str,
    marks: Mapping[str, float],
    gestures: Sequence[GestureRequest],
    config: TimingConfig = TimingConfig(),
    absolute_delay: float = 0.0,
) -> ChunkTiming:
    """Solve chunk ``chunk``'s timing.

    ``earliest_onset`` is the earliest speech onset on the utterance clock (the previous
    speech end plus the pause, or the utterance start) and ``onset_reason`` says so in
    words; ``arm_free`` is when this chunk's gestures may start preparing. ``marks`` are
    the time tags' times from the chunk's speech onset (the TTS's marks). Gestures on the
    same arm are ordered by their stroke onset as the spec asks for it. Absolute times are
    counted from the absolute clock start, at least ``absolute_delay`` after the utterance
    start (the delay earlier chunks needed).
    """
    net = TemporalNetwork()
    speech = speech_point(chunk)
    net.at_least(speech, ZERO, earliest_onset, onset_reason)
    net.at_least(ABSOLUTE, ZERO, absolute_delay, f"absolute timings run {absolute_delay:.3f} s late")
    for tag, offset in marks.items():
        net.exactly(tag_point(tag), speech, offset, f"time tag {tag} at {offset:.3f} s into the speech of chunk {chunk + 1}")
    for gesture in gestures:
        _add_gesture(net, gesture, arm_free, arm_free_reason, config)
    _order_same_arm(net, gestures, marks)
    times, pred = net.solve(f"chunk {chunk + 1}")
    onset = times[speech]
    stretch = None
    if onset - earliest_onset > 1e-9:
        chain = net.binding_chain(pred, speech)
        behaviors = [b for _, b in chain if b is not None]
        stretch = PauseStretch(
            chunk=chunk,
            amount=onset - earliest_onset,
            reason="; ".join(name for name, _ in chain),
            behavior=behaviors[0] if behaviors else None,
        )
    timed = tuple(_fill_stroke(gesture, times, config) for gesture in gestures)
    delay = times[ABSOLUTE]
    absolute_stretch = None
    if delay - absolute_delay > 1e-9:
        chain = net.binding_chain(pred, ABSOLUTE)
        behaviors = [b for _, b in chain if b is not None]
        absolute_stretch = PauseStretch(chunk, delay - absolute_delay, "; ".join(name for name, _ in chain), behaviors[0] if behaviors else None)
    return ChunkTiming(onset, timed, stretch, delay, absolute_stretch)


def _points(behavior: str) -> tuple[str, str, str]:
    return f"preparation start of {behavior}", f"stroke onset of {behavior}", f"stroke end of {behavior}"


def _add_gesture(net: TemporalNetwork, g: GestureRequest, arm_free: float, arm_free_reason: str, config: TimingConfig) -> None:
    b = g.behavior
    prep, onset, span_end = _points(b)
    if g.absolute is not None:
        start, end = g.absolute
        net.exactly(onset, ABSOLUTE, start, f"{b}: stroke onset at absolute {start:.3f} s", b)
        net.exactly(span_end, ABSOLUTE, end, f"{b}: stroke end at absolute {end:.3f} s", b)
    else:
        first, last = g.affiliate
        net.exactly(onset, tag_point(first), -config.stroke_lead,
                    f"{b}: stroke onset {config.stroke_lead:.3f} s before affiliate onset {first}", b)
        net.at_least(span_end, tag_point(last), 0.0, f"{b}: stroke spans its affiliate up to {last}", b)
        if g.demands.dynamic and g.demands.stroke_duration > 0:
            net.at_least(span_end, onset, g.demands.stroke_duration,
                         f"{b}: stroke lasts at least its natural {g.demands.stroke_duration:.3f} s", b)
    net.at_least(onset, prep, g.preparation, f"{b}: preparation takes {g.preparation:.3f} s", b)
    net.at_least(prep, ZERO, arm_free, f"{b}: {arm_free_reason}", b)


def _order_same_arm(net: TemporalNetwork, gestures: Sequence[GestureRequest], marks: Mapping[str, float]) -> None:
    def requested_onset(g: GestureRequest) -> float:
        return g.absolute[0] if g.absolute is not None else math.inf if g.affiliate is None else marks[g.affiliate[0]]

    ordered = sorted(gestures, key=requested_onset)
    last_on_arm: dict[str, GestureRequest] = {}
    for g in ordered:
        for arm in sorted(g.demands.arms):
            earlier = last_on_arm.get(arm)
            if earlier is not None:
                net.at_least(_points(g.behavior)[0], _points(earlier.behavior)[2], 0.0,
                             f"{g.behavior} prepares after the stroke of {earlier.behavior} on the {arm} arm", g.behavior)
            last_on_arm[arm] = g


def _fill_stroke(g: GestureRequest, times: Mapping[str, float], config: TimingConfig) -> GestureTiming:
    prep, onset, span_end = (times[p] for p in _points(g.behavior))
    accent = times[tag_point(g.affiliate[0])] if g.affiliate is not None else onset
    accent = min(max(accent, onset), span_end)
    span = span_end - onset
    natural = g.demands.stroke_duration
    if not g.demands.dynamic or natural <= 0:
        return GestureTiming(g.behavior, prep, onset, accent, span_end, span_end, 1, "static", 1.0)
    factor = span / natural
    if factor <= config.max_slowdown:
        return GestureTiming(g.behavior, prep, onset, accent, span_end, span_end, 1, "slowed", factor)
    if g.demands.repeatable and factor >= 2.0:
        count = math.floor(factor)
        return GestureTiming(g.behavior, prep, onset, accent, span_end, span_end, count, "repeated", factor / count)
    stroke_end = onset + natural * config.max_slowdown
    return GestureTiming(g.behavior, prep, onset, min(accent, stroke_end), stroke_end, span_end, 1, "held", config.max_slowdown)
