"""What a corpus run says about its items: warnings said once, reasons grouped by kind.

A planner may say the same thing several times for one item (the same unrealized slot in
every leaf, in every behaviour); :func:`summarize_warnings` says it once per item, naming
the subjects and how often. Over a whole corpus, failures and warnings are grouped by
*kind*: the message with what varies between instances masked — the place
(``FILE:LINE:COL``), the subject (``sign 'X':``, ``behaviour 'g1':``), quoted names, HamNoSys
symbol names and numbers (:func:`reason_kind`) — each kind with its count and a few
examples in full.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

#: Examples kept per kind in a report.
EXAMPLES_PER_KIND = 3
#: Longest subject prefix (``subject: message``) read as naming the item's part.
_SUBJECT_CHARS = 80

_PLACE = re.compile(r"^(?:\S.*?):\d+:\d+: ")
_EMBEDDED_PLACE = re.compile(r"[^\s:'\"]+:\d+:\d+")
_SUBJECT = re.compile(r"^(?:sign|behaviour|gesture|function) '(?:[^'\\]|\\.)*':\s*")
_QUOTED = re.compile(r"'(?:[^'\\]|\\.)*'|\"(?:[^\"\\]|\\.)*\"")
_SYMBOL = re.compile(r"\bham\w+")
_NUMBER = re.compile(r"(?<![\w.])[-+]?\d+(?:\.\d+)?(?![\w.])")


def reason_kind(message: str) -> str:
    """``message`` with what varies between instances of the same reason masked."""
    text = _PLACE.sub("", message.strip())
    while (match := _SUBJECT.match(text)) is not None:
        text = text[match.end():]
    text = _EMBEDDED_PLACE.sub("FILE:LINE:COL", text)
    text = _QUOTED.sub("'…'", text)
    text = _SYMBOL.sub("ham…", text)
    return _NUMBER.sub("N", text)


def summarize_warnings(warnings: Sequence[str]) -> tuple[str, ...]:
    """One line per distinct message: ``subjects: message``, ``(×N)`` when said more often
    than it has subjects; in the order first said."""
    subjects: dict[str, list[str]] = {}
    counts: dict[str, int] = {}
    for warning in warnings:
        subject, message = split_subject(warning)
        subjects.setdefault(message, [])
        if subject is not None and subject not in subjects[message]:
            subjects[message].append(subject)
        counts[message] = counts.get(message, 0) + 1
    lines = []
    for message, who in subjects.items():
        head = f"{', '.join(who)}: " if who else ""
        times = f" (×{counts[message]})" if counts[message] > max(len(who), 1) else ""
        lines.append(f"{head}{message}{times}")
    return tuple(lines)


def split_subject(warning: str) -> tuple[str | None, str]:
    subject, sep, message = warning.partition(": ")
    if not sep or not message or len(subject) > _SUBJECT_CHARS or re.search(r":\d+:\d+$", subject):
        return None, warning
    return subject, message


@dataclass(frozen=True)
class Example:
    """One instance of a kind: the item it came from and the message in full."""

    item: str
    source: str
    message: str

    def as_json(self) -> dict:
        return {"item": self.item, "source": self.source, "message": self.message}


def group_by_kind(instances: Iterable[Example]) -> dict[str, dict]:
    """``kind -> {"count", "examples"}``, kinds by falling count then name, at most
    :data:`EXAMPLES_PER_KIND` examples each (the first met)."""
    groups: dict[str, list[Example]] = {}
    counts: dict[str, int] = {}
    for example in instances:
        kind = reason_kind(example.message)
        counts[kind] = counts.get(kind, 0) + 1
        kept = groups.setdefault(kind, [])
        if len(kept) < EXAMPLES_PER_KIND:
            kept.append(example)
    order = sorted(counts, key=lambda kind: (-counts[kind], kind))
    return {kind: {"count": counts[kind], "examples": [e.as_json() for e in groups[kind]]} for kind in order}
