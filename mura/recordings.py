"""Recordings of indicating verbs: the training data of the verb models (seed 001).

A *performance* is one recorded instance of a verb for one arrangement of its subject and
object on the arc around the signer (−1 = the signer's far left … +1 = far right). For each
hand it holds the location and the orientation at each *keyframe* (two for straight-path
verbs: the start and the end of the movement; more allowed), and the keyframe times.

**Frame and units.** Locations are in the *signer frame*, normalised to the signer's body:
origin midway between the shoulder joints, y up, +z the way the signer faces, +x the
signer's left (H-Anim), lengths in shoulder widths (the distance between the two shoulder
joints). Orientations are unit quaternions ``(x, y, z, w)`` in the same frame: the global
rotation taking the hand from the canonical rest posture — arm hanging, fingers down
(``−y``), palm facing the thigh (normal ``+x`` for the right hand, ``−x`` for the left),
thumb forward — to the recorded posture. Times are seconds from the performance's start.

Two table forms hold the same data (BVH clips with a sidecar are read by
:mod:`mura.capture`):

* **CSV**, one row per performance, keyframe and hand, with the header
  ``performance,verb,signer,subject,object,keyframe,time,hand,x,y,z,qx,qy,qz,qw``
  (``subject`` may be empty for verbs that indicate their object only);
* **JSON**: ``{"format": "mura verb recordings", "version": 1, "synthetic": bool,
  "description": "…", "performances": [{"id", "verb", "signer", "subject", "object",
  "times": [..], "hands": {"right": {"location": [[x, y, z], ..], "orientation":
  [[x, y, z, w], ..]}, "left": {..}}}, ..]}``.

**Refusals.** A bad performance — a missing right hand, a hand missing at some keyframe,
NaN or infinite numbers, a zero quaternion, an arc position outside [−1, 1], times not
increasing, fewer than two keyframes, or a keyframe structure that differs from the verb's
other performances — is refused with its file and row (CSV line, or the line where the
JSON performance starts) and the others are kept: one bad row never stops a session.
Limits: :data:`MAX_RECORDING_BYTES`, :data:`MAX_PERFORMANCES`, :data:`MAX_KEYFRAMES`.
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mura.errors import SourceLocation, SpecError

#: The hands, dominant first.
HANDS: tuple[str, ...] = ("right", "left")
#: Largest recording file read, bytes.
MAX_RECORDING_BYTES = 64 * 1024 * 1024
#: Most performances in one file, and most keyframes in one performance.
MAX_PERFORMANCES = 100_000
MAX_KEYFRAMES = 64
#: The CSV header, in order.
CSV_COLUMNS: tuple[str, ...] = (
    "performance", "verb", "signer", "subject", "object", "keyframe", "time", "hand",
    "x", "y", "z", "qx", "qy", "qz", "qw",
)  # fmt: skip
#: The ``format`` of the JSON form.
JSON_FORMAT = "mura verb recordings"
_UNIT_QUATERNION = 1e-6


@dataclass(frozen=True, eq=False)
class HandKeyframes:
    """One hand at each keyframe: locations ``(K, 3)`` in shoulder widths (signer frame)
    and orientations ``(K, 4)``, unit quaternions ``(x, y, z, w)``."""

    location: np.ndarray
    orientation: np.ndarray


@dataclass(frozen=True, eq=False)
class Performance:
    """One recorded instance of a verb (module docstring: frame, units).

    Attributes:
        id: the performance's name in its file.
        verb: the verb's gloss, upper case (``GIVE``).
        signer: who performed it (a name; synthetic signers are ``synthetic-…``).
        subject, object: arc positions in [−1, 1]; ``subject`` is None when not recorded.
        times: keyframe times ``(K,)``, seconds, increasing.
        hands: ``right`` (always) and ``left`` (two-handed verbs) → keyframes.
        where: the file and row it came from.
    """

    id: str
    verb: str
    signer: str
    subject: float | None
    object: float
    times: np.ndarray
    hands: Mapping[str, HandKeyframes]
    where: SourceLocation = field(default_factory=lambda: SourceLocation("<input>"))

    @property
    def keyframes(self) -> int:
        return int(self.times.shape[0])

    @property
    def two_handed(self) -> bool:
        return "left" in self.hands


@dataclass(frozen=True)
class RecordingSession:
    """Performances read from one or more files, and what was refused.

    ``synthetic`` is True when any source declares itself synthetic (made by a generator,
    not captured from a signer); ``description`` says where the data come from.
    """

    performances: tuple[Performance, ...]
    refused: tuple[SpecError, ...] = ()
    synthetic: bool = False
    description: str = ""

    @property
    def verbs(self) -> tuple[str, ...]:
        """The verbs recorded, in order of first appearance."""
        return tuple(dict.fromkeys(p.verb for p in self.performances))

    def of(self, verb: str) -> tuple[Performance, ...]:
        """The performances of one verb."""
        return tuple(p for p in self.performances if p.verb == verb)

    def merged(self, other: RecordingSession) -> RecordingSession:
        """Both sessions' performances and refusals, the keyframe structure checked again."""
        kept, refused = _consistent(self.performances + other.performances)
        description = "; ".join(d for d in (self.description, other.description) if d)
        return RecordingSession(kept, self.refused + other.refused + refused, self.synthetic or other.synthetic, description)


