"""The gesture lexicon: gestures chosen by communicative function (seed 004, section 3).

An utterance may ask for a gesture by what it should do — ``<function name="refer_to_loc">``
with parameters — instead of describing its form. The lexicon maps each function to a
constraint tree written in the same language as utterances, with ``$param`` placeholders
that the call's parameters fill in. It also holds a scene: named places (``Loc-Bar_1``)
that parameters may refer to as ``$Loc-Bar_1``.

Lexicon file::

    <lexicon unit="m">
      <scene><location name="Loc-Bar_1" position="-0.30 0.05 0.55"/></scene>
      <entry function="refer_to_loc">
        <param name="refloc"/>                      <!-- required -->
        <param name="hand" default="right_arm"/>     <!-- optional -->
        <constraints> … value="$refloc" … </constraints>
      </entry>
    </lexicon>
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from types import MappingProxyType

from lxml import etree

from mura.resources import SPECS_DIR
from mura.xml_source import XmlSource

DEFAULT_LEXICON = SPECS_DIR / "lexicon" / "gestures.xml"


@dataclass(frozen=True)
class LexiconEntry:
    """One function's gesture: its parameters (``None`` default = required) and form."""

    function: str
    params: Mapping[str, str | None]
    constraints: etree._Element
    source: XmlSource


@dataclass(frozen=True)
class SceneLocation:
    """A named place: ``position`` numbers in the declaring file's unit, or grid ``value`` names."""

    name: str
    text: str
    is_position: bool
    source: XmlSource
    element: etree._Element
    unit: str


@dataclass(frozen=True)
class GestureLexicon:
    """Functions by name and the scene's named places."""

    entries: Mapping[str, LexiconEntry]
    scene: Mapping[str, SceneLocation]
    unit: str

    def entry(self, name: str) -> LexiconEntry | None:
        return self.entries.get(name)


def read_scene(source: XmlSource, scene: etree._Element, unit: str) -> dict[str, SceneLocation]:
    """The ``<location>`` children of a ``<scene>`` element, by name."""
    places: dict[str, SceneLocation] = {}
    for element in scene:
        if element.tag != "location":
            raise source.error(f"unexpected <{element.tag}> in <scene> (expected <location>)", element)
        name = element.get("name")
        if not name:
            raise source.error("<location> needs a name", element)
        if name in places:
            raise source.error(f"scene location {name!r} is defined twice", element, "name")
        position, value = element.get("position"), element.get("value")
        if (position is None) == (value is None):
            raise source.error(f"scene location {name!r} needs either position or value", element)
        text = position if position is not None else value
        assert text is not None
        places[name] = SceneLocation(name, text, position is not None, source, element, unit)
    return places


def load_lexicon(path: str | Path = DEFAULT_LEXICON) -> GestureLexicon:
    """Read a lexicon file; a malformed one is a :class:`SpecError` naming the place."""
    return _load_cached(str(Path(path).resolve()))


@lru_cache(maxsize=8)
def _load_cached(path: str) -> GestureLexicon:
    source = XmlSource.from_path(path)
    root = source.root
    if root.tag != "lexicon":
        raise source.error(f"a lexicon file has root <lexicon>, not <{root.tag}>", root)
    unit = root.get("unit", "m")
    if unit not in ("mm", "cm", "m"):
        raise source.error(f"unknown unit {unit!r} (expected mm, cm or m)", root, "unit")
    entries: dict[str, LexiconEntry] = {}
    scene: dict[str, SceneLocation] = {}
    for element in root:
        if element.tag == "scene":
            scene.update(read_scene(source, element, unit))
        elif element.tag == "entry":
            entry = _read_entry(source, element)
            if entry.function in entries:
                raise source.error(f"function {entry.function!r} is defined twice", element, "function")
            entries[entry.function] = entry
        else:
            raise source.error(f"unexpected <{element.tag}> in <lexicon> (expected <scene> or <entry>)", element)
    return GestureLexicon(MappingProxyType(entries), MappingProxyType(scene), unit)


def _read_entry(source: XmlSource, element: etree._Element) -> LexiconEntry:
    function = element.get("function")
    if not function:
        raise source.error("<entry> needs a function attribute", element)
    params: dict[str, str | None] = {}
    constraints = None
    for child in element:
        if child.tag == "param":
            name = child.get("name")
            if not name:
                raise source.error("<param> needs a name", child)
            params[name] = child.get("default")
        elif child.tag == "constraints":
            if constraints is not None:
                raise source.error(f"function {function!r} has two <constraints>", child)
            constraints = child
        else:
            raise source.error(f"unexpected <{child.tag}> in <entry> (expected <param> or <constraints>)", child)
    if constraints is None:
        raise source.error(f"function {function!r} has no <constraints>", element)
    return LexiconEntry(function, MappingProxyType(params), constraints, source)


def bind_params(entry: LexiconEntry, given: Mapping[str, str]) -> dict[str, str]:
    """The call's parameters completed with defaults; raises ValueError naming what is wrong."""
    unknown = sorted(set(given) - set(entry.params))
    if unknown:
        raise ValueError(f"function {entry.function!r} has no parameter {unknown[0]!r} (it takes {', '.join(sorted(entry.params)) or 'none'})")
    bound: dict[str, str] = {}
    for name, default in entry.params.items():
        if name in given:
            bound[name] = given[name]
        elif default is not None:
            bound[name] = default
        else:
            raise ValueError(f"function {entry.function!r} needs parameter {name!r}")
    return bound
