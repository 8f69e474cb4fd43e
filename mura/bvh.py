"""Reading Biovision Hierarchy (BVH) motion clips: the skeleton and the channel values.

This module only reads the text (what a motion-capture session exports) into plain
arrays; the clip's kinematics are computed where geometry lives
(:mod:`motor.verbs.capture`). Every problem is a :class:`SpecError` naming the file and
line. Limits: :data:`MAX_BVH_BYTES`, :data:`MAX_JOINTS`.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mura.errors import SourceLocation, SpecError

#: Largest BVH file read, bytes, and most joints in its hierarchy.
MAX_BVH_BYTES = 512 * 1024 * 1024
MAX_JOINTS = 1024
#: The channel names BVH knows.
CHANNEL_NAMES: tuple[str, ...] = ("Xposition", "Yposition", "Zposition", "Xrotation", "Yrotation", "Zrotation")


@dataclass(frozen=True, eq=False)
class BvhClip:
    """A BVH clip.

    Attributes:
        file: where it came from.
        names: joint names, parents before children.
        parents: each joint's parent index, −1 for the root ``(J,)``.
        offsets: each joint's offset from its parent at rest ``(J, 3)``, file units.
        channels: each joint's channel names, in file order.
        first_column: where each joint's channels start in a frame's values ``(J,)``.
        frames: channel values ``(F, C)`` (degrees for rotations, file units for positions).
        frame_time: seconds between frames.
    """

    file: str
    names: tuple[str, ...]
    parents: np.ndarray
    offsets: np.ndarray
    channels: tuple[tuple[str, ...], ...]
    first_column: np.ndarray
    frames: np.ndarray
    frame_time: float

    @property
    def duration(self) -> float:
        """Time of the last frame, seconds."""
        return (self.frames.shape[0] - 1) * self.frame_time

    def children(self, joint: int) -> list[int]:
        return [j for j in range(len(self.names)) if self.parents[j] == joint]


def read_bvh(path: str | Path) -> BvhClip:
    """Read a BVH file (module docstring)."""
    path = Path(path)
    where = SourceLocation(str(path))
    try:
        if path.stat().st_size > MAX_BVH_BYTES:
            raise SpecError(f"file is larger than the limit of {MAX_BVH_BYTES} bytes", where)
        text = path.read_text(encoding="utf-8", errors="strict")
    except OSError as error:
        raise SpecError(f"cannot read: {error.strerror or error}", where) from None
    except UnicodeDecodeError as error:
        raise SpecError(f"not text ({error.reason} at byte {error.start})", where) from None
    return parse_bvh(text, str(path))


def parse_bvh(text: str, file: str = "<input>") -> BvhClip:
    """A BVH clip from its text."""
    lines = text.splitlines()
    reader = _Hierarchy(lines, file)
    reader.read()
    return _motion(lines, reader, file)


class _Hierarchy:
    def __init__(self, lines: list[str], file: str) -> None:
        self.lines, self.file = lines, file
        self.line = 0
        self.names: list[str] = []
        self.parents: list[int] = []
        self.offsets: list[list[float]] = []
        self.channels: list[tuple[str, ...]] = []

    def error(self, message: str) -> SpecError:
        return SpecError(message, SourceLocation(self.file, self.line + 1, 1))

    def words(self) -> list[str]:
        while self.line < len(self.lines):
            words = self.lines[self.line].split()
            if words:
                return words
            self.line += 1
        raise SpecError("the file ends inside the HIERARCHY", SourceLocation(self.file, len(self.lines), 1))

    def take(self) -> list[str]:
        words = self.words()
        self.line += 1
        return words

    def read(self) -> None:
        if self.take() != ["HIERARCHY"]:
            self.line -= 1
            raise self.error("expected HIERARCHY")
        words = self.take()
        if len(words) != 2 or words[0] != "ROOT":
            self.line -= 1
            raise self.error("expected ROOT and a joint name")
        self.joint(words[1], -1)

    def joint(self, name: str, parent: int) -> None:
        if len(self.names) >= MAX_JOINTS:
            raise self.error(f"more than {MAX_JOINTS} joints")
        if name in self.names:
            raise self.error(f"joint {name!r} is defined twice")
        index = len(self.names)
        self.names.append(name)
        self.parents.append(parent)
        if self.take() != ["{"]:
            self.line -= 1
            raise self.error(f"expected {{ after joint {name!r}")
        self.offsets.append(self.offset())
        words = self.take()
        if words[0] != "CHANNELS" or len(words) < 2 or not words[1].isdigit() or len(words) != 2 + int(words[1]):
            self.line -= 1
            raise self.error(f"joint {name!r}: expected CHANNELS, their count and their names")
        unknown = [w for w in words[2:] if w not in CHANNEL_NAMES]
        if unknown:
            self.line -= 1
            raise self.error(f"joint {name!r}: unknown channel(s) {unknown} (expected {', '.join(CHANNEL_NAMES)})")
        self.channels.append(tuple(words[2:]))
        while True:
            words = self.take()
            if words == ["}"]:
                return
            if words[0] == "JOINT" and len(words) == 2:
                self.joint(words[1], index)
            elif words[:2] == ["End", "Site"]:
                if self.take() != ["{"]:
                    self.line -= 1
                    raise self.error("expected { after End Site")
                self.offset()
                if self.take() != ["}"]:
                    self.line -= 1
                    raise self.error("expected } closing End Site")
            else:
                self.line -= 1
                raise self.error(f"joint {name!r}: expected JOINT, End Site or }}, found {' '.join(words)!r}")

    def offset(self) -> list[float]:
        words = self.take()
        try:
            values = [float(w) for w in words[1:]]
        except ValueError:
            values = []
        if words[0] != "OFFSET" or len(values) != 3 or not all(np.isfinite(values)):
            self.line -= 1
            raise self.error("expected OFFSET and three numbers")
        return values


def _motion(lines: list[str], hierarchy: _Hierarchy, file: str) -> BvhClip:
    line = hierarchy.line
    header = []
    while line < len(lines) and len(header) < 3:
        if lines[line].strip():
            header.append((line, lines[line].strip()))
        line += 1
    if len(header) < 3 or header[0][1] != "MOTION":
        at = header[0][0] if header else len(lines) - 1
        raise SpecError("expected MOTION, Frames: and Frame Time: after the hierarchy", SourceLocation(file, at + 1, 1))
    (_, _), (frames_line, frames_text), (time_line, time_text) = header
    count = _header_number(frames_text, "Frames:", frames_line, file)
    frame_time = _header_number(time_text, "Frame Time:", time_line, file)
    if count != int(count) or count < 1:
        raise SpecError(f"Frames: {frames_text[7:].strip()} is not a positive whole number", SourceLocation(file, frames_line + 1, 1))
    if not frame_time > 0:
        raise SpecError("Frame Time: must be positive", SourceLocation(file, time_line + 1, 1))
    width = sum(len(c) for c in hierarchy.channels)
    rows = [(number, text) for number, text in enumerate(lines[line:], start=line) if text.strip()]
    if len(rows) < int(count):
        raise SpecError(f"Frames: says {int(count)} but the file has {len(rows)} frame lines", SourceLocation(file, frames_line + 1, 1))
    values = _frame_values(rows[: int(count)], width, file)
    first = np.concatenate([[0], np.cumsum([len(c) for c in hierarchy.channels])[:-1]]).astype(int)
    return BvhClip(
        file, tuple(hierarchy.names), np.array(hierarchy.parents), np.array(hierarchy.offsets, dtype=float),
        tuple(hierarchy.channels), first, values, float(frame_time),
    )  # fmt: skip


def _frame_values(rows: list[tuple[int, str]], width: int, file: str) -> np.ndarray:
    """All frames at once; only when that fails are the lines read one by one, to name the bad one."""
    try:
        values = np.array(" ".join(text for _, text in rows).split(), dtype=float)
        if values.size == len(rows) * width and np.all(np.isfinite(values)):
            return values.reshape(len(rows), width)
    except ValueError:
        pass
    for number, text in rows:
        try:
            row = np.array(text.split(), dtype=float)
        except ValueError:
            raise SpecError("frame holds something that is not a number", SourceLocation(file, number + 1, 1)) from None
        if row.shape[0] != width:
            raise SpecError(f"frame has {row.shape[0]} values, the hierarchy {width} channels", SourceLocation(file, number + 1, 1))
        if not np.all(np.isfinite(row)):
            raise SpecError("frame holds NaN or infinite values", SourceLocation(file, number + 1, 1))
    raise SpecError("frames cannot be read", SourceLocation(file, rows[0][0] + 1, 1))


def _header_number(text: str, label: str, line: int, file: str) -> float:
    if not text.startswith(label):
        raise SpecError(f"expected {label}", SourceLocation(file, line + 1, 1))
    try:
        return float(text[len(label) :].strip())
    except ValueError:
        raise SpecError(f"{label} {text[len(label):].strip()!r} is not a number", SourceLocation(file, line + 1, 1)) from None