def read_recordings(path: str | Path) -> RecordingSession:
    """Read a CSV or JSON keyframe table (by extension). A file that cannot be read at all
    raises :class:`SpecError`; bad performances are refused (:attr:`RecordingSession.refused`)."""
    path = Path(path)
    text = _read_text(path)
    if path.suffix.lower() == ".csv":
        return parse_recordings_csv(text, str(path))
    if path.suffix.lower() == ".json":
        return parse_recordings_json(text, str(path))
    raise SpecError(f"unknown recording format {path.suffix!r} (expected .csv or .json; BVH clips are read with their sidecar)", SourceLocation(str(path)))


def _read_text(path: Path) -> str:
    try:
        size = path.stat().st_size
        if size > MAX_RECORDING_BYTES:
            raise SpecError(f"file is {size} bytes, more than the limit of {MAX_RECORDING_BYTES}", SourceLocation(str(path)))
        return path.read_text(encoding="utf-8")
    except OSError as error:
        raise SpecError(f"cannot read: {error.strerror or error}", SourceLocation(str(path))) from None
    except UnicodeDecodeError as error:
        raise SpecError(f"not UTF-8 text ({error.reason} at byte {error.start})", SourceLocation(str(path))) from None


# -- CSV ----------------------------------------------------------------------------------


def parse_recordings_csv(text: str, file: str = "<input>") -> RecordingSession:
    """The performances of a CSV keyframe table (module docstring)."""
    reader = csv.reader(io.StringIO(text))
    header = next(reader, None)
    if header is None:
        raise SpecError("empty file (expected the header " + ",".join(CSV_COLUMNS) + ")", SourceLocation(file, 1, 1))
    header = [name.strip().lower() for name in header]
    missing = [name for name in CSV_COLUMNS if name not in header]
    if missing:
        raise SpecError(f"header lacks the column(s) {', '.join(missing)}", SourceLocation(file, 1, 1))
    column = {name: header.index(name) for name in CSV_COLUMNS}
    groups: dict[str, list[tuple[int, list[str]]]] = {}
    refused: list[SpecError] = []
    for line, row in enumerate(reader, start=2):
        if not any(cell.strip() for cell in row):
            continue
        if len(row) < len(header):
            refused.append(SpecError(f"row has {len(row)} fields, the header {len(header)}", SourceLocation(file, line, 1)))
            continue
        groups.setdefault(row[column["performance"]].strip(), []).append((line, row))
        if len(groups) > MAX_PERFORMANCES:
            raise SpecError(f"more than {MAX_PERFORMANCES} performances", SourceLocation(file, line, 1))
    performances = []
    for name, rows in groups.items():
        try:
            performances.append(_performance_from_rows(name, rows, column, file))
        except SpecError as error:
            refused.append(error)
    kept, inconsistent = _consistent(tuple(performances))
    return RecordingSession(kept, tuple(refused) + inconsistent, False, f"{file} (CSV keyframe table)")


