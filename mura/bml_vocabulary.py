"""The BML 1.0 vocabulary mura reads: namespaces, behaviour elements with their sync points
and attributes, what mura does with each, gesture lexemes and modes (see :mod:`mura.bml`)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from mura.constraints import Arm

BML_NAMESPACE = "http://www.bml-initiative.org/bml/bml-1.0"
#: The namespace AsapRealizer reads embedded MURML gestures in (``<murmlgesture>``).
MURML_NAMESPACE = "http://www.techfak.uni-bielefeld.de/ags/soa/murml"
COMPOSITIONS = ("MERGE", "APPEND", "REPLACE")

GESTURE_SYNC = ("start", "ready", "strokeStart", "stroke", "strokeEnd", "relax", "end")
FACE_SYNC = ("start", "attackPeak", "relax", "end")
HOLD_SYNC = ("start", "ready", "relax", "end")
SHIFT_SYNC = ("start", "end")


@dataclass(frozen=True)
class BehaviorType:
    """A BML behaviour element: its sync points, its own attributes (besides ``id`` and
    the sync points) and what mura does with it: ``performed``, ``timed`` (timed, listed
    and warned about, no motor module performs it yet) or ``unsupported`` (left out)."""

    sync: tuple[str, ...]
    attributes: frozenset[str]
    support: str


BEHAVIORS: Mapping[str, BehaviorType] = {
    "speech": BehaviorType(SHIFT_SYNC, frozenset(), "performed"),
    "gesture": BehaviorType(GESTURE_SYNC, frozenset({"lexeme", "mode", "target"}), "performed"),
    "pointing": BehaviorType(GESTURE_SYNC, frozenset({"target", "mode"}), "performed"),
    "murmlgesture": BehaviorType(GESTURE_SYNC, frozenset({"scope"}), "performed"),
    "head": BehaviorType(GESTURE_SYNC, frozenset({"lexeme", "repetition", "amount"}), "performed"),
    "headDirectionShift": BehaviorType(SHIFT_SYNC, frozenset({"target"}), "timed"),
    "gaze": BehaviorType(HOLD_SYNC, frozenset({"target", "influence", "offsetAngle", "offsetDirection"}), "performed"),
    "gazeShift": BehaviorType(SHIFT_SYNC, frozenset({"target", "influence", "offsetAngle", "offsetDirection"}), "timed"),
    "faceLexeme": BehaviorType(FACE_SYNC, frozenset({"lexeme", "amount"}), "performed"),
    "faceFacs": BehaviorType(FACE_SYNC, frozenset({"au", "side", "amount"}), "timed"),
    "faceShift": BehaviorType(SHIFT_SYNC, frozenset({"lexeme", "amount"}), "timed"),
    "posture": BehaviorType(HOLD_SYNC, frozenset(), "timed"),
    "postureShift": BehaviorType(SHIFT_SYNC, frozenset(), "timed"),
    "locomotion": BehaviorType(SHIFT_SYNC, frozenset({"target", "manner"}), "unsupported"),
}

#: BML gesture lexemes and the lexicon functions that perform them; any other lexeme is
#: looked up as a lexicon function of the same name in lower case (``SHOW_SIZE``).
GESTURE_LEXEMES: Mapping[str, str] = {
    "BEAT": "emphasize",
    "POINT": "refer_to_loc",
    "SIZE": "show_size",
    "OFFER": "present",
    "NEGATE": "negate",
}
#: BML gesture modes and the arm mura gives the gesture (``None``: both hands, mirrored).
MODES: Mapping[str, Arm | None] = {"RIGHT_HAND": Arm.RIGHT, "LEFT_HAND": Arm.LEFT, "BOTH_HANDS": None}
HEAD_LEXEMES = ("NOD", "SHAKE", "TILT")
GAZE_INFLUENCES = ("EYES", "HEAD", "SHOULDER", "WAIST", "WHOLE")
