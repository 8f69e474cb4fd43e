"""How a stroke fills its span, from its onset to ``relax`` (seed 004, section 5).

With ``d`` the natural duration of one performance of the stroke, ``r`` the natural time
to return from its end to its start (``GestureDemands.repetition_return``), the span
``s`` and ``f = s / d``:

* a static stroke holds its posture;
* ``f ≤ max_slowdown`` (1.5): one performance, slowed by ``f``;
* a repeatable stroke with ``f ≥ 2`` is performed ``k`` times, ``k`` the most
  performances that fit with the returns between them at their natural pace
  (``k·d + (k−1)·r ≤ s``), slowed evenly to fill the span (at most by ``max_slowdown``,
  the rest held). When the returns leave room for fewer than ``⌊f⌋`` performances, the
  hold replaces the others: relaxation step 4, ``hold_instead_of_repeat``;
* otherwise one performance slowed by ``max_slowdown``, its end posture held until the
  span ends (a post-stroke hold, ``stroke_end < relax``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from blackboard.planning import GestureDemands
from blackboard.relaxation import Relaxation, RelaxationStep


@dataclass(frozen=True)
class StrokeFill:
    """How a stroke fills its span: ``mode`` (``static``, ``slowed``, ``repeated`` or
    ``held``), performances, the slowdown of the performed movement, where the movement
    ends (s, utterance clock), and the relaxation taken, if any."""

    mode: str
    repetitions: int
    slowdown: float
    stroke_end: float
    relaxation: Relaxation | None = None


def fill_stroke(behavior: str, demands: GestureDemands, onset: float, span_end: float, max_slowdown: float) -> StrokeFill:
    """Fill ``[onset, span_end]`` with ``behavior``'s stroke (module docstring)."""
    span = span_end - onset
    natural = demands.stroke_duration
    if not demands.dynamic or natural <= 0:
        return StrokeFill("static", 1, 1.0, span_end)
    factor = span / natural
    if factor <= max_slowdown:
        return StrokeFill("slowed", 1, factor, span_end)
    if demands.repeatable and factor >= 2.0:
        wanted = math.floor(factor + 1e-9)
        back = demands.repetition_return
        count = min(wanted, math.floor((span + back) / (natural + back) + 1e-9))
        hold = None
        if count < wanted:
            hold = Relaxation(
                behavior, RelaxationStep.HOLD_INSTEAD_OF_REPEAT, float(wanted - count), "repetitions",
                f"{behavior}: {wanted} performances fill its span of {span:.3f} s",
                (f"{behavior}: each performance takes {natural:.3f} s and the return to its start {back:.3f} s",),
                0.0,
            )
        if count >= 2:
            performed = count * natural + (count - 1) * back
            slowdown = min(span / performed, max_slowdown)
            return StrokeFill("repeated", count, slowdown, min(span_end, onset + performed * slowdown), hold)
        return StrokeFill("held", 1, max_slowdown, onset + natural * max_slowdown, hold)
    return StrokeFill("held", 1, max_slowdown, onset + natural * max_slowdown)