def _performance_from_rows(name: str, rows: list[tuple[int, list[str]]], column: Mapping[str, int], file: str) -> Performance:
    first_line, first = rows[0]
    where = SourceLocation(file, first_line, 1)

    def cell(line: int, row: list[str], key: str) -> str:
        return row[column[key]].strip()

    def number(line: int, row: list[str], key: str) -> float:
        text = cell(line, row, key)
        try:
            value = float(text)
        except ValueError:
            raise SpecError(f"performance {name!r}: {key} {text!r} is not a number", SourceLocation(file, line, column[key] + 1)) from None
        if not math.isfinite(value):
            raise SpecError(f"performance {name!r}: {key} is {text}", SourceLocation(file, line, column[key] + 1))
        return value

    if not name:
        raise SpecError("row has no performance name", where)
    verb, signer = cell(first_line, first, "verb").upper(), cell(first_line, first, "signer")
    subject = None if not cell(first_line, first, "subject") else number(first_line, first, "subject")
    obj = number(first_line, first, "object")
    for line, row in rows[1:]:
        same = (cell(line, row, "verb").upper(), cell(line, row, "signer"), cell(line, row, "subject"), cell(line, row, "object"))
        if same != (verb, signer, cell(first_line, first, "subject"), cell(first_line, first, "object")):
            raise SpecError(f"performance {name!r}: verb, signer, subject or object differs from its first row (line {first_line})", SourceLocation(file, line, 1))
    frames: dict[str, dict[int, tuple[int, np.ndarray]]] = {}
    times: dict[int, tuple[int, float]] = {}
    for line, row in rows:
        hand = cell(line, row, "hand").lower()
        if hand not in HANDS:
            raise SpecError(f"performance {name!r}: hand {hand!r} is not right or left", SourceLocation(file, line, column["hand"] + 1))
        key_text = cell(line, row, "keyframe")
        if not key_text.isdigit():
            raise SpecError(f"performance {name!r}: keyframe {key_text!r} is not a whole number", SourceLocation(file, line, column["keyframe"] + 1))
        key = int(key_text)
        if key >= MAX_KEYFRAMES:
            raise SpecError(f"performance {name!r}: keyframe {key} beyond the limit of {MAX_KEYFRAMES}", SourceLocation(file, line, column["keyframe"] + 1))
        if key in frames.get(hand, {}):
            raise SpecError(f"performance {name!r}: keyframe {key} of the {hand} hand given twice (first at line {frames[hand][key][0]})", SourceLocation(file, line, 1))
        time = number(line, row, "time")
        if key in times and abs(times[key][1] - time) > 1e-9:
            raise SpecError(f"performance {name!r}: keyframe {key} has time {time} here and {times[key][1]} at line {times[key][0]}", SourceLocation(file, line, column["time"] + 1))
        times.setdefault(key, (line, time))
        values = np.array([number(line, row, k) for k in ("x", "y", "z", "qx", "qy", "qz", "qw")])
        frames.setdefault(hand, {})[key] = (line, values)
    count = len(times)
    if sorted(times) != list(range(count)):
        raise SpecError(f"performance {name!r}: keyframes {sorted(times)} are not numbered 0 … {count - 1}", where)
    hands = {}
    for hand in HANDS:
        if hand not in frames:
            continue
        lacking = [k for k in range(count) if k not in frames[hand]]
        if lacking:
            raise SpecError(f"performance {name!r}: the {hand} hand is missing at keyframe(s) {lacking}", where)
        table = np.stack([frames[hand][k][1] for k in range(count)])
        hands[hand] = HandKeyframes(table[:, :3], table[:, 3:])
    return _checked(name, verb, signer, subject, obj, np.array([times[k][1] for k in range(count)]), hands, where)


# -- JSON ---------------------------------------------------------------------------------


def parse_recordings_json(text: str, file: str = "<input>") -> RecordingSession:
    """The performances of a JSON keyframe table (module docstring); each refusal names
    the line where its performance starts."""
    try:
        document = json.loads(text)
    except json.JSONDecodeError as error:
        raise SpecError(f"not JSON: {error.msg}", SourceLocation(file, error.lineno, error.colno)) from None
    top = SourceLocation(file, 1, 1)
    if not isinstance(document, dict) or document.get("format") != JSON_FORMAT:
        raise SpecError(f'not a recording table (expected an object with "format": "{JSON_FORMAT}")', top)
    if document.get("version") != 1:
        raise SpecError(f"unknown version {document.get('version')!r} (expected 1)", top)
    entries = document.get("performances")
    if not isinstance(entries, list):
        raise SpecError('"performances" must be a list', top)
    if len(entries) > MAX_PERFORMANCES:
        raise SpecError(f"{len(entries)} performances, more than the limit of {MAX_PERFORMANCES}", top)
    lines = performance_lines(text, len(entries))
    performances, refused = [], []
    for index, (entry, line) in enumerate(zip(entries, lines)):
        where = SourceLocation(file, line, 1)
        try:
            performances.append(_performance_from_json(entry, index, where))
        except SpecError as error:
            refused.append(error)
    kept, inconsistent = _consistent(tuple(performances))
    synthetic = bool(document.get("synthetic", False))
    description = str(document.get("description", "")) or file
    return RecordingSession(kept, tuple(refused) + inconsistent, synthetic, description)


