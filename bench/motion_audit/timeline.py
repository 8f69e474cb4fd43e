"""The render's timeline, as far as the audit uses it: behaviours with their phases, words.

``mura render`` writes ``NAME.timeline.json`` beside ``NAME.bvh``; ``mura sign`` writes
no such file but puts the same JSON into its page ``NAME.html``
(``<script type="application/json" id="mura-timeline">``). The timeline only tells the
audit *where to look* (which arm performs which behaviour, roughly when its stroke is)
and the words and their times; every figure is measured on the motion and the audio.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path

#: Largest timeline or page read, bytes.
MAX_TIMELINE_BYTES = 64 * 1024 * 1024
_ISLAND = re.compile(r'<script type="application/json" id="mura-timeline">(.*?)</script>', re.DOTALL)
_ARMS = {"right": "r", "left": "l", "right_arm": "r", "left_arm": "l", "r": "r", "l": "l"}
PHASES = ("start", "ready", "stroke_start", "stroke", "stroke_end", "relax", "end")


class TimelineError(ValueError):
    """A timeline that cannot be read; the message names the file and the field."""


@dataclass(frozen=True)
class Behaviour:
    """A gesture or sign: ``sides`` (``"l"``, ``"r"``) it moves, its planned ``phases``
    (seconds), its affiliate's onset and end (None when it has none) and whether those are
    absolute times (``<timing>``) rather than words."""

    id: str
    kind: str
    sides: tuple[str, ...]
    phases: dict[str, float]
    affiliate_onset: float | None
    affiliate_end: float | None
    absolute: bool
    mode: str


@dataclass(frozen=True)
class Word:
    text: str
    start: float
    end: float


@dataclass(frozen=True)
class Timeline:
    """``motion_start``: the time of the BVH's first frame on the timeline's clock."""

    source: str
    motion_start: float
    behaviours: tuple[Behaviour, ...]
    words: tuple[Word, ...]


def _number(value: object, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise TimelineError(f"{where}: expected a number, got {value!r}")
    return float(value)


def parse_timeline(data: object, source: str) -> Timeline:
    """The audit's view of a timeline JSON object; TimelineError naming the field."""
    if not isinstance(data, dict):
        raise TimelineError(f"{source}: expected a JSON object")
    behaviours = []
    for number, entry in enumerate(data.get("behaviors") or []):
        where = f"{source}: behaviors[{number}]"
        if not isinstance(entry, dict) or not isinstance(entry.get("phases"), dict):
            raise TimelineError(f"{where}: expected an object with 'phases'")
        phases = {name: _number(entry["phases"][name], f"{where}.phases.{name}") for name in PHASES if name in entry["phases"]}
        missing = [name for name in ("start", "stroke_start", "stroke_end", "end") if name not in phases]
        if missing:
            raise TimelineError(f"{where}: phases lack {', '.join(missing)}")
        sides = tuple(dict.fromkeys(_ARMS[arm] for arm in entry.get("arms") or [] if arm in _ARMS))
        affiliate = entry.get("affiliate") if isinstance(entry.get("affiliate"), dict) else {}
        onset, end = affiliate.get("onset"), affiliate.get("end")
        behaviours.append(
            Behaviour(
                id=str(entry.get("id", number)),
                kind=str(entry.get("kind", "")),
                sides=sides,
                phases=phases,
                affiliate_onset=None if onset is None else _number(onset, f"{where}.affiliate.onset"),
                affiliate_end=None if end is None else _number(end, f"{where}.affiliate.end"),
                absolute=bool(affiliate.get("absolute", False)),
                mode=str(entry.get("mode", "")),
            )
        )
    words = tuple(
        Word(str(word.get("text", "")), _number(word.get("start"), f"{source}: words[{n}].start"), _number(word.get("end"), f"{source}: words[{n}].end"))
        for n, word in enumerate(data.get("words") or [])
        if isinstance(word, dict)
    )
    start = data.get("motion_start_time", 0.0)
    return Timeline(source=source, motion_start=_number(start, f"{source}: motion_start_time"), behaviours=tuple(behaviours), words=words)


def _read(path: Path) -> str:
    if path.stat().st_size > MAX_TIMELINE_BYTES:
        raise TimelineError(f"{path}: larger than {MAX_TIMELINE_BYTES} bytes")
    return path.read_text(encoding="utf-8")


def timeline_for(bvh_path: Path) -> Timeline | None:
    """The timeline of the render ``bvh_path`` belongs to: ``NAME.timeline.json``, else the
    data island of ``NAME.html``; None when neither exists."""
    stem = bvh_path.with_suffix("")
    json_path, page_path = stem.with_name(stem.name + ".timeline.json"), bvh_path.with_suffix(".html")
    try:
        if json_path.is_file():
            return parse_timeline(json.loads(_read(json_path)), str(json_path))
        if page_path.is_file():
            match = _ISLAND.search(_read(page_path))
            if match is None:
                return None
            return parse_timeline(json.loads(match.group(1)), str(page_path))
    except json.JSONDecodeError as error:
        raise TimelineError(f"{json_path if json_path.is_file() else page_path}:{error.lineno}:{error.colno}: not JSON: {error.msg}") from None
    except (OSError, UnicodeDecodeError) as error:
        raise TimelineError(f"{bvh_path}: cannot read its timeline: {error}") from None
    return None
