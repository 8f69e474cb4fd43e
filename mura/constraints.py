"""The constraint tree of a gesture or sign: feature slots and how their values combine.

Leaves are ``static`` (a slot holds a value) and ``dynamic`` (a slot moves through
segments); nodes are ``parallel``, ``sequence``, ``symmetrical`` and ``repetition``
(seed 004, section 3). MURML gestures and HamNoSys/SiGML signs both parse into it.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from enum import Enum
from typing import Union

from mura.errors import SourceLocation
from mura.values import Direction, SlotValue

#: Slots that a static or dynamic constraint may name; arm slots are realized by ``motor/``.
ARM_SLOTS: tuple[str, ...] = ("HandShape", "PalmOrientation", "ExtFingerOrientation", "HandLocation")
#: Slots kept in the model though no arm realizes them.
OTHER_SLOTS: tuple[str, ...] = ("GazeDirection", "Neck", "HeadDirection", "FaceExpression", "Mouth", "Shoulders", "Torso")


class Arm(Enum):
    """Which arm a constraint belongs to."""

    RIGHT = "right_arm"
    LEFT = "left_arm"

    @property
    def other(self) -> Arm:
        return Arm.LEFT if self is Arm.RIGHT else Arm.RIGHT

    @property
    def side(self) -> str:
        """``"right"`` or ``"left"``, the prefix side of the arm's joints (``r_``, ``l_``)."""
        return "right" if self is Arm.RIGHT else "left"


@dataclass(frozen=True)
class Symmetry:
    """Mirror symmetry of the non-dominant hand (MURML ``Sym``, ``SymMS``, ``SymMST`` …).

    ``planes`` holds the mirror planes: ``S`` sagittal (left–right), ``T`` transversal
    (up–down), ``F`` frontal (front–back). Plain ``Sym`` names no plane; mura reads it as
    the sagittal mirror, the symmetry of almost every two-handed gesture. ``alternating``
    makes the hands take turns (HamNoSys ``hamalternatingmotion`` after the operator).
    """

    planes: frozenset[str]
    name: str
    alternating: bool = False

    @property
    def mirrors_sagittal(self) -> bool:
        return "S" in self.planes


class SegmentKind(Enum):
    """Guiding-stroke shapes of a dynamic constraint."""

    LINEAR = "linear"
    CURVE = "curve"
    CIRCLE = "circle"


@dataclass(frozen=True)
class Segment:
    """One submovement of a dynamic constraint (MURML ``segment`` / ``dynamicElement``).

    For ``HandLocation`` the fields describe a path: a start and an end location, or a
    start, a direction and a distance (metres); curves add the normal of their plane, a
    shape (``LeftC``, ``RightC``, ``LeftS``, ``RightS``), an extent (bulge relative to the
    chord), roundness and skewedness in [-1, 1]. For other slots only ``start`` and ``end``
    are used, as the values to move between.

    Signs add the HamNoSys qualities of the movement: ``manner`` (``targetted`` by
    default for signs, ``fast``, ``slow``, ``tense``, ``rest``, ``halt``), ``size``
    (``small``, ``large``, ``increasing``, ``decreasing``) and ``modifiers``, further
    qualifiers as ``key`` or ``key=value`` strings (see :mod:`mura.signs`).
    """

    kind: SegmentKind
    start: SlotValue | None = None
    end: SlotValue | None = None
    direction: Direction | None = None
    distance: float | None = None
    normal: Direction | None = None
    shape: str | None = None
    extent: float | None = None
    roundness: float | None = None
    skewedness: float | None = None
    where: SourceLocation | None = field(default=None, compare=False)
    manner: str | None = None
    size: str | None = None
    modifiers: tuple[str, ...] = ()


@dataclass(frozen=True)
class Static:
    """A feature held for the stroke: ``slot`` keeps ``value``."""

    slot: str
    value: SlotValue
    scope: Arm | str | None = None
    mode: str | None = None
    where: SourceLocation | None = field(default=None, compare=False)


@dataclass(frozen=True)
class KeyFrame:
    """One frame of a keyframed movement (published MURML ``<frame ftime>``).

    ``time`` is seconds from the start of the keyframing (phases laid end to end);
    ``joints`` holds ``(name, values)`` as written in the ``<posture>``: a joint or morph
    name (H-Anim joints such as ``vc4``, ``r_shoulder``; morph targets such as
    ``dB_Smile``) and its degrees of freedom — three are roll, pitch and yaw in degrees
    for a joint, as the published realizer reads them.
    """

    time: float
    joints: tuple[tuple[str, tuple[float, ...]], ...]


@dataclass(frozen=True)
class Keyframing:
    """A keyframed movement of named joints (published MURML ``<keyframing>``).

    ``mode`` is the interpolation (``spline``, ``linear``, ``squad``, ``quaternion``,
    ``raw``); ``easescale`` and ``easeturningpoint`` shape the ease in and out;
    ``start_frame`` says whether the current posture is inserted as a first frame.
    """

    frames: tuple[KeyFrame, ...]
    mode: str = "spline"
    easescale: float = 1.0
    easeturningpoint: float = 0.5
    start_frame: bool = True


@dataclass(frozen=True)
class Dynamic:
    """A feature performing a significant submovement: ``slot`` follows ``segments``
    (and, for keyframed movements, ``keyframes``)."""

    slot: str
    segments: tuple[Segment, ...]
    scope: Arm | str | None = None
    where: SourceLocation | None = field(default=None, compare=False)
    keyframes: Keyframing | None = None


@dataclass(frozen=True)
class Parallel:
    """Constraints that hold at the same time."""

    children: tuple[Constraint, ...]
    where: SourceLocation | None = field(default=None, compare=False)


@dataclass(frozen=True)
class Sequence:
    """Constraints that follow one another."""

    children: tuple[Constraint, ...]
    where: SourceLocation | None = field(default=None, compare=False)


@dataclass(frozen=True)
class Symmetrical:
    """The dominant arm's constraints, mirrored onto the other arm.

    ``center`` is the spec's optional symmetry center, kept as written (spec units).
    """

    child: Constraint
    dominant: Arm
    symmetry: Symmetry
    center: tuple[float, ...] | None = None
    where: SourceLocation | None = field(default=None, compare=False)


@dataclass(frozen=True)
class Repetition:
    """A constraint performed ``count`` times in a row (``count`` ≥ 2).

    ``mode`` says where each repetition starts (HamNoSys): ``fromstart`` (back to the
    initial posture), ``continue`` (on from where the last one ended) or ``reverse``
    (back along the same path); ``alternating`` makes the two hands take turns.
    ``displacement`` is a straight movement that shifts every pass after the first by
    its direction and size once more (HamNoSys ``( move repeat move )``: a repetition
    with displacement, such as shelves stacked downwards), None for repetition in place.
    """

    child: Constraint
    count: int = 2
    where: SourceLocation | None = field(default=None, compare=False)
    mode: str = "fromstart"
    alternating: bool = False
    displacement: Segment | None = None


Constraint = Union[Static, Dynamic, Parallel, Sequence, Symmetrical, Repetition]


def iter_leaves(node: Constraint) -> Iterator[Static | Dynamic]:
    """Every ``static`` and ``dynamic`` leaf of a constraint tree, in document order."""
    if isinstance(node, (Static, Dynamic)):
        yield node
    elif isinstance(node, (Parallel, Sequence)):
        for child in node.children:
            yield from iter_leaves(child)
    else:
        yield from iter_leaves(node.child)