def performance_lines(text: str, count: int) -> list[int]:
    """The line where each element of the top-level ``performances`` list starts."""
    decoder = json.JSONDecoder()
    position = _skip(text, 0)
    if text[position : position + 1] != "{":
        return [0] * count
    position = _skip(text, position + 1)
    while position < len(text) and text[position] != "}":
        key, position = decoder.raw_decode(text, position)
        position = _skip(text, _skip(text, position) + 1)  # past the colon
        if key == "performances" and text[position] == "[":
            starts = []
            position = _skip(text, position + 1)
            while text[position] != "]":
                starts.append(text.count("\n", 0, position) + 1)
                _, position = decoder.raw_decode(text, position)
                position = _skip(text, position)
                if text[position] == ",":
                    position = _skip(text, position + 1)
            return starts
        _, position = decoder.raw_decode(text, position)
        position = _skip(text, position)
        if text[position] == ",":
            position = _skip(text, position + 1)
    return [0] * count


def _skip(text: str, position: int) -> int:
    while position < len(text) and text[position] in " \t\r\n":
        position += 1
    return position


def _performance_from_json(entry: object, index: int, where: SourceLocation) -> Performance:
    label = f"performance {index + 1}"
    if not isinstance(entry, dict):
        raise SpecError(f"{label} is not an object", where)
    name = str(entry.get("id", f"#{index + 1}"))
    label = f"performance {name!r}"
    verb, signer = entry.get("verb"), entry.get("signer", "")
    if not isinstance(verb, str) or not verb:
        raise SpecError(f"{label} has no verb", where)
    subject = entry.get("subject")
    subject = None if subject is None else _json_number(subject, label, "subject", where)
    obj = _json_number(entry.get("object"), label, "object", where)
    times = _json_array(entry.get("times"), label, "times", where, 1)
    hands_entry = entry.get("hands")
    if not isinstance(hands_entry, dict):
        raise SpecError(f"{label} has no hands", where)
    unknown = [h for h in hands_entry if h not in HANDS]
    if unknown:
        raise SpecError(f"{label}: unknown hand(s) {unknown} (expected right, left)", where)
    hands = {}
    for hand in (h for h in HANDS if h in hands_entry):
        item = hands_entry[hand]
        if not isinstance(item, dict):
            raise SpecError(f"{label}: the {hand} hand is not an object", where)
        location = _json_array(item.get("location"), label, f"{hand} location", where, 2)
        orientation = _json_array(item.get("orientation"), label, f"{hand} orientation", where, 2)
        for array, width, what in ((location, 3, "location"), (orientation, 4, "orientation")):
            if array.shape != (times.shape[0], width):
                raise SpecError(f"{label}: the {hand} hand's {what} is {array.shape[0]}×{array.shape[1] if array.ndim == 2 else 0}, expected {times.shape[0]}×{width} (one per keyframe)", where)
        hands[hand] = HandKeyframes(location, orientation)
    return _checked(name, verb.upper(), str(signer), subject, obj, times, hands, where)


def _json_number(value: object, label: str, key: str, where: SourceLocation) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise SpecError(f"{label}: {key} {value!r} is not a finite number", where)
    return float(value)


def _json_array(value: object, label: str, key: str, where: SourceLocation, ndim: int) -> np.ndarray:
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise SpecError(f"{label}: {key} is not a table of numbers", where) from None
    if array.ndim != ndim or array.size == 0:
        raise SpecError(f"{label}: {key} must be a {'list' if ndim == 1 else 'list of lists'} of numbers", where)
    if not np.all(np.isfinite(array)):
        raise SpecError(f"{label}: {key} holds NaN or infinite values", where)
    return array


# -- checks -------------------------------------------------------------------------------


