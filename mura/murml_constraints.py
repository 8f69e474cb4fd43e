"""Reading MURML constraint trees: ``parallel``, ``sequence``, ``symmetrical``,
``repetition``, ``static`` and ``dynamic``, in utterances and in gesture lexicons.

Both dialects are read (the seed's ``<segment>`` and the published ``<dynamicElement>``),
with the published constructs the realizers that read them accept:

* ``<dynamic slot=… value=…/>`` with a value and no segments: the slot moves to that value;
* ``<dynamicElement>`` with values named by ``id`` instead of ``type`` (orientations and
  hand shapes passed through in order), or with only a ``start`` (a hold there);
* segment type ``chop``: a straight stroke performed fast and stopped sharply — a beat
  (ACE marks it to keep the elbow's swivel; mura keeps the swivel its planner picks);
  ``via`` reads as ``linear``;
* ``<keyframing>`` inside a ``<dynamic>``: phases of ``<frame ftime>`` postures of named
  joints, kept as :class:`~mura.constraints.Keyframing` (the motor core reports them as
  not realized);
* ``$name`` placeholders anywhere in an attribute value, filled from the calling
  function's parameters (a lexicon entry) — other ``$names`` are scene places.

Length units: a number may carry its unit (``125mm``); a bare number is in the unit the
reader is given (see :mod:`mura.murml`).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field

from lxml import etree

from mura import murml_vocabulary as vocabulary
from mura.constraints import (
    ARM_SLOTS,
    OTHER_SLOTS,
    Arm,
    Constraint,
    Dynamic,
    KeyFrame,
    Keyframing,
    Parallel,
    Repetition,
    Segment,
    SegmentKind,
    Sequence,
    Static,
    Symmetrical,
    Symmetry,
)
from mura.errors import SourceLocation, SpecError
from mura.lexicon import PLACEHOLDER, SceneLocation
from mura.limits import DEFAULT_LIMITS, Limits, hint
from mura.murml_vocabulary import DEFAULT_SYMBOLS, SymbolTable
from mura.values import Direction, Location, PalmOrientation, PointLocation, SlotValue, Symbol, Vector
from mura.xml_source import XmlSource

UNIT_METRES = {"mm": 0.001, "cm": 0.01, "m": 1.0}
_NUMBER = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(mm|cm|m)?\s*$")
_SYMMETRY = re.compile(r"^Sym(?:M([STF]+))?$")
_EXTENTS = {"Flat": 0.25, "Normal": 0.5, "Large": 0.75}
_ROUNDNESS = {"Sharpe": 0.9, "Sharp": 0.9, "Normal": 0.0, "Broad": -0.9}
_SKEWEDNESS = {"Round": 0.0, "FunnelS": -0.9, "FunnelE": 0.9}
_SEGMENT_VALUE_TYPES = ("start", "end", "direction", "distance", "normal", "shape", "extent", "extension", "roundness", "skewedness")
#: Segment types and the guiding stroke each is read as (module docstring).
_SEGMENT_TYPES: dict[str, SegmentKind] = {
    "linear": SegmentKind.LINEAR, "curve": SegmentKind.CURVE, "circle": SegmentKind.CIRCLE,
    "chop": SegmentKind.LINEAR, "via": SegmentKind.LINEAR,
}  # fmt: skip
_KEYFRAMING_MODES = ("spline", "linear", "squad", "quaternion", "raw")
#: Slots whose values aim the eyes or the head (see :mod:`mura.murml`, *Head and gaze values*).
_HEAD_SLOTS = ("GazeDirection", "Neck", "HeadDirection")
_POSTURE_JOINT = re.compile(r"\(([^()]*)\)")
#: Frames of one keyframing read at most, a bound against runaway documents.
MAX_KEYFRAMES = 10_000


@dataclass
class ConstraintReader:
    """Reads a constraint tree, filling ``$param`` placeholders and resolving scene places.

    ``call_site`` is where a lexicon entry was called from: errors inside the entry are
    reported there, naming the place in the lexicon too.
    """

    source: XmlSource
    unit: str
    scene: Mapping[str, SceneLocation]
    params: Mapping[str, str]
    call_site: SourceLocation | None = None
    symbols: SymbolTable = field(default_factory=lambda: DEFAULT_SYMBOLS)
    limits: Limits = DEFAULT_LIMITS
    published: bool = False

    def read_root(self, constraints: etree._Element, scope: Arm | None) -> Constraint:
        """The one constraint inside ``<constraints>`` (or a lexicon's wrapper element)."""
        children = [child for child in constraints if isinstance(child.tag, str)]
        if len(children) != 1:
            raise self.error(f"<{constraints.tag}> must hold exactly one constraint, found {len(children)}", constraints)
        return self.read(children[0], self._scope(constraints) or scope)

    def read(self, element: etree._Element, scope: Arm | None) -> Constraint:
        scope = self._scope(element) or scope
        where = self.source.where(element)
        tag = element.tag
        if tag in ("parallel", "sequence"):
            children = tuple(self.read(child, scope) for child in element if isinstance(child.tag, str))
            if not children:
                raise self.error(f"<{tag}> is empty", element)
            return Parallel(children, where) if tag == "parallel" else Sequence(children, where)
        if tag == "symmetrical":
            return self._symmetrical(element, where)
        if tag == "repetition":
            return self._repetition(element, scope, where)
        if tag == "static":
            return self._static(element, scope, where)
        if tag == "dynamic":
            return self._dynamic(element, scope, where)
        raise self.error(f"unknown constraint <{tag}> (expected parallel, sequence, symmetrical, repetition, static or dynamic)", element)

    def _symmetrical(self, element: etree._Element, where: SourceLocation) -> Symmetrical:
        dominant = arm_or_none(self._attr(element, "dominant"))
        if dominant is None:
            raise self.error(f"dominant {element.get('dominant')!r} is not an arm (expected right_arm or left_arm)", element, "dominant")
        symmetry = self._symmetry(element)
        center = None
        if element.get("center") is not None:
            center = self._numbers(element, "center", None)
        children = [child for child in element if isinstance(child.tag, str)]
        if len(children) != 1:
            raise self.error(f"<symmetrical> must hold exactly one constraint, found {len(children)}", element)
        return Symmetrical(self.read(children[0], dominant), dominant, symmetry, center, where)

    def _symmetry(self, element: etree._Element) -> Symmetry:
        name = self._attr(element, "symmetry")
        match = _SYMMETRY.match(name)
        if match is None or (match.group(1) and len(set(match.group(1))) != len(match.group(1))):
            raise self.error(f"unknown symmetry {name!r} (expected Sym, SymMS, SymMT, SymMF or a combination such as SymMST)", element, "symmetry")
        planes = frozenset(match.group(1) or "S")
        return Symmetry(planes, name)

    def _repetition(self, element: etree._Element, scope: Arm | None, where: SourceLocation) -> Repetition:
        attribute = "count" if element.get("count") is not None else "number"
        text = self._attr(element, attribute) if element.get(attribute) is not None else "2"
        digits = text.strip()
        if not (digits.isascii() and digits.isdigit()) or not digits.strip("0"):
            raise self.error(f"repetition {attribute} {text!r} is not a positive whole number", element, attribute)
        significant = digits.lstrip("0")
        if len(significant) > 18 or int(significant) > self.limits.max_movements:
            raise self.error(f"repetition {attribute} {significant[:20]} is more than the limit of {self.limits.max_movements} "
                             f"movements ({hint('max_movements')})", element, attribute)
        children = [child for child in element if isinstance(child.tag, str)]
        if len(children) != 1:
            raise self.error(f"<repetition> must hold exactly one constraint, found {len(children)}", element)
        return Repetition(self.read(children[0], scope), int(significant), where)

    def _static(self, element: etree._Element, scope: Arm | None, where: SourceLocation) -> Static:
        slot = self._slot(element)
        mode = element.get("mode")
        value = self._slot_value(slot, self._attr(element, "value"), mode, element, "value")
        return Static(slot, value, self._leaf_scope(element, slot, scope), mode, where)

    def _dynamic(self, element: etree._Element, scope: Arm | None, where: SourceLocation) -> Dynamic:
        slot = self._slot(element)
        segments: list[Segment] = []
        keyframes: Keyframing | None = None
        for child in (c for c in element if isinstance(c.tag, str)):
            if child.tag == "keyframing":
                if keyframes is not None:
                    raise self.error(f"dynamic {slot} has two <keyframing>", child)
                keyframes = self._keyframing(child)
            else:
                segments.extend(self._segments(child, slot))
        if element.get("value") is not None:
            if segments or keyframes is not None:
                raise self.error(f"dynamic {slot} gives both a value and segments", element, "value")
            value = self._slot_value(slot, self._attr(element, "value"), element.get("mode"), element, "value")
            segments.append(Segment(SegmentKind.LINEAR, end=value, where=where))
        if not segments and keyframes is None:
            raise self.error(f"dynamic {slot} has no segments (give <dynamicElement>s, a <keyframing> or a value attribute)", element)
        return Dynamic(slot, tuple(segments), self._leaf_scope(element, slot, scope), where, keyframes)

    def _leaf_scope(self, element: etree._Element, slot: str, scope: Arm | None) -> Arm | str | None:
        if slot in ARM_SLOTS:
            return scope if scope is not None else Arm.RIGHT
        return element.get("scope")

    def _slot(self, element: etree._Element) -> str:
        slot = self._attr(element, "slot")
        if slot not in ARM_SLOTS and slot not in OTHER_SLOTS:
            raise self.error(f"unknown slot {slot!r} (expected one of {', '.join(ARM_SLOTS + OTHER_SLOTS)})", element, "slot")
        return slot

    # -- segments -------------------------------------------------------------------

    def _segments(self, element: etree._Element, slot: str) -> list[Segment]:
        """The segments of one ``<segment>``/``<dynamicElement>``: one, or for a value
        sequence of another slot (values by ``id``), one per value after the first."""
        if element.tag not in ("segment", "dynamicElement"):
            raise self.error(f"unexpected <{element.tag}> in <dynamic> (expected <segment>, <dynamicElement> or <keyframing>)", element)
        kind_name = self._attr(element, "type") if element.get("type") is not None else "linear"
        if kind_name.lower() not in _SEGMENT_TYPES:
            raise self.error(f"unknown segment type {kind_name!r} (expected {', '.join(_SEGMENT_TYPES)})", element, "type")
        kind = _SEGMENT_TYPES[kind_name.lower()]
        chop = kind_name.lower() == "chop"
        fields: dict[str, object] = {}
        passes: list[SlotValue] = []
        for value in (v for v in element if isinstance(v.tag, str)):
            if value.tag != "value":
                raise self.error(f"unexpected <{value.tag}> in <{element.tag}> (expected <value>)", value)
            attribute = "name" if value.get("name") is not None else "value"
            value_type = value.get("type", "")
            if not value_type and value.get("id") is not None and slot != "HandLocation":
                passes.append(self._segment_value(slot, "end", self._attr(value, attribute), value, attribute))  # type: ignore[arg-type]
                continue
            if value_type not in _SEGMENT_VALUE_TYPES:
                raise self.error(f"unknown segment value type {value_type!r} (expected one of {', '.join(_SEGMENT_VALUE_TYPES)})", value, "type")
            key = "extent" if value_type == "extension" else value_type
            if key in fields:
                raise self.error(f"segment gives its {key} twice", value, "type")
            fields[key] = self._segment_value(slot, key, self._attr(value, attribute), value, attribute)
        where = self.source.where(element)
        manner, modifiers = ("fast", ("chop",)) if chop else (None, ())
        if passes:
            return self._value_sequence(slot, kind, fields, passes, where, element)
        if slot == "HandLocation" and set(fields) == {"start"}:
            fields["end"] = fields["start"]  # a start and nothing else: a hold there
        segment = Segment(kind=kind, where=where, manner=manner, modifiers=modifiers, **fields)  # type: ignore[arg-type]
        self._check_segment(segment, slot, element)
        return [segment]

    def _value_sequence(
        self, slot: str, kind: SegmentKind, fields: dict[str, object], passes: list[SlotValue], where: SourceLocation, element: etree._Element
    ) -> list[Segment]:
        values = [fields["start"]] if "start" in fields else []
        values += passes + ([fields["end"]] if "end" in fields else [])
        segments = [Segment(kind, start=values[0], end=values[min(1, len(values) - 1)], where=where)]  # type: ignore[arg-type]
        segments += [Segment(kind, end=value, where=where) for value in values[2:]]  # type: ignore[arg-type]
        for segment in segments:
            self._check_segment(segment, slot, element)
        return segments

    def _segment_value(self, slot: str, key: str, text: str, element: etree._Element, attribute: str) -> object:
        if key in ("start", "end"):
            return self._slot_value(slot, text, None, element, attribute)
        if key in ("direction", "normal"):
            return self._direction(text, element, attribute)
        if key == "distance":
            return self._distance(text, element, attribute)
        if key == "shape":
            if text not in vocabulary.CURVE_SHAPES:
                raise self.error(f"unknown curve shape {text!r} (expected {', '.join(vocabulary.CURVE_SHAPES)})", element, attribute)
            return text
        table = {"extent": _EXTENTS, "roundness": _ROUNDNESS, "skewedness": _SKEWEDNESS}[key]
        return self._scalar(text, table, key, element, attribute)

    def _check_segment(self, segment: Segment, slot: str, element: etree._Element) -> None:
        if slot != "HandLocation":
            if segment.start is None and segment.end is None:
                raise self.error(f"a {slot} segment needs a start or an end value", element)
            return
        has_path = segment.end is not None or (segment.direction is not None and segment.distance is not None)
        if not has_path:
            raise self.error("a HandLocation segment needs an end, a direction and a distance, or a start to hold", element)
        if segment.kind is SegmentKind.CURVE and segment.end is None:
            raise self.error("a curve segment needs an end", element)
        if segment.distance is not None and segment.distance <= 0:
            raise self.error(f"segment distance must be positive, got {segment.distance} m", element)

    # -- keyframing -----------------------------------------------------------------

    def _keyframing(self, element: etree._Element) -> Keyframing:
        """Phases of frames laid end to end: a phase's frame times continue from the
        last frame time of the phase before (as the published realizer merges them)."""
        mode = element.get("mode", "spline").lower()
        if mode not in _KEYFRAMING_MODES:
            raise self.error(f"unknown keyframing mode {mode!r} (expected {', '.join(_KEYFRAMING_MODES)})", element, "mode")
        frames: list[KeyFrame] = []
        offset = 0.0
        for phase in (p for p in element if isinstance(p.tag, str)):
            if phase.tag != "phase":
                raise self.error(f"unexpected <{phase.tag}> in <keyframing> (expected <phase>)", phase)
            last = 0.0
            for frame in (f for f in phase if isinstance(f.tag, str)):
                if frame.tag != "frame":
                    raise self.error(f"unexpected <{frame.tag}> in <phase> (expected <frame>)", frame)
                last = self._number(frame, "ftime")
                if last < 0:
                    raise self.error(f"frame time {last} is negative", frame, "ftime")
                frames.append(KeyFrame(last + offset, self._posture(frame)))
                if len(frames) > MAX_KEYFRAMES:
                    raise self.error(f"more than {MAX_KEYFRAMES} frames", frame)
            offset += last
        if not frames:
            raise self.error("<keyframing> has no frames", element)
        times = [frame.time for frame in frames]
        if any(b < a for a, b in zip(times, times[1:])):
            raise self.error("frame times go backwards", element)
        return Keyframing(
            tuple(frames), mode, self._optional_number(element, "easescale", 1.0),
            self._optional_number(element, "easeturningpoint", 0.5), element.get("dont_insert_startframe", "false").lower() not in ("true", "1"),
        )  # fmt: skip

    def _posture(self, frame: etree._Element) -> tuple[tuple[str, tuple[float, ...]], ...]:
        postures = [child for child in frame if child.tag == "posture"]
        if len(postures) != 1:
            raise self.error(f"<frame> needs one <posture>, found {len(postures)}", frame)
        joints = []
        for spec in _POSTURE_JOINT.findall(postures[0].text or ""):
            parts = spec.split()
            if len(parts) < 2:
                raise self.error(f"posture entry ({spec}) needs a joint name and its values", postures[0])
            values = parts[2:] if len(parts) > 2 else parts[1:]
            try:
                numbers = tuple(float(v) for v in values)
            except ValueError:
                raise self.error(f"posture entry ({spec}) holds a value that is not a number", postures[0]) from None
            if len(parts) > 2 and (not parts[1].isdigit() or int(parts[1]) != len(numbers)):
                raise self.error(f"posture entry ({spec}) announces {parts[1]} values but gives {len(numbers)}", postures[0])
            joints.append((parts[0], numbers))
        if not joints:
            raise self.error("<posture> names no joint: expected (joint n v1 … vn) entries", postures[0])
        return tuple(joints)

    # -- values ---------------------------------------------------------------------

    def _slot_value(self, slot: str, text: str, mode: str | None, element: etree._Element, attribute: str) -> SlotValue:
        try:
            return self._parse_slot_value(slot, text, mode, element, attribute)
        except SpecError:
            raise
        except ValueError as error:
            raise self.error(f"{slot}: {error}", element, attribute) from None

    def _parse_slot_value(self, slot: str, text: str, mode: str | None, element: etree._Element, attribute: str) -> SlotValue:
        if slot == "HandShape":
            return vocabulary.parse_handshape(text)
        if slot == "HandLocation" or (mode == "pointTo" and slot in ("ExtFingerOrientation", "PalmOrientation")):
            return self._location(text, element, attribute)
        if slot == "ExtFingerOrientation":
            return self._direction(text, element, attribute)
        if slot == "PalmOrientation":
            if is_numbers(text) and len(text.split()) == 3:
                return PalmOrientation(self._direction(text, element, attribute).vector, text, mode == "relative")
            palm = vocabulary.parse_palm_orientation(text, self.symbols)
            return PalmOrientation(palm.direction, palm.name, mode == "relative")
        if slot in _HEAD_SLOTS:
            return self._head_value(text, mode, element, attribute)
        if is_numbers(text):
            return Vector(tuple(float(part) for part in text.split()))
        if text.startswith("Dir"):
            return vocabulary.parse_direction(text)
        if text.startswith("$"):
            return self._location(text, element, attribute)
        if not text.strip():
            raise ValueError("empty value")
        return Symbol(text.strip())

    def _head_value(self, text: str, mode: str | None, element: etree._Element, attribute: str) -> SlotValue:
        """A gaze or head value (:mod:`mura.murml`, *Head and gaze values*)."""
        if is_numbers(text):
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
        if is_numbers(text):
            values = self._numbers_text(text, element, attribute, self.unit)
            if len(values) != 3:
                raise ValueError(f"a position needs three numbers, got {len(values)}")
            return PointLocation(values)  # type: ignore[arg-type]
        return vocabulary.parse_grid_location(text, self.symbols)

    def _scene_location(self, name: str, element: etree._Element, attribute: str) -> Location:
        place = self.scene.get(name)
        if place is None:
            known = ", ".join(sorted(self.scene)) or "none"
            raise ValueError(f"unknown place ${name} (the scene has: {known})")
        if not place.is_position:
            return vocabulary.parse_grid_location(place.text, self.symbols)
        values = self._numbers_text(place.text, place.element, "position", place.unit)
        if len(values) != 3:
            raise ValueError(f"place ${name} needs three numbers, got {len(values)}")
        return PointLocation(values)  # type: ignore[arg-type]

    def _direction(self, text: str, element: etree._Element, attribute: str) -> Direction:
        if text.startswith("Dir"):
            try:
                return vocabulary.parse_direction(text)
            except ValueError as error:
                raise self.error(str(error), element, attribute) from None
        values = self._numbers(element, attribute, None, text)
        if len(values) != 3:
            raise self.error(f"a direction needs three numbers or a Dir… name, got {text!r}", element, attribute)
        norm = sum(v * v for v in values) ** 0.5
        if norm < 1e-12:
            raise self.error(f"direction {text!r} has zero length", element, attribute)
        return Direction((values[0] / norm, values[1] / norm, values[2] / norm), text)

    def _distance(self, text: str, element: etree._Element, attribute: str) -> float:
        named = self.symbols.movement_distance(text)
        if named is not None:
            return named
        expected = f"a distance is one number or one of {', '.join(vocabulary.DISTANCES)}, not {text!r}"
        if not is_numbers(text) or len(text.split()) != 1:
            raise self.error(expected, element, attribute)
        return self._numbers(element, attribute, self.unit, text)[0]

    def _scalar(self, text: str, names: Mapping[str, float], key: str, element: etree._Element, attribute: str) -> float:
        if text in names:
            return names[text]
        value = float_or_none(text)
        if value is None:
            raise self.error(f"{key} {text!r} is neither a number nor one of {', '.join(names)}", element, attribute)
        return value

    def _number(self, element: etree._Element, attribute: str) -> float:
        value = float_or_none(self._attr(element, attribute))
        if value is None:
            raise self.error(f"{attribute}={element.get(attribute)!r} is not a number", element, attribute)
        return value

    def _optional_number(self, element: etree._Element, attribute: str, default: float) -> float:
        return default if element.get(attribute) is None else self._number(element, attribute)

    def _numbers(self, element: etree._Element, attribute: str, unit: str | None, text: str | None = None) -> tuple[float, ...]:
        text = self._attr(element, attribute) if text is None else text
        try:
            return self._numbers_text(text, element, attribute, unit)
        except ValueError as error:
            raise self.error(str(error), element, attribute) from None

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
                number *= UNIT_METRES[match.group(2) or unit]
                self.limits.check_length(number, f"length {part!r} =")
            elif match.group(2):
                raise ValueError(f"{part!r} takes no unit here")
            values.append(number)
        if not values:
            raise ValueError("expected numbers, found none")
        return tuple(values)

    def _scope(self, element: etree._Element) -> Arm | None:
        scope = element.get("scope")
        return None if scope is None else arm_or_none(self.fill(scope))

    def _attr(self, element: etree._Element, name: str) -> str:
        value = element.get(name)
        if value is None:
            raise self.error(f"<{element.tag}> needs a {name} attribute", element)
        return self.fill(value)

    def fill(self, value: str) -> str:
        """``value`` with each ``$name`` of a bound parameter replaced by its value."""
        if "$" not in value or not self.params:
            return value
        return PLACEHOLDER.sub(lambda m: self.params.get(m.group(1), m.group(0)), value)

    def error(self, message: str, element: etree._Element, attribute: str | None = None) -> SpecError:
        if self.call_site is not None:
            where = self.source.where(element, attribute)
            return SpecError(f"{message} (in the lexicon at {where})", self.call_site)
        return self.source.error(message, element, attribute)


def arm_or_none(scope: str | None) -> Arm | None:
    """The arm a scope names (``right_arm``, ``left arm`` …), None for anything else."""
    if scope is None:
        return None
    normalized = scope.strip().replace(" ", "_").lower()
    for arm in Arm:
        if normalized == arm.value:
            return arm
    return None


def float_or_none(text: str) -> float | None:
    """A finite number, or None."""
    try:
        value = float(text)
    except ValueError:
        return None
    return value if value == value and abs(value) != float("inf") else None


def is_numbers(text: str) -> bool:
    """Whether ``text`` is one or more numbers (each with an optional unit)."""
    parts = text.split()
    return bool(parts) and all(_NUMBER.match(part) for part in parts)
