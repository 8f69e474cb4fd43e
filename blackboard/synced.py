"""Behaviours timed by sync constraints (BML) on the blackboard.

What the scheduler needs to time a BML block's behaviours in the same temporal network as
MURML's affiliates (:mod:`blackboard.chunk_timing`): the timing request of each behaviour,
the block's constraints as :class:`~blackboard.chunk_timing.SyncLink` between network
points, and the times of points already timed with an earlier chunk. A constraint is
solved with the later of the chunks its two ends belong to (a time on the block clock
belongs to none). A speech's sync points are anchored on the audio like MURML's time
tags: ``start`` and each ``<sync>`` at the acoustic onset of the word after it, ``end``
at the acoustic end of the last word.

Behaviours no motor module performs yet (head, gaze, face, posture) are still timed, so
that the block's constraints hold for them and the timeline lists them; their phases take
the nominal durations of :data:`NOMINAL_PHASES` (seconds), which the motor modules that
perform them will replace with their own.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from blackboard.chunk_timing import ABSOLUTE, SyncedPhases, SyncLink, TimingConfig, end_point, onset_point, peg_point
from blackboard.planning import GestureDemands
from blackboard.timeline import Timeline
from mura.model import BML_SYNC_PEGS, BehaviorSpec, SyncRef, SyncTiming, Utterance

#: Nominal (preparation, stroke, retraction) seconds of behaviours without a motor module;
#: a head movement's stroke is per repetition.
NOMINAL_PHASES: Mapping[str, tuple[float, float, float]] = {
    "head": (0.15, 0.4, 0.15),
    "headDirectionShift": (0.3, 0.0, 0.0),
    "gaze": (0.2, 0.0, 0.2),
    "gazeShift": (0.2, 0.0, 0.0),
    "faceLexeme": (0.2, 0.0, 0.3),
    "faceFacs": (0.2, 0.0, 0.3),
    "faceShift": (0.3, 0.0, 0.0),
    "posture": (0.5, 0.0, 0.5),
    "postureShift": (0.5, 0.0, 0.0),
}
#: Behaviours with a stroke point inside their stroke (the others have no stroke phase).
STROKED = frozenset({"gesture", "pointing", "murmlgesture", "head"})


def is_synced(behavior: BehaviorSpec) -> bool:
    return isinstance(behavior.timing, SyncTiming)


def unperformed(utterance: Utterance, chunk: int) -> tuple[BehaviorSpec, ...]:
    """The synced behaviours of ``chunk`` that no motor module performs: timed and listed only."""
    return tuple(b for b in utterance.behaviors_in_chunk(chunk) if is_synced(b) and not b.moves_arms)


def nominal_demands(behavior: BehaviorSpec) -> GestureDemands:
    """What a behaviour without a motor module asks of the timing: no arm, nominal stroke."""
    stroke = NOMINAL_PHASES.get(behavior.kind, (0.0, 0.0, 0.0))[1] * _repetitions(behavior)
    return GestureDemands(frozenset(), stroke, stroke > 0.0, False, 0.0)


def phases(behavior: BehaviorSpec, config: TimingConfig, retraction: float | None = None) -> SyncedPhases:
    """How ``behavior``'s phases hold together; ``retraction`` (s) for a performed gesture
    (its motor's estimate); a behaviour no motor performs takes its nominal phases."""
    lead = config.stroke_lead if behavior.kind in STROKED else 0.0
    if behavior.moves_arms:
        return SyncedPhases(behavior.timing.named, True, lead, retraction or 0.0)
    preparation, _, nominal_retraction = NOMINAL_PHASES.get(behavior.kind, (0.0, 0.0, 0.0))
    return SyncedPhases(behavior.timing.named, False, lead, nominal_retraction, preparation)


def links(utterance: Utterance, chunk: int) -> tuple[list[SyncLink], set[str]]:
    """The block's constraints to solve with ``chunk``, and the points among their ends that
    earlier chunks timed (to be fixed at their times)."""
    chunk_of = _chunk_of_behaviors(utterance)
    out, foreign = [], set()
    for constraint in utterance.constraints:
        ends = [chunk_of.get(ref.behavior) for ref in (constraint.point, constraint.anchor) if ref.behavior is not None]
        if max(ends, default=0) != chunk:
            continue
        point, anchor = node(constraint.point, utterance), node(constraint.anchor, utterance)
        for ref, name in ((constraint.point, point), (constraint.anchor, anchor)):
            if ref.behavior is not None and chunk_of[ref.behavior] < chunk:
                foreign.add(name)
        offset = constraint.anchor.offset - constraint.point.offset
        out.append(SyncLink(point, anchor, constraint.relation, offset, str(constraint), constraint.point.behavior, constraint.required))
    return out, foreign


def node(ref: SyncRef, utterance: Utterance) -> str:
    """The network point a reference names (the block clock's start for a time)."""
    if ref.behavior is None:
        return ABSOLUTE
    if ref.behavior in _speeches(utterance):
        tag = f"{ref.behavior}:{ref.point}"
        return end_point(tag) if ref.point == "end" else onset_point(tag)
    return peg_point(ref.behavior, BML_SYNC_PEGS[ref.point])


def fixed_times(points: set[str], utterance: Utterance, timeline: Timeline, origin: float) -> dict[str, float]:
    """The session-clock times of ``points`` as earlier chunks timed them."""
    known: dict[str, float] = {}
    for tag, anchor in dict(timeline.tag_anchors).items():
        known[onset_point(tag)] = origin + anchor["acoustic_onset"]
        known[end_point(tag)] = origin + anchor["acoustic_end"]
    for entry in list(timeline.behaviors):
        for peg, time in entry.phases.items():
            known[peg_point(entry.id, peg)] = origin + time
    return {point: known[point] for point in points if point in known}


def named_end(behaviors: Sequence[BehaviorSpec]) -> set[str]:
    """The synced behaviours whose ``end`` some constraint names."""
    return {b.id for b in behaviors if is_synced(b) and "end" in b.timing.named}


def _speeches(utterance: Utterance) -> dict[str, int]:
    return {c.speech: c.index for c in utterance.chunks if c.speech is not None}


def _chunk_of_behaviors(utterance: Utterance) -> dict[str, int]:
    chunk_of = {b.id: b.chunk if b.chunk is not None else 0 for b in utterance.behaviors}
    chunk_of.update(_speeches(utterance))
    return chunk_of


def _repetitions(behavior: BehaviorSpec) -> int:
    text = dict(behavior.params).get("repetition", "1")
    return int(float(text)) if text.replace(".", "", 1).isdigit() else 1
