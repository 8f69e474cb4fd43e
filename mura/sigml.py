"""SiGML documents: ``<hns_sign>`` tag streams and ``<hamgestural_sign>`` feature trees.

A SiGML document (root ``<sigml>`` or ``<sigml_collection>``) holds signs in either of two
forms. ``<hns_sign>`` writes the HamNoSys manual stream as a list of empty tags in
``<hamnosys_manual>`` (read by :mod:`mura.hamnosys`) with nonmanual tiers in
``<hamnosys_nonmanual>``. ``<hamgestural_sign>`` writes the same features as a tree
(``<sign_manual>`` with ``<handconfig>``, ``<location_bodyarm>``, ``<directedmotion>`` …,
seed 000 Figure 7). Both become :class:`~mura.signs.Sign`.

Each sign is read on its own: one broken sign becomes a :class:`~mura.signs.SignFailure`
with its reason and the others still parse. Reading is safe: no network, no DTD, no
entity expansion; inputs over ``Limits.max_input_bytes`` and signs whose repetitions
expand to more than ``Limits.max_movements`` movements are refused.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace

from lxml import etree

from mura.constraints import (
    Arm,
    Constraint,
    Dynamic,
    Parallel,
    Repetition,
    Segment,
    SegmentKind,
    Sequence,
)
from mura.errors import SourceLocation, SpecError
from mura.expansion import check_sign
from mura.hamnosys import Token, parse_manual, scoped_to, tokens_from_names
from mura.hamnosys_symbols import lookup as lookup_symbol
from mura.limits import DEFAULT_LIMITS, Limits
from mura.signs import (
    HandConstellation,
    HandPosture,
    NonmanualItem,
    SigmlParseResult,
    Sign,
    SignFailure,
    SignSymmetry,
)
from mura.values import (
    BASIC_HANDSHAPES,
    FINGER_BENDINGS,
    FINGERS,
    BetweenLocation,
    BodySite,
    Direction,
    FingerBend,
    HandShape,
    Location,
    PalmOrientation,
    direction_from_letters,
)
from mura.xml_source import XmlSource

ROOTS: tuple[str, ...] = ("sigml", "sigml_collection")
SIGN_TAGS: tuple[str, ...] = ("hns_sign", "hamgestural_sign")



def parse_sigml(source: str | bytes, file: str = "<input>", limits: Limits = DEFAULT_LIMITS) -> SigmlParseResult:
    """Every sign of a SiGML document; broken signs are reported one by one.

    Raises SpecError only when the document as a whole cannot be read (not XML, too
    large, wrong root).
    """
    data = source.encode("utf-8") if isinstance(source, str) else source
    return read_sigml(XmlSource.from_bytes(data, file, limits=limits), limits)


def read_sigml(source: XmlSource, limits: Limits = DEFAULT_LIMITS) -> SigmlParseResult:
    """Every sign of an already parsed SiGML document."""
    root = source.root
    where_of: Callable[[etree._Element], SourceLocation] = source.where
    if root.tag not in ROOTS:
        raise SpecError(f"root element <{root.tag}> is not <sigml> or <sigml_collection>", where_of(root))
    signs: list[Sign] = []
    failures: list[SignFailure] = []
    for index, element in enumerate(e for e in root if isinstance(e.tag, str)):
        gloss = element.get("gloss", f"#{index}")
        try:
            signs.append(read_sign_element(element, gloss, where_of, limits))
        except SpecError as error:
            failures.append(SignFailure(gloss, index, error))
    return SigmlParseResult(tuple(signs), tuple(failures), source.file)


def read_sign_element(element: etree._Element, gloss: str, where_of: Callable[[etree._Element], SourceLocation],
                      limits: Limits = DEFAULT_LIMITS) -> Sign:
    """One ``<hns_sign>`` or ``<hamgestural_sign>`` element as a :class:`Sign`; the sign
    elements of a SiGML document and those inside MURML utterances read alike. A sign
    whose repetitions expand to more than ``limits.max_movements`` movements is refused."""
    if element.tag == "hns_sign":
        return check_sign(_hns_sign(element, gloss, where_of), limits)
    if element.tag == "hamgestural_sign":
        return check_sign(_GesturalReader(gloss, where_of).sign(element), limits)
    raise SpecError(f"unexpected element <{element.tag}> (expected <hns_sign> or <hamgestural_sign>)", where_of(element))


def _nonmanual_tiers(
    element: etree._Element | None, where_of: Callable[[etree._Element], SourceLocation] | None = None
) -> dict[str, tuple[NonmanualItem, ...]]:
    """Tier name → the items written in it, in order.

    A child with children of its own is a tier (``<head_tier>…</head_tier>`` in gestural
    SiGML); a childless child is an item in the tier of its own name without ``hnm_``
    (``<hnm_mouthpicture picture="…"/>`` in ``<hamnosys_nonmanual>``).
    """
    tiers: dict[str, list[NonmanualItem]] = {}
    if element is None:
        return {}
    for child in (c for c in element if isinstance(c.tag, str)):
        items = [e for e in child.iterdescendants() if isinstance(e.tag, str)] or [child]
        tier = tiers.setdefault(child.tag.removeprefix("hnm_"), [])
        tier.extend(NonmanualItem(item.tag, tuple(sorted(item.attrib.items())), where_of(item) if where_of else None) for item in items)
    return {tier: tuple(items) for tier, items in tiers.items()}


def _hns_sign(element: etree._Element, gloss: str, where_of: Callable[[etree._Element], SourceLocation]) -> Sign:
    where = where_of(element)
    manual = element.find("hamnosys_manual")
    if manual is None:
        raise SpecError(f"sign {gloss!r}: no <hamnosys_manual>", where)
    if (manual.text or "").strip():
        raise SpecError(f"sign {gloss!r}: text {manual.text.strip()[:20]!r} in <hamnosys_manual> (expected only ham… tags)", where_of(manual))
    names = [(child.tag, where_of(child)) for child in manual if isinstance(child.tag, str)]
    tokens: list[Token] = tokens_from_names(names, gloss)
    nonmanual = _nonmanual_tiers(element.find("hamnosys_nonmanual"), where_of)
    return parse_manual(tokens, gloss, where, nonmanual=nonmanual)


# --- gestural SiGML -----------------------------------------------------------------------

_TRUE = {"true": True, "false": False}
_SIDES = {"right_at": "lrat", "left_at": "lrat", "right_beside": "lrbeside", "left_beside": "lrbeside"}
_MANNERS = ("fast", "slow", "tense", "rest", "halt", "targetted")
_SIZES = {"small": "small", "big": "large", "large": "large", "increasing": "increasing", "decreasing": "decreasing"}
_REPETITIONS: dict[str, tuple[str, int]] = {
    "fromstart": ("fromstart", 2),
    "fromstart_several": ("fromstart", 3),
    "continue": ("continue", 2),
    "continue_several": ("continue", 3),
    "reverse": ("reverse", 2),
}
_WRIST_MOTIONS: dict[str, tuple[str, SegmentKind]] = {
    "nodding": ("ExtFingerOrientation", SegmentKind.LINEAR),
    "swinging": ("ExtFingerOrientation", SegmentKind.LINEAR),
    "twisting": ("PalmOrientation", SegmentKind.LINEAR),
    "stircw": ("HandLocation", SegmentKind.CIRCLE),
    "stirccw": ("HandLocation", SegmentKind.CIRCLE),
}
#: The HamNoSys symbol family each direction attribute stands for.
_DIRECTION_SYMBOLS = {"extfidir": "hamextfinger", "palmor": "hampalm", "direction": "hammove", "axis": "hamcircle"}
_CURVES = {"l": "arcl", "u": "arcu", "r": "arcr", "d": "arcd", "wavy": "wavy", "zigzag": "zigzag"}
_HANDCONFIG_ATTRS = frozenset(
    {"handshape", "thumbpos", "mainbend", "second_handshape", "second_thumbpos", "second_mainbend", "ceeopening",
     "extfidir", "second_extfidir", "palmor", "second_palmor", "rel_palmor", "specialfingers",
     "bend1", "bend2", "bend3", "bend4", "bend5"}
    # written by public tools, read and not realized: approximations and relative forms
    | {"second_ceeopening", "approx_shape", "approx_extfidir", "approx_palmor", "rel_extfidir"}
)
_MOTION_TAGS = frozenset(
    {"directedmotion", "circularmotion", "wristmotion", "fingerplay", "nomotion", "tgt_motion", "rpt_motion",
     "seq_motion", "par_motion", "split_motion", "nonman_motion", "changeposture"}
)
_LOCATION_ATTRS = frozenset({"location", "second_location", "side", "second_side", "contact", "second_contact", "digits", "second_digits", "approx_location"})
#: Hand shapes as gestural SiGML writes them, where the name differs from the HamNoSys tag.
_HANDSHAPE_NAMES = {"flat": "flathand", "cee12open": "ceeopen", "pinchopen": "pinch12open"}
#: Thumb positions as gestural SiGML writes them: ``opposed`` is HamNoSys's open thumb.
_THUMB_NAMES = {"out": "out", "across": "across", "opposed": "open", "open": "open"}
#: Finger parts written without ``finger`` (``location="midjoint"`` in ``<location_hand>``).
_FINGER_PARTS = {"tip": "fingertip", "nail": "fingernail", "pad": "fingerpad", "midjoint": "fingermidjoint", "base": "fingerbase", "side": "fingerside"}
#: Location names besides the HamNoSys location symbols (without ``ham``).
_LOCATION_NAMES = {"neutral": "neutralspace", **_FINGER_PARTS}
#: Sides of a hand site (palm side, back, thumb side, little-finger side, …): read, not
#: realized (the motor places the site itself).
_HAND_SITE_SIDES = frozenset({"palmar", "dorsal", "radial", "ulnar", "front", "back", "left", "right"})
#: Contacts and distances a location may name.
_CONTACT_NAMES = frozenset({"touch", "close", "medium", "near", "far", "armextended", "behind", "brushing", "interlock", "cross"})
_QUALITIES = frozenset({"size", "manner"})
#: Attributes each motion element may carry.
_MOTION_ATTRS: dict[str, frozenset[str]] = {
    "directedmotion": _QUALITIES | {"direction", "second_direction", "curve", "curve_size", "zigzag_style", "second_size"},
    "circularmotion": _QUALITIES | {"axis", "second_axis", "start", "end", "ellipse_direction", "ellipse_size", "zigzag_style", "second_size"},
    "wristmotion": _QUALITIES | {"motion"},
    "fingerplay": _QUALITIES | {"digits"},
    "nomotion": frozenset(),
    "rpt_motion": frozenset({"repetition", "outofphase"}),
    "seq_motion": frozenset({"fused"}),
    "par_motion": frozenset(),
    "split_motion": frozenset(),
    "tgt_motion": _QUALITIES,
    "changeposture": frozenset(),
}
_POSTURE_TAGS = frozenset({"handconfig", "split_handconfig", "location_bodyarm", "location_hand", "handconstellation", "split_location"})


@dataclass
class _GesturalReader:
    """Reads one ``<hamgestural_sign>`` into a :class:`Sign`."""

    gloss: str
    where_of: Callable[[etree._Element], SourceLocation]
    dominant: Arm = Arm.RIGHT
    nonmanual: dict[str, list[NonmanualItem]] = field(default_factory=dict)

    def error(self, element: etree._Element, message: str) -> SpecError:
        return SpecError(f"sign {self.gloss!r}: <{element.tag}>: {message}", self.where_of(element))

    def sign(self, element: etree._Element) -> Sign:
        manual = element.find("sign_manual")
        if manual is None:
            raise self.error(element, "no <sign_manual>")
        for tier, items in _nonmanual_tiers(element.find("sign_nonmanual"), self.where_of).items():
            self.nonmanual.setdefault(tier, []).extend(items)
        self.dominant = Arm.LEFT if manual.get("nondominant") == "true" or manual.get("dominant") == "left" else Arm.RIGHT
        both = self.flag(manual, "both_hands")
        symmetry = self.symmetry(manual)
        dominant_hand: dict[str, object] = {}
        other_hand: dict[str, object] | None = None
        constellation: HandConstellation | None = None
        motions: list[Constraint] = []
        children = [c for c in manual if isinstance(c.tag, str)]
        if not children:
            raise self.error(manual, "empty sign")
        for child in children:
            tag = child.tag
            if tag in _POSTURE_TAGS and motions:
                raise self.error(child, "a posture after the movement (expected a motion element)")
            if tag == "handconfig":
                dominant_hand.update(self.handconfig(child))
            elif tag == "location_bodyarm" or tag == "location_hand":
                dominant_hand["location"] = self.location(child)
            elif tag in ("split_handconfig", "split_location"):
                first, second = self.split(child, self.handconfig if tag == "split_handconfig" else self.location_part)
                dominant_hand.update(first)
                other_hand = {**(other_hand or {}), **second}
            elif tag == "handconstellation":
                constellation = self.constellation(child)
            elif tag == "nonman_motion":
                self.keep_nonmanual(child)
            elif tag in _MOTION_TAGS:
                motions.append(self.motion(child))
            else:
                raise self.error(child, "unknown element in <sign_manual>")
        if not dominant_hand and constellation is None:
            raise self.error(manual, "no hand configuration")
        movement = motions[0] if len(motions) == 1 else (Sequence(tuple(motions)) if motions else None)
        return Sign(
            gloss=self.gloss,
            posture=_posture(dominant_hand),
            dominant=self.dominant,
            two_handed=both or symmetry is not None or other_hand is not None or constellation is not None,
            symmetry=symmetry,
            nondominant=_posture(other_hand) if other_hand is not None else None,
            constellation=constellation,
            movement=movement,
            nonmanual={tier: tuple(items) for tier, items in self.nonmanual.items()},
            where=self.where_of(element),
        )

    def flag(self, element: etree._Element, name: str) -> bool:
        value = element.get(name)
        if value is None:
            return False
        if value not in _TRUE:
            raise self.error(element, f"{name}={value!r} (expected true or false)")
        return _TRUE[value]

    def symmetry(self, manual: etree._Element) -> SignSymmetry | None:
        planes = {plane for attr, plane in (("lr_symm", "S"), ("ud_symm", "T"), ("oi_symm", "F")) if self.flag(manual, attr)}
        alternating = self.flag(manual, "outofphase")
        nonipsi = self.flag(manual, "nonipsi")
        if planes:
            return SignSymmetry("lr", frozenset(planes), alternating, nonipsi)
        if self.flag(manual, "both_hands") and manual.find("split_handconfig") is None:
            return SignSymmetry("par", frozenset(), alternating, nonipsi)
        return None

    # -- posture ---------------------------------------------------------------------------
    def handconfig(self, element: etree._Element) -> dict[str, object]:
        unknown = set(element.attrib) - _HANDCONFIG_ATTRS
        if unknown:
            raise self.error(element, f"unknown attribute {sorted(unknown)[0]!r}")
        features: dict[str, object] = {}
        if element.get("handshape") is not None:
            shape = self.handshape(element, "")
            if element.get("second_handshape") is not None:
                shape = replace(shape, between=self.handshape(element, "second_"))
            features["shape"] = shape
        if element.get("extfidir") is not None:
            features["ext_finger"] = self.direction(element, "extfidir")
        if element.get("palmor") is not None:
            palm = self.direction(element, "palmor")
            features["palm"] = PalmOrientation(palm.vector, palm.name, relative=element.get("rel_palmor") == "true")
        if not features:
            raise self.error(element, "names no hand shape, extended-finger direction or palm orientation")
        return features

    def handshape(self, element: etree._Element, prefix: str) -> HandShape:
        written = element.get(prefix + "handshape", "")
        basic = _HANDSHAPE_NAMES.get(written, written)
        if basic not in BASIC_HANDSHAPES:
            known = ", ".join(sorted(set(BASIC_HANDSHAPES) | set(_HANDSHAPE_NAMES)))
            raise self.error(element, f"unknown {prefix}handshape {written!r} (expected one of {known})")
        thumb = element.get(prefix + "thumbpos")
        if thumb is not None and thumb not in _THUMB_NAMES:
            raise self.error(element, f"unknown {prefix}thumbpos {thumb!r} (expected one of {', '.join(_THUMB_NAMES)})")
        thumb = _THUMB_NAMES.get(thumb or "")
        bending = element.get(prefix + "mainbend")
        if bending is not None and bending not in FINGER_BENDINGS:
            raise self.error(element, f"unknown {prefix}mainbend {bending!r}")
        bends = []
        for digit, finger in enumerate(FINGERS, start=1):
            value = element.get(f"bend{digit}") if not prefix else None
            if value is None:
                continue
            if value not in FINGER_BENDINGS:
                raise self.error(element, f"unknown bend{digit} {value!r}")
            bends.append(FingerBend((finger,), value))
        special = element.get("specialfingers") if not prefix else None
        extended = None
        if special is not None:
            if not special or any(c not in "12345" for c in special):
                raise self.error(element, f"specialfingers={special!r} (expected digits 1 to 5)")
            extended = tuple(FINGERS[int(c) - 1] for c in special)
        return HandShape(basic, thumb, bending, tuple(bends), extended, element.get("ceeopening"), name="ham" + basic)

    def direction(self, element: etree._Element, attr: str) -> Direction:
        first = self.letters(element, attr)
        second_letters = element.get("second_" + attr)
        if second_letters is None:
            return first
        second = self.letters(element, "second_" + attr)
        total = tuple(a + b for a, b in zip(first.vector, second.vector))
        norm = sum(c * c for c in total) ** 0.5
        if norm < 1e-9:
            raise self.error(element, f"{attr} and second_{attr} are opposite")
        return Direction(tuple(c / norm for c in total), f"{first.name} hambetween {second.name}")  # type: ignore[arg-type]

    def letters(self, element: etree._Element, attr: str) -> Direction:
        """A direction attribute, named like the HamNoSys symbol it stands for."""
        value = element.get(attr, "")
        prefix = _DIRECTION_SYMBOLS[attr.removeprefix("second_")]
        try:
            return Direction(direction_from_letters(value), prefix + value)
        except ValueError as error:
            raise self.error(element, f"{attr}={value!r}: {error}") from None

    def location(self, element: etree._Element) -> Location:
        return self.location_part(element)["location"]  # type: ignore[return-value]

    def location_part(self, element: etree._Element) -> dict[str, object]:
        """A ``<location_bodyarm>`` or ``<location_hand>``: the site (with its second site
        halfway, side and contact) and, from a ``<location_hand>`` inside it, the part of the
        moving hand that is there."""
        if element.tag not in ("location_bodyarm", "location_hand"):
            raise self.error(element, "expected <location_bodyarm> or <location_hand>")
        unknown = set(element.attrib) - _LOCATION_ATTRS
        if unknown:
            raise self.error(element, f"unknown attribute {sorted(unknown)[0]!r}")
        contact = element.get("contact")
        if contact is not None and contact not in _CONTACT_NAMES:
            raise self.error(element, f"unknown contact {contact!r} (expected one of {', '.join(sorted(_CONTACT_NAMES))})")
        place: Location = self.site(element, "")
        if element.get("second_location") or element.get("second_digits"):
            place = BetweenLocation(place, self.site(element, "second_"))
        parts = [child for child in element if isinstance(child.tag, str)]
        for part in parts:
            if part.tag != "location_hand":
                raise self.error(part, f"inside <{element.tag}> only <location_hand> (the hand part that is there) may stand")
        if parts:
            hand_part = self.site(parts[0], "")
            place = _with_hand_part(place, replace(hand_part, proximity=None))
        return {"location": place}

    def site(self, element: etree._Element, prefix: str) -> BodySite:
        """One site of a location element (``prefix`` ``second_`` for its second site)."""
        written = element.get(prefix + "location")
        digits = element.get(prefix + "digits") or (element.get("digits") if prefix else None)
        if digits is not None and (not digits or any(c not in "12345" for c in digits)):
            raise self.error(element, f"{prefix}digits={digits!r} (expected digits 1 to 5)")
        finger = FINGERS[int(digits[0]) - 1] if digits else None
        if not written:
            if element.tag == "location_hand" and finger is not None:
                return BodySite("finger", proximity=element.get("contact"), finger=finger)
            raise self.error(element, f"no {prefix}location attribute")
        name = _LOCATION_NAMES.get(written, written)
        symbol = lookup_symbol("ham" + name)
        if symbol is None or not (symbol.category.startswith("location") or symbol.category == "finger"):
            raise self.error(element, f"unknown {prefix}location {written!r} (expected a HamNoSys location name such as chest, cheek, palm or midjoint)")
        if symbol.category == "finger":
            name, finger = "finger", FINGERS[("hamthumb", "hamindexfinger", "hammiddlefinger", "hamringfinger", "hampinky").index(symbol.name)]
        side = element.get(prefix + "side") or (element.get("side") if prefix else None)
        if side is not None and side not in _SIDES and not (element.tag == "location_hand" and side in _HAND_SITE_SIDES):
            expected = ", ".join(sorted(set(_SIDES) | _HAND_SITE_SIDES)) if element.tag == "location_hand" else ", ".join(_SIDES)
            raise self.error(element, f"unknown {prefix}side {side!r} (expected one of {expected})")
        return BodySite(symbol.name[3:] if symbol.category != "finger" else name, _SIDES.get(side or ""), element.get("contact"), finger)

    def split(self, element: etree._Element, read: Callable[[etree._Element], dict[str, object]]) -> tuple[dict[str, object], dict[str, object]]:
        parts = [c for c in element if isinstance(c.tag, str)]
        if len(parts) != 2:
            raise self.error(element, f"has {len(parts)} parts (expected two: dominant and non-dominant hand)")
        return read(parts[0]), read(parts[1])

    def constellation(self, element: etree._Element) -> HandConstellation:
        hands = [c for c in element if c.tag == "location_hand"]
        body = [c for c in element if c.tag == "location_bodyarm"]
        if len(hands) not in (0, 2):
            raise self.error(element, f"has {len(hands)} <location_hand> (expected none or two)")
        contact = element.get("contact")
        if contact is not None and contact not in _CONTACT_NAMES:
            raise self.error(element, f"unknown contact {contact!r} (expected one of {', '.join(sorted(_CONTACT_NAMES))})")
        first, second = (self.location(hands[0]), self.location(hands[1])) if hands else (None, None)
        return HandConstellation(first, second, contact, self.location(body[0]) if body else None)

    # -- motion ------------------------------------------------------------------------------
    def motion(self, element: etree._Element) -> Constraint:
        tag = element.tag
        where = self.where_of(element)
        allowed = _MOTION_ATTRS.get(tag)
        if allowed is not None and not set(element.attrib) <= allowed:
            raise self.error(element, f"unknown attribute {sorted(set(element.attrib) - allowed)[0]!r}")
        if tag == "directedmotion":
            direction = self.direction(element, "direction")
            curve = element.get("curve")
            if curve is not None and curve not in _CURVES:
                raise self.error(element, f"unknown curve {curve!r}")
            kind = SegmentKind.CURVE if curve else SegmentKind.LINEAR
            segment = Segment(kind, direction=direction, shape=_CURVES.get(curve or ""), where=where)
            return Dynamic("HandLocation", (self.qualities(element, segment),), where=where)
        if tag == "circularmotion":
            axis = self.direction(element, "axis")
            modifiers = tuple(f"{key}={element.get(key)}" for key in ("start", "end") if element.get(key))
            if element.get("ellipse_direction"):
                modifiers += (f"ellipse={element.get('ellipse_direction')}",)
            segment = Segment(SegmentKind.CIRCLE, normal=axis, where=where, modifiers=modifiers)
            return Dynamic("HandLocation", (self.qualities(element, segment),), where=where)
        if tag == "wristmotion":
            motion = element.get("motion", "")
            if motion not in _WRIST_MOTIONS:
                raise self.error(element, f"unknown motion {motion!r} (expected one of {', '.join(_WRIST_MOTIONS)})")
            slot, kind = _WRIST_MOTIONS[motion]
            return Dynamic(slot, (self.qualities(element, Segment(kind, shape=motion, where=where)),), where=where)
        if tag == "fingerplay":
            return Dynamic("HandShape", (self.qualities(element, Segment(SegmentKind.LINEAR, shape="fingerplay", where=where)),), where=where)
        if tag == "nomotion":
            return Dynamic("HandLocation", (Segment(SegmentKind.LINEAR, shape="nomotion", where=where, manner="targetted"),), where=where)
        if tag in ("tgt_motion", "changeposture"):
            return self.target_motion(element)
        if tag == "rpt_motion":
            return self.repetition(element)
        if tag in ("seq_motion", "par_motion"):
            children = self.children_motions(element)
            return (Sequence if tag == "seq_motion" else Parallel)(tuple(children), where=where)
        if tag == "split_motion":
            parts = self.children_motions(element)
            if len(parts) != 2:
                raise self.error(element, f"has {len(parts)} parts (expected two: dominant and non-dominant hand)")
            return Parallel((scoped_to(parts[0], self.dominant), scoped_to(parts[1], self.dominant.other)), where=where)
        raise self.error(element, "unknown motion element")

    def keep_nonmanual(self, element: etree._Element) -> None:
        """A ``<nonman_motion>`` inside the manual part goes to the nonmanual tiers."""
        for tier, items in _nonmanual_tiers(element, self.where_of).items():
            self.nonmanual.setdefault(tier, []).extend(items)

    def qualities(self, element: etree._Element, segment: Segment) -> Segment:
        size = element.get("size")
        if size is not None and size not in _SIZES:
            raise self.error(element, f"unknown size {size!r} (expected small, big, large, increasing or decreasing)")
        manner = element.get("manner", "targetted")
        if manner not in _MANNERS:
            raise self.error(element, f"unknown manner {manner!r} (expected one of {', '.join(_MANNERS)})")
        return replace(segment, size=_SIZES.get(size or ""), manner=manner)

    def children_motions(self, element: etree._Element) -> list[Constraint]:
        motions = []
        for child in (c for c in element if isinstance(c.tag, str)):
            if child.tag == "nonman_motion":
                self.keep_nonmanual(child)
            else:
                motions.append(self.motion(child))
        if not motions:
            raise self.error(element, "has no motion inside")
        return motions

    def repetition(self, element: etree._Element) -> Constraint:
        value = element.get("repetition", "")
        if value not in _REPETITIONS:
            raise self.error(element, f"unknown repetition {value!r} (expected one of {', '.join(_REPETITIONS)})")
        mode, count = _REPETITIONS[value]
        children = self.children_motions(element)
        child = children[0] if len(children) == 1 else Sequence(tuple(children))
        return Repetition(child, count, where=self.where_of(element), mode=mode, alternating=self.flag(element, "outofphase"))

    def target_motion(self, element: etree._Element) -> Constraint:
        """A movement to a target posture (``<tgt_motion>``/``<changeposture>``): one
        one-segment leaf per feature the targets name, in parallel with the motions inside.
        ``<changeposture/>`` with nothing inside only marks a change of posture."""
        where = self.where_of(element)
        leaves: list[Constraint] = []
        manner = element.get("manner", "targetted")
        if manner not in _MANNERS:
            raise self.error(element, f"unknown manner {manner!r} (expected one of {', '.join(_MANNERS)})")
        for child in (c for c in element if isinstance(c.tag, str)):
            tag = child.tag
            if tag == "changeposture" and not len(child):
                continue
            if tag in ("handconfig", "location_bodyarm", "location_hand"):
                features = self.handconfig(child) if tag == "handconfig" else self.location_part(child)
                leaves.extend(_target_leaves(features, None, where, manner))
            elif tag in ("split_handconfig", "split_location"):
                first, second = self.split(child, self.handconfig if tag == "split_handconfig" else self.location_part)
                leaves.extend(_target_leaves(first, self.dominant, where, manner))
                leaves.extend(_target_leaves(second, self.dominant.other, where, manner))
            elif tag == "handconstellation":
                leaves.append(self.constellation_target(child, manner))
            elif tag == "nonman_motion":
                self.keep_nonmanual(child)
            else:
                leaves.append(self.motion(child))
        if not leaves:
            raise self.error(element, "has no target or motion inside")
        return leaves[0] if len(leaves) == 1 else Parallel(tuple(leaves), where=where)

    def constellation_target(self, element: etree._Element, manner: str) -> Constraint:
        """The dominant hand moving to meet the other hand as a ``<handconstellation>`` says:
        to the other hand's site, with the contact, its own site as the part that is there."""
        constellation = self.constellation(element)
        where = self.where_of(element)
        target: Location = constellation.nondominant or BodySite("palm")
        if isinstance(target, BodySite):
            target = replace(target, proximity=constellation.contact or target.proximity)
            if isinstance(constellation.dominant, BodySite):
                target = replace(target, hand_part=constellation.dominant)
        return Dynamic("HandLocation", (Segment(SegmentKind.LINEAR, end=target, where=where, manner=manner),), scope=self.dominant, where=where)


_SLOTS_OF_FEATURES = {"shape": "HandShape", "ext_finger": "ExtFingerOrientation", "palm": "PalmOrientation", "location": "HandLocation"}


def _target_leaves(features: dict[str, object], scope: Arm | None, where: SourceLocation, manner: str) -> list[Constraint]:
    """One one-segment leaf per feature a target names (scoped to one arm, or to both under symmetry)."""
    return [
        Dynamic(_SLOTS_OF_FEATURES[key], (Segment(SegmentKind.LINEAR, end=value, where=where, manner=manner),), scope=scope, where=where)  # type: ignore[arg-type]
        for key, value in features.items()
    ]


def _with_hand_part(location: Location, part: BodySite) -> Location:
    if isinstance(location, BodySite):
        return replace(location, hand_part=part)
    if isinstance(location, BetweenLocation):
        return replace(location, first=_with_hand_part(location.first, part))
    return location


def _posture(features: dict[str, object]) -> HandPosture:
    return HandPosture(
        shape=features.get("shape"),  # type: ignore[arg-type]
        ext_finger=features.get("ext_finger"),  # type: ignore[arg-type]
        palm=features.get("palm"),  # type: ignore[arg-type]
        location=features.get("location"),  # type: ignore[arg-type]
    )

