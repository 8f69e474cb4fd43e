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

from collections.abc import Mapping

from mura.errors import SourceLocation, SpecError, SpecErrors
from mura.expansion import check_movements
from mura.gesture_functions import function_gesture as lexicon_gesture
from mura.hamnosys import parse_hamnosys
from mura.lexicon import GestureLexicon, SceneLocation, load_lexicons, read_scene
from mura.limits import DEFAULT_LIMITS, LimitError, Limits
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
from mura.space import SpatialReference
from mura.space_markup import is_spatial_sign, read_space, read_spatial_sign
from mura.xml_source import XmlSource

#: Stroke duration (s) given to a gesture written without timing, and the time (s) left
#: between two such strokes (module docstring).
UNTIMED_STROKE = 1.0
UNTIMED_GAP = 1.2

_NCNAME = re.compile(r"^[A-Za-z_][\w.\-]*$")
_SIGN_FORMS = ("hamnosys", "hns_sign", "hamgestural_sign")
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
    lexicon = lexicon if lexicon is not None else load_lexicons(())
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
    if unit not in UNIT_METRES:
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
        return Utterance(tuple(chunks), tuple(_with_untimed_scheduled(behaviors)), self.source.file, space=tuple(self.placed.values()))

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
        onset, end = float_or_none(onset_text), float_or_none(end_text)
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
            name = function_element.get("name", "")
            params = {param.get("name"): param.get("value") for param in function_element.iterchildren("param")}
            call = FunctionCall(name, params, self.source.where(function_element))
            if self.lexicon.entry(name) is None:
                known = ", ".join(self.lexicon.functions) or "none"
                raise self.source.error(f"unknown gesture function {name!r} (the lexicon has: {known})", function_element, "name")
            return function_gesture(call, element.get("id") or behavior_id, scope, self.lexicon, self.scene, self.source.where(element), self.limits)
        constraints = element.find("constraints")
        if constraints is None:
            raise self.source.error(f"gesture {behavior_id!r} needs <function> or <constraints>", element)
        reader = ConstraintReader(self.source, self.unit, self.scene, {}, symbols=self.lexicon.symbols, limits=self.limits, published=self.published)
        tree = reader.read_root(constraints, arm_or_none(scope))
        check_movements(tree, self.limits, f"gesture {behavior_id!r}", self.source.where(element))
        return Gesture(element.get("id") or behavior_id, tree, None, scope, self.source.where(element))


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
    call's place for an unknown function, a missing parameter or a problem in the entry);
    BML reads its function gestures with it. See :func:`mura.gesture_functions.function_gesture`."""
    return lexicon_gesture(lexicon, call, scope, scene, gesture_id, where, limits)


def read_gesture_element(
    source: XmlSource, element: etree._Element, behavior_id: str, lexicon: GestureLexicon, unit: str = "m",
    limits: Limits = DEFAULT_LIMITS,
) -> Gesture:
    """A MURML ``<gesture>``-like element (``<function>`` or ``<constraints>`` inside, plain
    names without a namespace) read as the MURML reader reads it; lengths without a unit are
    in ``unit``. BML reads the MURML gestures it embeds with it."""
    return _UtteranceReader(source, unit, dict(lexicon.scene), lexicon, limits)._read_gesture(element, behavior_id)


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
