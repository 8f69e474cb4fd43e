"""The symbolic names MURML writes, and the HamNoSys features they stand for.

MURML borrows its vocabulary from HamNoSys (seed 004, section 3): hand shapes (``BSflat``,
``ASLb`` with modifiers such as ``(FBround all o)(ThCpart o)``), directions (``DirA``,
``DirUL``), palm orientations (``PalmL``) and the ACE signing-space grid
(``LocShoulder LocCenterRight LocNorm``). This module maps each name to the shared values
of :mod:`mura.values`, so that the motor core sees one vocabulary for gestures and signs.

The grid names are those of the published MURML symbol table (``billie_hns.xml``), plus
``LocCenter``, which published utterances write for ``LocCCenter``. Every avatar gives
those *core* names coordinates. A :class:`SymbolTable` adds names beyond them — a few
built in (:data:`EXTRA_HEIGHTS`: ``LocBelowHip`` …) and any a published symbol table
(``<hns>`` file, read by :mod:`mura.lexicon`) lists, each by its published value in cm:
such a location is read as the point on the line through the two nearest core names of
its axis, at the published value (a :class:`~mura.values.BetweenLocation` whose fraction
may lie outside [0, 1]), so it scales with the avatar as the core names do.

Locations are read as the published realizer reads them: a height, then optionally a
lateral position (``LocCCenter`` when left out) and a distance (``LocNorm`` when left
out), in any order; a palm orientation may also be a single number, the published
table's roll angle in degrees (``PalmR`` 0, ``PalmD`` 90, ``PalmL`` 180, ``PalmU`` -90).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

from mura.values import (
    BetweenLocation,
    Direction,
    FingerBend,
    GridLocation,
    HandShape,
    Location,
    PalmOrientation,
    direction_from_letters,
)

#: Heights of the grid, bottom to top, with their published heights in cm above the hip.
GRID_HEIGHTS: dict[str, float] = {
    "LocHip": 0.0,
    "LocLowerStomach": 5.0,
    "LocStomach": 8.0,
    "LocUpperStomach": 10.0,
    "LocAbdomen": 15.0,
    "LocLowerChest": 20.0,
    "LocChest": 25.0,
    "LocUpperChest": 30.0,
    "LocShoulder": 35.0,
    "LocNeck": 40.0,
    "LocLowerChin": 42.0,
    "LocChin": 44.0,
    "LocMouth": 46.0,
    "LocNose": 48.0,
    "LocEyes": 50.0,
    "LocForeHead": 52.0,
    "LocHead": 54.0,
    "LocAboveHead": 60.0,
}

#: Lateral positions with their published offsets in cm, positive to the avatar's left.
GRID_LATERALS: dict[str, float] = {
    "LocCCenter": 0.0,
    "LocCCenterLeft": 15.0,
    "LocCenterLeft": 25.0,
    "LocCenterLLeft": 30.0,
    "LocPeripheryLeft": 35.0,
    "LocExtremePeripheryLeft": 45.0,
    "LocLeft": 55.0,
    "LocCCenterRight": -15.0,
    "LocCenterRight": -25.0,
    "LocCenterRRight": -30.0,
    "LocPeripheryRight": -35.0,
    "LocExtremePeripheryRight": -45.0,
    "LocRight": -54.0,
}

#: Distances from the body with their published values in cm.
GRID_DISTANCES: dict[str, float] = {
    "LocContact": 10.0,
    "LocNear": 15.0,
    "LocNorm": 20.0,
    "LocFar": 25.0,
    "LocFFar": 30.0,
    "LocStreched": 40.0,
}

#: Spellings found in published utterances for canonical grid names.
GRID_ALIASES: dict[str, str] = {
    "LocCenter": "LocCCenter",
    "LocStretched": "LocStreched",
    "LocForehead": "LocForeHead",
}

#: Heights beyond the core grid, cm above the hip, as published tables name them
#: (mura's estimates where no published value is at hand: a hand's width below the hip).
EXTRA_HEIGHTS: dict[str, float] = {"LocBelowHip": -10.0}

#: Movement distances of the symbol table, metres.
DISTANCES: dict[str, float] = {"DistShort": 0.10, "DistNorm": 0.20, "DistFar": 0.30, "DistFFar": 0.40}

#: The grid's axes: (name, core table, default name when a location leaves the axis out).
_AXES: tuple[tuple[str, Mapping[str, float], str | None], ...] = (
    ("height", GRID_HEIGHTS, None),
    ("lateral", GRID_LATERALS, "LocCCenter"),
    ("distance", GRID_DISTANCES, "LocNorm"),
)


@dataclass(frozen=True)
class SymbolTable:
    """Names of a MURML symbol table beyond the core vocabulary.

    ``heights``, ``laterals`` and ``distances`` map grid names to their published values
    (cm, as in the core tables); ``movement_distances`` map ``Dist…`` names to metres;
    ``palm_angles`` map palm-orientation names to roll angles in degrees. Core names listed
    again keep their core meaning (the avatar's grid gives them coordinates).
    """

    heights: Mapping[str, float] = field(default_factory=lambda: MappingProxyType({}))
    laterals: Mapping[str, float] = field(default_factory=lambda: MappingProxyType({}))
    distances: Mapping[str, float] = field(default_factory=lambda: MappingProxyType({}))
    movement_distances: Mapping[str, float] = field(default_factory=lambda: MappingProxyType({}))
    palm_angles: Mapping[str, float] = field(default_factory=lambda: MappingProxyType({}))

    def merged(self, other: SymbolTable) -> SymbolTable:
        """This table with ``other``'s names added (``other`` wins where both name one)."""
        return SymbolTable(
            MappingProxyType({**self.heights, **other.heights}),
            MappingProxyType({**self.laterals, **other.laterals}),
            MappingProxyType({**self.distances, **other.distances}),
            MappingProxyType({**self.movement_distances, **other.movement_distances}),
            MappingProxyType({**self.palm_angles, **other.palm_angles}),
        )

    def axis(self, index: int) -> Mapping[str, float]:
        return (self.heights, self.laterals, self.distances)[index]

    def movement_distance(self, name: str) -> float | None:
        """A ``Dist…`` name in metres, None when neither table knows it."""
        return DISTANCES.get(name, self.movement_distances.get(name))


#: The table of the built-in names beyond the core.
DEFAULT_SYMBOLS = SymbolTable(heights=MappingProxyType(dict(EXTRA_HEIGHTS)))

#: Curve shapes: the side the curve bulges to, and whether it is an S (two bulges).
CURVE_SHAPES: tuple[str, ...] = ("LeftC", "RightC", "LeftS", "RightS")

#: MURML direction letters and the HamNoSys axes they name (A ahead = out, T towards = in).
_MURML_DIRECTION_LETTERS: dict[str, str] = {"U": "u", "D": "d", "L": "l", "R": "r", "A": "o", "T": "i", "B": "i"}

#: Basic hand shapes by MURML name: (basic shape, thumb, default bending, extended fingers, opening).
_BASIC_SHAPES: dict[str, tuple[str, str | None, str | None, tuple[str, ...] | None, str | None]] = {
    "BSfist": ("fist", None, None, None, None),
    "BSflat": ("flathand", None, None, None, None),
    "BSflatc": ("flathand", "across", None, None, None),
    "BSflato": ("flathand", "out", None, None, None),
    "BSifinger": ("finger2", None, None, None, None),
    "BSpoint": ("finger2", None, None, None, None),
    "BSimcfinger": ("finger23", None, None, None, None),
    "BSimofinger": ("finger23spread", None, None, None, None),
    "BSffinger": ("finger2345", None, None, None, None),
    "BSneutral": ("flathand", None, "halfbent", None, None),
    "BSdfistc": ("fist", "across", None, None, None),
    "BSdfisto": ("fist", "out", None, None, None),
    "BSdflatc": ("flathand", "across", None, None, None),
    "BSdflato": ("flathand", "out", None, None, None),
    "BSdifingerc": ("finger2", "across", None, None, None),
    "BSdifingero": ("finger2", "out", None, None, None),
    "ASL2": ("finger23spread", "across", None, None, None),
    "ASL5": ("finger2345", "out", None, None, None),
    "ASLa": ("fist", None, None, None, None),
    "ASLb": ("flathand", "across", None, None, None),
    "ASLc": ("ceeall", None, None, None, None),
    "ASLcsmall": ("ceeall", None, None, None, "narrow"),
    "ASLclarge": ("ceeall", None, None, None, "wide"),
    "ASLg": ("finger2", "out", None, None, None),
    "ASLo": ("pinchall", None, None, None, None),
    "ASLy": ("finger2", "out", None, ("pinky",), None),
    "ASLgrasp": ("ceeall", None, None, None, "wide"),
}

#: Finger-bending modifier stems and the HamNoSys bendings they name.
_FINGER_BENDINGS: dict[str, str] = {
    "str": "straight",
    "stiff": "straight",
    "angle": "bent",
    "round": "round",
    "bent": "hooked",
    "roll": "dblhooked",
    "rol": "dblhooked",
}

#: Finger selectors of modifiers: digits (HamNoSys numbering) and the table's letters.
_FINGER_SELECTORS: dict[str, tuple[str, ...]] = {
    "all": ("index", "middle", "ring", "pinky"),
    "1": ("thumb",),
    "2": ("index",),
    "3": ("middle",),
    "4": ("ring",),
    "5": ("pinky",),
    "t": ("thumb",),
    "p": ("index",),
    "m": ("middle",),
    "r": ("ring",),
    "l": ("pinky",),
}

#: Thumb modifiers: ThExt splayed out, ThAcr folded across, ThCpart opposed to the fingers.
_THUMB_MODIFIERS: dict[str, str | None] = {
    "ThExt": "out",
    "ThAcr": "across",
    "ThCpart": "open",
    "ThNorm": None,
    "ThDown": "across",
}

#: Opening parameters: c closed, no normally open, o open, wo wide open.
_OPENINGS: dict[str, str] = {"c": "narrow", "no": "normal", "o": "normal", "wo": "wide"}
_OPENING_SYMBOLS: dict[str, str] = {"OpNorm": "normal", "OpWide": "wide", "OpNarrow": "narrow"}

_MODIFIER = re.compile(r"\(([^()]*)\)")
_HANDSHAPE = re.compile(r"^\s*([A-Za-z0-9]+)\s*((?:\([^()]*\)\s*)*)$")


def parse_direction(name: str) -> Direction:
    """A MURML direction name (``DirA``, ``DirUL``, ``DirDA``) as a unit vector.

    Raises ValueError with the reason for anything else.
    """
    if not name.startswith("Dir") or len(name) <= 3:
        raise ValueError(f"unknown direction {name!r} (expected Dir followed by U, D, L, R, A or T)")
    letters = ""
    for letter in name[3:]:
        if letter not in _MURML_DIRECTION_LETTERS:
            raise ValueError(f"unknown direction {name!r}: letter {letter!r} is not one of U, D, L, R, A, T")
        letters += _MURML_DIRECTION_LETTERS[letter]
    return Direction(direction_from_letters(letters), name)


def parse_palm_orientation(name: str, symbols: SymbolTable = DEFAULT_SYMBOLS) -> PalmOrientation:
    """A palm orientation: ``PalmL``, ``PalmLU`` …, a direction name such as ``DirR``, a
    name of the symbol table, or a roll angle in degrees (``"90"`` is ``PalmD``)."""
    if name in symbols.palm_angles:
        return palm_from_angle(symbols.palm_angles[name], name)
    if name.startswith("Palm") and len(name) > 4:
        letters = name[4:]
        try:
            return PalmOrientation(parse_direction("Dir" + letters).vector, name)
        except ValueError:
            raise ValueError(f"unknown palm orientation {name!r} (expected Palm followed by U, D, L, R, A or T)") from None
    if name.startswith("Dir"):
        return PalmOrientation(parse_direction(name).vector, name)
    try:
        angle = float(name)
    except ValueError:
        angle = math.nan
    if math.isfinite(angle):
        return palm_from_angle(angle, name)
    raise ValueError(f"unknown palm orientation {name!r} (expected PalmL, PalmU, …, a Dir… name or an angle in degrees)")


def palm_from_angle(degrees: float, name: str) -> PalmOrientation:
    """The palm normal of the published table's roll angle: 0 faces right, 90 down,
    180 left, -90 up (avatar frame, +x left, +y up)."""
    radians = math.radians(degrees)
    return PalmOrientation((-math.cos(radians), -math.sin(radians), 0.0), name)


def parse_grid_location(text: str, symbols: SymbolTable = DEFAULT_SYMBOLS) -> Location:
    """A grid location ``"LocShoulder LocCenterRight LocNorm"`` (height, lateral, distance).

    The names may come in any order, each on its own axis; the lateral position
    (``LocCCenter``) and the distance (``LocNorm``) may be left out, as the published
    realizer reads them. A name of ``symbols`` beyond the core grid makes the location a
    :class:`~mura.values.BetweenLocation` of core ones (module docstring).
    """
    names = text.split()
    if not 1 <= len(names) <= 3:
        raise ValueError(f"location {text!r} needs a height, a lateral position and a distance (three names at most)")
    chosen: list[str | None] = [None, None, None]
    for raw in names:
        name = GRID_ALIASES.get(raw, raw)
        axes = [i for i, (_, core, _) in enumerate(_AXES) if name in core or name in symbols.axis(i)]
        if not axes:
            raise ValueError(f"unknown location name {raw!r} in {text!r}")
        if chosen[axes[0]] is not None:
            raise ValueError(f"location {text!r} names two values on the same axis ({raw!r})")
        chosen[axes[0]] = name
    if chosen[0] is None:
        raise ValueError(f"location {text!r} names no height (LocHip … LocAboveHead)")
    resolved = [name if name is not None else _AXES[i][2] for i, name in enumerate(chosen)]
    return _grid_point(resolved, symbols)  # type: ignore[arg-type]


def _grid_point(names: list[str], symbols: SymbolTable) -> Location:
    """The grid point of core names, or a line through core points for an extra name."""
    for index, (_, core, _) in enumerate(_AXES):
        if names[index] in core:
            continue
        value = symbols.axis(index)[names[index]]
        near, far = sorted(core, key=lambda n: (abs(core[n] - value), n))[:2]
        if core[far] == core[near]:
            raise ValueError(f"cannot place {names[index]!r}: the core names {near!r} and {far!r} have the same value")
        fraction = (value - core[near]) / (core[far] - core[near])
        first = _grid_point([near if i == index else n for i, n in enumerate(names)], symbols)
        second = _grid_point([far if i == index else n for i, n in enumerate(names)], symbols)
        return BetweenLocation(first, second, fraction)
    return GridLocation(names[0], names[1], names[2])


def parse_handshape(text: str) -> HandShape:
    """A MURML hand shape: a basic shape name and parenthesized modifiers.

    ``"BSflat(FBround all o)(ThCpart o)"`` is the flat hand with all fingers rounded, the
    thumb opposed and the hand open. Modifiers: finger bendings ``FB<bend> <fingers> [opening]``
    or ``FB<digit><bend>``; thumbs ``Th…``; openings ``Op…``; spreading ``FAbd``/``FAdd``.
    """
    match = _HANDSHAPE.match(text)
    if match is None:
        raise ValueError(f"hand shape {text!r} is not a name followed by (modifiers)")
    name, modifier_text = match.group(1), match.group(2)
    if name not in _BASIC_SHAPES:
        raise ValueError(f"unknown hand shape {name!r}")
    basic, thumb, bending, extended, opening = _BASIC_SHAPES[name]
    finger_bends: list[FingerBend] = []
    for modifier in _MODIFIER.findall(modifier_text):
        words = modifier.split()
        if not words:
            raise ValueError(f"empty modifier () in hand shape {text!r}")
        head, params = words[0], words[1:]
        if head in _THUMB_MODIFIERS:
            thumb = _THUMB_MODIFIERS[head] or thumb
            opening = _opening_of(params, text) or opening
        elif head in _OPENING_SYMBOLS:
            opening = _OPENING_SYMBOLS[head]
        elif head.startswith("FB"):
            bend = _finger_bend(head, params, text)
            finger_bends.append(bend)
            opening = _opening_of(params[1:] if params and params[0] in _FINGER_SELECTORS else params, text) or opening
        elif head in ("FAbd", "FAdd"):
            basic = _spread(basic, head == "FAbd")
        else:
            raise ValueError(f"unknown hand-shape modifier {head!r} in {text!r}")
    return HandShape(
        basic=basic,
        thumb=thumb,
        bending=bending,
        finger_bends=tuple(finger_bends),
        extended=extended,
        opening=opening,
        name=text.strip(),
    )


def _finger_bend(head: str, params: list[str], text: str) -> FingerBend:
    stem = head[2:]
    fingers: tuple[str, ...] = _FINGER_SELECTORS["all"]
    if stem[:1].isdigit():
        fingers = _FINGER_SELECTORS[stem[0]] if stem[0] in "12345" else ()
        stem = stem[1:]
        if not fingers:
            raise ValueError(f"unknown finger {head[2]!r} in {head!r} of {text!r}")
    elif params and params[0] in _FINGER_SELECTORS:
        fingers = _FINGER_SELECTORS[params[0]]
    if stem not in _FINGER_BENDINGS:
        raise ValueError(f"unknown finger bending {head!r} in {text!r}")
    return FingerBend(fingers, _FINGER_BENDINGS[stem])


def _opening_of(params: list[str], text: str) -> str | None:
    if not params:
        return None
    if params[0] not in _OPENINGS:
        raise ValueError(f"unknown opening {params[0]!r} in {text!r} (expected c, no, o or wo)")
    return _OPENINGS[params[0]]


def _spread(basic: str, abducted: bool) -> str:
    spread = {"finger23": "finger23spread"}
    closed = {value: key for key, value in spread.items()}
    return (spread if abducted else closed).get(basic, basic)
