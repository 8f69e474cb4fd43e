"""Reading BML 1.0 blocks into the model of :mod:`mura.model`, the one MURML utterances use.

A ``<bml id composition characterId>`` block (namespace :data:`BML_NAMESPACE`) becomes one
:class:`~mura.model.Utterance`:

* each ``<speech>`` is one chunk, in document order (one voice speaks them one after the
  other); its ``<text>`` is the chunk's text and each ``<sync id>`` marker a time tag named
  ``SPEECH:SYNC``; ``SPEECH:start`` and ``SPEECH:end`` are tags at the text's two ends;
* ``<gesture lexeme mode>``, ``<pointing target mode>`` and MURML gestures embedded as
  AsapRealizer embeds them (``<murmlgesture>`` in :data:`MURML_NAMESPACE` holding a
  ``<murml-description>`` with a MURML constraint tree or ``<function>``) become gesture
  behaviours, resolved through the gesture lexicon like MURML's functions;
* ``<head>``, ``<headDirectionShift>``, ``<gaze>``, ``<gazeShift>``, ``<faceLexeme>``,
  ``<faceFacs>``, ``<faceShift>``, ``<posture>`` and ``<postureShift>`` become behaviours
  with their attributes as ``params``: they are timed like every behaviour, but no motor
  module performs them yet (a warning says so);
* every sync-point attribute (``stroke="s1:tm1+0.2"``, ``start="1.5"``) and every
  ``<constraint>`` (``<synchronize>``, ``<before>``, ``<after>`` over ``<sync ref>``
  elements) becomes a :class:`~mura.model.SyncConstraint` of the utterance; the scheduler
  solves them in the same temporal network as MURML's affiliates.

What the spec lets a realizer refuse is refused politely: an unknown or unsupported
behaviour (``<locomotion>``, an unknown gesture lexeme, a pointing target the scene does
not have), an unknown attribute or an element of another namespace is left out with a
:class:`BmlWarning` and the rest of the block runs — unless it stands inside
``<required>``, where it fails the block. What is not BML (malformed XML, a missing id,
a reference to a behaviour or sync point that does not exist, a negative or non-numeric
time) is a :class:`SpecError` naming file, line and column.

Behaviours are timed chunk by chunk: a behaviour goes with the first speech it is tied to
(directly or through other behaviours' constraints), or with the first chunk when it is
tied to none; a constraint between two chunks is solved with the later one, the earlier
times fixed.
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path

from lxml import etree

from mura.constraints import Arm, Constraint, Symmetrical, Symmetry, iter_leaves
from mura.errors import SourceLocation, SpecError, SpecErrors
from mura.lexicon import GestureLexicon, load_lexicon
from mura.model import (
    BML_SYNC_PEGS,
    BehaviorSpec,
    ChunkSpec,
    FunctionCall,
    Gesture,
    SyncConstraint,
    SyncRef,
    SyncTiming,
    TimeTag,
    Utterance,
)
from mura.bml_vocabulary import (
    BEHAVIORS,
    BML_NAMESPACE,
    COMPOSITIONS,
    GAZE_INFLUENCES,
    GESTURE_LEXEMES,
    HEAD_LEXEMES,
    MODES,
    MURML_NAMESPACE,
)
from mura.bml_head import HEAD_SCOPE, HEAD_SLOTS, head_constraint
from mura.bml_sync import NAME, chunks_of, number, parse_reference
from mura.murml import function_gesture, read_gesture_element
from mura.xml_source import XmlSource

__all__ = ["BML_NAMESPACE", "MURML_NAMESPACE", "BmlBlock", "BmlWarning", "is_bml", "load_bml", "parse_bml", "read_bml"]

_NUMERIC = {"repetition": "count", "amount": "number", "offsetAngle": "number", "au": "count"}


@dataclass(frozen=True)
class BmlWarning:
    """Something of a block that mura leaves out or does not perform, and where.

    ``kind``: ``UNKNOWN_BEHAVIOR``, ``UNSUPPORTED_BEHAVIOR``, ``CANNOT_REALIZE``,
    ``NOT_PERFORMED``, ``UNKNOWN_ATTRIBUTE``, ``EXTENSION_IGNORED``, ``CONSTRAINT_DROPPED``.
    """

    kind: str
    message: str
    where: SourceLocation

    def __str__(self) -> str:
        return f"{self.where}: warning: {self.message}"


@dataclass(frozen=True)
class BmlBlock:
    """One BML block read into the model, with what the block-level feedback needs.

    ``sync_points`` gives each behaviour's BML sync points (a speech's are ``start``,
    ``end`` and its ``<sync>`` ids); ``kinds`` its element name; ``performed`` the ids of the
    behaviours a motor module (or the voice) performs.
    """

    id: str
    composition: str
    character: str | None
    utterance: Utterance
    warnings: tuple[BmlWarning, ...]
    sync_points: Mapping[str, tuple[str, ...]]
    kinds: Mapping[str, str]
    performed: frozenset[str]
    where: SourceLocation = field(compare=False, default=SourceLocation("<input>"))


def is_bml(root: etree._Element) -> bool:
    """True when ``root`` is a BML block (``<bml>`` in the BML 1.0 namespace, or without one)."""
    return isinstance(root.tag, str) and etree.QName(root).localname == "bml" and etree.QName(root).namespace in (BML_NAMESPACE, None)


def load_bml(path: str | Path, lexicon: GestureLexicon | None = None) -> BmlBlock:
    """The BML block of a file; raises :class:`SpecError` naming where it is wrong."""
    return read_bml(XmlSource.from_path(path), lexicon)


def parse_bml(data: str | bytes, file: str = "<bml>", lexicon: GestureLexicon | None = None) -> BmlBlock:
    """The BML block given as text."""
    raw = data.encode("utf-8") if isinstance(data, str) else data
    return read_bml(XmlSource.from_bytes(raw, file), lexicon)


def read_bml(source: XmlSource, lexicon: GestureLexicon | None = None) -> BmlBlock:
    """Read and check the block at ``source``'s root (see the module docstring)."""
    return _BlockReader(source, lexicon if lexicon is not None else load_lexicon()).read()


