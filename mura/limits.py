"""The limits on input, as validated numbers in one place.

Specs and command lines come from users and from the web; without bounds a 200-byte
file can ask for a day of animation, 2³⁰ repeated movements or a billion frames. Every
limit here is checked where the input is read (``mura check`` refuses what ``mura
render`` would refuse, naming FILE:LINE:COL), is documented in the README, and can be
raised for a legitimate large job: ``--limit max_duration=3600`` on any command, or
``Limits(max_duration=3600)`` from Python.

The defaults are far above what real inputs need: utterances of the corpora last seconds,
their chunks (intonational phrases) hold under 200 characters, the largest sign of the
SiGML corpora expands to 20 movements, and gestures span less than a metre.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable
from dataclasses import dataclass


class LimitError(ValueError):
    """A value outside its limit, or a limit that is itself not a valid number."""


@dataclass(frozen=True)
class LimitInfo:
    """What a limit bounds, in which unit, for messages and ``--limit`` help."""

    unit: str
    what: str


#: Every limit's unit and meaning, in the order the README lists them.
LIMIT_INFO: dict[str, LimitInfo] = {
    "max_input_bytes": LimitInfo("bytes", "size of one spec file or stream"),
    "stream_timeout": LimitInfo("s", "longest wait for data from a pipe, FIFO or device"),
    "max_duration": LimitInfo("s", "length of one utterance on its clock (absolute timings, the performance's end)"),
    "max_chunk_chars": LimitInfo("characters", "spoken text of one chunk (and of `mura say`)"),
    "max_movements": LimitInfo("movements", "movements of one gesture or sign once its repetitions are expanded"),
    "max_length": LimitInfo("m", "a distance or coordinate written in a spec"),
    "max_frames": LimitInfo("frames", "frames of one rendered performance (duration × fps)"),
    "min_fps": LimitInfo("frames/s", "lowest frame rate"),
    "max_fps": LimitInfo("frames/s", "highest frame rate"),
    "min_rate": LimitInfo("×", "slowest relative speaking rate"),
    "max_rate": LimitInfo("×", "fastest relative speaking rate"),
}


@dataclass(frozen=True)
class Limits:
    """The input limits (units in :data:`LIMIT_INFO`); construction validates them."""

    max_input_bytes: int = 32 * 1024 * 1024
    stream_timeout: float = 10.0
    max_duration: float = 600.0
    max_chunk_chars: int = 2000
    max_movements: int = 1000
    max_length: float = 10.0
    max_frames: int = 100_000
    min_fps: float = 1.0
    max_fps: float = 240.0
    min_rate: float = 0.25
    max_rate: float = 4.0

    def __post_init__(self) -> None:
        for item in dataclasses.fields(self):
            value = getattr(self, item.name)
            integral = item.type in ("int", int)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or (integral and not float(value).is_integer()):
                kind = "a whole number" if integral else "a number"
                raise LimitError(f"limit {item.name} must be {kind}, got {value!r}")
            if not math.isfinite(value) or value <= 0:
                raise LimitError(f"limit {item.name} must be a positive finite number, got {value!r}")
            if integral:
                object.__setattr__(self, item.name, int(value))
        for low, high in (("min_fps", "max_fps"), ("min_rate", "max_rate")):
            if getattr(self, low) > getattr(self, high):
                raise LimitError(f"limit {low} ({getattr(self, low)}) is above {high} ({getattr(self, high)})")

    def with_overrides(self, assignments: Iterable[str]) -> Limits:
        """These limits with ``NAME=VALUE`` assignments applied (the ``--limit`` option)."""
        changes: dict[str, float | int] = {}
        for assignment in assignments:
            name, equals, text = assignment.partition("=")
            name = name.strip().replace("-", "_")
            if not equals or name not in LIMIT_INFO:
                raise LimitError(f"--limit {assignment!r}: expected NAME=VALUE with NAME one of {', '.join(LIMIT_INFO)}")
            try:
                number = float(text)
            except ValueError:
                raise LimitError(f"--limit {assignment!r}: {text.strip()!r} is not a number") from None
            changes[name] = int(number) if number.is_integer() and math.isfinite(number) else number
        return dataclasses.replace(self, **changes)

    def check_fps(self, fps: float) -> float:
        """``fps`` as a float when it lies in [min_fps, max_fps], else :class:`LimitError`."""
        return self._in_range("frame rate", "fps", fps, self.min_fps, self.max_fps)

    def check_rate(self, rate: float) -> float:
        """``rate`` as a float when it lies in [min_rate, max_rate], else :class:`LimitError`."""
        return self._in_range("speaking rate", "rate", rate, self.min_rate, self.max_rate)

    def check_chunk_text(self, text: str, what: str = "spoken text") -> None:
        """Refuse spoken text longer than ``max_chunk_chars``."""
        if len(text) > self.max_chunk_chars:
            raise LimitError(f"{what} has {len(text)} characters, more than the limit of {self.max_chunk_chars} "
                             f"({hint('max_chunk_chars')})")

    def check_time(self, seconds: float, what: str) -> None:
        """Refuse a time (seconds on the utterance clock) that is not finite or lies past ``max_duration``."""
        if not math.isfinite(seconds):
            raise LimitError(f"{what} {seconds} is not a finite number of seconds")
        if abs(seconds) > self.max_duration:
            raise LimitError(f"{what} {seconds:g} s is beyond the limit of {self.max_duration:g} s ({hint('max_duration')})")

    def check_length(self, metres: float, what: str) -> None:
        """Refuse a length (metres) that is not finite or larger than ``max_length``."""
        if not math.isfinite(metres):
            raise LimitError(f"{what} {metres} is not a finite number")
        if abs(metres) > self.max_length:
            raise LimitError(f"{what} {metres:g} m is more than the limit of {self.max_length:g} m ({hint('max_length')})")

    def check_performance(self, end: float, fps: float, what: str) -> None:
        """Refuse a performance that would last until ``end`` seconds: past ``max_duration``,
        or more than ``max_frames`` frames at ``fps``."""
        if not math.isfinite(end) or end > self.max_duration:
            raise LimitError(f"{what} would end at {end:.1f} s, beyond the limit of {self.max_duration:g} s "
                             f"({hint('max_duration')})")
        frames = end * fps
        if frames > self.max_frames:
            raise LimitError(f"{what} would take {frames:.0f} frames ({end:.1f} s at {fps:g} frames/s), more than the "
                             f"limit of {self.max_frames} ({hint('max_frames')})")

    def _in_range(self, what: str, option: str, value: float, low: float, high: float) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise LimitError(f"{what} (--{option}) must be a finite number, got {value!r}")
        if not low <= value <= high:
            raise LimitError(f"{what} (--{option}) {value:g} is outside {low:g}..{high:g} "
                             f"(change the range with --limit min_{option}=N or --limit max_{option}=N)")
        return float(value)


def hint(name: str) -> str:
    """How to raise limit ``name``, for messages."""
    return f"raise with --limit {name}=N"


#: The limits unless the user sets others.
DEFAULT_LIMITS = Limits()
