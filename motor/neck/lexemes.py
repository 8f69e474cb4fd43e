"""Head lexemes: nods, shakes, tilts, turns as neck LMPs with seed 000's temporal profiles.

A head lexeme is a rotation of the head about one of its own axes — ``x`` (the avatar's
left: pitch, positive looks down), ``y`` (up: yaw, positive turns left) or ``z``
(forward: roll, positive brings the crown toward the right shoulder) — performed either
as a *held posture* (tilt, turn, chin up or down, head pushed forward or back) or as a
*repeated swing* (nod: down and back, shake: side to side). :data:`HEAD_LEXEMES` gives
each its axis, peak angle and, for swings, the number of swings and the time of one.

:func:`head_lexeme` is the constructor a realizer calls — for MURML ``Neck`` values, the
HamNoSys head tier (:data:`HAMNOSYS_HEAD` codes) and BML ``<head lexeme="NOD"
repetition="2" amount="0.5"/>`` alike. ``amount`` scales the angle (HamNoSys ``small`` /
``large`` are 0.5 and 1.6); ``repetitions`` replaces a swing's count; the manner
(``fast``, ``slow``, ``tense`` …) scales the swing time by its biocontrol duration and
shapes the attack of a held posture (:mod:`motor.trajectory.envelope`). The LMP's
:meth:`HeadMovementLMP.sample` gives, per frame, the rotation vector of the head
relative to where gaze puts it (head frame, radians) and the protrusion angle (radians
of lower-neck flexion compensated at the skull, which moves the face forward level).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from motor.trajectory.biocontrol import MANNERS
from motor.trajectory.envelope import Envelope

CHANNEL = ("neck", "head")
#: Rise and fall of a swing's amplitude at its ends, at most, seconds.
SWING_RAMP = 0.12
#: Amount of HamNoSys sizes.
SIZES: dict[str, float] = {"small": 0.5, "large": 1.6}


@dataclass(frozen=True)
class HeadLexeme:
    """A head movement: ``axis`` (head frame, unit), peak ``angle`` (radians), ``swings``
    (0 for a held posture) of ``swing_time`` seconds each; ``one_sided`` swings go out and
    back (a nod) instead of to both sides (a shake); ``protrusion`` moves the face forward
    (positive) or back instead of turning it."""

    name: str
    axis: tuple[float, float, float] = (1.0, 0.0, 0.0)
    angle: float = 0.0
    swings: int = 0
    swing_time: float = 0.4
    one_sided: bool = False
    protrusion: float = 0.0

    @property
    def held(self) -> bool:
        return self.swings == 0


HEAD_LEXEMES: dict[str, HeadLexeme] = {
    lexeme.name: lexeme
    for lexeme in (
        HeadLexeme("NOD", (1.0, 0.0, 0.0), 0.17, swings=2, swing_time=0.42, one_sided=True),
        HeadLexeme("SHAKE", (0.0, 1.0, 0.0), 0.22, swings=3, swing_time=0.45),
        HeadLexeme("BEAT", (1.0, 0.0, 0.0), 0.05, swings=1, swing_time=0.35, one_sided=True),
        HeadLexeme("TILT_RIGHT", (0.0, 0.0, 1.0), 0.2),
        HeadLexeme("TILT_LEFT", (0.0, 0.0, -1.0), 0.2),
        HeadLexeme("TURN_LEFT", (0.0, 1.0, 0.0), 0.35),
        HeadLexeme("TURN_RIGHT", (0.0, -1.0, 0.0), 0.35),
        HeadLexeme("TILT_FORWARD", (1.0, 0.0, 0.0), 0.22),
        HeadLexeme("TILT_BACK", (-1.0, 0.0, 0.0), 0.22),
        HeadLexeme("PUSH_FORWARD", protrusion=0.18),
        HeadLexeme("PUSH_BACK", protrusion=-0.12),
    )
}
#: Other names of lexemes (BML and MURML spellings), upper case, without ``_``.
ALIASES: dict[str, str] = {
    "TILT": "TILT_RIGHT", "DOWN": "TILT_FORWARD", "UP": "TILT_BACK", "CHINDOWN": "TILT_FORWARD", "CHINUP": "TILT_BACK",
    "NODDING": "NOD", "SHAKING": "SHAKE", "TURNLEFT": "TURN_LEFT", "TURNRIGHT": "TURN_RIGHT", "TILTLEFT": "TILT_LEFT",
    "TILTRIGHT": "TILT_RIGHT", "TILTFORWARD": "TILT_FORWARD", "TILTBACK": "TILT_BACK", "PUSHFORWARD": "PUSH_FORWARD",
    "PUSHBACK": "PUSH_BACK",
}  # fmt: skip
#: HamNoSys head tier codes (SiGML ``hnm_head tag``) → lexemes; right and left are the signer's.
HAMNOSYS_HEAD: dict[str, str] = {
    "NO": "NOD", "SH": "SHAKE", "SR": "TURN_RIGHT", "SL": "TURN_LEFT", "TR": "TILT_RIGHT", "TL": "TILT_LEFT",
    "NF": "TILT_FORWARD", "NB": "TILT_BACK", "PF": "PUSH_FORWARD", "PB": "PUSH_BACK",
}  # fmt: skip


class UnknownHeadLexeme(ValueError):
    """A head lexeme name or HamNoSys head code that no table knows."""


def lexeme_named(name: str) -> HeadLexeme:
    """The lexeme of a name, alias or HamNoSys head code (case-insensitive); raises
    :class:`UnknownHeadLexeme` listing the known names."""
    key = name.strip().upper()
    key = HAMNOSYS_HEAD.get(key, key)
    key = ALIASES.get(key.replace("_", "").replace("-", ""), key)
    if key not in HEAD_LEXEMES:
        known = sorted(HEAD_LEXEMES) + sorted(HAMNOSYS_HEAD)
        raise UnknownHeadLexeme(f"unknown head lexeme {name!r} (known: {', '.join(known)})")
    return HEAD_LEXEMES[key]


def natural_duration(lexeme: HeadLexeme, repetitions: int | None = None, manner: str = "targetted") -> float:
    """Seconds a swing takes at its own pace (its swings times the swing time, scaled by
    the manner), or a held posture's shortest hold (0.3 s)."""
    if lexeme.held:
        return 0.3
    scale = MANNERS[manner].duration_scale if manner in MANNERS else 1.0
    return (repetitions or lexeme.swings) * lexeme.swing_time * scale


