"""Reading a BVH file into its skeleton and its channel values, with no code from mura.

A BVH file is a ``HIERARCHY`` of joints — each with an ``OFFSET`` from its parent and a
list of ``CHANNELS`` (``Xposition``… ``Zrotation`` in any order), ``End Site`` leaves
— followed by ``MOTION``: ``Frames: n``, ``Frame Time: dt`` and ``n`` lines holding the
channel values of every joint in the order the hierarchy lists them. Angles are degrees;
lengths are in the file's unit (mura writes centimetres; the audit finds the scale from
the avatar, :mod:`bench.motion_audit.skeleton_match`).

The reader is strict: anything it cannot read is a :class:`BvhError` naming the file,
the line and what was expected, never a traceback from deep inside. Limits (documented,
checked before the work): :data:`MAX_BYTES` per file, :data:`MAX_JOINTS` joints.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

#: Largest BVH file read, bytes (about 40 minutes of a 53-joint skeleton at 60 fps).
MAX_BYTES = 256 * 1024 * 1024
#: Most joints in one hierarchy.
MAX_JOINTS = 1000
#: Channel names a BVH joint may list.
CHANNEL_NAMES = ("Xposition", "Yposition", "Zposition", "Xrotation", "Yrotation", "Zrotation")


class BvhError(ValueError):
    """A BVH file that cannot be read; the message names the file, the line and what was wrong."""


@dataclass(frozen=True)
class BvhJoint:
    """One joint of the hierarchy: ``parent`` is an index into the joint list (-1 for the
    root), ``offset`` in the file's length unit, ``channels`` as written (e.g.
    ``("Zrotation", "Xrotation", "Yrotation")``), ``first_channel`` its first column in a
    frame line."""

    name: str
    parent: int
    offset: tuple[float, float, float]
    channels: tuple[str, ...]
    first_channel: int


@dataclass(frozen=True)
class BvhMotion:
    """A whole BVH file: joints in file order (parents before children), ``values``
    ``(frames, channels)`` as written, ``frame_time`` in seconds."""

    path: str
    joints: tuple[BvhJoint, ...]
    frame_time: float
    values: np.ndarray

    @property
    def fps(self) -> float:
        return 1.0 / self.frame_time

    @property
    def frame_count(self) -> int:
        return int(self.values.shape[0])

    @property
    def joint_names(self) -> tuple[str, ...]:
        return tuple(joint.name for joint in self.joints)

    def index(self, name: str) -> int:
        """The index of joint ``name``; BvhError naming the file if it has no such joint."""
        for position, joint in enumerate(self.joints):
            if joint.name == name:
                return position
        raise BvhError(f"{self.path}: no joint named {name!r} in the hierarchy")

    def channel_values(self, joint: int, channel: str) -> np.ndarray | None:
        """The column ``(frames,)`` of ``channel`` of joint number ``joint``, None if absent."""
        spec = self.joints[joint]
        if channel not in spec.channels:
            return None
        return self.values[:, spec.first_channel + spec.channels.index(channel)]


_TOKEN = re.compile(r"\S+")


class _Tokens:
    """The hierarchy's words with their line numbers, consumed in order."""

    def __init__(self, path: str, text: str) -> None:
        self.path = path
        self.words: list[tuple[str, int]] = [
            (match.group(), number) for number, line in enumerate(text.splitlines(), start=1) for match in _TOKEN.finditer(line)
        ]
        self.position = 0

    def error(self, message: str, line: int | None = None) -> BvhError:
        """An error at ``line``, or at the word about to be read."""
        if line is None:
            line = self.words[min(self.position, len(self.words) - 1)][1] if self.words else 1
        return BvhError(f"{self.path}:{line}: {message}")

    def next(self, what: str) -> str:
        if self.position >= len(self.words):
            raise self.error(f"the file ends where {what} was expected")
        word = self.words[self.position][0]
        self.position += 1
        return word

    def expect(self, word: str) -> None:
        found = self.next(repr(word))
        if found != word:
            self.position -= 1
            raise self.error(f"expected {word!r}, found {found!r}")

    def number(self, what: str) -> float:
        word = self.next(what)
        try:
            value = float(word)
        except ValueError:
            self.position -= 1
            raise self.error(f"expected {what} (a number), found {word!r}") from None
        if not np.isfinite(value):
            self.position -= 1
            raise self.error(f"{what} is {word}, not a finite number")
        return value

    def peek(self) -> str | None:
        return self.words[self.position][0] if self.position < len(self.words) else None

    @property
    def line(self) -> int:
        return self.words[self.position][1] if self.position < len(self.words) else (self.words[-1][1] if self.words else 1)


def read_bvh(path: str | Path) -> BvhMotion:
    """Read the BVH file at ``path``; BvhError naming file and line when it cannot."""
    path = Path(path)
    try:
        size = path.stat().st_size
        if size > MAX_BYTES:
            raise BvhError(f"{path}: {size} bytes, more than the limit of {MAX_BYTES} bytes")
        text = path.read_text(encoding="utf-8", errors="strict")
    except UnicodeDecodeError as error:
        raise BvhError(f"{path}: not a text file ({error.reason} at byte {error.start})") from None
    except OSError as error:
        raise BvhError(f"{path}: cannot read: {error.strerror or error}") from None
    return parse_bvh(text, str(path))


