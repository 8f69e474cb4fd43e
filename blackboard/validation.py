"""What the scheduler refuses before planning anything, naming the behaviour at fault.

Checks: something to say or do; every affiliate names time tags of its own chunk, onset
before end; gestures have timing; two gestures on one arm in one chunk do not have
overlapping affiliates (the earlier stroke spans its affiliate, the later one starts
before its own, so no relaxation separates them). Affiliates that merely touch, or come
close, are left to the temporal network, which relaxes what it can
(:mod:`blackboard.relaxation`) and names the constraints it cannot satisfy.
"""

from __future__ import annotations

import itertools

from blackboard.errors import BehaviorError, OverlappingGestures, ScheduleError
from blackboard.planning import MotorControl
from mura.model import Affiliate, BehaviorSpec, Utterance


def validate(utterance: Utterance, motor: MotorControl) -> None:
    """Refuse an utterance the scheduler cannot perform (module docstring)."""
    if not utterance.chunks and not utterance.behaviors:
        raise ScheduleError(f"{utterance.source}: the utterance has neither text nor behaviours")
    if not utterance.chunks and not any(b.moves_arms for b in utterance.behaviors):
        raise ScheduleError(f"{utterance.source}: the utterance has no text and no gesture to perform")
    tags = utterance.time_tags
    for b in utterance.behaviors:
        if b.moves_arms and b.timing is None:
            raise BehaviorError(f"behaviour {b.id!r}: a gesture needs an affiliate or an absolute timing")
        if isinstance(b.timing, Affiliate):
            _check_affiliate(b, tags)
    for chunk in utterance.chunks:
        _check_same_arm(utterance.behaviors_in_chunk(chunk.index), tags, motor)


def _check_affiliate(b: BehaviorSpec, tags) -> None:
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
        if shared and tags[later.timing.onset].offset < tags[earlier.timing.end].offset:
            raise OverlappingGestures(
                f"gestures {earlier.id!r} and {later.id!r} both need the {', '.join(sorted(shared))} arm "
                f"and their affiliates overlap ({earlier.timing.onset}–{earlier.timing.end} and "
                f"{later.timing.onset}–{later.timing.end})"
            )
