"""What can go wrong on the blackboard, each error naming the chunk, behaviour or constraint."""

from __future__ import annotations


class ScheduleError(ValueError):
    """An utterance the scheduler cannot perform: bad input or an unsatisfiable plan."""


class BehaviorError(ScheduleError):
    """A behaviour whose timing cannot be read against its utterance (names the behaviour)."""


class OverlappingGestures(ScheduleError):
    """Two gestures whose strokes need the same arm at the same time (names both)."""


class TimingConflict(ScheduleError):
    """Within-chunk constraints that no timing satisfies.

    ``constraints`` holds the names of the constraints on the offending cycle, in the
    spec's own words (behaviour ids, time tags, "speech onset of chunk 2").
    """

    def __init__(self, message: str, constraints: tuple[str, ...]) -> None:
        super().__init__(message)
        self.constraints = constraints


class IllegalTransition(ScheduleError):
    """A chunk asked to move between two states the state machine does not connect."""
