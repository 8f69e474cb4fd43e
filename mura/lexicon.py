"""Gesture lexicons: gestures chosen by communicative function (seed 004, section 3).

An utterance may ask for a gesture by what it should do — ``<function name="refer_to_loc">``
with parameters — instead of describing its form. A lexicon maps each function to a
constraint tree written in the same language as utterances, with ``$param`` placeholders
that the call's parameters fill in. It also holds a scene (named places such as
``Loc-Bar_1`` that parameters refer to as ``$Loc-Bar_1``) and the symbol table of location,
distance and palm-orientation names beyond the core vocabulary.

Three file formats are read (the root element says which):

* mura's ``<lexicon unit="m">`` with ``<scene>`` and ``<entry function=…>`` holding
  ``<param name=… [default=…]/>`` and ``<constraints>`` (``specs/lexicon/gestures.xml``);
* the published MURML gesture lexicon (the ACE port's): ``<gestures>`` of
  ``<gesture name=…>`` entries. An entry's function is its ``<function name=…>`` child,
  else its ``name`` (or ``id``); the function's ``<param name=… [value=…]/>`` declare the
  parameters (``value`` is the default), and any other ``$name`` written in the entry and
  not a scene place is a required parameter too. The form is the entry's
  ``<constraints>`` (or ``<murml-description>``), or the one constraint element written
  directly in the entry. Several entries for one function are variants: the first is
  used. Lengths are in cm unless the root says ``unit``, as in published utterances;
* a published symbol table, ``<hns>`` with ``<symbols>`` of ``<symbol class=… name=…
  value=…/>`` (classes ``handReferences``, ``handLocators``, ``handDistances`` in cm,
  ``distances`` in cm, ``palmOrientations`` in degrees): its names extend the vocabulary
  (:class:`mura.murml_vocabulary.SymbolTable`).

:func:`load_lexicons` layers files over the bundled lexicon in order: a function (or
place, or symbol) defined again replaces the earlier one. :func:`mura.gesture_functions.
function_gesture` turns a call into a constraint tree; MURML utterances and BML use it.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from types import MappingProxyType

from lxml import etree

from mura.murml_vocabulary import DEFAULT_SYMBOLS, SymbolTable
from mura.resources import SPECS_DIR
from mura.xml_source import XmlSource

DEFAULT_LEXICON = SPECS_DIR / "lexicon" / "gestures.xml"

#: A ``$name`` placeholder in an attribute value: a parameter, or else a scene place.
PLACEHOLDER = re.compile(r"\$([A-Za-z_][\w\-]*)")

#: Root elements of the files a lexicon is read from.
LEXICON_ROOTS: tuple[str, ...] = ("lexicon", "gestures", "hns")
#: Elements of a published entry that are not its form.
_ENTRY_EXTRAS = frozenset({"function", "timing", "affiliate", "description", "meaning", "comment"})
#: Elements that wrap an entry's one constraint.
_FORM_WRAPPERS = ("constraints", "murml-description")
_CONSTRAINTS = frozenset({"parallel", "sequence", "symmetrical", "repetition", "static", "dynamic"})
_UNITS = ("mm", "cm", "m")
_SYMBOL_CLASSES = ("handReferences", "handLocators", "handDistances", "distances", "palmOrientations")


@dataclass(frozen=True)
class LexiconEntry:
    """One function's gesture: its parameters (``None`` default = required) and form.

    ``form`` is the constraint element; ``scope`` the arm its wrapper names, if any;
    ``unit`` the lexicon file's length unit; ``name`` the entry's own name.
    """

    function: str
    params: Mapping[str, str | None]
    form: etree._Element
    source: XmlSource
    unit: str = "m"
    scope: str | None = None
    name: str | None = None


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
    """Functions by name, the scene's named places, the symbol table and where they came from."""

    entries: Mapping[str, LexiconEntry]
    scene: Mapping[str, SceneLocation]
    unit: str = "m"
    symbols: SymbolTable = field(default_factory=lambda: DEFAULT_SYMBOLS)
    files: tuple[str, ...] = ()

    def entry(self, name: str) -> LexiconEntry | None:
        return self.entries.get(name)

    @property
    def functions(self) -> tuple[str, ...]:
        """The functions the lexicon knows, sorted."""
        return tuple(sorted(self.entries))


