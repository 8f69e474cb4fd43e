"""MURML face slots planned into face tracks on a gesture's time pegs.

``FaceExpression`` takes a face lexeme (``Smile``, ``RAISE_BROWS`` …,
:mod:`motor.face.expressions`), held from the stroke to ``relax`` with an attack before
and a release after; ``Mouth`` takes a SAMPA mouth picture (``hVlU``), spoken over the
stroke, or over its natural length (0.12 s a consonant, twice that a vowel) when the
stroke is shorter. An unknown lexeme or SAMPA character is reported (behaviour, place in
the file, name) and left out.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from motor.face.expressions import UnknownExpression, face_lexeme
from motor.face.lipsync import MOUTHING_UNITS, mouth_picture
from motor.face.phonemes import lookup, sampa_symbols
from motor.program.lmp import TimePegs
from mura.constraints import Constraint, Dynamic, Static, iter_leaves
from mura.values import Symbol

#: The slots this module realizes.
FACE_SLOTS: frozenset[str] = frozenset({"FaceExpression", "Mouth"})
#: Seconds of one unit of a mouth picture at its own pace.
MOUTHING_UNIT_TIME = 0.12


@dataclass
class FacePlan:
    """The face tracks of one behaviour and what planning noted."""

    tracks: list = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)


def plan_face(behavior: str, tree: Constraint | None, pegs: TimePegs) -> FacePlan:
    """The face tracks of the face slots of ``tree`` on ``pegs`` (module docstring)."""
    plan = FacePlan()
    if tree is None:
        return plan
    for leaf in iter_leaves(tree):
        if leaf.slot not in FACE_SLOTS:
            continue
        where = str(leaf.where) if leaf.where is not None else "unknown place"
        value = leaf.value if isinstance(leaf, Static) else _first_value(leaf)
        if not isinstance(value, Symbol):
            plan.warnings.append(f"{behavior} ({where}): {leaf.slot} needs a name, got {value!r}; not realized")
            continue
        if leaf.slot == "FaceExpression":
            try:
                plan.tracks.append(face_lexeme(value.name, pegs.stroke_start, max(pegs.relax, pegs.stroke_start)))
            except UnknownExpression as error:
                plan.warnings.append(f"{behavior} ({where}): {error}; the face stays as it is")
        else:
            plan.tracks.extend(_mouthing(behavior, where, value.name, pegs, plan))
    return plan


def mouthing_duration(picture: str) -> float:
    """Seconds a SAMPA mouth picture takes at its own pace."""
    symbols, _ = sampa_symbols(picture)
    units = [MOUTHING_UNITS[1 if lookup(s, "sampa")[1] == "vowel" else 0] for s in symbols]
    return MOUTHING_UNIT_TIME * sum(units)


def _mouthing(behavior: str, where: str, picture: str, pegs: TimePegs, plan: FacePlan) -> list:
    end = max(pegs.stroke_end, pegs.stroke_start + mouthing_duration(picture))
    articulation, skipped = mouth_picture(picture, pegs.stroke_start, end)
    for position, char in skipped:
        plan.warnings.append(f"{behavior} ({where}): mouth picture {picture!r}: unknown SAMPA symbol {char!r} at position {position}; left out")
    return [articulation] if articulation is not None else []


def _first_value(leaf: Dynamic) -> object:
    return next((v for segment in leaf.segments for v in (segment.start, segment.end) if v is not None), None)
