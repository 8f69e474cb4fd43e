"""Relax, never refuse: the steps by which conflicting timing constraints give way, in order.

A performable utterance always renders. When the constraints of a chunk (or of the
absolute clock) cannot all hold, the scheduler relaxes them in this order and reports
every step with its amount:

1. ``co_articulation`` — a gesture that follows another on the same arm prepares from
   where the earlier stroke ended: the earlier retraction is skipped and the preparation
   (Fitts' law) is timed on the stroke-to-stroke distance, not from the rest position.
   Amount: seconds of preparation saved.
2. ``shorter_preparation`` — a preparation faster than Fitts' law, down to the shortest
   minimum-jerk movement that stays within its manner's speed budget
   (``motor.trajectory.speed_budget``). Amount: seconds taken off.
3. ``later_stroke_onset`` — the stroke of a gesture that follows another on the same arm
   starts closer to its affiliate's acoustic onset, down to no lead at all. Amount:
   seconds later.
4. ``hold_instead_of_repeat`` — a stroke the timing rules would repeat to fill its span
   is repeated fewer times (or once) and its end posture held, when the repetitions with
   the returns between them do not fit the span at their natural pace. Amount:
   repetitions replaced by the hold. (It changes how a span is filled, never a time point.)
5. ``stretched_pause`` — the pause before a chunk's speech grows (only at a chunk border:
   the speech of a chunk is never cut inside); for absolutely timed behaviours, the
   absolute clock starts later. Amount: seconds.
6. ``longer_stroke`` — an absolutely timed stroke too short for its path at its speed
   budget (the whole path as one minimum-jerk movement) ends later than its
   ``<timing end>``. Amount: seconds.
7. ``dropped_repetition`` — a repetition written in the gesture (``<repetition count>``)
   is performed fewer times. Amount: repetitions dropped.

A later step is used only as far as the earlier ones cannot make room (the temporal
network finds this lexicographic minimum, see :mod:`blackboard.timing`); a spec that no
relaxation satisfies fails with the names of the constraints in conflict.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum


class RelaxationStep(Enum):
    """The relaxation steps; their declaration order is the order in which they are tried."""

    CO_ARTICULATION = "co_articulation"
    SHORTER_PREPARATION = "shorter_preparation"
    LATER_STROKE_ONSET = "later_stroke_onset"
    HOLD_INSTEAD_OF_REPEAT = "hold_instead_of_repeat"
    STRETCHED_PAUSE = "stretched_pause"
    LONGER_STROKE = "longer_stroke"
    DROPPED_REPETITION = "dropped_repetition"

    @property
    def rank(self) -> int:
        """Position in the relaxation order, 0 first."""
        return list(RelaxationStep).index(self)


#: The relaxation order, as documented above.
RELAXATION_ORDER: tuple[RelaxationStep, ...] = tuple(RelaxationStep)


@dataclass(frozen=True)
class Relaxation:
    """One relaxation taken: ``step`` applied to ``behavior`` by ``amount`` ``unit``.

    ``constraint`` names the constraint that gave way; ``conflict`` the constraints that
    could not all hold without it (the cycle it keeps consistent); ``seconds`` is how far
    the constraint's bound moved (0 for ``hold_instead_of_repeat``, which moves none).
    """

    behavior: str | None
    step: RelaxationStep
    amount: float
    unit: str
    constraint: str
    conflict: tuple[str, ...]
    seconds: float

    def describe(self) -> str:
        """One line for the warnings: who, which step, how much, and why."""
        who = self.behavior if self.behavior is not None else "timing"
        amount = f"{self.amount:.3f} s" if self.unit == "s" else f"{self.amount:g} {self.unit}"
        return f"{who}: relaxed by {self.step.value} ({amount}) on '{self.constraint}'; conflict: " + "; ".join(self.conflict)

    def to_json(self) -> dict:
        return {"step": self.step.value, "amount": self.amount, "unit": self.unit, "constraint": self.constraint,
                "conflict": list(self.conflict)}


def merged(relaxations: list[Relaxation]) -> tuple[Relaxation, ...]:
    """Relaxations of the same behaviour, step and constraint summed into one, in first-taken order."""
    out: dict[tuple, Relaxation] = {}
    for r in relaxations:
        key = (r.behavior, r.step, r.constraint)
        if key in out:
            previous = out[key]
            out[key] = Relaxation(r.behavior, r.step, previous.amount + r.amount, r.unit, r.constraint,
                                  tuple(dict.fromkeys(previous.conflict + r.conflict)), previous.seconds + r.seconds)
        else:
            out[key] = r
    return tuple(out.values())
