"""Torso and shoulders: the HamNoSys body and shoulder tiers as LMPs.

The torso turns and leans at the lower lumbar joint ``vl5``, the joint that carries the
torso's collision volume, so the whole upper body — arms included — moves rigidly with
it; the shoulders rise and come forward at the sternoclavicular joints, on top of the
clavicle rotation the arm's IK chose. The arms are not solved again: hands ride along
with a leaning torso or a shrug (a few centimetres), as a signer's do.

Codes (SiGML ``hnm_body`` and ``hnm_shoulder`` tags; right and left are the signer's):
body ``RL``/``RR`` turned left/right, ``TL``/``TR`` leaning left/right, ``TF``/``TB``
leaning forward/back; shoulders ``UL``/``UR``/``UB`` raised (left, right, both),
``HL``/``HR``/``HB`` hunched (raised and brought forward), ``SL``/``SR``/``SB``
shrugging (up and down once). Each is held with an attack, a sustain and a release
(seed 000), shrugs swing once. MURML ``Torso`` and ``Shoulders`` values take the same
codes or the names in :data:`TRUNK_NAMES`. The angles are mura's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from motor.trajectory.envelope import Envelope

CHANNEL = ("neck", "trunk")
#: Code → (torso rotation vector, left clavicle rotation vector, right clavicle rotation
#: vector, radians in the avatar frame, and whether it swings once instead of holding).
TRUNK_CODES: dict[str, tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float], bool]] = {
    "RL": ((0.0, 0.25, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), False),
    "RR": ((0.0, -0.25, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), False),
    "TL": ((0.0, 0.0, -0.12), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), False),
    "TR": ((0.0, 0.0, 0.12), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), False),
    "TF": ((0.15, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), False),
    "TB": ((-0.1, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), False),
    "UL": ((0.0, 0.0, 0.0), (0.0, 0.0, 0.2), (0.0, 0.0, 0.0), False),
    "UR": ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, -0.2), False),
    "UB": ((0.0, 0.0, 0.0), (0.0, 0.0, 0.2), (0.0, 0.0, -0.2), False),
    "HL": ((0.0, 0.0, 0.0), (0.0, -0.15, 0.12), (0.0, 0.0, 0.0), False),
    "HR": ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.15, -0.12), False),
    "HB": ((0.0, 0.0, 0.0), (0.0, -0.15, 0.12), (0.0, 0.15, -0.12), False),
    "SL": ((0.0, 0.0, 0.0), (0.0, 0.0, 0.25), (0.0, 0.0, 0.0), True),
    "SR": ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, -0.25), True),
    "SB": ((0.0, 0.0, 0.0), (0.0, 0.0, 0.25), (0.0, 0.0, -0.25), True),
}
#: Names MURML ``Torso``/``Shoulders`` values may use (lower case, no separators).
TRUNK_NAMES: dict[str, str] = {
    "turnleft": "RL", "turnright": "RR", "leanleft": "TL", "leanright": "TR", "leanforward": "TF", "leanback": "TB",
    "raiseleft": "UL", "raiseright": "UR", "raise": "UB", "raiseshoulders": "UB", "hunch": "HB", "hunched": "HB",
    "shrug": "SB", "shrugleft": "SL", "shrugright": "SR",
}  # fmt: skip
#: Duration of a shrug's swing, seconds.
SHRUG_TIME = 0.7


class UnknownTrunkCode(ValueError):
    """A body or shoulder code no table knows."""


def trunk_code(name: str) -> str:
    """The code of a HamNoSys code or a name (case-insensitive); raises
    :class:`UnknownTrunkCode` listing the known ones."""
    key = name.strip().upper()
    if key in TRUNK_CODES:
        return key
    alias = TRUNK_NAMES.get(name.strip().lower().replace("_", "").replace("-", "").replace(" ", ""))
    if alias is None:
        raise UnknownTrunkCode(f"unknown body or shoulder movement {name!r} (known: {', '.join(sorted(TRUNK_CODES) + sorted(TRUNK_NAMES))})")
    return alias


@dataclass(frozen=True, eq=False)
class TrunkLMP:
    """One body or shoulder movement, held from ``start`` to ``end`` (a shrug swings up
    and down once over that span), at ``amount`` times its angles."""

    code: str
    start: float
    end: float
    amount: float = 1.0
    manner: str = "targetted"
    attack: float = 0.25
    release: float = 0.3
    channel: tuple[str, str] = CHANNEL

    def __post_init__(self) -> None:
        if self.code not in TRUNK_CODES:
            raise UnknownTrunkCode(f"unknown body or shoulder code {self.code!r}")
        if not (np.isfinite(self.start) and np.isfinite(self.end) and self.end >= self.start and np.isfinite(self.amount)):
            raise ValueError(f"{self.code}: needs finite start ≤ end and amount, got {self.start}, {self.end}, {self.amount}")

    @property
    def swings(self) -> bool:
        return TRUNK_CODES[self.code][3]

    @property
    def first(self) -> float:
        return self.start if self.swings else self.start - self.attack

    @property
    def last(self) -> float:
        return self.end if self.swings else self.end + self.release

    def sample(self, times: np.ndarray) -> np.ndarray:
        """``(n, 9)``: rotation vectors of the torso, the left and the right clavicle."""
        t = np.asarray(times, dtype=float)
        if self.swings:
            u = np.clip((t - self.start) / max(self.end - self.start, 1e-9), 0.0, 1.0)
            amount = 0.5 * (1.0 - np.cos(2.0 * np.pi * u))
        else:
            amount = Envelope.around(self.start, self.end, self.attack, self.release, self.manner).sample(t)
        torso, left, right, _ = TRUNK_CODES[self.code]
        return (self.amount * amount)[:, None] * np.concatenate([torso, left, right])[None, :]


def trunk_movement(name: str, start: float, end: float | None = None, *, amount: float = 1.0, manner: str = "targetted") -> TrunkLMP:
    """The body or shoulder movement ``name`` from ``start`` to ``end`` seconds (a
    shrug's own :data:`SHRUG_TIME` when None)."""
    code = trunk_code(name)
    stop = (start + SHRUG_TIME if TRUNK_CODES[code][3] else start + 0.3) if end is None else end
    return TrunkLMP(code, float(start), float(stop), float(amount), manner)
