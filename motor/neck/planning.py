"""MURML head slots planned into neck LMPs on a gesture's time pegs (seed 004, 4).

The arm's compiler leaves the non-arm slots of a constraint tree to the modules that
realize them; this one takes ``GazeDirection``, ``Neck``, ``HeadDirection``, ``Torso``
and ``Shoulders`` (:data:`NECK_SLOTS`):

* **Gaze** (``GazeDirection``): a static value is a target (a point, a place, a
  direction, or a name such as ``Listener`` or ``RightHand``, :mod:`motor.neck.gaze`);
  the eyes and head shift so as to be on it when the stroke starts — the shift begins at
  the gesture's start, or later, its natural duration before the stroke — hold it until
  ``relax``, and go back to rest with the retraction. Several static values: the last one
  counts (warning). A dynamic value's segments are targets visited one after the other
  across the stroke.
* **Deictic gaze**: a gesture that points (``mode="pointTo"`` on ``HandLocation`` or
  ``ExtFingerOrientation``) and says nothing about gaze looks where it points.
* **Head** (``Neck``, ``HeadDirection``): a head lexeme name (``Nod``, ``Shake``,
  ``TiltLeft`` … or a HamNoSys code, :mod:`motor.neck.lexemes`) starts with the stroke: a
  swing at its own pace (a nod is not slowed to fill a long affiliate; repetitions of the
  ``repetition`` nodes above it multiply its swings), a held posture until ``relax``; a
  direction or a point turns the head to face it (the eyes look there too unless a gaze
  target is given).
* **Torso, shoulders**: HamNoSys body and shoulder codes or names
  (:mod:`motor.neck.trunk`), held from the stroke to ``relax``.

Unknown names are not errors that stop the utterance: the planner warns, naming the
behaviour, the place in the file and the name, and does what the warning says (looks at
the listener instead, or leaves the head or the trunk still).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field

import numpy as np

from motor.body.locations import resolve_location
from motor.neck.control import NeckControl, NeckLMP
from motor.neck.gaze import (
    EYE_LIMIT,
    FORWARD,
    HEAD_LIMIT,
    GazeTarget,
    UnknownGazeTarget,
    direction,
    gaze,
    gaze_target,
    listener,
    point,
    rest,
)
from motor.neck.lexemes import UnknownHeadLexeme, head_lexeme, natural_duration
from motor.neck.trunk import UnknownTrunkCode, trunk_movement
from motor.program.lmp import TimePegs
from mura.constraints import Constraint, Dynamic, Parallel, Repetition, Sequence, Static
from mura.errors import SourceLocation
from mura.values import BetweenLocation, BodySite, Direction, GridLocation, PointLocation, Symbol, Vector

#: The slots this module realizes.
NECK_SLOTS: frozenset[str] = frozenset({"GazeDirection", "Neck", "HeadDirection", "Torso", "Shoulders"})
_HEAD_SLOTS = ("Neck", "HeadDirection")
_POINTING_SLOTS = ("HandLocation", "ExtFingerOrientation")


@dataclass
class NeckPlan:
    """The neck LMPs of one behaviour and what planning noted."""

    lmps: list[NeckLMP] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)


def repeated_leaves(node: Constraint, count: int = 1) -> Iterator[tuple[Static | Dynamic, int]]:
    """Every leaf with the product of the repetition counts above it."""
    if isinstance(node, (Static, Dynamic)):
        yield node, count
    elif isinstance(node, (Parallel, Sequence)):
        for child in node.children:
            yield from repeated_leaves(child, count)
    elif isinstance(node, Repetition):
        yield from repeated_leaves(node.child, count * node.count)
    else:
        yield from repeated_leaves(node.child, count)


class NeckPlanner:
    """Plans the head slots of behaviours for one :class:`NeckControl` (module docstring)."""

    def __init__(self, control: NeckControl) -> None:
        self.control = control
        self.avatar = control.avatar

    def plan(self, behavior: str, tree: Constraint | None, pegs: TimePegs) -> NeckPlan:
        """The neck LMPs of the constraint tree of ``behavior`` on ``pegs``."""
        plan = NeckPlan()
        if tree is None:
            return plan
        leaves = [(leaf, count) for leaf, count in repeated_leaves(tree) if leaf.slot in NECK_SLOTS]
        gazes = [leaf for leaf, _ in leaves if leaf.slot == "GazeDirection"]
        heads = [(leaf, count) for leaf, count in leaves if leaf.slot in _HEAD_SLOTS]
        facing = self._head_target(behavior, heads, plan)
        targets = self._gaze_targets(behavior, gazes, plan) or self._pointed_at(tree)
        if not targets and facing is not None:
            targets = [facing]
        self._gaze_lmps(targets, facing, pegs, plan)
        for leaf, count in heads:
            self._head_movement(behavior, leaf, count, pegs, plan)
        for leaf, _ in leaves:
            if leaf.slot in ("Torso", "Shoulders"):
                self._trunk(behavior, leaf, pegs, plan)
        return plan

    def preparation(self, behavior: str, tree: Constraint | None, at: float) -> float:
        """Seconds the gaze of ``tree`` needs to get on its first target from the gaze at ``at``."""
        if tree is None:
            return 0.0
        scratch = NeckPlan()
        leaves = list(repeated_leaves(tree))
        facing = self._head_target(behavior, [(leaf, count) for leaf, count in leaves if leaf.slot in _HEAD_SLOTS], scratch)
        gazes = [leaf for leaf, _ in leaves if leaf.slot == "GazeDirection"]
        targets = self._gaze_targets(behavior, gazes, scratch) or self._pointed_at(tree) or ([facing] if facing else [])
        if not targets:
            return 0.0
        alone = facing is not None and facing is targets[0]
        probe = gaze(self.avatar, targets[0], at, head=None if alone else facing, head_share=1.0 if alone else None)
        return self.control.shift_duration(probe, at)

    # -- gaze ---------------------------------------------------------------------

    def _gaze_targets(self, behavior: str, leaves: list[Static | Dynamic], plan: NeckPlan) -> list[GazeTarget]:
        statics = [leaf for leaf in leaves if isinstance(leaf, Static)]
        if len(statics) > 1:
            plan.warnings.append(f"{behavior}: {len(statics)} static GazeDirection values at once; the last ({_where(statics[-1].where)}) counts")
        dynamic = next((leaf for leaf in leaves if isinstance(leaf, Dynamic)), None)
        if dynamic is not None:
            values = [v for segment in dynamic.segments for v in (segment.start, segment.end) if v is not None]
            return [self._target(behavior, value, dynamic.where, plan) for value in values]
        return [self._target(behavior, statics[-1].value, statics[-1].where, plan)] if statics else []

    def _target(self, behavior: str, value: object, where: SourceLocation | None, plan: NeckPlan) -> GazeTarget:
        """The gaze target a slot value names (module docstring)."""
        try:
            if isinstance(value, PointLocation):
                return point(np.array(value.position), f"point {list(value.position)}")
            if isinstance(value, (GridLocation, BodySite, BetweenLocation)):
                return point(resolve_location(self.avatar, value, "r"), _label(value))
            if isinstance(value, Direction):
                return self._reachable(behavior, direction(self.avatar, np.array(value.vector), value.name or "direction"), where, plan)
            if isinstance(value, Vector) and len(value.values) == 3:
                return self._reachable(behavior, direction(self.avatar, np.array(value.values)), where, plan)
            if isinstance(value, Symbol):
                return gaze_target(self.avatar, value.name, self.control.hands)
            raise UnknownGazeTarget(f"{value!r} is not a gaze target")
        except (UnknownGazeTarget, ValueError) as error:
            plan.warnings.append(f"{behavior} ({_where(where)}): {error}; looking at the listener instead")
            return listener(self.avatar)

    def _reachable(self, behavior: str, target: GazeTarget, where: SourceLocation | None, plan: NeckPlan) -> GazeTarget:
        aim = target.points(np.zeros(1))[0] - self.control.origin
        angle = float(np.arccos(np.clip(aim @ FORWARD / np.linalg.norm(aim), -1.0, 1.0)))
        if angle > HEAD_LIMIT + EYE_LIMIT:
            plan.warnings.append(
                f"{behavior} ({_where(where)}): gaze {target.label} is {np.degrees(angle):.0f}° from straight ahead; "
                f"eyes and head reach {np.degrees(HEAD_LIMIT + EYE_LIMIT):.0f}°, so they turn as far as they reach"
            )
        return target

    def _pointed_at(self, tree: Constraint) -> list[GazeTarget]:
        """Where a deictic gesture points: the first ``pointTo`` location in the tree."""
        for leaf, _ in repeated_leaves(tree):
            if isinstance(leaf, Static) and leaf.mode == "pointTo" and leaf.slot in _POINTING_SLOTS:
                try:
                    return [point(resolve_location(self.avatar, leaf.value, "r"), f"where it points ({_label(leaf.value)})")]
                except (ValueError, TypeError, AttributeError):
                    return []
        return []

    def _gaze_lmps(self, targets: list[GazeTarget], facing: GazeTarget | None, pegs: TimePegs, plan: NeckPlan) -> None:
        if not targets:
            return
        head_share = 1.0 if facing is not None and facing is targets[0] else None
        head = None if head_share is not None else facing
        times = [pegs.stroke_start] if len(targets) == 1 else list(np.linspace(pegs.stroke_start, max(pegs.stroke_end, pegs.stroke_start), len(targets)))
        begin = pegs.start
        for target, arrive in zip(targets, times):
            probe = gaze(self.avatar, target, begin, head=head, head_share=head_share)
            start = max(begin, arrive - self.control.shift_duration(probe, begin))
            plan.lmps.append(gaze(self.avatar, target, start, pegs.relax, head=head, head_share=head_share))
            begin = start
        plan.lmps.append(gaze(self.avatar, rest(self.avatar), max(pegs.relax, begin), pegs.end, returning=True))

    # -- head and trunk -----------------------------------------------------------

    def _head_target(self, behavior: str, heads: list[tuple[Static | Dynamic, int]], plan: NeckPlan) -> GazeTarget | None:
        """What the head is told to face, if a head slot gives a direction or a place."""
        for leaf, _ in heads:
            if isinstance(leaf, Static) and not isinstance(leaf.value, Symbol):
                return self._target(behavior, leaf.value, leaf.where, plan)
        return None

    def _head_movement(self, behavior: str, leaf: Static | Dynamic, count: int, pegs: TimePegs, plan: NeckPlan) -> None:
        values = [leaf.value] if isinstance(leaf, Static) else [v for s in leaf.segments for v in (s.start, s.end) if v is not None]
        names = [value.name for value in values if isinstance(value, Symbol)]
        for name in names:
            try:
                probe = head_lexeme(name, pegs.stroke_start)
            except UnknownHeadLexeme as error:
                plan.warnings.append(f"{behavior} ({_where(leaf.where)}): {error}; the head does not move for it")
                continue
            repetitions = count * probe.lexeme.swings if count > 1 and not probe.lexeme.held else None
            end = pegs.stroke_start + natural_duration(probe.lexeme, repetitions)
            if probe.lexeme.held:
                end = max(pegs.relax, end)
            plan.lmps.append(head_lexeme(name, pegs.stroke_start, end, repetitions=repetitions))

    def _trunk(self, behavior: str, leaf: Static | Dynamic, pegs: TimePegs, plan: NeckPlan) -> None:
        value = leaf.value if isinstance(leaf, Static) else next((s.end or s.start for s in leaf.segments), None)
        if not isinstance(value, Symbol):
            plan.warnings.append(f"{behavior} ({_where(leaf.where)}): {leaf.slot} needs a HamNoSys code or a name such as Shrug or LeanForward, got {value!r}; not realized")
            return
        try:
            plan.lmps.append(trunk_movement(value.name, pegs.stroke_start, max(pegs.relax, pegs.stroke_start)))
        except UnknownTrunkCode as error:
            plan.warnings.append(f"{behavior} ({_where(leaf.where)}): {error}; the {leaf.slot.lower()} stay still")


def _where(where: SourceLocation | None) -> str:
    return str(where) if where is not None else "unknown place"


def _label(value: object) -> str:
    if isinstance(value, GridLocation):
        return f"{value.height} {value.lateral} {value.distance}"
    if isinstance(value, BodySite):
        return value.site
    if isinstance(value, PointLocation):
        return f"point {list(value.position)}"
    return type(value).__name__