@dataclass(frozen=True, eq=False)
class HeadMovementLMP:
    """One head lexeme performed from ``start`` to ``end`` seconds (module docstring).

    A swing fills ``[start, end]`` with its ``repetitions`` swings, its amplitude rising
    and falling over :data:`SWING_RAMP` at the ends; a held posture rises during
    ``attack`` seconds before ``start`` in ``manner``, holds until ``end`` and falls over
    ``release`` seconds after it.
    """

    lexeme: HeadLexeme
    start: float
    end: float
    amount: float = 1.0
    repetitions: int | None = None
    manner: str = "targetted"
    attack: float = 0.2
    release: float = 0.25
    channel: tuple[str, str] = CHANNEL

    def __post_init__(self) -> None:
        if not (np.isfinite(self.start) and np.isfinite(self.end) and self.end >= self.start):
            raise ValueError(f"head lexeme {self.lexeme.name}: needs finite start ≤ end, got {self.start}, {self.end}")
        if not np.isfinite(self.amount) or self.amount < 0.0:
            raise ValueError(f"head lexeme {self.lexeme.name}: amount must be a finite number ≥ 0, got {self.amount}")
        if self.repetitions is not None and self.repetitions < 1:
            raise ValueError(f"head lexeme {self.lexeme.name}: repetitions must be at least 1, got {self.repetitions}")

    @property
    def first(self) -> float:
        """When the movement begins to show, seconds."""
        return self.start if not self.lexeme.held else self.start - self.attack

    @property
    def last(self) -> float:
        """When it has ended, seconds."""
        return self.end if not self.lexeme.held else self.end + self.release

    def envelope(self) -> Envelope:
        if self.lexeme.held:
            return Envelope.around(self.start, self.end, self.attack, self.release, self.manner)
        ramp = min(SWING_RAMP, 0.25 * (self.end - self.start))
        return Envelope.around(self.start + ramp, self.end - ramp, ramp, ramp, "lax")

    def sample(self, times: np.ndarray) -> np.ndarray:
        """``(n, 4)``: the head-frame rotation vector (radians) and the protrusion angle."""
        t = np.asarray(times, dtype=float)
        amount = self.amount * self.envelope().sample(t)
        if self.lexeme.held:
            swing = np.ones_like(t)
        else:
            count = self.repetitions or self.lexeme.swings
            u = np.clip((t - self.start) / max(self.end - self.start, 1e-9), 0.0, 1.0)
            swing = 0.5 * (1.0 - np.cos(2.0 * np.pi * count * u)) if self.lexeme.one_sided else np.sin(2.0 * np.pi * count * u)
        out = np.zeros((t.size, 4))
        out[:, :3] = (amount * swing * self.lexeme.angle)[:, None] * np.asarray(self.lexeme.axis)[None, :]
        out[:, 3] = amount * self.lexeme.protrusion
        return out


def head_lexeme(
    name: str, start: float, end: float | None = None, *, amount: float = 1.0, repetitions: int | None = None,
    manner: str = "targetted",
) -> HeadMovementLMP:  # fmt: skip
    """The head lexeme ``name`` (:data:`HEAD_LEXEMES`, an alias or a HamNoSys head code)
    from ``start`` to ``end`` seconds (its natural duration when ``end`` is None), at
    ``amount`` times its angle, with ``repetitions`` swings instead of its own count.
    Raises :class:`UnknownHeadLexeme` or ValueError for a bad number."""
    lexeme = lexeme_named(name)
    stop = start + natural_duration(lexeme, repetitions, manner) if end is None else end
    return HeadMovementLMP(lexeme, float(start), float(stop), float(amount), repetitions, manner)
