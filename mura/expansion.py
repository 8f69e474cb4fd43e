"""How many movements a constraint tree becomes once its repetitions are expanded.

A repetition is written once and performed ``count`` times, so nested repetitions
multiply: thirty ``hamrepeatfromstart`` after one move are 2³⁰ movements, which the motor
core would try to plan one by one. Bounding the nesting depth does not help (32 levels
still allow 2³² passes); what is bounded is the number of resulting movements, computed
here in time linear in the size of the tree (Python integers do not overflow).

Counted as movements: each segment of a ``dynamic`` leaf and each ``static`` leaf (a
posture the hand moves to); ``parallel`` and ``sequence`` add up their parts;
``symmetrical`` counts its dominant-arm tree; a ``repetition`` counts ``count`` passes of
its child, and at least ``count`` even when the child holds still.
"""

from __future__ import annotations

from mura.constraints import Constraint, Dynamic, Parallel, Repetition, Sequence, Static, Symmetrical
from mura.errors import SourceLocation, SpecError
from mura.limits import LimitError, Limits, hint
from mura.model import AbsoluteTiming, Utterance
from mura.signs import Sign


def movement_count(node: Constraint | None) -> int:
    """Movements ``node`` expands to (see the module docstring); 0 for no tree."""
    if node is None:
        return 0
    if isinstance(node, Dynamic):
        return len(node.segments)
    if isinstance(node, Static):
        return 1
    if isinstance(node, (Parallel, Sequence)):
        return sum(movement_count(child) for child in node.children)
    if isinstance(node, Symmetrical):
        return movement_count(node.child)
    if isinstance(node, Repetition):
        return node.count * max(1, movement_count(node.child))
    raise TypeError(f"not a constraint: {type(node).__name__}")


def check_movements(node: Constraint | None, limits: Limits, what: str, where: SourceLocation | None) -> None:
    """Refuse ``node`` (``what`` names it: ``gesture 'g1'``, ``sign 'HOUSE'``) when it
    expands to more than ``limits.max_movements`` movements."""
    count = movement_count(node)
    if count > limits.max_movements:
        raise SpecError(
            f"{what} expands to {_amount(count)} movements once its repetitions are performed, more than the limit of "
            f"{limits.max_movements} ({hint('max_movements')})",
            where,
        )


def check_sign(sign: Sign, limits: Limits) -> Sign:
    """``sign`` itself when its movement stays within ``limits.max_movements``."""
    check_movements(sign.movement, limits, f"sign {sign.gloss!r}", sign.where)
    return sign


def _amount(count: int) -> str:
    """A count for a message: exact when short, else as a power of ten (2**1000 has 302 digits)."""
    text = str(count)
    return text if len(text) <= 12 else f"about 10^{len(text) - 1}"


def check_utterance(utterance: Utterance, limits: Limits) -> Utterance:
    """``utterance`` itself when a model built in Python (not read from a file, where the
    readers check as they go) keeps within ``limits``: chunk text, absolute times, movements."""
    for chunk in utterance.chunks:
        try:
            limits.check_chunk_text(chunk.text, f"chunk {chunk.index + 1}")
        except LimitError as error:
            raise SpecError(str(error), SourceLocation(utterance.source)) from None
    for behavior in utterance.behaviors:
        where = behavior.where or SourceLocation(utterance.source)
        if isinstance(behavior.timing, AbsoluteTiming):
            for which in ("onset", "end"):
                try:
                    limits.check_time(getattr(behavior.timing, which), f"timing {which} of {behavior.id!r}:")
                except LimitError as error:
                    raise SpecError(str(error), where) from None
        if behavior.gesture is not None:
            check_movements(behavior.gesture.constraints, limits, f"gesture {behavior.id!r}", where)
        if behavior.sign is not None:
            check_sign(behavior.sign, limits)
    return utterance