@dataclass
class _Behavior:
    """A behaviour element found in the block, before it becomes part of the model."""

    id: str
    kind: str
    element: etree._Element
    required: bool
    dropped: bool = False


@dataclass
class _BlockReader:
    source: XmlSource
    lexicon: GestureLexicon
    warnings: list[BmlWarning] = field(default_factory=list)
    errors: list[SpecError] = field(default_factory=list)
    behaviors: dict[str, _Behavior] = field(default_factory=dict)
    speech_syncs: dict[str, tuple[str, ...]] = field(default_factory=dict)
    constraints: list[SyncConstraint] = field(default_factory=list)
    block_id: str = ""
    _points: dict[str, tuple[str, ...]] | None = None
    _kinds: dict[str, str] = field(default_factory=dict)

    # -- the block --------------------------------------------------------------------

    def read(self) -> BmlBlock:
        root = self.source.root
        if not is_bml(root):
            raise self.source.error(f"not a BML block: the root is <{etree.QName(root).localname}>, expected <bml>", root)
        if etree.QName(root).namespace is None:
            self._warn("EXTENSION_IGNORED", f"<bml> without the BML 1.0 namespace {BML_NAMESPACE}; read as BML 1.0", root)
        self.block_id = self._id(root, "block")
        composition = root.get("composition", "MERGE")
        if composition not in COMPOSITIONS:
            raise self.source.error(f"composition {composition!r} is not one of {', '.join(COMPOSITIONS)}", root, "composition")
        self._check_attributes(root, "bml", frozenset({"id", "composition", "characterId"}))
        constraint_elements = self._collect(root, required=False)
        models: dict[str, BehaviorSpec | ChunkSpec] = {}
        for behavior in list(self.behaviors.values()):
            self._guard(lambda b=behavior: self._realize(b, models))
        for element, required in constraint_elements:
            self._guard(lambda e=element, r=required: self._read_constraint(e, r))
        for behavior in self.behaviors.values():
            self._guard(lambda b=behavior: self._read_sync_attributes(b))
        if not self.behaviors and not self.errors:
            self.errors.append(self.source.error(f"block {self.block_id!r} holds no behaviour", root))
        self._raise_errors()
        self.constraints.sort(key=lambda c: (c.where.line, c.where.column))  # document order: the later yields in a conflict
        kept = self._kept_constraints()
        self._raise_errors()
        utterance = self._utterance(models, kept)
        performed = frozenset(b.id for b in self.behaviors.values() if not b.dropped and BEHAVIORS[b.kind].support == "performed")
        return BmlBlock(
            id=self.block_id,
            composition=composition,
            character=root.get("characterId"),
            utterance=utterance,
            warnings=tuple(sorted(self.warnings, key=lambda w: (w.where.line, w.where.column))),
            sync_points={b.id: self._sync_points(b) for b in self.behaviors.values() if not b.dropped},
            kinds={b.id: b.kind for b in self.behaviors.values() if not b.dropped},
            performed=performed,
            where=self.source.where(root),
        )

    def _collect(self, parent: etree._Element, required: bool) -> list[tuple[etree._Element, bool]]:
        """Note every behaviour below ``parent``; returns the ``<constraint>`` elements."""
        constraints = []
        for child in parent:
            if not isinstance(child.tag, str):
                continue
            namespace, name = etree.QName(child).namespace, etree.QName(child).localname
            if namespace == MURML_NAMESPACE and name == "murmlgesture":
                self._guard(lambda c=child: self._add_behavior(c, "murmlgesture", required))
            elif namespace not in (BML_NAMESPACE, None):
                self._leave_out(child, required, "EXTENSION_IGNORED", f"<{name}> of namespace {namespace} is not read by mura")
            elif name == "required":
                if required:
                    self.errors.append(self.source.error("<required> inside <required>", child))
                    continue
                self._check_attributes(child, "required", frozenset({"id"}))
                constraints.extend(self._collect(child, required=True))
            elif name == "constraint":
                constraints.append((child, required))
            elif name in BEHAVIORS:
                self._guard(lambda c=child, n=name: self._add_behavior(c, n, required))
            else:
                self._leave_out(child, required, "UNKNOWN_BEHAVIOR", f"unknown behaviour <{name}>")
        return constraints

    def _add_behavior(self, element: etree._Element, kind: str, required: bool) -> None:
        behavior_id = self._id(element, kind)
        if behavior_id in self.behaviors:
            raise self.source.error(f"behaviour id {behavior_id!r} is used twice in block {self.block_id!r}", element, "id")
        behavior = _Behavior(behavior_id, kind, element, required)
        self.behaviors[behavior_id] = behavior
        self._check_attributes(element, kind, BEHAVIORS[kind].attributes | set(BEHAVIORS[kind].sync) | {"id"})
        if BEHAVIORS[kind].support == "unsupported":
            behavior.dropped = True
            self._leave_out(element, required, "UNSUPPORTED_BEHAVIOR", f"<{kind}> {behavior_id!r} is not supported by mura")

    # -- behaviours into the model ----------------------------------------------------

    def _realize(self, behavior: _Behavior, models: dict[str, BehaviorSpec | ChunkSpec]) -> None:
        if behavior.dropped:
            return
        element, kind = behavior.element, behavior.kind
        if kind == "speech":
            models[behavior.id] = self._speech(behavior)
            return
        support = BEHAVIORS[kind].support
        if support == "timed" or kind in HEAD_SLOTS:
            self._check_params(behavior)
        try:
            gesture = self._gesture(behavior) if support == "performed" else None
        except _CannotRealize as reason:
            behavior.dropped = True
            self._leave_out(element, behavior.required, "CANNOT_REALIZE", str(reason), reason.attribute)
            return
        params = tuple((name, value) for name, value in sorted(element.attrib.items()) if name in BEHAVIORS[kind].attributes)
        if support == "timed":
            self._warn("NOT_PERFORMED", f"<{kind}> {behavior.id!r} is timed but not performed: no motor module for it yet", element)
        models[behavior.id] = BehaviorSpec(behavior.id, kind, None, gesture, None, self.source.where(element), params=params)

    def _speech(self, behavior: _Behavior) -> ChunkSpec:
        element = behavior.element
        texts = [child for child in element if isinstance(child.tag, str) and etree.QName(child).localname == "text"]
        for child in element:
            if isinstance(child.tag, str) and etree.QName(child).localname == "description":
                self._warn("EXTENSION_IGNORED", f"speech {behavior.id!r}: <description> ignored; mura speaks the <text>", child)
        if len(texts) != 1:
            raise self.source.error(f"speech {behavior.id!r} needs exactly one <text>, found {len(texts)}", element)
        text, marks = self._spoken_text(texts[0], behavior.id)
        if not text:
            raise self.source.error(f"speech {behavior.id!r} has no words", texts[0])
        syncs = tuple(sync_id for sync_id, _, _ in marks)
        self.speech_syncs[behavior.id] = syncs
        where = self.source.where(element)
        tags = [TimeTag(f"{behavior.id}:start", -1, 0, where=where)]
        tags += [TimeTag(f"{behavior.id}:{sync_id}", -1, offset, where=self.source.where(sync)) for sync_id, offset, sync in marks]
        tags.append(TimeTag(f"{behavior.id}:end", -1, len(text), where=where))
        return ChunkSpec(-1, text, tuple(tags), speech=behavior.id)

    def _spoken_text(self, text_element: etree._Element, speech: str) -> tuple[str, list[tuple[str, int, etree._Element]]]:
        """The text with whitespace collapsed, and each ``<sync>`` with its offset into it."""
        raw = ""
        marks: list[tuple[str, int, etree._Element]] = []

        def add(piece: str | None) -> None:
            nonlocal raw
            collapsed = re.sub(r"\s+", " ", piece or "")
            raw += collapsed.lstrip(" ") if raw.endswith(" ") or not raw else collapsed

        add(text_element.text)
        for child in text_element:
            if not isinstance(child.tag, str):
                add(child.tail)
                continue
            if etree.QName(child).localname != "sync":
                raise self.source.error(f"speech {speech!r}: unexpected <{etree.QName(child).localname}> in the text (only <sync> may stand there)", child)
            sync_id = self._id(child, "sync")
            if sync_id in BEHAVIORS["speech"].sync or any(sync_id == m[0] for m in marks):
                raise self.source.error(f"speech {speech!r}: sync id {sync_id!r} is used twice (start and end are the speech's own)", child, "id")
            before = raw[-1:] or " "
            after = (child.tail or " ")[:1]
            if before.isalnum() and after.isalnum():
                raise self.source.error(f"speech {speech!r}: sync {sync_id!r} stands inside a word; put it between words", child)
            marks.append((sync_id, len(raw), child))
            add(child.tail)
        text = raw.strip()
        lead = len(raw) - len(raw.lstrip())
        placed = []
        for sync_id, offset, child in marks:
            at = min(max(offset - lead, 0), len(text))
            while at < len(text) and text[at] == " ":
                at += 1
            placed.append((sync_id, at, child))
        return text, placed

    def _gesture(self, behavior: _Behavior) -> Gesture:
        element, kind = behavior.element, behavior.kind
        if kind == "murmlgesture":
            return self._murml_gesture(behavior)
        if kind in HEAD_SLOTS:
            warn = lambda what, message, attribute: self._warn(what, message, element, attribute)
            tree = head_constraint(self.source, element, kind, behavior.id, self.lexicon, warn)
            return Gesture(behavior.id, tree, None, HEAD_SCOPE, self.source.where(element))
        mode = element.get("mode")
        if mode is not None and mode not in MODES:
            raise self.source.error(f"mode {mode!r} is not one of {', '.join(MODES)}", element, "mode")
        if kind == "pointing":
            function, params = "refer_to_loc", {"refloc": self._target(element)}
        else:
            lexeme = self._required_attribute(element, "lexeme")
            function = GESTURE_LEXEMES.get(lexeme, lexeme.lower())
            if self.lexicon.entry(function) is None:
                known = ", ".join(sorted(set(GESTURE_LEXEMES) | {name.upper() for name in self.lexicon.entries}))
                raise _CannotRealize(f"gesture {behavior.id!r}: unknown lexeme {lexeme!r} (mura performs {known})", "lexeme")
            params = {"refloc": self._target(element)} if function == "refer_to_loc" else {}
        entry = self.lexicon.entry(function)
        arm = MODES.get(mode or "RIGHT_HAND")
        if "hand" in entry.params:
            params["hand"] = (arm or Arm.RIGHT).value
        call = FunctionCall(function, params, self.source.where(element))
        gesture = function_gesture(call, behavior.id, (arm or Arm.RIGHT).value, self.lexicon, self.lexicon.scene, self.source.where(element))
        if mode == "BOTH_HANDS" and not _two_handed(gesture.constraints):
            mirrored = Symmetrical(gesture.constraints, Arm.RIGHT, Symmetry(frozenset("S"), "SymMS"), None, self.source.where(element))
            return Gesture(gesture.id, mirrored, gesture.function, gesture.scope, gesture.where)
        if mode is not None and _two_handed(gesture.constraints) and mode != "BOTH_HANDS":
            self._warn("UNKNOWN_ATTRIBUTE", f"gesture {behavior.id!r}: {function} is two-handed; mode {mode} ignored", element, "mode")
        return gesture

    def _target(self, element: etree._Element) -> str:
        target = element.get("target")
        if target is None:
            raise self.source.error(f"<{etree.QName(element).localname}> needs a target (a place of the scene: {', '.join(sorted(self.lexicon.scene))})", element)
        name = target[1:] if target.startswith("$") else target
        if name not in self.lexicon.scene:
            raise _CannotRealize(f"unknown target {target!r} (the scene has: {', '.join(sorted(self.lexicon.scene)) or 'none'})", "target")
        return f"${name}"

    def _murml_gesture(self, behavior: _Behavior) -> Gesture:
        """The embedded MURML read by MURML's reader (its elements renamed to plain names in
        place: a source is read once)."""
        element = behavior.element
        descriptions = [c for c in element if isinstance(c.tag, str) and etree.QName(c).localname == "murml-description"]
        if len(descriptions) != 1:
            raise self.source.error(f"murmlgesture {behavior.id!r} needs exactly one <murml-description>", element)
        description = descriptions[0]
        for node in description.iter(etree.Element):
            if etree.QName(node).namespace not in (MURML_NAMESPACE, BML_NAMESPACE, None):
                raise self.source.error(f"murmlgesture {behavior.id!r}: <{etree.QName(node).localname}> of namespace {etree.QName(node).namespace} in a MURML description", node)
            node.tag = etree.QName(node).localname  # MURML's own reader reads plain names
        content = [c for c in description if isinstance(c.tag, str)]
        holder = description
        if not any(c.tag in ("function", "constraints") for c in content):
            description.tag = "constraints"
            holder = element
        unit = "cm" if any(True for _ in description.iter("dynamicElement")) else "mm"
        return read_gesture_element(self.source, holder, behavior.id, self.lexicon, unit)

    def _check_params(self, behavior: _Behavior) -> None:
        element = behavior.element
        for name, kind in _NUMERIC.items():
            text = element.get(name)
            if text is None:
                continue
            value = number(text)
            if value is None or (kind == "count" and (value < 1 or value != int(value))):
                expected = "a positive whole number" if kind == "count" else "a number"
                raise self.source.error(f"{name} {text!r} of {behavior.id!r} is not {expected}", element, name)
        lexeme = element.get("lexeme")
        if behavior.kind == "head" and lexeme not in HEAD_LEXEMES:
            raise self.source.error(f"head {behavior.id!r}: lexeme {lexeme!r} is not one of {', '.join(HEAD_LEXEMES)}", element, "lexeme")
        influence = element.get("influence")
        if influence is not None and influence not in GAZE_INFLUENCES:
            raise self.source.error(f"influence {influence!r} is not one of {', '.join(GAZE_INFLUENCES)}", element, "influence")

    # -- timing -----------------------------------------------------------------------

    def _read_sync_attributes(self, behavior: _Behavior) -> None:
        element = behavior.element
        for sync in BEHAVIORS[behavior.kind].sync:
            text = element.get(sync)
            if text is None:
                continue
            where = self.source.where(element, sync)
            anchor = self._reference(text, where)
            point = SyncRef(behavior.id, sync, 0.0, where)
            self.constraints.append(SyncConstraint(point, "=", anchor, behavior.required, where))

    def _read_constraint(self, element: etree._Element, required: bool) -> None:
        self._check_attributes(element, "constraint", frozenset({"id"}))
        for child in element:
            if not isinstance(child.tag, str):
                continue
            name = etree.QName(child).localname
            relation = {"synchronize": "=", "before": "<=", "after": ">="}.get(name)
            if relation is None or etree.QName(child).namespace not in (BML_NAMESPACE, None):
                self._leave_out(child, required, "EXTENSION_IGNORED", f"<{name}> in <constraint> is not read by mura")
                continue
            syncs = [s for s in child if isinstance(s.tag, str) and etree.QName(s).localname == "sync"]
            points = [self._reference(self._required_attribute(s, "ref"), self.source.where(s, "ref"), allow_time=False) for s in syncs]
            ref = child.get("ref")
            if ref is not None:
                anchor = self._reference(ref, self.source.where(child, "ref"))
            elif relation == "=" and len(points) >= 2:
                anchor, points = points[0], points[1:]
            else:
                raise self.source.error(f"<{name}> needs a ref attribute" if relation != "=" else "<synchronize> needs a ref or at least two <sync> elements", child)
            if not points:
                raise self.source.error(f"<{name}> holds no <sync ref>", child)
            for point in points:
                self.constraints.append(SyncConstraint(point, relation, anchor, required, point.where))

    def _reference(self, text: str, where: SourceLocation, allow_time: bool = True) -> SyncRef:
        if self._points is None:  # every behaviour and speech marker is known once the behaviours are read
            self._points = {b.id: self._sync_points(b) for b in self.behaviors.values()}
            self._kinds = {b.id: b.kind for b in self.behaviors.values()}
        return parse_reference(text, where, self.block_id, self._points, self._kinds, allow_time)

    def _sync_points(self, behavior: _Behavior) -> tuple[str, ...]:
        if behavior.kind == "speech":
            return ("start",) + self.speech_syncs.get(behavior.id, ()) + ("end",)
        return BEHAVIORS[behavior.kind].sync

    def _kept_constraints(self) -> list[SyncConstraint]:
        """The constraints between behaviours that are performed or timed; a constraint on a
        left-out behaviour is dropped with a warning (an error when required)."""
        kept = []
        for constraint in self.constraints:
            gone = [ref.behavior for ref in (constraint.point, constraint.anchor) if ref.behavior is not None and self.behaviors[ref.behavior].dropped]
            if not gone:
                kept.append(constraint)
                continue
            message = f"constraint {constraint} names {', '.join(sorted(set(gone)))}, which is left out"
            if constraint.required:
                self.errors.append(SpecError(f"required {message}", constraint.where))
            else:
                self.warnings.append(BmlWarning("CONSTRAINT_DROPPED", f"{message}; the constraint is dropped", constraint.where))
        return kept

    # -- the utterance ----------------------------------------------------------------

    def _utterance(self, models: Mapping[str, BehaviorSpec | ChunkSpec], constraints: list[SyncConstraint]) -> Utterance:
        speeches = [b.id for b in self.behaviors.values() if b.kind == "speech" and not b.dropped]
        chunk_of_speech = {speech: index for index, speech in enumerate(speeches)}
        chunks = []
        for index, speech in enumerate(speeches):
            spec = models[speech]
            tags = tuple(TimeTag(t.id, index, t.offset, False, t.where) for t in spec.time_tags)
            chunks.append(ChunkSpec(index, spec.text, tags, speech))
        others = [b.id for b in self.behaviors.values() if b.kind != "speech" and not b.dropped]
        chunk = chunks_of(others, chunk_of_speech, constraints)
        named: dict[str, set[str]] = {b: set() for b in others}
        for constraint in constraints:
            for ref in (constraint.point, constraint.anchor):
                if ref.behavior in named:
                    named[ref.behavior].add(BML_SYNC_PEGS[ref.point])
        behaviors = []
        for behavior_id in others:
            spec = models[behavior_id]
            timing = SyncTiming(self.block_id, BEHAVIORS[self.behaviors[behavior_id].kind].sync, frozenset(named[behavior_id]))
            behaviors.append(BehaviorSpec(spec.id, spec.kind, timing, spec.gesture, chunk[behavior_id], spec.where, params=spec.params))
        warnings = tuple(str(w) for w in sorted(self.warnings, key=lambda w: (w.where.line, w.where.column)))
        return Utterance(tuple(chunks), tuple(behaviors), self.source.file, tuple(constraints), warnings)

    # -- small helpers ----------------------------------------------------------------

    def _id(self, element: etree._Element, what: str) -> str:
        value = element.get("id")
        if value is None:
            raise self.source.error(f"<{etree.QName(element).localname}> needs an id", element)
        if not NAME.match(value):
            raise self.source.error(f"{what} id {value!r} is not a valid name (letters, digits, '.', '-', '_'; no ':')", element, "id")
        return value

    def _required_attribute(self, element: etree._Element, name: str) -> str:
        value = element.get(name)
        if value is None:
            raise self.source.error(f"<{etree.QName(element).localname}> needs a {name} attribute", element)
        return value

    def _check_attributes(self, element: etree._Element, kind: str, known: frozenset[str] | set[str]) -> None:
        for name in element.attrib:
            qname = etree.QName(name)
            if qname.namespace is not None:
                if qname.namespace != "http://www.w3.org/XML/1998/namespace":
                    self._warn("EXTENSION_IGNORED", f"<{kind}>: attribute {qname.localname} of namespace {qname.namespace} ignored", element, name)
            elif name not in known:
                self._warn("UNKNOWN_ATTRIBUTE", f"<{kind}>: unknown attribute {name!r} ignored", element, name)

    def _leave_out(self, element: etree._Element, required: bool, kind: str, message: str, attribute: str | None = None) -> None:
        if required:
            self.errors.append(self.source.error(f"{message}, and it is required", element, attribute))
        else:
            self._warn(kind, f"{message}; left out, the rest of the block runs", element, attribute)

    def _warn(self, kind: str, message: str, element: etree._Element, attribute: str | None = None) -> None:
        where = self.source.where(element, attribute if attribute and element.get(attribute) is not None else None)
        self.warnings.append(BmlWarning(kind, message, where))

    def _guard(self, step) -> None:
        try:
            step()
        except SpecErrors as many:
            self.errors.extend(many.errors)
        except SpecError as error:
            self.errors.append(error)

    def _raise_errors(self) -> None:
        if self.errors:
            ordered = sorted(self.errors, key=lambda e: (e.line, e.column))
            raise ordered[0] if len(ordered) == 1 else SpecErrors(ordered)


class _CannotRealize(Exception):
    """A behaviour that is valid BML but that mura cannot perform (left out, or fails a required block)."""

    def __init__(self, message: str, attribute: str | None = None) -> None:
        super().__init__(message)
        self.attribute = attribute


def _two_handed(tree: Constraint) -> bool:
    scopes = {leaf.scope for leaf in iter_leaves(tree) if isinstance(leaf.scope, Arm)}
    return len(scopes) == 2 or any(isinstance(node, Symmetrical) for node in _nodes(tree))


def _nodes(tree: Constraint) -> Iterator[Constraint]:
    yield tree
    for child in getattr(tree, "children", ()) or ((tree.child,) if hasattr(tree, "child") else ()):
        yield from _nodes(child)
