"""The typed, immutable model that MURML utterances (and SiGML signs) parse into.

An :class:`Utterance` is speech text cut into chunks at chunk borders, with named time
tags between its words, and behaviours whose timing refers to those tags (an affiliate)
or to the utterance clock (absolute timing). A gesture is either a communicative
function resolved through a lexicon or a constraint tree over feature slots:
``parallel``, ``sequence``, ``symmetrical`` and ``repetition`` nodes with ``static``
and ``dynamic`` leaves (seed 004, section 3).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from mura.constraints import Constraint
from mura.errors import SourceLocation
from mura.signs import Sign
from mura.space import SpatialReference, SpatialSign


@dataclass(frozen=True)
class FunctionCall:
    """A gesture asked for by its communicative function, resolved through the lexicon."""

    name: str
    params: Mapping[str, str]
    where: SourceLocation | None = field(default=None, compare=False)


@dataclass(frozen=True)
class Gesture:
    """A gesture: its constraint tree, and the function it was chosen for, if any."""

    id: str | None
    constraints: Constraint
    function: FunctionCall | None = None
    scope: str | None = None
    where: SourceLocation | None = field(default=None, compare=False)


@dataclass(frozen=True)
class Affiliate:
    """The words a behaviour belongs to, between two time tags."""

    onset: str
    end: str
    where: SourceLocation | None = field(default=None, compare=False)


@dataclass(frozen=True)
class AbsoluteTiming:
    """A behaviour placed on the utterance clock, seconds."""

    onset: float
    end: float
    where: SourceLocation | None = field(default=None, compare=False)


#: BML sync-point names and the time pegs they are (``attackPeak`` of the face behaviours
#: is the end of their attack, the peg ``ready``).
BML_SYNC_PEGS: Mapping[str, str] = {
    "start": "start",
    "ready": "ready",
    "attackPeak": "ready",
    "strokeStart": "stroke_start",
    "stroke": "stroke",
    "strokeEnd": "stroke_end",
    "relax": "relax",
    "end": "end",
}


@dataclass(frozen=True)
class SyncRef:
    """A time a BML constraint names: sync point ``point`` of behaviour ``behavior`` plus
    ``offset`` seconds, or ``offset`` seconds on the block clock when ``behavior`` is None.

    ``point`` is a BML sync-point name (``strokeEnd``) or, for a speech behaviour, the id
    of one of its ``<sync>`` markers.
    """

    behavior: str | None
    point: str | None
    offset: float = 0.0
    where: SourceLocation | None = field(default=None, compare=False)

    def __str__(self) -> str:
        if self.behavior is None:
            return f"{self.offset:g} s"
        shift = f"{self.offset:+g}" if self.offset else ""
        return f"{self.behavior}:{self.point}{shift}"


@dataclass(frozen=True)
class SyncConstraint:
    """One BML timing constraint: ``point`` is at ``anchor`` (``relation`` ``=``), at or
    before it (``<=``, BML ``<before>``) or at or after it (``>=``, BML ``<after>``).

    ``required`` constraints come from a ``<required>`` block: when no timing satisfies
    them the block fails; the others may be dropped (with a warning) to save the rest.
    """

    point: SyncRef
    relation: str
    anchor: SyncRef
    required: bool = False
    where: SourceLocation | None = field(default=None, compare=False)

    def __str__(self) -> str:
        where = f" ({self.where})" if self.where is not None else ""
        return f"{self.point} {self.relation} {self.anchor}{where}"


@dataclass(frozen=True)
class SyncTiming:
    """A behaviour timed by its BML block's sync constraints (:attr:`Utterance.constraints`).

    ``points`` are the BML sync points the behaviour has; ``named`` the time pegs that
    some constraint names (only those phases may stretch, see ``blackboard.timing``).
    """

    block: str
    points: tuple[str, ...]
    named: frozenset[str] = frozenset()


@dataclass(frozen=True)
class BehaviorSpec:
    """One behaviour of an utterance.

    ``kind`` is the element that carried it (``gesture``, ``sign``, or another behaviour
    such as ``facial`` kept for the timeline). A ``sign`` behaviour carries a HamNoSys/SiGML
    sign performed by the arms, timed like a gesture, or a ``spatial`` sign: pointing at an
    arc position or an indicating verb (:mod:`mura.space`). ``chunk`` is the index of the chunk
    whose time tags the affiliate names, None for absolute timing; for a BML behaviour
    (:class:`SyncTiming`) the chunk it is timed with. ``params`` are the attributes of a
    behaviour no motor module reads yet (BML ``<head lexeme="NOD" repetition="2">``), kept
    as written.
    """

    id: str
    kind: str
    timing: Affiliate | AbsoluteTiming | SyncTiming | None
    gesture: Gesture | None = None
    chunk: int | None = None
    where: SourceLocation | None = field(default=None, compare=False)
    sign: Sign | None = None
    params: tuple[tuple[str, str], ...] = ()
    spatial: SpatialSign | None = None

    @property
    def moves_arms(self) -> bool:
        """True for the behaviours the motor core performs: gestures and signs."""
        return self.gesture is not None or self.sign is not None or self.spatial is not None


@dataclass(frozen=True)
class TimeTag:
    """A named point in the spoken text: between words, at a character offset of its chunk."""

    id: str
    chunk: int
    offset: int
    chunkborder: bool = False
    where: SourceLocation | None = field(default=None, compare=False)


@dataclass(frozen=True)
class ChunkSpec:
    """One intonational phrase of the utterance: its text and the time tags inside it.

    A chunk-border tag closes the chunk it ends (its offset is the chunk's text length).
    ``speech`` is the id of the BML ``<speech>`` behaviour the chunk speaks, if any.
    """

    index: int
    text: str
    time_tags: tuple[TimeTag, ...]
    speech: str | None = None


@dataclass(frozen=True)
class Utterance:
    """A whole multimodal utterance: chunks of speech and the behaviours that go with them.

    ``constraints`` are the timing constraints of a BML block between its behaviours' sync
    points (empty for MURML, whose behaviours are timed by affiliates); ``warnings`` what
    the reader left out or will not perform (``FILE:LINE:COL: warning: …``).
    """

    chunks: tuple[ChunkSpec, ...]
    behaviors: tuple[BehaviorSpec, ...]
    source: str = "<input>"
    constraints: tuple[SyncConstraint, ...] = ()
    warnings: tuple[str, ...] = ()
    space: tuple[SpatialReference, ...] = ()

    @property
    def time_tags(self) -> Mapping[str, TimeTag]:
        """Every time tag by id."""
        return {tag.id: tag for chunk in self.chunks for tag in chunk.time_tags}

    @property
    def text(self) -> str:
        """The whole spoken text, chunks joined by a space."""
        return " ".join(chunk.text for chunk in self.chunks if chunk.text)

    def behaviors_in_chunk(self, index: int) -> tuple[BehaviorSpec, ...]:
        """Behaviours whose affiliate lies in chunk ``index``."""
        return tuple(b for b in self.behaviors if b.chunk == index)