def parse_bvh(text: str, path: str = "<bvh>") -> BvhMotion:
    """Parse BVH ``text``; ``path`` is only used in error messages."""
    split = re.search(r"^\s*MOTION\s*$", text, flags=re.MULTILINE)
    if split is None:
        raise BvhError(f"{path}: no MOTION line: not a BVH file or cut short")
    tokens = _Tokens(path, text[: split.start()])
    tokens.expect("HIERARCHY")
    joints: list[BvhJoint] = []
    tokens.expect("ROOT")
    _joint(tokens, joints, parent=-1)
    if tokens.peek() is not None:
        raise tokens.error(f"unexpected {tokens.peek()!r} after the root joint's closing brace")
    channel_count = sum(len(joint.channels) for joint in joints)
    motion_line = text.count("\n", 0, split.start()) + 1
    frame_time, values = _motion(text[split.end() :], path, motion_line, channel_count)
    return BvhMotion(path=path, joints=tuple(joints), frame_time=frame_time, values=values)


def _joint(tokens: _Tokens, joints: list[BvhJoint], parent: int) -> None:
    """Read one ``ROOT``/``JOINT`` block (its keyword already consumed) and its children."""
    name = tokens.next("a joint name")
    if name == "{":
        raise tokens.error("a joint without a name")
    if len(joints) >= MAX_JOINTS:
        raise tokens.error(f"more than {MAX_JOINTS} joints")
    tokens.expect("{")
    tokens.expect("OFFSET")
    offset = tuple(tokens.number(f"the OFFSET of {name!r}") for _ in range(3))
    channels: tuple[str, ...] = ()
    if tokens.peek() == "CHANNELS":
        line = tokens.line
        tokens.next("CHANNELS")
        count = tokens.number(f"the channel count of {name!r}")
        if count != int(count) or not 0 <= count <= 6:
            raise tokens.error(f"joint {name!r}: channel count {count:g} is not 0 to 6", line)
        channels = tuple(tokens.next(f"a channel name of {name!r}") for _ in range(int(count)))
        unknown = [channel for channel in channels if channel not in CHANNEL_NAMES]
        if unknown:
            raise tokens.error(f"joint {name!r}: unknown channel {unknown[0]!r} (expected one of {', '.join(CHANNEL_NAMES)})", line)
        if len(set(channels)) != len(channels):
            raise tokens.error(f"joint {name!r}: a channel is listed twice in {' '.join(channels)}", line)
    first = sum(len(joint.channels) for joint in joints)
    index = len(joints)
    joints.append(BvhJoint(name=name, parent=parent, offset=offset, channels=channels, first_channel=first))  # type: ignore[arg-type]
    while True:
        word = tokens.next(f"JOINT, End Site or '}}' closing {name!r}")
        if word == "}":
            return
        if word == "JOINT":
            _joint(tokens, joints, parent=index)
        elif word == "End":
            tokens.expect("Site")
            tokens.expect("{")
            tokens.expect("OFFSET")
            for _ in range(3):
                tokens.number(f"the End Site OFFSET under {name!r}")
            tokens.expect("}")
        else:
            tokens.position -= 1
            raise tokens.error(f"expected JOINT, End Site or '}}' in joint {name!r}, found {word!r}")


def _motion(text: str, path: str, motion_line: int, channel_count: int) -> tuple[float, np.ndarray]:
    """``Frames:`` and ``Frame Time:`` then the frame lines, checked for their count and width."""
    lines = text.splitlines()
    header = [(number, line.strip()) for number, line in enumerate(lines, start=motion_line) if line.strip()][:2]
    if len(header) < 2:
        raise BvhError(f"{path}:{motion_line}: expected 'Frames:' and 'Frame Time:' after MOTION")
    (frames_line, frames_text), (time_line, time_text) = header
    frames_match = re.fullmatch(r"Frames:\s*(\d+)", frames_text)
    if frames_match is None:
        raise BvhError(f"{path}:{frames_line}: expected 'Frames: <count>', found {frames_text[:40]!r}")
    time_match = re.fullmatch(r"Frame Time:\s*(\S+)", time_text)
    try:
        frame_time = float(time_match.group(1)) if time_match else float("nan")
    except ValueError:
        frame_time = float("nan")
    if not (np.isfinite(frame_time) and frame_time > 0):
        raise BvhError(f"{path}:{time_line}: expected 'Frame Time: <seconds>' with a positive time, found {time_text[:40]!r}")
    frames = int(frames_match.group(1))
    if frames == 0:
        raise BvhError(f"{path}:{frames_line}: the file has no frames")
    body_start = time_line - motion_line + 1
    body = lines[body_start:]
    words = " ".join(body).split()
    if len(words) != frames * channel_count:
        rows = [line for line in body if line.strip()]
        raise BvhError(
            f"{path}:{time_line + 1}: expected {frames} frames of {channel_count} channel values, "
            f"found {len(rows)} lines with {len(words)} values"
        )
    try:
        values = np.array(words, dtype=float).reshape(frames, channel_count)
    except ValueError:
        raise BvhError(f"{path}:{_bad_line(body, time_line + 1)}: a channel value is not a number") from None
    if not np.all(np.isfinite(values)):
        row = int(np.argwhere(~np.isfinite(values))[0, 0])
        raise BvhError(f"{path}: frame {row} holds a value that is not finite (NaN or infinity)")
    return frame_time, values


def _bad_line(lines: list[str], first_number: int) -> int:
    """The number of the first line holding a word that is not a number (error path only)."""
    for number, line in enumerate(lines, start=first_number):
        for word in line.split():
            try:
                float(word)
            except ValueError:
                return number
    return first_number
