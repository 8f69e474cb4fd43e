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

**Head and gaze values** (``GazeDirection``, ``Neck``, ``HeadDirection``): a ``Dir…``
name or three numbers are a direction from the eyes in the avatar frame; with
``mode="pointTo"`` three numbers are a position like any other (the document's unit,
relative to the root joint); ``$place`` and grid names are places. The published dialect
writes gaze vectors in its own frame — x ahead, y up, z to the avatar's right, judging by
its files (``1000 -500 0`` looks ahead and down, ``1000 -500 1000`` down toward the right
hand's periphery) — and, ``pointTo`` or not, as seen from the eyes: mura reads them as
directions in that frame. Any other word (``Nod``, ``Listener``, ``RightHand`` …) is kept
as a :class:`~mura.values.Symbol` for ``motor/`` to read; so is the value of the other
non-arm slots (``FaceExpression``, ``Mouth``, ``Shoulders``, ``Torso``) when it is not a
vector, a direction or a place.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from lxml import etree

from mura import murml_vocabulary as vocabulary
from mura.constraints import (
    ARM_SLOTS,
    OTHER_SLOTS,
    Arm,
    Constraint,
    Dynamic,
    Parallel,
    Repetition,
    Segment,
    SegmentKind,
    Sequence,
    Static,
    Symmetrical,
    Symmetry,
)
from mura.errors import SourceLocation, SpecError, SpecErrors
from mura.expansion import check_movements
from mura.hamnosys import parse_hamnosys
from mura.lexicon import (
    GestureLexicon,
    SceneLocation,
    bind_params,
    load_lexicon,
    read_scene,
)
from mura.limits import DEFAULT_LIMITS, LimitError, Limits, hint
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
from mura.schema import validate_murml
from mura.sigml import read_sign_element
from mura.signs import Sign
from mura.space import SpatialReference
from mura.space_markup import is_spatial_sign, read_space, read_spatial_sign
from mura.values import (
    Direction,
    Location,
    PalmOrientation,
    PointLocation,
    SlotValue,
    Symbol,
    Vector,
)
from mura.xml_source import XmlSource

_UNIT_METRES = {"mm": 0.001, "cm": 0.01, "m": 1.0}
_NUMBER = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(mm|cm|m)?\s*$")
_NCNAME = re.compile(r"^[A-Za-z_][\w.\-]*$")
_SYMMETRY = re.compile(r"^Sym(?:M([STF]+))?$")
_EXTENTS = {"Flat": 0.25, "Normal": 0.5, "Large": 0.75}
_ROUNDNESS = {"Sharpe": 0.9, "Sharp": 0.9, "Normal": 0.0, "Broad": -0.9}
_SKEWEDNESS = {"Round": 0.0, "FunnelS": -0.9, "FunnelE": 0.9}
_SEGMENT_VALUE_TYPES = ("start", "end", "direction", "distance", "normal", "shape", "extent", "extension", "roundness", "skewedness")
_SIGN_FORMS = ("hamnosys", "hns_sign", "hamgestural_sign")
#: Slots whose values aim the eyes or the head (see *Head and gaze values*).
_HEAD_SLOTS = ("GazeDirection", "Neck", "HeadDirection")
_TRUE = {"true", "1", "yes"}
_FALSE = {"false", "0", "no"}


def load_utterances(path: str | Path, lexicon: GestureLexicon | None = None, limits: Limits = DEFAULT_LIMITS) -> tuple[Utterance, ...]:
    """Every utterance of a MURML file, checked (also against ``limits``); raises :class:`SpecError` on the first problems."""
    return read_utterances(XmlSource.from_path(path, limits=limits), lexicon, limits)


def load_utterance(path: str | Path, lexicon: GestureLexicon | None = None, limits: Limits = DEFAULT_LIMITS) -> Utterance:
    """The single utterance of a MURML file."""
    return _single(load_utterances(path, lexicon, limits), str(path))


def parse_utterance(data: str | bytes, file: str = "<input>", lexicon: GestureLexicon | None = None,
                    limits: Limits = DEFAULT_LIMITS) -> Utterance:
    """The single utterance of a MURML document given as text."""
    raw = data.encode("utf-8") if isinstance(data, str) else data
    return _single(read_utterances(XmlSource.from_bytes(raw, file, limits=limits), lexicon, limits), file)


def _single(utterances: tuple[Utterance, ...], file: str) -> Utterance:
    if len(utterances) != 1:
        raise SpecError(f"expected one utterance, found {len(utterances)}", SourceLocation(file, 1, 1))
    return utterances[0]


def read_utterances(source: XmlSource, lexicon: GestureLexicon | None = None, limits: Limits = DEFAULT_LIMITS) -> tuple[Utterance, ...]:
    """Check ``source`` against the schema and ``limits``, and read its utterances into the model."""
    validate_murml(source)
    root = source.root
    unit = _document_unit(source, root)
    lexicon = lexicon if lexicon is not None else load_lexicon()
    if root.tag == "utterance":
        return (_UtteranceReader(source, unit, dict(lexicon.scene), lexicon, limits, published=_is_published(root)).read(root),)
    scene = dict(lexicon.scene)
    for child in root.iterchildren("scene"):
        scene.update(read_scene(source, child, unit))
    placed: dict[str, SpatialReference] = {}
    for child in root.iterchildren("space"):
        read_space(source, child, placed)
    return tuple(
        _UtteranceReader(source, _element_unit(source, child, unit), scene, lexicon, limits, placed=dict(placed), published=_is_published(root)).read(child)
        for child in root.iterchildren("utterance")
    )


def _document_unit(source: XmlSource, root: etree._Element) -> str:
    return _element_unit(source, root, "cm" if _is_published(root) else "mm")


def _is_published(root: etree._Element) -> bool:
    """Whether a document is in the published dialect (module docstring)."""
    return any(True for _ in root.iter("timing", "dynamicElement"))


def _element_unit(source: XmlSource, element: etree._Element, default: str) -> str:
    unit = element.get("unit")
    if unit is None:
        return default
    if unit not in _UNIT_METRES:
        raise source.error(f"unknown unit {unit!r} (expected mm, cm or m)", element, "unit")
    return unit


@dataclass
class _UtteranceReader:
    source: XmlSource
    unit: str
    scene: dict[str, SceneLocation]
    lexicon: GestureLexicon
    limits: Limits = DEFAULT_LIMITS
    tags: dict[str, TimeTag] = field(default_factory=dict)
    placed: dict[str, SpatialReference] = field(default_factory=dict)
    published: bool = False

    def read(self, utterance: etree._Element) -> Utterance:
        for child in utterance.iterchildren("scene"):
            self.scene.update(read_scene(self.source, child, self.unit))
        for child in utterance.iterchildren("space"):
            read_space(self.source, child, self.placed)
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
        return Utterance(tuple(chunks), tuple(behaviors), self.source.file, space=tuple(self.placed.values()))

    # -- speech ---------------------------------------------------------------------

    def _read_specification(self, specification: etree._Element) -> tuple[ChunkSpec, ...]:
        chunks: list[ChunkSpec] = []
        buffer = _TextBuffer()
        pending: list[tuple[etree._Element, int]] = []
        opening = specification  # where the chunk being collected begins, for messages
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
                chunks.append(self._close_chunk(len(chunks), buffer, pending, specification, opening))
                buffer, pending, opening = _TextBuffer(), [], child
            buffer.add(child.tail)
        if buffer.text or pending:
            chunks.append(self._close_chunk(len(chunks), buffer, pending, specification, opening))
        return tuple(chunks)

    def _close_chunk(self, index: int, buffer: _TextBuffer, pending: list[tuple[etree._Element, int]], spec: etree._Element,
                     opening: etree._Element) -> ChunkSpec:
        text = buffer.text
        if not text:
            anchor = pending[-1][0] if pending else spec
            raise self.source.error(f"chunk {index + 1} has no words", anchor)
        try:
            self.limits.check_chunk_text(text, f"chunk {index + 1}")
        except LimitError as error:
            raise self.source.error(f"{error}; put chunk borders between its phrases", opening) from None
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
        spatial = read_spatial_sign(self.source, body, behavior_id, self.placed) if body.tag == "sign" and is_spatial_sign(body) else None
        sign = self._read_sign(body, behavior_id) if body.tag == "sign" and spatial is None else None
        if (gesture is not None or sign is not None or spatial is not None) and timing is None:
            raise self.source.error(f"{body.tag} {behavior_id!r} has neither an <affiliate> nor a <timing>", body)
        chunk = self.tags[timing.onset].chunk if isinstance(timing, Affiliate) else None
        return BehaviorSpec(behavior_id, body.tag, timing, gesture, chunk, self.source.where(element), sign, spatial=spatial)

    def _read_sign(self, element: etree._Element, behavior_id: str) -> Sign:
        """A sign behaviour: ``<hamnosys>`` text (HamNoSys 4 Unicode) or a SiGML
        ``<hns_sign>``/``<hamgestural_sign>`` element, beside its timing."""
        forms = [child for child in element if child.tag not in ("affiliate", "timing")]
        if len(forms) != 1 or forms[0].tag not in _SIGN_FORMS:
            raise self.source.error(f"sign {behavior_id!r} needs exactly one of <{'>, <'.join(_SIGN_FORMS)}>", element)
        form = forms[0]
        gloss = element.get("gloss") or form.get("gloss") or behavior_id
        if form.tag != "hamnosys":
            return read_sign_element(form, gloss, self.source.where, self.limits)
        text = (form.text or "").strip()
        if not text:
            raise self.source.error(f"sign {behavior_id!r}: <hamnosys> is empty", form)
        try:
            return parse_hamnosys(text, gloss=gloss, file=str(self.source.where(form)), limits=self.limits)
        except SpecError as error:
            raise SpecError(error.message, self.source.where(form)) from None

    def _read_timing(self, element: etree._Element, behavior_id: str) -> Affiliate | AbsoluteTiming:
        onset_text, end_text = element.get("onset", ""), element.get("end", "")
        if element.tag == "timing":
            self._check_times(element, behavior_id, onset_text, end_text)
        onset, end = _float_or_none(onset_text), _float_or_none(end_text)
        if element.tag == "timing" and onset is not None and end is not None:
            if onset < 0:
                raise self.source.error(f"timing of {behavior_id!r} starts before the utterance (onset {onset})", element, "onset")
            if end <= onset:
                raise self.source.error(f"timing of {behavior_id!r} ends at {end} s, not after its onset {onset} s", element, "end")
            return AbsoluteTiming(onset, end, self.source.where(element))
        return self._read_affiliate(element, onset_text, end_text, behavior_id)

    def _check_times(self, element: etree._Element, behavior_id: str, *texts: str) -> None:
        """Times on the utterance clock must be finite and within ``limits.max_duration``
        (not ``nan``, ``1e300``, or a day of animation)."""
        for attribute, text in zip(("onset", "end"), texts):
            if text in self.tags:
                continue
            try:
                seconds = float(text)
            except ValueError:
                continue
            try:
                self.limits.check_time(seconds, f"timing {attribute} of {behavior_id!r}:")
            except LimitError as error:
                raise self.source.error(str(error), element, attribute) from None

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
            return self._read_function_gesture(function_element, element, behavior_id, scope)
        constraints = element.find("constraints")
        if constraints is None:
            raise self.source.error(f"gesture {behavior_id!r} needs <function> or <constraints>", element)
        reader = _ConstraintReader(self.source, self.unit, self.scene, {}, limits=self.limits, published=self.published)
        tree = reader.read_root(constraints, _arm_or_none(scope))
        check_movements(tree, self.limits, f"gesture {behavior_id!r}", self.source.where(element))
        return Gesture(element.get("id") or behavior_id, tree, None, scope, self.source.where(element))

    def _read_function_gesture(self, function: etree._Element, gesture: etree._Element, behavior_id: str, scope: str | None) -> Gesture:
        name = function.get("name", "")
        params = {param.get("name"): param.get("value") for param in function.iterchildren("param")}
        if self.lexicon.entry(name) is None:
            known = ", ".join(sorted(self.lexicon.entries)) or "none"
            raise self.source.error(f"unknown gesture function {name!r} (the lexicon has: {known})", function, "name")
        call = FunctionCall(name, params, self.source.where(function))
        return function_gesture(call, gesture.get("id") or behavior_id, scope, self.lexicon, self.scene, self.source.where(gesture), self.limits)


def function_gesture(
    call: FunctionCall,
    gesture_id: str,
    scope: str | None,
    lexicon: GestureLexicon,
    scene: Mapping[str, SceneLocation],
    where: SourceLocation | None,
    limits: Limits = DEFAULT_LIMITS,
) -> Gesture:
    """The gesture a lexicon function makes for ``call`` (raises :class:`SpecError` at the
    call's place for an unknown function or a missing parameter); also read by BML."""
    entry = lexicon.entry(call.name)
    if entry is None:
        known = ", ".join(sorted(lexicon.entries)) or "none"
        raise SpecError(f"unknown gesture function {call.name!r} (the lexicon has: {known})", call.where)
    try:
        bound = bind_params(entry, call.params)
    except ValueError as error:
        raise SpecError(str(error), call.where) from None
    reader = _ConstraintReader(entry.source, lexicon.unit, scene, bound, call_site=call.where, limits=limits)
    tree = reader.read_root(entry.constraints, _arm_or_none(scope))
    check_movements(tree, limits, f"gesture {gesture_id!r}", where)
    return Gesture(gesture_id, tree, call, scope, where)


def read_gesture_element(
    source: XmlSource, element: etree._Element, behavior_id: str, lexicon: GestureLexicon, unit: str = "m",
    limits: Limits = DEFAULT_LIMITS,
) -> Gesture:
    """A MURML ``<gesture>``-like element (``<function>`` or ``<constraints>`` inside, plain
    names without a namespace) read as the MURML reader reads it; lengths without a unit are
    in ``unit``. BML reads the MURML gestures it embeds with it."""
    return _UtteranceReader(source, unit, dict(lexicon.scene), lexicon, limits)._read_gesture(element, behavior_id)


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


@dataclass
class _ConstraintReader:
    """Reads a constraint tree, filling ``$param`` placeholders and resolving scene places."""

    source: XmlSource
    unit: str
    scene: Mapping[str, SceneLocation]
    params: Mapping[str, str]
    call_site: SourceLocation | None = None
    limits: Limits = DEFAULT_LIMITS
    published: bool = False

    def read_root(self, constraints: etree._Element, scope: Arm | None) -> Constraint:
        children = list(constraints)
        if len(children) != 1:
            raise self._error(f"<{constraints.tag}> must hold exactly one constraint, found {len(children)}", constraints)
        return self.read(children[0], self._scope(constraints) or scope)

    def read(self, element: etree._Element, scope: Arm | None) -> Constraint:
        scope = self._scope(element) or scope
        where = self.source.where(element)
        tag = element.tag
        if tag in ("parallel", "sequence"):
            children = tuple(self.read(child, scope) for child in element)
            if not children:
                raise self._error(f"<{tag}> is empty", element)
            return Parallel(children, where) if tag == "parallel" else Sequence(children, where)
        if tag == "symmetrical":
            return self._symmetrical(element, where)
        if tag == "repetition":
            return self._repetition(element, scope, where)
        if tag == "static":
            return self._static(element, scope, where)
        if tag == "dynamic":
            return self._dynamic(element, scope, where)
        raise self._error(f"unknown constraint <{tag}> (expected parallel, sequence, symmetrical, repetition, static or dynamic)", element)

    def _symmetrical(self, element: etree._Element, where: SourceLocation) -> Symmetrical:
        dominant = _arm_or_none(self._attr(element, "dominant"))
        if dominant is None:
            raise self._error(f"dominant {element.get('dominant')!r} is not an arm (expected right_arm or left_arm)", element, "dominant")
        symmetry = self._symmetry(element)
        center = None
        if element.get("center") is not None:
            center = self._numbers(element, "center", None)
        children = list(element)
        if len(children) != 1:
            raise self._error(f"<symmetrical> must hold exactly one constraint, found {len(children)}", element)
        return Symmetrical(self.read(children[0], dominant), dominant, symmetry, center, where)

    def _symmetry(self, element: etree._Element) -> Symmetry:
        name = self._attr(element, "symmetry")
        match = _SYMMETRY.match(name)
        if match is None or (match.group(1) and len(set(match.group(1))) != len(match.group(1))):
            raise self._error(f"unknown symmetry {name!r} (expected Sym, SymMS, SymMT, SymMF or a combination such as SymMST)", element, "symmetry")
        planes = frozenset(match.group(1) or "S")
        return Symmetry(planes, name)

    def _repetition(self, element: etree._Element, scope: Arm | None, where: SourceLocation) -> Repetition:
        attribute = "count" if element.get("count") is not None else "number"
        text = element.get(attribute, "2")
        digits = text.strip()
        if not (digits.isascii() and digits.isdigit()) or not digits.strip("0"):
            raise self._error(f"repetition {attribute} {text!r} is not a positive whole number", element, attribute)
        significant = digits.lstrip("0")
        if len(significant) > 18 or int(significant) > self.limits.max_movements:
            raise self._error(f"repetition {attribute} {significant[:20]} is more than the limit of {self.limits.max_movements} "
                              f"movements ({hint('max_movements')})", element, attribute)
        children = list(element)
        if len(children) != 1:
            raise self._error(f"<repetition> must hold exactly one constraint, found {len(children)}", element)
        return Repetition(self.read(children[0], scope), int(significant), where)

    def _static(self, element: etree._Element, scope: Arm | None, where: SourceLocation) -> Static:
        slot = self._slot(element)
        mode = element.get("mode")
        value = self._slot_value(slot, self._attr(element, "value"), mode, element, "value")
        return Static(slot, value, self._leaf_scope(element, slot, scope), mode, where)

    def _dynamic(self, element: etree._Element, scope: Arm | None, where: SourceLocation) -> Dynamic:
        slot = self._slot(element)
        segments = tuple(self._segment(child, slot) for child in element)
        if not segments:
            raise self._error(f"dynamic {slot} has no segments", element)
        return Dynamic(slot, segments, self._leaf_scope(element, slot, scope), where)

    def _leaf_scope(self, element: etree._Element, slot: str, scope: Arm | None) -> Arm | str | None:
        if slot in ARM_SLOTS:
            return scope if scope is not None else Arm.RIGHT
        return element.get("scope")

    def _slot(self, element: etree._Element) -> str:
        slot = self._attr(element, "slot")
        if slot not in ARM_SLOTS and slot not in OTHER_SLOTS:
            raise self._error(f"unknown slot {slot!r} (expected one of {', '.join(ARM_SLOTS + OTHER_SLOTS)})", element, "slot")
        return slot

    def _segment(self, element: etree._Element, slot: str) -> Segment:
        if element.tag not in ("segment", "dynamicElement"):
            raise self._error(f"unexpected <{element.tag}> in <dynamic> (expected <segment> or <dynamicElement>)", element)
        kind_name = element.get("type", "linear")
        try:
            kind = SegmentKind(kind_name)
        except ValueError:
            raise self._error(f"unknown segment type {kind_name!r} (expected linear, curve or circle)", element, "type") from None
        fields: dict[str, object] = {}
        for value in element:
            if value.tag != "value":
                raise self._error(f"unexpected <{value.tag}> in <{element.tag}> (expected <value>)", value)
            value_type = value.get("type", "")
            if value_type not in _SEGMENT_VALUE_TYPES:
                raise self._error(f"unknown segment value type {value_type!r} (expected one of {', '.join(_SEGMENT_VALUE_TYPES)})", value, "type")
            key = "extent" if value_type == "extension" else value_type
            if key in fields:
                raise self._error(f"segment gives its {key} twice", value, "type")
            attribute = "name" if value.get("name") is not None else "value"
            fields[key] = self._segment_value(slot, key, self._attr(value, attribute), value, attribute)
        segment = Segment(kind=kind, where=self.source.where(element), **fields)  # type: ignore[arg-type]
        self._check_segment(segment, slot, element)
        return segment

    def _segment_value(self, slot: str, key: str, text: str, element: etree._Element, attribute: str) -> object:
        if key in ("start", "end"):
            return self._slot_value(slot, text, None, element, attribute)
        if key in ("direction", "normal"):
            return self._direction(text, element, attribute)
        if key == "distance":
            return self._distance(text, element, attribute)
        if key == "shape":
            if text not in vocabulary.CURVE_SHAPES:
                raise self._error(f"unknown curve shape {text!r} (expected {', '.join(vocabulary.CURVE_SHAPES)})", element, attribute)
            return text
        table = {"extent": _EXTENTS, "roundness": _ROUNDNESS, "skewedness": _SKEWEDNESS}[key]
        return self._scalar(text, table, key, element, attribute)

    def _check_segment(self, segment: Segment, slot: str, element: etree._Element) -> None:
        if slot != "HandLocation":
            if segment.start is None and segment.end is None:
                raise self._error(f"a {slot} segment needs a start or an end value", element)
            return
        has_path = segment.end is not None or (segment.direction is not None and segment.distance is not None)
        if not has_path:
            raise self._error("a HandLocation segment needs an end, or a direction and a distance", element)
        if segment.kind is SegmentKind.CURVE and segment.end is None:
            raise self._error("a curve segment needs an end", element)
        if segment.distance is not None and segment.distance <= 0:
            raise self._error(f"segment distance must be positive, got {segment.distance} m", element)

    # -- values ---------------------------------------------------------------------

    def _slot_value(self, slot: str, text: str, mode: str | None, element: etree._Element, attribute: str) -> SlotValue:
        try:
            return self._parse_slot_value(slot, text, mode, element, attribute)
        except SpecError:
            raise
        except ValueError as error:
            raise self._error(f"{slot}: {error}", element, attribute) from None

    def _parse_slot_value(self, slot: str, text: str, mode: str | None, element: etree._Element, attribute: str) -> SlotValue:
        if slot == "HandShape":
            return vocabulary.parse_handshape(text)
        if slot == "HandLocation" or (mode == "pointTo" and slot in ("ExtFingerOrientation", "PalmOrientation")):
            return self._location(text, element, attribute)
        if slot == "ExtFingerOrientation":
            return self._direction(text, element, attribute)
        if slot == "PalmOrientation":
            if _is_numbers(text):
                return PalmOrientation(self._direction(text, element, attribute).vector, text, mode == "relative")
            palm = vocabulary.parse_palm_orientation(text)
            return PalmOrientation(palm.direction, palm.name, mode == "relative")
        if slot in _HEAD_SLOTS:
            return self._head_value(text, mode, element, attribute)
        if _is_numbers(text):
            return Vector(tuple(float(part) for part in text.split()))
        if text.startswith("Dir"):
            return vocabulary.parse_direction(text)
        if text.startswith("$"):
            return self._location(text, element, attribute)
        if not text.strip():
            raise ValueError("empty value")
        return Symbol(text.strip())

    def _head_value(self, text: str, mode: str | None, element: etree._Element, attribute: str) -> SlotValue:
        """A gaze or head value (module docstring, *Head and gaze values*)."""
        if _is_numbers(text):
            if self.published:
                x, y, z = self._three(self._numbers(element, attribute, None, text), text)
                return Direction(self._direction(f"{-z} {y} {x}", element, attribute).vector, text)
            if mode == "pointTo":
                return self._location(text, element, attribute)
            return self._direction(text, element, attribute)
        if text.startswith("Dir"):
            return self._direction(text, element, attribute)
        if text.startswith("$") or text.startswith("Loc"):
            return self._location(text, element, attribute)
        if not text.strip():
            raise ValueError("empty value")
        return Symbol(text.strip())

    @staticmethod
    def _three(values: tuple[float, ...], text: str) -> tuple[float, float, float]:
        if len(values) != 3:
            raise ValueError(f"a gaze or head vector needs three numbers, got {text!r}")
        return values[0], values[1], values[2]

    def _location(self, text: str, element: etree._Element, attribute: str) -> Location:
        if text.startswith("$"):
            return self._scene_location(text[1:], element, attribute)
        if _is_numbers(text):
            values = self._numbers_text(text, element, attribute, self.unit)
            if len(values) != 3:
                raise ValueError(f"a position needs three numbers, got {len(values)}")
            return PointLocation(values)  # type: ignore[arg-type]
        return vocabulary.parse_grid_location(text)

    def _scene_location(self, name: str, element: etree._Element, attribute: str) -> Location:
        place = self.scene.get(name)
        if place is None:
            known = ", ".join(sorted(self.scene)) or "none"
            raise ValueError(f"unknown place ${name} (the scene has: {known})")
        if not place.is_position:
            return vocabulary.parse_grid_location(place.text)
        values = self._numbers_text(place.text, place.element, "position", place.unit)
        if len(values) != 3:
            raise ValueError(f"place ${name} needs three numbers, got {len(values)}")
        return PointLocation(values)  # type: ignore[arg-type]

    def _direction(self, text: str, element: etree._Element, attribute: str) -> Direction:
        if text.startswith("Dir"):
            try:
                return vocabulary.parse_direction(text)
            except ValueError as error:
                raise self._error(str(error), element, attribute) from None
        values = self._numbers(element, attribute, None, text)
        if len(values) != 3:
            raise self._error(f"a direction needs three numbers or a Dir… name, got {text!r}", element, attribute)
        norm = sum(v * v for v in values) ** 0.5
        if norm < 1e-12:
            raise self._error(f"direction {text!r} has zero length", element, attribute)
        return Direction((values[0] / norm, values[1] / norm, values[2] / norm), text)

    def _distance(self, text: str, element: etree._Element, attribute: str) -> float:
        if text in vocabulary.DISTANCES:
            return vocabulary.DISTANCES[text]
        expected = f"a distance is one number or one of {', '.join(vocabulary.DISTANCES)}, not {text!r}"
        if not _is_numbers(text) or len(text.split()) != 1:
            raise self._error(expected, element, attribute)
        return self._numbers(element, attribute, self.unit, text)[0]

    def _scalar(self, text: str, names: Mapping[str, float], key: str, element: etree._Element, attribute: str) -> float:
        if text in names:
            return names[text]
        value = _float_or_none(text)
        if value is None:
            raise self._error(f"{key} {text!r} is neither a number nor one of {', '.join(names)}", element, attribute)
        return value

    def _numbers(self, element: etree._Element, attribute: str, unit: str | None, text: str | None = None) -> tuple[float, ...]:
        text = self._attr(element, attribute) if text is None else text
        try:
            return self._numbers_text(text, element, attribute, unit)
        except ValueError as error:
            raise self._error(str(error), element, attribute) from None

    def _numbers_text(self, text: str, element: etree._Element, attribute: str, unit: str | None) -> tuple[float, ...]:
        values = []
        for part in text.split():
            match = _NUMBER.match(part)
            if match is None:
                raise ValueError(f"{part!r} is not a number")
            number = float(match.group(1))
            if not math.isfinite(number):
                raise ValueError(f"{part!r} is too large to be a number")
            if unit is not None:
                number *= _UNIT_METRES[match.group(2) or unit]
                self.limits.check_length(number, f"length {part!r} =")
            elif match.group(2):
                raise ValueError(f"{part!r} takes no unit here")
            values.append(number)
        if not values:
            raise ValueError("expected numbers, found none")
        return tuple(values)

    def _scope(self, element: etree._Element) -> Arm | None:
        scope = element.get("scope")
        if scope is not None and scope.startswith("$") and scope[1:] in self.params:
            scope = self.params[scope[1:]]
        return _arm_or_none(scope)

    def _attr(self, element: etree._Element, name: str) -> str:
        value = element.get(name)
        if value is None:
            raise self._error(f"<{element.tag}> needs a {name} attribute", element)
        if value.startswith("$") and value[1:] in self.params:
            return self.params[value[1:]]
        return value

    def _error(self, message: str, element: etree._Element, attribute: str | None = None) -> SpecError:
        if self.call_site is not None:
            where = self.source.where(element, attribute)
            return SpecError(f"{message} (in the lexicon at {where})", self.call_site)
        return self.source.error(message, element, attribute)


def _arm_or_none(scope: str | None) -> Arm | None:
    if scope is None:
        return None
    normalized = scope.strip().replace(" ", "_").lower()
    for arm in Arm:
        if normalized == arm.value:
            return arm
    return None


def _boolean(source: XmlSource, element: etree._Element, attribute: str, default: bool) -> bool:
    text = element.get(attribute)
    if text is None:
        return default
    if text.lower() in _TRUE:
        return True
    if text.lower() in _FALSE:
        return False
    raise source.error(f"{attribute} must be true or false, not {text!r}", element, attribute)


def _float_or_none(text: str) -> float | None:
    try:
        value = float(text)
    except ValueError:
        return None
    return value if value == value and abs(value) != float("inf") else None


def _is_numbers(text: str) -> bool:
    parts = text.split()
    return bool(parts) and all(_NUMBER.match(part) for part in parts)