def read_scene(source: XmlSource, scene: etree._Element, unit: str) -> dict[str, SceneLocation]:
    """The ``<location>`` children of a ``<scene>`` element, by name."""
    places: dict[str, SceneLocation] = {}
    for element in (e for e in scene if isinstance(e.tag, str)):
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
    """Read one lexicon file of any of the three formats; a malformed one is a
    :class:`SpecError` naming the place."""
    return _load_cached(str(Path(path).resolve()))


def load_lexicons(paths: Iterable[str | Path], with_default: bool = True) -> GestureLexicon:
    """The bundled lexicon (unless ``with_default`` is false) with ``paths`` layered over it
    in order (module docstring)."""
    lexicons = [load_lexicon()] if with_default else []
    lexicons.extend(load_lexicon(path) for path in paths)
    return combine_lexicons(lexicons)


def combine_lexicons(lexicons: Sequence[GestureLexicon]) -> GestureLexicon:
    """One lexicon of several; later ones replace earlier functions, places and symbols."""
    entries: dict[str, LexiconEntry] = {}
    scene: dict[str, SceneLocation] = {}
    symbols = DEFAULT_SYMBOLS
    files: list[str] = []
    for lexicon in lexicons:
        entries.update(lexicon.entries)
        scene.update(lexicon.scene)
        symbols = symbols.merged(lexicon.symbols)
        files.extend(lexicon.files)
    unit = lexicons[0].unit if lexicons else "m"
    return GestureLexicon(MappingProxyType(entries), MappingProxyType(scene), unit, symbols, tuple(files))


def read_lexicon(source: XmlSource) -> GestureLexicon:
    """A lexicon from a parsed document of any of the three formats."""
    root = source.root
    readers = {"lexicon": _read_mura_lexicon, "gestures": _read_gestures, "hns": _read_symbol_table}
    reader = readers.get(root.tag)
    if reader is None:
        raise source.error(f"a lexicon file has root <lexicon>, <gestures> or <hns>, not <{root.tag}>", root)
    return reader(source)


@lru_cache(maxsize=16)
def _load_cached(path: str) -> GestureLexicon:
    return read_lexicon(XmlSource.from_path(path))


def _unit(source: XmlSource, root: etree._Element, default: str) -> str:
    unit = root.get("unit", default)
    if unit not in _UNITS:
        raise source.error(f"unknown unit {unit!r} (expected mm, cm or m)", root, "unit")
    return unit


def _read_mura_lexicon(source: XmlSource) -> GestureLexicon:
    root = source.root
    unit = _unit(source, root, "m")
    entries: dict[str, LexiconEntry] = {}
    scene: dict[str, SceneLocation] = {}
    for element in (e for e in root if isinstance(e.tag, str)):
        if element.tag == "scene":
            scene.update(read_scene(source, element, unit))
        elif element.tag == "entry":
            entry = _read_entry(source, element, unit)
            if entry.function in entries:
                raise source.error(f"function {entry.function!r} is defined twice", element, "function")
            entries[entry.function] = entry
        else:
            raise source.error(f"unexpected <{element.tag}> in <lexicon> (expected <scene> or <entry>)", element)
    return GestureLexicon(MappingProxyType(entries), MappingProxyType(scene), unit, SymbolTable(), (source.file,))


def _read_entry(source: XmlSource, element: etree._Element, unit: str) -> LexiconEntry:
    function = element.get("function")
    if not function:
        raise source.error("<entry> needs a function attribute", element)
    params: dict[str, str | None] = {}
    constraints = None
    for child in (c for c in element if isinstance(c.tag, str)):
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
    form = _single_form(source, constraints, f"function {function!r}")
    return LexiconEntry(function, MappingProxyType(params), form, source, unit, constraints.get("scope"))


