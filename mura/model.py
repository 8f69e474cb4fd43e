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


@dataclass(frozen=True)
class BehaviorSpec:
    """One behaviour of an utterance.

    ``kind`` is the element that carried it (``gesture``, ``sign``, or another behaviour
    such as ``facial`` kept for the timeline). A ``sign`` behaviour carries a HamNoSys/SiGML
    sign performed by the arms, timed like a gesture, or a ``spatial`` sign: pointing at an
    arc position or an indicating verb (:mod:`mura.space`). ``chunk`` is the index of the chunk
    whose time tags the affiliate names, None for absolute timing.
    """

    id: str
    kind: str
    timing: Affiliate | AbsoluteTiming | None
    gesture: Gesture | None = None
    chunk: int | None = None
    where: SourceLocation | None = field(default=None, compare=False)
    sign: Sign | None = None
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
    """

    index: int
    text: str
    time_tags: tuple[TimeTag, ...]


@dataclass(frozen=True)
class Utterance:
    """A whole multimodal utterance: chunks of speech and the behaviours that go with them."""

    chunks: tuple[ChunkSpec, ...]
    behaviors: tuple[BehaviorSpec, ...]
    source: str = "<input>"
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
