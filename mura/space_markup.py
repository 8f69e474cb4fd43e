"""The markup of spatial reference points and spatial signs in MURML and SiGML (seed 001).

The markup::

    <utterance>
      <space>
        <place entity="john" arc="0.9"/>
        <place entity="mary" arc="-0.6"/>
      </space>
      <specification> John <time id="t1"/> asks <time id="t2"/> Mary. <time id="t3"/> </specification>
      <behaviorspec id="there">
        <sign point="john"><affiliate onset="t1" end="t2"/></sign>
      </behaviorspec>
      <behaviorspec id="ask">
        <sign verb="ASK" subject="john" object="mary" model="point"><affiliate onset="t2" end="t3"/></sign>
      </behaviorspec>
    </utterance>

- ``<space>`` (in ``<utterance>``, or in ``<definition>`` for all its utterances) holds
  ``<place entity="NAME" arc="A"/>``: the entity NAME is placed at arc position A.
- ``<sign point="X">`` points at X; ``<sign verb="V" subject="X" object="Y">`` is the
  indicating verb V inflected for its subject and object. X and Y are a placed entity's
  name or an arc position written as a number. Object-only verbs (SCOLD, TELL) take no
  subject. ``model`` is ``point`` (default), ``vector`` or ``uninflected``.
- They are behaviours like every ``<sign>``: timed by ``<affiliate>`` or ``<timing>``.
"""

from __future__ import annotations

import math

from lxml import etree

from mura.errors import SpecError
from mura.space import VERB_MODELS, ArcTarget, IndicatingVerbSign, PointingSign, SpatialReference, SpatialSign
from mura.verb_lexicon import load_verb_lexicon
from mura.xml_source import XmlSource


def is_spatial_sign(element: etree._Element) -> bool:
    """True for a ``<sign>`` that points or is an indicating verb."""
    return element.get("verb") is not None or element.get("point") is not None


def read_space(source: XmlSource, element: etree._Element, placed: dict[str, SpatialReference]) -> None:
    """Add the places of a ``<space>`` element to ``placed`` (an entity placed twice in one
    space is an error; a later space may move it)."""
    here: set[str] = set()
    for child in element:
        if child.tag != "place":
            raise source.error(f"unexpected <{child.tag}> in <space> (expected <place entity=… arc=…/>)", child)
        entity = (child.get("entity") or "").strip()
        if not entity:
            raise source.error("<place> needs an entity name", child)
        if entity in here:
            raise source.error(f"entity {entity!r} is placed twice in this <space>", child, "entity")
        arc = _arc_number(source, child, "arc", child.get("arc"))
        if arc is None:
            raise source.error(f"<place entity={entity!r}> needs an arc position (a number in [-1, 1])", child, "arc")
        here.add(entity)
        placed[entity] = SpatialReference(entity, arc, source.where(child))


def read_spatial_sign(source: XmlSource, element: etree._Element, behavior_id: str, placed: dict[str, SpatialReference]) -> SpatialSign:
    """A pointing sign or an indicating verb from a ``<sign>`` element (module docstring)."""
    where = source.where(element)
    forms = [child.tag for child in element if child.tag not in ("affiliate", "timing")]
    if forms:
        raise source.error(f"sign {behavior_id!r}: a pointing sign or indicating verb takes no <{forms[0]}>", element)
    if element.get("point") is not None:
        if element.get("verb") is not None:
            raise source.error(f"sign {behavior_id!r}: give either point or verb, not both", element, "point")
        return PointingSign(_target(source, element, "point", placed), where)
    name = element.get("verb", "").strip()
    try:
        entry = load_verb_lexicon().entry(name)
    except SpecError as error:
        raise source.error(error.message, element, "verb") from None
    model = element.get("model", "point")
    if model not in VERB_MODELS:
        raise source.error(f"sign {behavior_id!r}: model {model!r} is not one of {', '.join(VERB_MODELS)}", element, "model")
    if element.get("object") is None:
        raise source.error(f"sign {behavior_id!r}: {entry.gloss} needs an object (an entity or an arc position)", element)
    subject = None
    if entry.object_only:
        if element.get("subject") is not None:
            raise source.error(f"sign {behavior_id!r}: {entry.gloss} indicates its object only; it takes no subject", element, "subject")
    else:
        if element.get("subject") is None:
            raise source.error(f"sign {behavior_id!r}: {entry.gloss} needs a subject (an entity or an arc position)", element)
        subject = _target(source, element, "subject", placed)
    return IndicatingVerbSign(entry.gloss, subject, _target(source, element, "object", placed), model, where)


def _target(source: XmlSource, element: etree._Element, attribute: str, placed: dict[str, SpatialReference]) -> ArcTarget:
    text = (element.get(attribute) or "").strip()
    number = _arc_number(source, element, attribute, text)
    if number is not None:
        return ArcTarget(number)
    reference = placed.get(text)
    if reference is None:
        known = ", ".join(sorted(placed)) or "none"
        raise source.error(f"{attribute} {text!r} is neither an arc position in [-1, 1] nor a placed entity (placed: {known})", element, attribute)
    return ArcTarget(reference.arc, reference.entity)


def _arc_number(source: XmlSource, element: etree._Element, attribute: str, text: str | None) -> float | None:
    """The arc position written in ``text``, None when it is not a number; an error when it
    is a number outside [−1, 1]."""
    try:
        value = float(text or "")
    except ValueError:
        return None
    if not math.isfinite(value) or not -1.0 <= value <= 1.0:
        raise source.error(f"arc position {text} is outside [-1, 1]", element, attribute)
    return value
