"""Spatial reference points and the signs that use them (seed 001), as plain data.

Entities under discussion are placed on the arc around the signer (−1 = far left … +1 =
far right, at chest height); signs then point at them, and indicating verbs move from the
subject's place to the object's. The markup that writes them is read by
:mod:`mura.space_markup`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from mura.errors import SourceLocation

#: The models an utterance may ask for.
VERB_MODELS: tuple[str, ...] = ("point", "vector", "uninflected")


@dataclass(frozen=True)
class SpatialReference:
    """An entity placed on the arc: its name and arc position in [−1, 1]."""

    entity: str
    arc: float
    where: SourceLocation | None = field(default=None, compare=False)


@dataclass(frozen=True)
class ArcTarget:
    """Where a sign is directed: an arc position, and the entity named for it, if any."""

    arc: float
    entity: str | None = None


@dataclass(frozen=True)
class PointingSign:
    """Pointing at an arc position (placing or referring to an entity)."""

    target: ArcTarget
    where: SourceLocation | None = field(default=None, compare=False)

    @property
    def gloss(self) -> str:
        return f"POINT-{self.target.entity or f'{self.target.arc:+.2f}'}"


@dataclass(frozen=True)
class IndicatingVerbSign:
    """An indicating verb inflected for its subject and object (the subject None for
    object-only verbs), by the named model."""

    verb: str
    subject: ArcTarget | None
    object: ArcTarget
    model: str = "point"
    where: SourceLocation | None = field(default=None, compare=False)

    @property
    def gloss(self) -> str:
        return self.verb


SpatialSign = PointingSign | IndicatingVerbSign
