"""The model a sign parses into, whether written as HamNoSys, ``<hns_sign>`` or gestural SiGML.

A sign is an initial posture of one or both hands followed by a movement. The posture is
made of the same feature values MURML gestures use (:mod:`mura.values`); the movement is a
constraint tree of :mod:`mura.model` (``Sequence``, ``Parallel``, ``Repetition``,
``Static``, ``Dynamic``). The conventions a motor core needs to read that tree:

- **Scope.** A leaf with ``scope=None`` belongs to the dominant hand, and under a
  symmetry also to the other hand, mirrored. ``scope`` set to an :class:`~mura.model.Arm`
  names one hand only (the parts of ``hamparbegin … hamplus … hamparend``).
- **Path movements** are ``Dynamic("HandLocation", …)`` segments. Straight moves are
  ``LINEAR`` with a ``direction``; arcs, wavy and zigzag paths are ``CURVE`` with the
  chord ``direction`` and ``shape`` ``arcl``/``arcu``/``arcr``/``arcd``/``wavy``/``zigzag``
  (the side an arc bulges to; ``normal`` is the plane's normal when it is defined).
  Circles are ``CIRCLE`` with ``normal`` the circle's axis (the letters of ``hamcircle…``);
  clock positions and ellipses go into ``modifiers`` as ``start=…``, ``end=…`` (clock
  letters, ``full`` for a whole turn) and ``ellipse=h|v|ur|ul``. A movement with a target
  location has it in ``end``.
- **Local movements** keep the hand in place and move a joint: ``nodding`` and
  ``swinging`` (wrist flexion and side to side) on ``ExtFingerOrientation``, ``twisting``
  (forearm rotation) on ``PalmOrientation``, ``fingerplay`` on ``HandShape``, stirring
  (``stircw``/``stirccw``) a small ``CIRCLE`` on ``HandLocation``; ``nomotion``,
  ``movecross`` and ``moveX`` on ``HandLocation``. Each is one segment whose ``shape`` is
  the movement's name (without ``ham``).
- **Change of posture** (``hamreplace``) is a ``Parallel`` of one-segment ``Dynamic``
  leaves, one per changed feature, with ``start`` the posture before and ``end`` after.
- **Contact** reached during a movement is ``modifiers`` ``contact=touch`` (or ``close``,
  ``brushing`` …); a contact or location reached with no movement is a ``Static``
  ``HandLocation`` (a bare contact, such as ``hamtouch`` alone, is the pseudo-site
  ``BodySite("contact", proximity=…)``: touch whatever the hand moves towards).
- **Manner** of a segment is ``targetted`` unless the sign says ``fast``, ``slow``,
  ``tense``, ``rest`` or ``halt`` (sudden stop); ``size`` is ``small``, ``large``,
  ``increasing`` or ``decreasing``, None for normal.
- **Repetition** counts 2 (``hamrepeat…``) or 3 (``…several``), with its ``mode``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from mura.constraints import (
    Arm,
    Constraint,
    Parallel,
    Sequence,
    Static,
    Symmetrical,
    Symmetry,
)
from mura.errors import SourceLocation, SpecError
from mura.values import Direction, HandShape, Location, PalmOrientation

#: Symmetry kinds: left-right mirror and parallel (HamNoSys ``hamsymmlr``/``hamsymmpar``).
SYMMETRY_KINDS: tuple[str, ...] = ("lr", "par")


@dataclass(frozen=True)
class SignSymmetry:
    """How the non-dominant hand copies the dominant one.

    Attributes:
        kind: ``lr`` (mirrored left–right) or ``par`` (moving in parallel, unmirrored).
        planes: the mirror planes (``S`` sagittal = left–right, ``T`` transversal =
            up–down, ``F`` frontal = front–back); empty for parallel symmetry.
        alternating: the hands take turns (``hamalternatingmotion``, SiGML ``outofphase``).
        nonipsi: the non-dominant hand does not make its own contact (``hamnonipsi``).
        fingerplay: the hands' fingers play alternately (``hamfingerplay`` after the symmetry).
    """

    kind: str
    planes: frozenset[str] = frozenset()
    alternating: bool = False
    nonipsi: bool = False
    fingerplay: bool = False

    def to_model(self) -> Symmetry:
        """The symmetry as the shared model's :class:`~mura.model.Symmetry`."""
        if self.kind == "par":
            return Symmetry(frozenset(), "par", self.alternating)
        return Symmetry(self.planes, "Sym" + "".join(sorted(self.planes)), self.alternating)