def _read_gestures(source: XmlSource) -> GestureLexicon:
    root = source.root
    unit = _unit(source, root, "cm")
    entries: dict[str, LexiconEntry] = {}
    scene: dict[str, SceneLocation] = {}
    for element in (e for e in root if isinstance(e.tag, str)):
        if element.tag == "scene":
            scene.update(read_scene(source, element, unit))
            continue
        if element.tag != "gesture":
            raise source.error(f"unexpected <{element.tag}> in <gestures> (expected <gesture> entries)", element)
        entry = _read_gesture(source, element, unit)
        entries.setdefault(entry.function, entry)
    for entry in entries.values():
        implicit = placeholders(entry.form) - set(entry.params) - set(scene)
        if implicit:
            params = {**entry.params, **{name: None for name in sorted(implicit)}}
            entries[entry.function] = LexiconEntry(entry.function, MappingProxyType(params), entry.form, source, unit, entry.scope, entry.name)
    return GestureLexicon(MappingProxyType(entries), MappingProxyType(scene), unit, SymbolTable(), (source.file,))


def _read_gesture(source: XmlSource, element: etree._Element, unit: str) -> LexiconEntry:
    name = element.get("name") or element.get("id")
    functions = [c for c in element if c.tag == "function"]
    if len(functions) > 1:
        raise source.error(f"gesture {name!r} names {len(functions)} functions (expected one)", functions[1])
    function = functions[0].get("name") if functions else name
    if not function:
        raise source.error("<gesture> needs a name (or a <function name=…>)", element)
    params: dict[str, str | None] = {}
    for param in (functions[0] if functions else ()):
        if not isinstance(param.tag, str):
            continue
        if param.tag != "param" or not param.get("name"):
            raise source.error(f"<function> of {function!r} holds <{param.tag}> (expected <param name=…>)", param)
        params[param.get("name")] = param.get("value", param.get("default"))
    forms = [c for c in element if isinstance(c.tag, str) and c.tag not in _ENTRY_EXTRAS]
    if len(forms) != 1:
        raise source.error(f"gesture {function!r} needs one form (<constraints> or one constraint), found {len(forms)}", element)
    wrapper = forms[0]
    if wrapper.tag in _FORM_WRAPPERS:
        return LexiconEntry(function, MappingProxyType(params), _single_form(source, wrapper, f"gesture {function!r}"), source, unit,
                            wrapper.get("scope") or element.get("scope"), name)  # fmt: skip
    if wrapper.tag not in _CONSTRAINTS:
        raise source.error(f"unexpected <{wrapper.tag}> in <gesture> (expected <function>, <constraints> or a constraint)", wrapper)
    return LexiconEntry(function, MappingProxyType(params), wrapper, source, unit, element.get("scope"), name)


def _single_form(source: XmlSource, wrapper: etree._Element, owner: str) -> etree._Element:
    children = [c for c in wrapper if isinstance(c.tag, str)]
    if len(children) != 1:
        raise source.error(f"<{wrapper.tag}> of {owner} must hold exactly one constraint, found {len(children)}", wrapper)
    return children[0]


def _read_symbol_table(source: XmlSource) -> GestureLexicon:
    tables: dict[str, dict[str, float]] = {name: {} for name in _SYMBOL_CLASSES}
    for symbol in source.root.iter("symbol"):
        kind, name, text = symbol.get("class"), symbol.get("name"), symbol.get("value", "")
        if kind not in tables or not name or not text.strip():
            continue  # hand shapes and other classes carry no value mura reads
        try:
            tables[kind][name] = float(text)
        except ValueError:
            raise source.error(f"symbol {name!r} has value {text!r}, not a number", symbol, "value") from None
    symbols = SymbolTable(
        MappingProxyType(tables["handReferences"]), MappingProxyType(tables["handLocators"]),
        MappingProxyType(tables["handDistances"]), MappingProxyType({k: v / 100.0 for k, v in tables["distances"].items()}),
        MappingProxyType(tables["palmOrientations"]),
    )  # fmt: skip
    return GestureLexicon(MappingProxyType({}), MappingProxyType({}), "cm", symbols, (source.file,))


def placeholders(element: etree._Element) -> set[str]:
    """Every ``$name`` written in an attribute of ``element`` or below it."""
    found: set[str] = set()
    for node in element.iter(etree.Element):
        for value in node.attrib.values():
            found.update(PLACEHOLDER.findall(value))
    return found


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
