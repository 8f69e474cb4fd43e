"""BML sync references and how a block's behaviours go with its speeches (see :mod:`mura.bml`).

A reference is ``[block:]behaviour:syncpoint`` with an optional ``+``/``-`` offset in
seconds (``s1:tm1 + 0.2``), or a time in seconds from the block start (``1.5``).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator, Mapping

from mura.errors import SourceLocation, SpecError
from mura.model import SyncConstraint, SyncRef

#: An XML name without a colon: behaviour, block and sync ids.
NAME = re.compile(r"^[^\W\d.\-:][\w.\-]*$", re.UNICODE)
_OFFSET = re.compile(r"^(?P<ref>.*?)\s*(?P<sign>[+-])\s*(?P<value>(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)$")


def parse_reference(text: str, where: SourceLocation, block: str, points: Mapping[str, tuple[str, ...]],
                    kinds: Mapping[str, str], allow_time: bool = True) -> SyncRef:
    """The reference ``text`` names, given each behaviour's sync points (and element name,
    for messages); a time only when ``allow_time``. :class:`SpecError` at ``where`` otherwise."""
    text = text.strip()
    value = number(text)
    if value is not None:
        if not allow_time:
            raise SpecError(f"a <sync> names a sync point, not a time ({text!r})", where)
        if value < 0:
            raise SpecError(f"time {text!r} lies before the block starts (times are seconds from the block start, ≥ 0)", where)
        return SyncRef(None, None, value, where)
    for ref, offset in _readings(text):
        parts = _parts(ref, block)
        if len(parts) == 3:
            raise SpecError(f"{text!r} refers to block {parts[0]!r}: mura reads references within the block only", where)
        if len(parts) == 2 and all(NAME.match(p) for p in parts) and parts[1] in points.get(parts[0], ()):
            return SyncRef(parts[0], parts[1], offset, where)
    raise _bad_reference(text, where, block, points, kinds)


def _readings(text: str) -> Iterator[tuple[str, float]]:
    """The ways to read ``text``: whole (a sync id may hold a ``-``), then with a trailing offset."""
    yield text, 0.0
    match = _OFFSET.match(text)
    if match is not None:
        offset = float(match.group("value")) * (-1.0 if match.group("sign") == "-" else 1.0)
        if math.isfinite(offset):
            yield match.group("ref"), offset


def _parts(ref: str, block: str) -> list[str]:
    parts = ref.split(":")
    return parts[1:] if len(parts) == 3 and parts[0] == block else parts


def _bad_reference(text: str, where: SourceLocation, block: str, points: Mapping[str, tuple[str, ...]],
                   kinds: Mapping[str, str]) -> SpecError:
    match = _OFFSET.match(text)
    parts = _parts(match.group("ref") if match is not None and ":" in match.group("ref") else text, block)
    if len(parts) != 2:
        return SpecError(f"{text!r} is neither a time in seconds nor a reference behaviour:syncpoint[+offset]", where)
    behavior, point = parts
    if behavior not in points:
        known = ", ".join(sorted(points)) or "none"
        return SpecError(f"{text!r} names unknown behaviour {behavior!r} (block {block!r} has: {known})", where)
    return SpecError(f"{text!r}: {kinds[behavior]} {behavior!r} has no sync point {point!r} (it has: {', '.join(points[behavior])})", where)


def chunks_of(behaviors: list[str], chunk_of_speech: Mapping[str, int], constraints: list[SyncConstraint]) -> dict[str, int]:
    """Each behaviour's chunk: the first speech its group (behaviours tied together by
    constraints) is tied to, else the first chunk."""
    group = {b: b for b in behaviors}

    def find(b: str) -> str:
        while group[b] != b:
            group[b] = group[group[b]]
            b = group[b]
        return b

    for constraint in constraints:
        a, b = constraint.point.behavior, constraint.anchor.behavior
        if a in group and b in group:
            group[find(a)] = find(b)
    ties: dict[str, int] = {}
    for constraint in constraints:
        for one, other in ((constraint.point.behavior, constraint.anchor.behavior), (constraint.anchor.behavior, constraint.point.behavior)):
            if one in group and other in chunk_of_speech:
                root = find(one)
                ties[root] = min(ties.get(root, chunk_of_speech[other]), chunk_of_speech[other])
    return {b: ties.get(find(b), 0) for b in behaviors}


def number(text: str) -> float | None:
    """``text`` as a finite number, or None."""
    try:
        value = float(text)
    except ValueError:
        return None
    return value if math.isfinite(value) else None