@dataclass(frozen=True)
class HandPosture:
    """The posture of one hand: shape, orientation and location; None where unspecified.

    ``location`` carries side and contact (:class:`~mura.values.BodySite`). ``etc`` marks
    HamNoSys's ``hametc`` ("as before"/"unspecified") in the description.
    """

    shape: HandShape | None = None
    ext_finger: Direction | None = None
    palm: PalmOrientation | None = None
    location: Location | None = None
    etc: bool = False


@dataclass(frozen=True)
class HandConstellation:
    """Where the two hands are relative to each other.

    ``dominant`` and ``nondominant`` are the sites of each hand that face one another
    (hand or arm :class:`~mura.values.BodySite`, None for the hand as a whole);
    ``contact`` is ``touch``, ``close``, ``interlock``, ``cross`` … or None;
    ``location`` is where the pair of hands is, relative to the body, or None.
    """

    dominant: Location | None
    nondominant: Location | None
    contact: str | None = None
    location: Location | None = None


@dataclass(frozen=True)
class NonmanualItem:
    """One item of a nonmanual tier, kept as written (tag and attributes) and where it
    stands in its source; ``motor/`` reads the codes."""

    tag: str
    attributes: tuple[tuple[str, str], ...] = ()
    where: SourceLocation | None = field(default=None, compare=False)


@dataclass(frozen=True)
class Sign:
    """One sign: who signs with which hand, the initial posture and the movement.

    Attributes:
        gloss: the sign's name.
        dominant: the dominant arm (right unless the source says otherwise).
        two_handed: whether the non-dominant hand takes part.
        symmetry: how the non-dominant hand copies the dominant one, or None.
        posture: the dominant hand's initial posture.
        nondominant: the non-dominant hand's own initial posture, when given.
        constellation: the two hands' relative location, when given.
        movement: the movement as a constraint tree, None for a static sign.
        manner: the manner of a static sign's held posture (``tense`` …), or None.
        nonmanual: tier name → items, kept raw for the timeline.
        symbols: the manual stream's symbols as written (canonical names), for messages.
        where: where the sign starts in its source.
    """

    gloss: str
    posture: HandPosture
    dominant: Arm = Arm.RIGHT
    two_handed: bool = False
    symmetry: SignSymmetry | None = None
    nondominant: HandPosture | None = None
    constellation: HandConstellation | None = None
    movement: Constraint | None = None
    manner: str | None = None
    nonmanual: Mapping[str, tuple[NonmanualItem, ...]] = field(default_factory=dict, compare=False)
    symbols: tuple[str, ...] = ()
    where: SourceLocation | None = field(default=None, compare=False)


    def to_constraint(self) -> Constraint:
        """The whole sign as one constraint tree, the form MURML gestures take.

        The initial posture becomes ``Static`` leaves (the non-dominant hand's scoped to
        its arm), followed in a ``Sequence`` by the movement; a symmetric sign is wrapped in
        ``Symmetrical`` with the dominant arm. The hand constellation is not a slot value
        and stays on :attr:`constellation`.
        """
        own_scope = self.dominant if self.nondominant is not None else None
        statics = _posture_statics(self.posture, own_scope)
        if self.nondominant is not None:
            statics += _posture_statics(self.nondominant, self.dominant.other)
        parts: list[Constraint] = []
        if statics:
            parts.append(statics[0] if len(statics) == 1 else Parallel(tuple(statics), where=self.where))
        if self.movement is not None:
            parts.append(self.movement)
        if not parts:
            raise SpecError(f"sign {self.gloss!r} has neither a posture nor a movement", self.where)
        tree: Constraint = parts[0] if len(parts) == 1 else Sequence(tuple(parts), where=self.where)
        if self.symmetry is None:
            return tree
        return Symmetrical(tree, self.dominant, self.symmetry.to_model(), where=self.where)


def _posture_statics(posture: HandPosture, scope: Arm | None) -> list[Constraint]:
    values = (
        ("HandShape", posture.shape),
        ("ExtFingerOrientation", posture.ext_finger),
        ("PalmOrientation", posture.palm),
        ("HandLocation", posture.location),
    )
    return [Static(slot, value, scope=scope) for slot, value in values if value is not None]


@dataclass(frozen=True)
class SignFailure:
    """A sign that could not be read: its gloss, its index in the document and why."""

    gloss: str
    index: int
    error: SpecError


@dataclass(frozen=True)
class SigmlParseResult:
    """The signs of one SiGML document that parsed, and each one that did not."""

    signs: tuple[Sign, ...]
    failures: tuple[SignFailure, ...]
    source: str = "<input>"

    @property
    def total(self) -> int:
        return len(self.signs) + len(self.failures)
