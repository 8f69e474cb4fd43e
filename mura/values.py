"""Feature values shared by MURML gestures and HamNoSys/SiGML signs.

Both spec languages describe a hand by the same features — hand shape, extended-finger
direction, palm orientation, location and movement — so both parse into these values and
the motor core realizes them without knowing which language they came from. Values are
symbolic here (names and unit direction vectors); ``motor/`` turns them into numbers for a
particular avatar.

Directions use the avatar frame: +x is the avatar's left, +y up, +z forward (away from
the body). Distances are metres.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Union

import numpy as np

#: The twelve basic hand shapes of HamNoSys, by their SiGML names without the ``ham`` prefix.
BASIC_HANDSHAPES: tuple[str, ...] = (
    "fist",
    "flathand",
    "finger2",
    "finger23",
    "finger23spread",
    "finger2345",
    "pinch12",
    "pinchall",
    "pinch12open",
    "cee12",
    "ceeall",
    "ceeopen",
)

#: Digits of the hand, thumb first (HamNoSys numbers them 1 to 5).
FINGERS: tuple[str, ...] = ("thumb", "index", "middle", "ring", "pinky")

#: Finger bendings as proportions of maximum bend of the (base, middle, end) joints (seed 000).
FINGER_BENDINGS: dict[str, tuple[float, float, float]] = {
    "straight": (0.0, 0.0, 0.0),
    "bent": (1.0, 0.0, 0.0),
    "round": (0.5, 0.5, 0.5),
    "hooked": (0.0, 1.0, 1.0),
    "dblbent": (1.0, 1.0, 0.0),
    "dblhooked": (1.0, 1.0, 1.0),
    "halfbent": (0.5, 0.0, 0.0),
}

#: Thumb modifiers: splayed out, folded across the palm, opposed (open).
THUMB_POSITIONS: tuple[str, ...] = ("out", "across", "open")

#: The gap between thumb and fingers in cee and pinch shapes.
OPENINGS: tuple[str, ...] = ("narrow", "normal", "wide")

#: Unit axes of the six basic directions: up, down, left, right, out (away), in (towards).
AXES: dict[str, tuple[float, float, float]] = {
    "u": (0.0, 1.0, 0.0),
    "d": (0.0, -1.0, 0.0),
    "l": (1.0, 0.0, 0.0),
    "r": (-1.0, 0.0, 0.0),
    "o": (0.0, 0.0, 1.0),
    "i": (0.0, 0.0, -1.0),
}


def direction_from_letters(letters: str) -> tuple[float, float, float]:
    """Unit vector of a compound direction such as ``"ul"`` or ``"do"``.

    Raises ValueError for an unknown letter or letters that cancel out (``"ud"``).
    """
    if not letters:
        raise ValueError("empty direction")
    total = np.zeros(3)
    for letter in letters:
        if letter not in AXES:
            raise ValueError(f"unknown direction letter {letter!r} in {letters!r}")
        total += AXES[letter]
    norm = float(np.linalg.norm(total))
    if norm < 1e-9:
        raise ValueError(f"direction {letters!r} has zero length")
    unit = total / norm
    return (float(unit[0]), float(unit[1]), float(unit[2]))


@dataclass(frozen=True)
class FingerBend:
    """A bending given to particular fingers, overriding the basic shape's."""

    fingers: tuple[str, ...]
    bending: str


@dataclass(frozen=True)
class HandShape:
    """A hand shape as HamNoSys describes it: a basic shape and its modifiers.

    Attributes:
        basic: one of :data:`BASIC_HANDSHAPES`.
        thumb: one of :data:`THUMB_POSITIONS`, or None for the basic shape's default.
        bending: a :data:`FINGER_BENDINGS` key for all extended fingers, or None.
        finger_bends: bendings of named fingers, applied after ``bending``.
        extended: fingers that replace the basic shape's extended fingers, or None.
        opening: one of :data:`OPENINGS` for cee and pinch shapes, or None.
        between: a second shape; the hand takes the shape halfway between the two.
        name: the symbol as written in the spec, for messages.
        contact: a contact between digits inside the shape, as HamNoSys writes it: the
            fingers, the site and the partner fingers, e.g. ``("index", "fingernail",
            "middle")``, or ``("middle", "between", "ring")`` for the thumb between two
            fingers; empty when none.
    """

    basic: str
    thumb: str | None = None
    bending: str | None = None
    finger_bends: tuple[FingerBend, ...] = ()
    extended: tuple[str, ...] | None = None
    opening: str | None = None
    between: HandShape | None = None
    name: str = ""
    contact: tuple[str, ...] = ()


@dataclass(frozen=True)
class Direction:
    """A direction in the avatar frame: a unit vector and the name it was written as."""

    vector: tuple[float, float, float]
    name: str = ""


@dataclass(frozen=True)
class PalmOrientation:
    """Which way the palm faces.

    ``direction`` is the nominal palm normal (unit vector, avatar frame). HamNoSys palm
    orientations are read relative to the extended-finger direction: the motor core keeps
    the component of ``direction`` perpendicular to the fingers. ``relative`` marks
    HamNoSys's relative form (``hamorirelative``), where the palm turns with the
    extended-finger direction.
    """

    direction: tuple[float, float, float]
    name: str = ""
    relative: bool = False


@dataclass(frozen=True)
class GridLocation:
    """A point of the MURML/ACE signing-space grid, e.g. ``LocShoulder LocCenterRight LocNorm``.

    The names are canonical keys of the grid vocabulary (height, lateral position,
    distance from the body); the avatar gives them coordinates.
    """

    height: str
    lateral: str
    distance: str


@dataclass(frozen=True)
class PointLocation:
    """An explicit position, metres, in the avatar frame relative to its root joint."""

    position: tuple[float, float, float]


@dataclass(frozen=True)
class BodySite:
    """A HamNoSys location on or near the body or the other hand.

    Attributes:
        site: a body or hand site name (``chest``, ``nose``, ``palm``, ``fingertip`` …).
        side: ``lrat`` (at the hand's side of the site), ``lrbeside`` (beside it), or None.
        proximity: ``touch``, ``close``, ``near``, ``far`` … distance from the site, or None
            for the default distance.
        finger: for hand sites, which finger (:data:`FINGERS`), or None.
        hand_part: the part of the moving hand that is at the site (HamNoSys 4's contact
            bracket ``site [touch thumb fingertip]``, gestural SiGML's ``<location_hand>``
            inside ``<location_bodyarm>``), or None for the hand as a whole.
    """

    site: str
    side: str | None = None
    proximity: str | None = None
    finger: str | None = None
    hand_part: BodySite | None = None


@dataclass(frozen=True)
class BetweenLocation:
    """The midpoint (or a given fraction) between two locations."""

    first: Location
    second: Location
    fraction: float = 0.5


Location = Union[GridLocation, PointLocation, BodySite, BetweenLocation]


@dataclass(frozen=True)
class Vector:
    """A raw numeric vector a slot takes as is (e.g. a gaze target), in spec units."""

    values: tuple[float, ...]


@dataclass(frozen=True)
class Symbol:
    """A name a head or face slot takes as written: a head lexeme (``Nod``), a gaze target
    (``Listener``, ``RightHand``), a face lexeme (``Smile``), a HamNoSys non-manual code
    (``UB``) or a SAMPA mouth picture (``hVlU``); ``motor/`` reads it."""

    name: str


SlotValue = Union[HandShape, Direction, PalmOrientation, GridLocation, PointLocation, BodySite, BetweenLocation, Vector, Symbol]
