"""The parameterized lexicon of indicating verbs (seed 001, Table 1): ``specs/verbs/lexicon.json``.

Each entry names a verb, what it indicates (``subject_object``: its path depends on both
the subject's and the object's arc positions; ``object``: on the object's only), the hands
it uses (the right hand dominant), each hand's shape as HamNoSys symbol names, its
keyframes (two for a straight path; SCOLD's wag has four), its description, and for the
verbs whose hands must meet in a particular way the *relation* that is checked (COPY: the
palms together at the start; EMAIL: the right hand's fingertips through the left hand's C
opening) with its tolerance in metres. *Sites* are named points of a hand in its
canonical frame (see :mod:`mura.recordings`): shoulder widths along the finger axis, the
palm normal and the thumb side. Which model realizes a verb is a matter for
:mod:`motor.verbs`; this module only reads and checks the entries.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from mura.errors import SourceLocation, SpecError
from mura.hamnosys import hamnosys_string, parse_hamnosys
from mura.recordings import HANDS
from mura.values import HandShape

LEXICON_PATH = Path(__file__).resolve().parents[1] / "specs" / "verbs" / "lexicon.json"
#: What a verb's path depends on.
INDICATES: tuple[str, ...] = ("subject_object", "object")
#: The relations between the hands that are checked.
RELATIONS: tuple[str, ...] = ("together_at_start", "passes_through")


@dataclass(frozen=True)
class HandRelation:
    """How the two hands of a verb meet: ``kind`` (:data:`RELATIONS`), the sites of each
    hand that meet (names of :attr:`VerbLexicon.sites`) and the tolerance, metres."""

    kind: str
    right_site: str
    left_site: str
    within: float


@dataclass(frozen=True)
class BodyAnchor:
    """A site of the dominant hand that touches a body location at one keyframe (TELL: the
    index fingertip at the chin at the start)."""

    site: str
    body: str
    keyframe: int


@dataclass(frozen=True)
class VerbEntry:
    """One indicating verb of the lexicon (module docstring)."""

    gloss: str
    meaning: str
    indicates: str
    hands: tuple[str, ...]
    handshapes: Mapping[str, HandShape]
    hamnosys: Mapping[str, str]
    keyframes: tuple[str, ...]
    description: str
    relation: HandRelation | None = None
    anchor: BodyAnchor | None = None

    @property
    def two_handed(self) -> bool:
        return "left" in self.hands

    @property
    def object_only(self) -> bool:
        return self.indicates == "object"


@dataclass(frozen=True)
class VerbLexicon:
    """The verbs by gloss and the named hand sites ``(along finger, along palm normal,
    along thumb side)`` in shoulder widths."""

    verbs: Mapping[str, VerbEntry]
    sites: Mapping[str, tuple[float, float, float]]
    source: str

    def entry(self, gloss: str) -> VerbEntry:
        """The verb ``gloss`` (any case); :class:`SpecError` naming the known ones otherwise."""
        entry = self.verbs.get(gloss.upper())
        if entry is None:
            raise SpecError(f"unknown indicating verb {gloss!r} (the lexicon has: {', '.join(self.verbs)})", SourceLocation(self.source))
        return entry


@lru_cache(maxsize=4)
def load_verb_lexicon(path: str | Path = LEXICON_PATH) -> VerbLexicon:
    """Read and check a verb lexicon; :class:`SpecError` naming the file and the entry."""
    where = SourceLocation(str(path))
    try:
        document = json.loads(Path(path).read_text(encoding="utf-8"))
    except OSError as error:
        raise SpecError(f"cannot read: {error.strerror or error}", where) from None
    except json.JSONDecodeError as error:
        raise SpecError(f"not JSON: {error.msg}", SourceLocation(str(path), error.lineno, error.colno)) from None
    if not isinstance(document, dict) or document.get("format") != "mura indicating verbs":
        raise SpecError('not a verb lexicon (expected "format": "mura indicating verbs")', where)
    sites = {}
    for name, offset in dict(document.get("sites", {})).items():
        if not isinstance(offset, list) or len(offset) != 3 or not all(isinstance(v, (int, float)) for v in offset):
            raise SpecError(f"site {name!r} must be three numbers", where)
        sites[name] = (float(offset[0]), float(offset[1]), float(offset[2]))
    verbs = {}
    for index, item in enumerate(document.get("verbs", [])):
        entry = _entry(item, index, sites, str(path))
        if entry.gloss in verbs:
            raise SpecError(f"verb {entry.gloss} is listed twice", where)
        verbs[entry.gloss] = entry
    if not verbs:
        raise SpecError("the lexicon lists no verbs", where)
    return VerbLexicon(verbs, sites, str(path))


def _entry(item: object, index: int, sites: Mapping[str, tuple[float, float, float]], file: str) -> VerbEntry:
    where = SourceLocation(file)
    label = f"verb {index + 1}"
    if not isinstance(item, dict) or not isinstance(item.get("gloss"), str):
        raise SpecError(f"{label} needs a gloss", where)
    gloss = item["gloss"].upper()
    label = f"verb {gloss}"
    indicates = item.get("indicates")
    if indicates not in INDICATES:
        raise SpecError(f"{label}: indicates {indicates!r} is not one of {', '.join(INDICATES)}", where)
    hands = tuple(item.get("hands", ()))
    if not hands or hands[0] != "right" or any(h not in HANDS for h in hands) or len(set(hands)) != len(hands):
        raise SpecError(f"{label}: hands {list(hands)} must be ['right'] or ['right', 'left']", where)
    names = dict(item.get("handshapes", {}))
    shapes, strings = {}, {}
    for hand in hands:
        if hand not in names:
            raise SpecError(f"{label}: no hand shape for the {hand} hand", where)
        try:
            strings[hand] = hamnosys_string(str(names[hand]).split())
            shapes[hand] = parse_hamnosys(strings[hand], gloss=gloss, file=file).posture.shape
        except (ValueError, SpecError) as error:
            raise SpecError(f"{label}: {hand} hand shape {names[hand]!r}: {getattr(error, 'message', error)}", where) from None
        if shapes[hand] is None:
            raise SpecError(f"{label}: {hand} hand shape {names[hand]!r} names no hand shape", where)
    keyframes = tuple(str(k) for k in item.get("keyframes", ()))
    if len(keyframes) < 2:
        raise SpecError(f"{label}: at least two keyframes are needed", where)
    relation = None
    if "relation" in item:
        raw = dict(item["relation"])
        relation = HandRelation(str(raw.get("kind")), str(raw.get("right_site")), str(raw.get("left_site")), float(raw.get("within", 0.03)))
        if relation.kind not in RELATIONS or len(hands) != 2:
            raise SpecError(f"{label}: relation {relation.kind!r} needs two hands and one of {', '.join(RELATIONS)}", where)
        for site in (relation.right_site, relation.left_site):
            if site not in sites:
                raise SpecError(f"{label}: unknown site {site!r} (known: {', '.join(sites)})", where)
    anchor = None
    if "anchor" in item:
        raw = dict(item["anchor"])
        anchor = BodyAnchor(str(raw.get("site")), str(raw.get("body")), int(raw.get("keyframe", 0)))
        if anchor.site not in sites or not 0 <= anchor.keyframe < len(keyframes):
            raise SpecError(f"{label}: anchor site {anchor.site!r} or keyframe {anchor.keyframe} unknown", where)
    return VerbEntry(
        gloss, str(item.get("meaning", "")), indicates, hands, shapes, strings, keyframes,
        str(item.get("description", "")), relation, anchor,
    )  # fmt: skip
