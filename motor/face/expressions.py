"""Facial expressions as ARKit morph weights: face lexemes and the HamNoSys facial tiers.

:func:`face_lexeme` is the constructor a realizer calls for a named expression over a
span of time — BML 1.0's ``<faceLexeme lexeme="RAISE_BROWS" amount="0.6"/>`` among them;
:func:`hamnosys_face` reads one item of a SiGML sign's facial tiers (eyebrows, eyelids,
nose, mouth gestures) into the same kind of :class:`FaceExpressionLMP`. Each is an
:class:`motor.trajectory.envelope.Envelope` (attack, sustain, release, seed 000) times a
fixed vector of morph weights.

**Lexemes** (:data:`FACE_LEXEMES`): the BML 1.0 core face lexemes (``RAISE_BROWS``,
``RAISE_LEFT_BROW``, ``RAISE_RIGHT_BROW``, ``LOWER_BROWS`` and its one-sided forms,
``OBLIQUE_BROWS``, ``RAISE_MOUTH_CORNERS`` / ``LOWER_MOUTH_CORNERS`` and their one-sided
forms, ``OPEN_MOUTH``, ``OPEN_LIPS``, ``WIDEN_EYES``, ``CLOSE_EYES``) and a few plain ones
(``SMILE``, ``FROWN``, ``PUFF_CHEEKS``, ``SQUINT``); names are case-insensitive.

**HamNoSys tiers** (:data:`EYEBROWS`, :data:`EYELIDS`, :data:`NOSE`): the two-letter codes
of the SiGML non-manual tags — eyebrows ``RB``/``RR``/``RL`` raised (both, right, left),
``FU`` furrowed; eyelids ``WB``/``WR``/``WL`` wide open, ``SB``/``SR``/``SL`` narrowed,
``CB``/``CR``/``CL`` closed, ``TB`` tightly shut, ``BB`` a blink; nose ``WR`` wrinkled,
``TW`` twitching, ``WI`` nostrils widened. Mouth gestures (``C01``, ``L12``, ``T03`` …)
are realized by their family letter — ``C`` cheeks (puffed), ``L`` lips (pursed),
``T`` tongue (shown), ``J`` jaw (lowered), ``D`` teeth (bared) — with a warning, since
mura has no table of the individual gestures. "Right" and "left" are the signer's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from motor.face.arkit import face_vector
from motor.trajectory.envelope import Envelope

#: Named expressions → morph weights at full amount.
FACE_LEXEMES: dict[str, dict[str, float]] = {
    "RAISE_BROWS": {"browInnerUp": 0.8, "browOuterUp*": 0.7},
    "RAISE_LEFT_BROW": {"browOuterUpLeft": 0.8, "browInnerUp": 0.3},
    "RAISE_RIGHT_BROW": {"browOuterUpRight": 0.8, "browInnerUp": 0.3},
    "LOWER_BROWS": {"browDown*": 0.8},
    "LOWER_LEFT_BROW": {"browDownLeft": 0.8},
    "LOWER_RIGHT_BROW": {"browDownRight": 0.8},
    "OBLIQUE_BROWS": {"browInnerUp": 0.8, "browDown*": 0.3},
    "RAISE_MOUTH_CORNERS": {"mouthSmile*": 0.7},
    "RAISE_LEFT_MOUTH_CORNER": {"mouthSmileLeft": 0.7},
    "RAISE_RIGHT_MOUTH_CORNER": {"mouthSmileRight": 0.7},
    "LOWER_MOUTH_CORNERS": {"mouthFrown*": 0.7},
    "LOWER_LEFT_MOUTH_CORNER": {"mouthFrownLeft": 0.7},
    "LOWER_RIGHT_MOUTH_CORNER": {"mouthFrownRight": 0.7},
    "OPEN_MOUTH": {"jawOpen": 0.5, "mouthLowerDown*": 0.2},
    "OPEN_LIPS": {"jawOpen": 0.1, "mouthLowerDown*": 0.3, "mouthUpperUp*": 0.2},
    "WIDEN_EYES": {"eyeWide*": 0.8},
    "CLOSE_EYES": {"eyeBlink*": 1.0},
    "SMILE": {"mouthSmile*": 0.7, "cheekSquint*": 0.35, "eyeSquint*": 0.15},
    "FROWN": {"browDown*": 0.6, "mouthFrown*": 0.4},
    "PUFF_CHEEKS": {"cheekPuff": 0.8, "mouthClose": 0.1},
    "SQUINT": {"eyeSquint*": 0.7},
}

#: HamNoSys eyebrow codes → morph weights.
EYEBROWS: dict[str, dict[str, float]] = {
    "RB": FACE_LEXEMES["RAISE_BROWS"],
    "RR": FACE_LEXEMES["RAISE_RIGHT_BROW"],
    "RL": FACE_LEXEMES["RAISE_LEFT_BROW"],
    "FU": {"browDown*": 0.8, "browInnerUp": 0.15, "noseSneer*": 0.1},
}
#: HamNoSys eyelid codes → morph weights (``BB``, a blink, is timed as a blink instead).
EYELIDS: dict[str, dict[str, float]] = {
    "WB": {"eyeWide*": 0.8}, "WR": {"eyeWideRight": 0.8}, "WL": {"eyeWideLeft": 0.8},
    "SB": {"eyeSquint*": 0.6, "eyeBlink*": 0.25}, "SR": {"eyeSquintRight": 0.6, "eyeBlinkRight": 0.25},
    "SL": {"eyeSquintLeft": 0.6, "eyeBlinkLeft": 0.25},
    "CB": {"eyeBlink*": 1.0}, "CR": {"eyeBlinkRight": 1.0}, "CL": {"eyeBlinkLeft": 1.0},
    "TB": {"eyeBlink*": 1.0, "eyeSquint*": 0.8, "cheekSquint*": 0.4},
}  # fmt: skip
#: HamNoSys nose codes → morph weights.
NOSE: dict[str, dict[str, float]] = {
    "WR": {"noseSneer*": 0.7}, "TW": {"noseSneer*": 0.4}, "WI": {"noseSneer*": 0.25, "mouthUpperUp*": 0.05},
}  # fmt: skip
#: Mouth-gesture families (the code's first letter) → (what the family moves, morph weights).
MOUTH_GESTURE_FAMILIES: dict[str, tuple[str, dict[str, float]]] = {
    "C": ("cheeks puffed", {"cheekPuff": 0.8, "mouthClose": 0.1}),
    "L": ("lips pursed", {"mouthPucker": 0.6, "mouthFunnel": 0.2}),
    "T": ("tongue shown", {"tongueOut": 0.6, "jawOpen": 0.15}),
    "J": ("jaw lowered", {"jawOpen": 0.35}),
    "D": ("teeth bared", {"mouthUpperUp*": 0.4, "mouthLowerDown*": 0.35, "mouthStretch*": 0.2}),
}
#: The eyelid code that is a blink, not a held posture.
BLINK_CODE = "BB"


class UnknownExpression(ValueError):
    """A face lexeme or HamNoSys facial code that no table knows."""


@dataclass(frozen=True, eq=False)
class FaceExpressionLMP:
    """Morph weights ``vector (52,)`` times an envelope: a held facial expression.

    Sampling gives ``(n, len(columns))``, the weights of the columns the vector moves.
    """

    envelope: Envelope
    vector: np.ndarray
    label: str = ""
    channel: tuple[str, str] = ("face", "expression")

    @property
    def columns(self) -> np.ndarray:
        return np.flatnonzero(self.vector)

    @property
    def start(self) -> float:
        return self.envelope.start

    @property
    def end(self) -> float:
        return self.envelope.end

    def sample(self, times: np.ndarray) -> np.ndarray:
        return self.envelope.sample(times)[:, None] * self.vector[self.columns][None, :]


def face_lexeme(name: str, start: float, end: float, amount: float = 1.0, attack: float = 0.2, release: float = 0.3,
                manner: str = "targetted") -> FaceExpressionLMP:  # fmt: skip
    """The expression ``name`` (:data:`FACE_LEXEMES`, case-insensitive) at ``amount``
    (0–1) held from ``start`` to ``end`` seconds, rising over ``attack`` seconds before
    ``start`` and fading over ``release`` after ``end``. Raises :class:`UnknownExpression`."""
    key = name.strip().upper()
    if key not in FACE_LEXEMES:
        raise UnknownExpression(f"unknown face lexeme {name!r} (known: {', '.join(sorted(FACE_LEXEMES))})")
    return expression(FACE_LEXEMES[key], Envelope.around(start, end, attack, release, manner), amount, key)


def expression(weights: dict[str, float], envelope: Envelope, amount: float = 1.0, label: str = "") -> FaceExpressionLMP:
    """Morph ``weights`` scaled by ``amount`` (clipped to 0–1) under ``envelope``."""
    if not np.isfinite(amount):
        raise ValueError(f"expression amount must be finite, got {amount}")
    return FaceExpressionLMP(envelope, np.clip(face_vector(weights) * float(amount), 0.0, 1.0), label)


def hamnosys_face(tier: str, code: str) -> tuple[dict[str, float], str | None]:
    """Morph weights of a HamNoSys facial code in ``tier`` (``eyebrows``, ``eyelids``,
    ``nose``, ``mouthgesture``) and a note when it is realized approximately. Raises
    :class:`UnknownExpression` naming the tier, the code and the known codes."""
    code = code.strip().upper()
    tables = {"eyebrows": EYEBROWS, "eyelids": EYELIDS, "nose": NOSE}
    if tier in tables:
        if code not in tables[tier]:
            known = ", ".join(sorted(tables[tier]) + ([BLINK_CODE] if tier == "eyelids" else []))
            raise UnknownExpression(f"unknown {tier} code {code!r} (known: {known})")
        return tables[tier][code], None
    if tier == "mouthgesture":
        family = MOUTH_GESTURE_FAMILIES.get(code[:1])
        if family is None or not code[1:].isdigit():
            raise UnknownExpression(f"unknown mouth gesture {code!r} (expected a family letter {', '.join(MOUTH_GESTURE_FAMILIES)} and a number, e.g. C01)")
        return family[1], f"mouth gesture {code} realized by its family: {family[0]}"
    raise UnknownExpression(f"no facial tier {tier!r}")