def _checked(
    name: str, verb: str, signer: str, subject: float | None, obj: float,
    times: np.ndarray, hands: dict[str, HandKeyframes], where: SourceLocation,
) -> Performance:  # fmt: skip
    """The performance, or a :class:`SpecError` saying what is wrong with it."""
    label = f"performance {name!r} ({verb})"
    for key, value in (("subject", subject), ("object", obj)):
        if value is not None and not -1.0 <= value <= 1.0:
            raise SpecError(f"{label}: {key} arc position {value} is outside [-1, 1]", where)
    if "right" not in hands:
        raise SpecError(f"{label} has no right hand", where)
    if times.shape[0] < 2:
        raise SpecError(f"{label} has {times.shape[0]} keyframe(s); at least 2 (start and end) are needed", where)
    if times.shape[0] > MAX_KEYFRAMES:
        raise SpecError(f"{label} has {times.shape[0]} keyframes, more than the limit of {MAX_KEYFRAMES}", where)
    if not np.all(np.isfinite(times)) or np.any(np.diff(times) <= 0):
        raise SpecError(f"{label}: keyframe times {times.tolist()} do not increase", where)
    normalized = {}
    for hand, frames in hands.items():
        for what, values in (("location", frames.location), ("orientation", frames.orientation)):
            if not np.all(np.isfinite(values)):
                bad = int(np.argmax(~np.all(np.isfinite(values), axis=1)))
                raise SpecError(f"{label}: the {hand} hand's {what} is NaN or infinite at keyframe {bad}", where)
        norms = np.linalg.norm(frames.orientation, axis=1)
        if np.any(norms < _UNIT_QUATERNION):
            raise SpecError(f"{label}: the {hand} hand's orientation is a zero quaternion at keyframe {int(np.argmin(norms))}", where)
        normalized[hand] = HandKeyframes(frames.location.copy(), frames.orientation / norms[:, None])
    return Performance(name, verb, signer, subject, obj, times.copy(), normalized, where)


def _consistent(performances: tuple[Performance, ...]) -> tuple[tuple[Performance, ...], tuple[SpecError, ...]]:
    """Performances whose hands and keyframe count match the first of their verb; the
    others refused."""
    structure: dict[str, tuple[int, tuple[str, ...], SourceLocation]] = {}
    kept, refused = [], []
    for performance in performances:
        shape = (performance.keyframes, tuple(performance.hands))
        first = structure.setdefault(performance.verb, (*shape, performance.where))
        if shape != first[:2]:
            refused.append(SpecError(
                f"performance {performance.id!r} ({performance.verb}): {shape[0]} keyframe(s) of {', '.join(shape[1])}, "
                f"but the verb's first performance ({first[2]}) has {first[0]} of {', '.join(first[1])}",
                performance.where,
            ))  # fmt: skip
            continue
        kept.append(performance)
    return tuple(kept), tuple(refused)


# -- writing ------------------------------------------------------------------------------


def recordings_json(performances: Iterable[Performance], synthetic: bool, description: str, digits: int = 5) -> str:
    """The JSON form, one performance per line."""

    def rounded(values: np.ndarray) -> list:
        return np.round(values, digits).tolist()

    lines = []
    for p in performances:
        entry = {
            "id": p.id, "verb": p.verb, "signer": p.signer, "subject": p.subject, "object": p.object,
            "times": rounded(p.times),
            "hands": {h: {"location": rounded(k.location), "orientation": rounded(k.orientation)} for h, k in p.hands.items()},
        }  # fmt: skip
        lines.append(json.dumps(entry, separators=(",", ":")))
    head = json.dumps({"format": JSON_FORMAT, "version": 1, "synthetic": synthetic, "description": description})[:-1]
    return head + ', "performances": [\n' + ",\n".join(lines) + "\n]}\n"


def recordings_csv(performances: Iterable[Performance], digits: int = 5) -> str:
    """The CSV form (module docstring)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(CSV_COLUMNS)
    for p in performances:
        for key in range(p.keyframes):
            for hand, frames in p.hands.items():
                numbers = [round(float(v), digits) for v in (*frames.location[key], *frames.orientation[key])]
                subject = "" if p.subject is None else p.subject
                writer.writerow([p.id, p.verb, p.signer, subject, p.object, key, round(float(p.times[key]), digits), hand, *numbers])
    return out.getvalue()
