"""Dropping written repetitions: relaxation step 7 (:mod:`blackboard.relaxation`).

A gesture's ``<repetition count="k">`` asks for its child to be performed ``k`` times.
When nothing earlier in the relaxation order makes room, the scheduler performs it fewer
times: each drop takes one performance from the repetition with the highest count (the
first in the spec on a tie), and a repetition down to one performance becomes its child.
Signs keep their repetitions (they are part of the sign's form).
"""

from __future__ import annotations

from dataclasses import replace

from mura.constraints import Constraint, Parallel, Repetition, Sequence, Symmetrical
from mura.model import BehaviorSpec


def with_fewer_repetitions(behavior: BehaviorSpec) -> tuple[BehaviorSpec, ...]:
    """``behavior`` with one, two, … written repetitions dropped, down to none left."""
    if behavior.gesture is None:
        return ()
    out = []
    tree = behavior.gesture.constraints
    while True:
        tree = _drop_one(tree)
        if tree is None:
            return tuple(out)
        out.append(replace(behavior, gesture=replace(behavior.gesture, constraints=tree)))


def _drop_one(tree: Constraint) -> Constraint | None:
    """The tree with one performance fewer of its most repeated repetition, None when it has none."""
    target = max(_repetitions(tree), key=lambda node: node.count, default=None)
    return None if target is None else _rebuilt(tree, target)


def _repetitions(node: Constraint) -> list[Repetition]:
    found = [node] if isinstance(node, Repetition) else []
    if isinstance(node, (Parallel, Sequence)):
        for child in node.children:
            found.extend(_repetitions(child))
    elif isinstance(node, (Symmetrical, Repetition)):
        found.extend(_repetitions(node.child))
    return found


def _rebuilt(node: Constraint, target: Repetition) -> Constraint:
    if node is target:
        return node.child if node.count <= 2 else replace(node, count=node.count - 1)
    if isinstance(node, (Parallel, Sequence)):
        return replace(node, children=tuple(_rebuilt(child, target) for child in node.children))
    if isinstance(node, (Symmetrical, Repetition)):
        return replace(node, child=_rebuilt(node.child, target))
    return node
