"""Reading MURML-like utterances into the model of :mod:`mura.model`.

Two dialects are read alike:

* the seed's (Fig. 2 of seed 004): ``<utterance><specification>`` with the spoken text and
  ``<time id=… chunkborder=…/>`` tags, ``<behaviorspec><gesture><affiliate onset end/>``,
  gestures by ``<function>`` or ``<constraints>``, guiding strokes as ``<segment>``;
* the published one (AsapRealizer's examples): ``<behaviorspec><gesture scope=…>`` with
  ``<timing onset end/>`` in seconds, ``<dynamicElement>`` for segments, ``scope`` on
  every leaf, ``dominant="right_arm"``, ``symmetry="Sym…"``.

**Length units.** The model holds metres. A number may carry its unit (``125mm``,
``12.5cm``, ``0.125m``); a bare number is in the document's unit: the ``unit`` attribute of
``<definition>`` or ``<utterance>`` when given, otherwise millimetres for the seed's dialect
(its ``distance`` of ``125.0`` is 12.5 cm, the size of "this big") and centimetres for the
published dialect (its symbol table is in cm, and ``40`` is a 40 cm zip-fastener stroke).
A document is in the published dialect when it contains ``<timing>`` or
``<dynamicElement>``.

**Untimed gestures.** A gesture or sign with neither ``<affiliate>`` nor ``<timing>`` is
performed as the realizers that read published MURML perform an unconstrained behaviour:
from the start of the utterance, in document order, each in the first free time: its
stroke keeps :data:`UNTIMED_GAP` seconds from every other stroke given in seconds (untimed
or ``<timing>``; the first begins that long after the utterance starts, so that its
preparation starts with the utterance), time for the arm to prepare any reach (Fitts' law of the design, ``0.24 · ln(100·A + 1)`` s, is 1.1 s for
A = 1 m) — with a stroke of :data:`UNTIMED_STROKE` seconds (the motor slows a shorter
stroke to fill it, or holds it). Its timing is an :class:`~mura.model.AbsoluteTiming`
like any other. Gestures timed by the speech are placed only when the speech is known, so
an untimed gesture may meet one of them; the scheduler then relaxes what it must.

Constraint trees are read by :mod:`mura.murml_constraints`; gestures asked for by
function are resolved by :func:`mura.gesture_functions.function_gesture` through the
lexicon (``lexicon``: the bundled one unless given, see :func:`mura.lexicon.load_lexicons`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field, replace
from pathlib import Path

from lxml import etree

from mura.errors import SourceLocation, SpecError, SpecErrors
from mura.gesture_functions import function_gesture
from mura.hamnosys import parse_hamnosys
from mura.lexicon import GestureLexicon, SceneLocation, load_lexicons, read_scene
from mura.model import (
    AbsoluteTiming,
    Affiliate,
    BehaviorSpec,
    ChunkSpec,
    FunctionCall,
    Gesture,
    TimeTag,
    Utterance,
)
from mura.murml_constraints import UNIT_METRES, ConstraintReader, arm_or_none, float_or_none
from mura.schema import validate_murml
from mura.sigml import read_sign_element
from mura.signs import Sign
from mura.xml_source import XmlSource

#: Stroke duration (s) given to a gesture written without timing, and the time (s) left
#: between two such strokes (module docstring).
UNTIMED_STROKE = 1.0
UNTIMED_GAP = 1.2

_NCNAME = re.compile(r"^[A-Za-z_][\w.\-]*$")
_SIGN_FORMS = ("hamnosys", "hns_sign", "hamgestural_sign")
_TRUE = {"true", "1", "yes"}
_FALSE = {"false", "0", "no"}


def load_utterances(path: str | Path, lexicon: GestureLexicon | None = None) -> tuple[Utterance, ...]:
    """Every utterance of a MURML file, checked; raises :class:`SpecError` on the first problems."""
    return read_utterances(XmlSource.from_path(path), lexicon)


def load_utterance(path: str | Path, lexicon: GestureLexicon | None = None) -> Utterance:
    """The single utterance of a MURML file."""
    return _single(load_utterances(path, lexicon), str(path))


def parse_utterance(data: str | bytes, file: str = "<input>", lexicon: GestureLexicon | None = None) -> Utterance:
    """The single utterance of a MURML document given as text."""
    raw = data.encode("utf-8") if isinstance(data, str) else data
    return _single(read_utterances(XmlSource.from_bytes(raw, file), lexicon), file)


def _single(utterances: tuple[Utterance, ...], file: str) -> Utterance:
    if len(utterances) != 1:
        raise SpecError(f"expected one utterance, found {len(utterances)}", SourceLocation(file, 1, 1))
    return utterances[0]


def read_utterances(source: XmlSource, lexicon: GestureLexicon | None = None) -> tuple[Utterance, ...]:
    """Check ``source`` against the schema and read its utterances into the model."""
    validate_murml(source)
    root = source.root
    unit = _document_unit(source, root)
    lexicon = lexicon if lexicon is not None else load_lexicons(())
    if root.tag == "utterance":
        return (_UtteranceReader(source, unit, dict(lexicon.scene), lexicon).read(root),)
    scene = dict(lexicon.scene)
    for child in root.iterchildren("scene"):
        scene.update(read_scene(source, child, unit))
    return tuple(
        _UtteranceReader(source, _element_unit(source, child, unit), scene, lexicon).read(child)
        for child in root.iterchildren("utterance")
    )


def _document_unit(source: XmlSource, root: etree._Element) -> str:
    published = any(True for _ in root.iter("timing", "dynamicElement"))
    return _element_unit(source, root, "cm" if published else "mm")


def _element_unit(source: XmlSource, element: etree._Element, default: str) -> str:
    unit = element.get("unit")
    if unit is None:
        return default
    if unit not in UNIT_METRES:
        raise source.error(f"unknown unit {unit!r} (expected mm, cm or m)", element, "unit")
    return unit


@dataclass
class _UtteranceReader:
    source: XmlSource
    unit: str
    scene: dict[str, SceneLocation]
    lexicon: GestureLexicon
    tags: dict[str, TimeTag] = field(default_factory=dict)

    def read(self, utterance: etree._Element) -> Utterance:
        for child in utterance.iterchildren("scene"):
            self.scene.update(read_scene(self.source, child, self.unit))
        specification = utterance.find("specification")
        chunks = self._read_specification(specification) if specification is not None else ()
        behaviors: list[BehaviorSpec] = []
        errors: list[SpecError] = []
        seen: dict[str, etree._Element] = {}
        for index, element in enumerate(utterance.iterchildren("behaviorspec")):
            try:
                behavior = self._read_behavior(element, index)
            except SpecErrors as many:
                errors.extend(many.errors)
                continue
            except SpecError as error:
                errors.append(error)
                continue
            if behavior.id in seen:
                errors.append(self.source.error(f"behaviour id {behavior.id!r} is used twice", element, "id"))
                continue
            seen[behavior.id] = element
            behaviors.append(behavior)
        if not chunks and not behaviors and not errors:
            errors.append(self.source.error("utterance has neither spoken text nor behaviours", utterance))
        if errors:
            raise errors[0] if len(errors) == 1 else SpecErrors(errors)
        return Utterance(tuple(chunks), tuple(_with_untimed_scheduled(behaviors)), self.source.file)

    # -- speech ---------------------------------------------------------------------

    def _read_specification(self, specification: etree._Element) -> tuple[ChunkSpec, ...]:
        chunks: list[ChunkSpec] = []
        buffer = _TextBuffer()
        pending: list[tuple[etree._Element, int]] = []
        buffer.add(specification.text)
        for child in specification:
            if child.tag != "time":
                raise self.source.error(f"unexpected <{child.tag}> in the spoken text (only <time> tags may stand there)", child)
            tag_id = child.get("id", "")
            if not _NCNAME.match(tag_id):
                raise self.source.error(f"time tag id {tag_id!r} is not a valid name", child, "id")
            if tag_id in self.tags or any(tag_id == e.get("id") for e, _ in pending):
                raise self.source.error(f"time tag {tag_id!r} is defined twice", child, "id")
            if buffer.inside_word(child.tail):
                raise self.source.error(f"time tag {tag_id!r} stands inside a word; put it between words", child)
            pending.append((child, buffer.length))
            if _boolean(self.source, child, "chunkborder", False):
                chunks.append(self._close_chunk(len(chunks), buffer, pending, specification))
                buffer, pending = _TextBuffer(), []
            buffer.add(child.tail)
        if buffer.text or pending:
            chunks.append(self._close_chunk(len(chunks), buffer, pending, specification))
        return tuple(chunks)

    def _close_chunk(self, index: int, buffer: _TextBuffer, pending: list[tuple[etree._Element, int]], spec: etree._Element) -> ChunkSpec:
        text = buffer.text
        if not text:
            anchor = pending[-1][0] if pending else spec
            raise self.source.error(f"chunk {index + 1} has no words", anchor)
        tags = []
        for element, raw_offset in pending:
            offset = buffer.offset_in_text(raw_offset)
            tag = TimeTag(element.get("id"), index, offset, element.get("chunkborder", "").lower() in _TRUE, self.source.where(element))
            self.tags[tag.id] = tag
            tags.append(tag)
        return ChunkSpec(index, text, tuple(tags))

    # -- behaviours -----------------------------------------------------------------

    def _read_behavior(self, element: etree._Element, index: int) -> BehaviorSpec:
        behavior_id = element.get("id") or f"behavior_{index + 1}"
        content = [child for child in element if child.tag != "timing"]
        if len(content) != 1:
            raise self.source.error(f"behaviour {behavior_id!r} must hold exactly one behaviour element", element)
        body = content[0]
        timing_element = _timing_element(element, body)
        timing = self._read_timing(timing_element, behavior_id) if timing_element is not None else None
        gesture = self._read_gesture(body, behavior_id) if body.tag == "gesture" else None
        sign = self._read_sign(body, behavior_id) if body.tag == "sign" else None
        chunk = self.tags[timing.onset].chunk if isinstance(timing, Affiliate) else None
        return BehaviorSpec(behavior_id, body.tag, timing, gesture, chunk, self.source.where(element), sign)

    def _read_sign(self, element: etree._Element, behavior_id: str) -> Sign:
        """A sign behaviour: ``<hamnosys>`` text (HamNoSys 4 Unicode) or a SiGML
        ``<hns_sign>``/``<hamgestural_sign>`` element, beside its timing."""
        forms = [child for child in element if child.tag not in ("affiliate", "timing")]
        if len(forms) != 1 or forms[0].tag not in _SIGN_FORMS:
            raise self.source.error(f"sign {behavior_id!r} needs exactly one of <{'>, <'.join(_SIGN_FORMS)}>", element)
        form = forms[0]
        gloss = element.get("gloss") or form.get("gloss") or behavior_id
        if form.tag != "hamnosys":
            return read_sign_element(form, gloss, self.source.where)
        text = (form.text or "").strip()
        if not text:
            raise self.source.error(f"sign {behavior_id!r}: <hamnosys> is empty", form)
        try:
            return parse_hamnosys(text, gloss=gloss, file=str(self.source.where(form)))
        except SpecError as error:
            raise SpecError(error.message, self.source.where(form)) from None

    def _read_timing(self, element: etree._Element, behavior_id: str) -> Affiliate | AbsoluteTiming:
        onset_text, end_text = element.get("onset", ""), element.get("end", "")
        onset, end = float_or_none(onset_text), float_or_none(end_text)
        if element.tag == "timing" and onset is not None and end is not None:
            if onset < 0:
                raise self.source.error(f"timing of {behavior_id!r} starts before the utterance (onset {onset})", element, "onset")
            if end <= onset:
                raise self.source.error(f"timing of {behavior_id!r} ends at {end} s, not after its onset {onset} s", element, "end")
            return AbsoluteTiming(onset, end, self.source.where(element))
        return self._read_affiliate(element, onset_text, end_text, behavior_id)

    def _read_affiliate(self, element: etree._Element, onset: str, end: str, behavior_id: str) -> Affiliate:
        for attribute, tag_id in (("onset", onset), ("end", end)):
            if tag_id not in self.tags:
                known = ", ".join(sorted(self.tags)) or "none"
                raise self.source.error(f"behaviour {behavior_id!r}: {attribute} names unknown time tag {tag_id!r} (known: {known})", element, attribute)
        first, last = self.tags[onset], self.tags[end]
        if first.chunk != last.chunk:
            raise self.source.error(
                f"behaviour {behavior_id!r}: affiliate from {onset!r} (chunk {first.chunk + 1}) to {end!r} (chunk {last.chunk + 1}) crosses a chunk border",
                element,
                "end",
            )
        if last.offset < first.offset:
            raise self.source.error(f"behaviour {behavior_id!r}: affiliate ends at {end!r}, before its onset {onset!r}", element, "end")
        if last.offset == first.offset:
            raise self.source.error(f"behaviour {behavior_id!r}: affiliate from {onset!r} to {end!r} spans no words", element, "end")
        return Affiliate(onset, end, self.source.where(element))

    def _read_gesture(self, element: etree._Element, behavior_id: str) -> Gesture:
        scope = element.get("scope")
        function_element = element.find("function")
        if function_element is not None:
            name = function_element.get("name", "")
            params = {param.get("name"): param.get("value") for param in function_element.iterchildren("param")}
            call = FunctionCall(name, params, self.source.where(function_element))
            if self.lexicon.entry(name) is None:
                known = ", ".join(self.lexicon.functions) or "none"
                raise self.source.error(f"unknown gesture function {name!r} (the lexicon has: {known})", function_element, "name")
            return function_gesture(self.lexicon, call, scope, self.scene, element.get("id") or behavior_id, self.source.where(element))
        constraints = element.find("constraints")
        if constraints is None:
            raise self.source.error(f"gesture {behavior_id!r} needs <function> or <constraints>", element)
        reader = ConstraintReader(self.source, self.unit, self.scene, {}, symbols=self.lexicon.symbols)
        tree = reader.read_root(constraints, arm_or_none(scope))
        return Gesture(element.get("id") or behavior_id, tree, None, scope, self.source.where(element))


def _with_untimed_scheduled(behaviors: list[BehaviorSpec]) -> list[BehaviorSpec]:
    """Behaviours with every untimed gesture or sign given its absolute timing (module docstring)."""
    taken = sorted((b.timing.onset, b.timing.end) for b in behaviors if isinstance(b.timing, AbsoluteTiming))
    clock = UNTIMED_GAP
    scheduled = []
    for behavior in behaviors:
        if behavior.moves_arms and behavior.timing is None:
            clock = _free_slot(clock, taken)
            behavior = replace(behavior, timing=AbsoluteTiming(clock, clock + UNTIMED_STROKE, behavior.where))
            taken.append((clock, clock + UNTIMED_STROKE))
            clock += UNTIMED_STROKE + UNTIMED_GAP
        scheduled.append(behavior)
    return scheduled


def _free_slot(clock: float, taken: list[tuple[float, float]]) -> float:
    """The earliest onset from ``clock`` whose stroke keeps :data:`UNTIMED_GAP` from every taken one."""
    moved = True
    while moved:
        moved = False
        for onset, end in taken:
            if onset < clock + UNTIMED_STROKE + UNTIMED_GAP and end + UNTIMED_GAP > clock:
                clock, moved = end + UNTIMED_GAP, True
    return clock


def _timing_element(behaviorspec: etree._Element, body: etree._Element) -> etree._Element | None:
    for candidate in (body.find("affiliate"), body.find("timing"), behaviorspec.find("timing")):
        if candidate is not None:
            return candidate
    return None


@dataclass
class _TextBuffer:
    """Spoken text being collected with whitespace collapsed, and offsets into it."""

    raw: str = ""

    def add(self, text: str | None) -> None:
        if not text:
            return
        collapsed = re.sub(r"\s+", " ", text)
        if self.raw.endswith(" "):
            collapsed = collapsed.lstrip(" ")
        self.raw += collapsed

    @property
    def length(self) -> int:
        return len(self.raw)

    @property
    def text(self) -> str:
        return self.raw.strip()

    def inside_word(self, following: str | None) -> bool:
        before = self.raw[-1:] if self.raw else " "
        after = following[:1] if following else " "
        return before.isalnum() and after.isalnum()

    def offset_in_text(self, raw_offset: int) -> int:
        lead = len(self.raw) - len(self.raw.lstrip())
        text = self.text
        offset = min(max(raw_offset - lead, 0), len(text))
        while offset < len(text) and text[offset] == " ":
            offset += 1
        return offset


def _boolean(source: XmlSource, element: etree._Element, attribute: str, default: bool) -> bool:
    text = element.get(attribute)
    if text is None:
        return default
    if text.lower() in _TRUE:
        return True
    if text.lower() in _FALSE:
        return False
    raise source.error(f"{attribute} must be true or false, not {text!r}", element, attribute)
