"""The grammar of the HamNoSys manual stream, and HamNoSys 4 Unicode strings.

A HamNoSys transcription is a flat string of symbols; this module reads it with a small
recursive-descent parser into a :class:`~mura.signs.Sign`. The grammar, as real corpora
write it (``[…]`` optional, ``{…}`` any number, ``|`` choice)::

    sign        = [alternatingmotion] [symmetry] posture [manner] {action}
                  {plus [symmetry] posture {action}}
    symmetry    = (symmlr | symmpar) {fingerstraightmod | largemod | alternatingmotion
                  | nonipsi | fingerplay}
    posture     = group {group}
    group       = hand | parbegin hand plus (hand | nomotion) parend [contact] [location]
    hand        = [nondominant] [etc] [shape] [etc] [extfinger] [palm] [etc]
                  [location [bending | thumbmod | fingers bending]]
    shape       = handshape {thumbmod | bending | fingers bending | fingers
                  | fingers (handsite | between) fingers} [between shape]
    extfinger   = extfinger [orirelative] [extfinger] [between extfinger] [orirelative]
    palm        = palm [between palm] [orirelative]
    location    = {contact} place [between place] {contact}
                  [seqbegin contact handpart seqend]
    place       = [side] (site | finger) {site | finger} [side]
    action      = unit {repeat [alternatingmotion] [move] | alternatingmotion | size | manner
                        | (seqbegin | parbegin | fusionbegin) repeat [move] end}
                | (size | manner) unit | repeat
    unit        = move {modifier} | circle {modifier} | local {modifier}
                | replace {size | manner} posture | posture
                | seqbegin {action} seqend | fusionbegin {action} fusionend
                | parbegin {action} [plus {action}] parend
                | location
    modifier    = size | manner | arc | clock | ellipse | between move | contact
                | location | alternatingmotion

Decisions the real corpora force (documented because they change meaning):

- After a symmetry symbol, ``hamlargemod`` adds the up–down mirror (plane ``T``) and
  ``hamfingerstraightmod`` the front–back mirror (plane ``F``): the corpora write the
  HamNoSys 4 composed mirror glyphs with those overstrikes.
- Two extended-finger directions in a row (``hamextfingeruo hamextfingerol``) and
  ``a hambetween b`` both mean the direction halfway between (the normalized sum).
- A repetition applies to the unit just before it (a bracket counts as one unit).
- A size or manner after a bracket applies to every segment inside it that has none.
- A shape or orientation in the movement part without ``hamreplace`` is a change of
  posture all the same; ``hamplus`` at the top level joins a further part of a compound
  sign, which starts with a change to its own posture.
- A manner after a posture with no movement (``… hampalmd hamtense``) is the sign's
  :attr:`~mura.signs.Sign.manner`; ``hamnondominant`` before a one-hand posture makes the
  whole sign with the non-dominant arm.
- Each part of a compound may write its own symmetry operator (``… hamplus hamsymmpar …``):
  a part whose operator differs from the sign's is a :class:`~mura.constraints.Symmetrical`
  node of the movement, both hands taking part in it.
- A straight movement right after a repetition inside a bracket is the repetition's
  *displacement* (``( move repeat move )``: each pass shifted, as shelves stacked
  downwards); so is a bracket that opens with a repetition after a movement
  (``move [ repeat move ]``). Outside brackets a movement after a repetition follows it.
- A repetition with no movement before it, when the hand touches its location
  (``shouldertop hambehind hamtouch hamrepeatfromstart``), repeats the contact: the hand
  leaves the site (``close``) and touches it again.
- A contact bracket after a location, ``seqbegin contact hand-part… seqend``
  (``hamnose [hamtouch hamthumb hamfingertip]``), names the part of the moving hand that
  makes the contact (:attr:`~mura.values.BodySite.hand_part`), in a one-handed location or
  either hand's in a split one; a bracket holding anything else is a movement.
- A finger bending (or thumb modifier) written after a location is the shape the hand
  holds there (HamNoSys 4's qualifiers after the location); a run of contact symbols is
  one contact, the last that is not ``hambehind`` (``hambehind hamtouch`` touches).
- ``hamneutralspace`` is a location like any other (the motor reads it as neutral space),
  for either hand.
- ``hamfusionbegin … hamfusionend`` (movements fused into one) is read as a sequence; a
  location after a movement is its end, after a bracket a ``Static`` target.
- Of alternatives ``hamaltbegin a hammetaalt b hamaltend`` the first is read.
- Punctuation, ``hamversion40``, ``hammime`` and the coreference tags annotate the
  stream and are skipped by the grammar (they stay in :attr:`Sign.symbols`).
- A hand site in a location without a partner is a site of the non-dominant hand;
  an arm site followed by a hand side (``hamlowerarm hampalm``) is written
  ``lowerarm:palm`` (the palm side of the lower arm).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from mura.constraints import (
    Arm,
    Constraint,
    Dynamic,
    Parallel,
    Repetition,
    Segment,
    SegmentKind,
    Static,
    Symmetrical,
)
from mura.constraints import Sequence as SequenceNode
from mura.errors import SourceLocation, SpecError
from mura.expansion import check_sign
from mura.hamnosys_symbols import Symbol, vocabulary
from mura.limits import DEFAULT_LIMITS, Limits
from mura.signs import HandConstellation, HandPosture, NonmanualItem, Sign, SignSymmetry
from mura.values import (
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

#: Symbols that annotate the stream and that the grammar skips.
ANNOTATIONS: frozenset[str] = frozenset(
    {"hamspace", "hamexclaim", "hamcomma", "hamfullstop", "hamquery", "hamversion40", "hammime", "hamcoreftag", "hamcorefref"}
)

_BENDINGS: dict[str, str] = {
    "hamfingerstraightmod": "straight",
    "hamfingerbendmod": "bent",
    "hamfingerhookmod": "hooked",
    "hamdoublebent": "dblbent",
    "hamdoublehooked": "dblhooked",
}
_THUMBS: dict[str, str] = {"hamthumboutmod": "out", "hamthumbacrossmod": "across", "hamthumbopenmod": "open"}
_FINGER_OF: dict[str, str] = dict(zip(("hamthumb", "hamindexfinger", "hammiddlefinger", "hamringfinger", "hampinky"), FINGERS))
_SIZES: dict[str, str] = {"hamsmallmod": "small", "hamlargemod": "large", "hamincreasing": "increasing", "hamdecreasing": "decreasing"}
_MANNERS: dict[str, str] = {"hamfast": "fast", "hamslow": "slow", "hamtense": "tense", "hamrest": "rest", "hamhalt": "halt"}
_REPEATS: dict[str, tuple[str, int]] = {
    "hamrepeatfromstart": ("fromstart", 2),
    "hamrepeatfromstartseveral": ("fromstart", 3),
    "hamrepeatcontinue": ("continue", 2),
    "hamrepeatcontinueseveral": ("continue", 3),
    "hamrepeatreverse": ("reverse", 2),
}
#: Contacts and proximities: the first five are contacts, the last two distances.
_CONTACTS: dict[str, str] = {
    "hamtouch": "touch",
    "hamclose": "close",
    "haminterlock": "interlock",
    "hamcross": "cross",
    "hambrushing": "brushing",
    "hamarmextended": "armextended",
    "hambehind": "behind",
}
#: Local movements: the slot each moves and the segment kind.
_LOCAL_MOVES: dict[str, tuple[str, SegmentKind]] = {
    "hamnodding": ("ExtFingerOrientation", SegmentKind.LINEAR),
    "hamswinging": ("ExtFingerOrientation", SegmentKind.LINEAR),
    "hamtwisting": ("PalmOrientation", SegmentKind.LINEAR),
    "hamfingerplay": ("HandShape", SegmentKind.LINEAR),
    "hamstircw": ("HandLocation", SegmentKind.CIRCLE),
    "hamstirccw": ("HandLocation", SegmentKind.CIRCLE),
    "hamnomotion": ("HandLocation", SegmentKind.LINEAR),
    "hammovecross": ("HandLocation", SegmentKind.LINEAR),
    "hammovex": ("HandLocation", SegmentKind.LINEAR),
}
#: Contacts a repeated contact repeats (touching the site, not hovering near it).
_TOUCHES = frozenset({"touch", "brushing", "interlock", "cross"})
_OPENER_OF: dict[str, str] = {"hamseqend": "hamseqbegin", "hamparend": "hamparbegin", "hamfusionend": "hamfusionbegin"}
#: Deepest nesting of brackets accepted (real signs nest three or four deep).
MAX_NESTING = 32
_FEATURE_STARTS = frozenset({"handshape", "extfinger", "palm"})
_SITE_CATEGORIES = frozenset({"location-head", "location-body", "location-arm", "location-hand"})
_HAND_SIDES = frozenset({"hampalm", "hamhandback", "hamthumbside", "hampinkyside"})
#: Categories of the symbols that name a part of the moving hand in a contact bracket.
_HAND_PART_CATEGORIES = frozenset({"finger", "location-hand", "location-arm", "side"})
_POSTURE_STARTS = frozenset(
    {"handshape", "thumbmod", "extfinger", "palm", "side", "finger", "contact"} | _SITE_CATEGORIES
)


@dataclass(frozen=True)
class Token:
    """One symbol of a manual stream, its index in the stream and where it was written."""

    symbol: Symbol
    index: int
    where: SourceLocation

    @property
    def name(self) -> str:
        return self.symbol.name

    @property
    def category(self) -> str:
        return self.symbol.category


def tokens_from_names(
    names: Iterable[tuple[str, SourceLocation]], gloss: str
) -> list[Token]:
    """Tokens for symbol names (tag names of ``<hamnosys_manual>``), with aliases resolved.

    Raises SpecError naming the sign, the symbol and its position for an unknown name.
    """
    table = vocabulary()
    tokens: list[Token] = []
    for index, (name, where) in enumerate(names):
        symbol = table.lookup(name)
        if symbol is None:
            raise SpecError(f"sign {gloss!r}: unknown HamNoSys symbol {name!r} at position {index}", where)
        tokens.append(Token(symbol, index, where))
    return tokens


def tokens_from_string(text: str, gloss: str, file: str = "<string>") -> list[Token]:
    """Tokens for a HamNoSys 4 Unicode string; whitespace is the font's space.

    Positions are 1-based columns of the string on line 1.
    """
    table = vocabulary()
    tokens: list[Token] = []
    for index, char in enumerate(text):
        where = SourceLocation(file, 1, index + 1)
        symbol = table.of_char(char)
        if symbol is None and char.isspace():
            symbol = table.lookup("hamspace")
        if symbol is None:
            raise SpecError(
                f"sign {gloss!r}: character U+{ord(char):04X} at position {index} is not a HamNoSys symbol", where
            )
        tokens.append(Token(symbol, index, where))
    return tokens


def hamnosys_string(names: Iterable[str]) -> str:
    """The HamNoSys 4 Unicode string of symbol names (aliases allowed)."""
    table = vocabulary()
    chars = []
    for name in names:
        symbol = table.lookup(name)
        if symbol is None:
            raise ValueError(f"unknown HamNoSys symbol {name!r}")
        chars.append(symbol.char)
    return "".join(chars)


def parse_hamnosys(text: str, gloss: str = "<string>", file: str = "<string>", limits: Limits = DEFAULT_LIMITS) -> Sign:
    """A sign from a HamNoSys 4 Unicode string (private-use codepoints U+E000 …).

    Raises SpecError naming the gloss, the symbol and its position for anything the
    grammar does not accept, and for a sign whose repetitions expand to more than
    ``limits.max_movements`` movements.
    """
    tokens = tokens_from_string(text, gloss, file)
    return check_sign(parse_manual(tokens, gloss, SourceLocation(file, 1, 1)), limits)


def parse_manual(
    tokens: Sequence[Token],
    gloss: str,
    where: SourceLocation | None = None,
    dominant: Arm = Arm.RIGHT,
    nonmanual: Mapping[str, tuple[NonmanualItem, ...]] | None = None,
) -> Sign:
    """Read a manual stream into a :class:`Sign` (see the module's grammar)."""
    where = where or SourceLocation("<input>")
    if not any(t.name not in ANNOTATIONS for t in tokens):
        raise SpecError(f"sign {gloss!r}: empty manual stream", where)
    stream = _first_alternatives([t for t in tokens if t.name not in ANNOTATIONS], gloss, where)
    parser = _Parser(stream, gloss, where, dominant)
    sign = parser.sign()
    return replace(sign, nonmanual=dict(nonmanual or {}), symbols=tuple(t.name for t in tokens))


def _first_alternatives(tokens: list[Token], gloss: str, where: SourceLocation) -> list[Token]:
    """Keep only the first alternative of each ``hamaltbegin … hammetaalt … hamaltend``."""
    kept: list[Token] = []
    stack: list[tuple[Token, bool]] = []  # (opening token, inside a dropped alternative)
    for token in tokens:
        dropping = bool(stack) and stack[-1][1]
        if token.name == "hamaltbegin":
            stack.append((token, dropping))
        elif token.name == "hammetaalt":
            if not stack:
                raise _misplaced(gloss, token, "hammetaalt outside hamaltbegin … hamaltend")
            stack[-1] = (stack[-1][0], True)
        elif token.name == "hamaltend":
            if not stack:
                raise _misplaced(gloss, token, "hamaltend without hamaltbegin")
            stack.pop()
        elif not dropping:
            kept.append(token)
    if stack:
        opening = stack[-1][0]
        raise SpecError(
            f"sign {gloss!r}: hamaltbegin at position {opening.index} is never closed by hamaltend", opening.where
        )
    return kept


def _misplaced(gloss: str, token: Token, why: str) -> SpecError:
    return SpecError(f"sign {gloss!r}: misplaced symbol {token.name} at position {token.index}: {why}", token.where)


def _direction(name: str, prefix: str) -> Direction:
    return Direction(direction_from_letters(name[len(prefix):]), name)


def _halfway(first: Direction, second: Direction, name: str) -> Direction | None:
    """The direction halfway between two, None when they are opposite."""
    total = np.add(first.vector, second.vector)
    norm = float(np.linalg.norm(total))
    if norm < 1e-9:
        return None
    unit = total / norm
    return Direction((float(unit[0]), float(unit[1]), float(unit[2])), name)


@dataclass
class _Hand:
    """Features of one hand collected while reading a posture description."""

    shape: HandShape | None = None
    ext_finger: Direction | None = None
    palm: PalmOrientation | None = None
    location: Location | None = None
    contact: str | None = None
    etc: bool = False
    nondominant: bool = False

    @property
    def only_location(self) -> bool:
        return self.shape is None and self.ext_finger is None and self.palm is None and self.location is not None

    def posture(self) -> HandPosture:
        return HandPosture(self.shape, self.ext_finger, self.palm, self.location, self.etc)


@dataclass
class _Posture:
    """A posture read from the stream: the dominant hand, the other hand and their constellation."""

    dominant: _Hand
    other: _Hand | None = None
    constellation: HandConstellation | None = None


@dataclass
class _Parser:
    tokens: list[Token]
    gloss: str
    where: SourceLocation
    dominant: Arm
    pos: int = 0
    depth: int = 0
    two_handed: bool = False
    current: dict[str, object] = field(default_factory=dict)

    # -- stream access -------------------------------------------------------------------
    def peek(self, ahead: int = 0) -> Token | None:
        index = self.pos + ahead
        return self.tokens[index] if index < len(self.tokens) else None

    def at(self, *names: str) -> bool:
        token = self.peek()
        return token is not None and token.name in names

    def at_category(self, *categories: str) -> bool:
        token = self.peek()
        return token is not None and token.category in categories

    def take(self) -> Token:
        token = self.peek()
        if token is None:
            raise self.truncated("a symbol")
        self.pos += 1
        return token

    def expect(self, name: str, context: str) -> Token:
        token = self.peek()
        if token is None:
            raise self.truncated(f"{name} to close {context}")
        if token.name != name:
            raise self.unexpected(token, f"{name} to close {context}")
        return self.take()

    def truncated(self, expected: str) -> SpecError:
        last = self.tokens[-1] if self.tokens else None
        where = last.where if last else self.where
        return SpecError(f"sign {self.gloss!r}: stream ends early at position {len(self.tokens)}: expected {expected}", where)

    def unexpected(self, token: Token, expected: str) -> SpecError:
        return SpecError(
            f"sign {self.gloss!r}: unexpected symbol {token.name} at position {token.index}: expected {expected}",
            token.where,
        )

    # -- sign ----------------------------------------------------------------------------
    def sign(self) -> Sign:
        alternating = False
        if self.at("hamalternatingmotion"):
            self.take()
            alternating = True
        symmetry = self.symmetry()
        posture = self.posture()
        if posture.dominant.nondominant and posture.other is None:
            self.dominant = self.dominant.other  # the whole sign is made by the non-dominant hand
        manner = None
        if self.at_category("manner") and self.peek(1) is None:
            manner = _MANNERS[self.take().name]  # a held posture performed tensely, …
        self.current = _features(posture.dominant)
        actions = self.actions(stop=())
        while self.at("hamplus"):
            actions.append(self.compound_part(symmetry))
        token = self.peek()
        if token is not None and token.name in _OPENER_OF:
            raise _misplaced(self.gloss, token, f"{token.name} without a matching {_OPENER_OF[token.name]}")
        if token is not None:
            raise self.unexpected(token, "a movement, a repetition or the end of the sign")
        movement = _sequence(actions)
        if alternating and movement is not None:
            movement = _alternating(movement)
        two_handed = symmetry is not None or posture.other is not None or posture.constellation is not None or self.two_handed
        return Sign(
            gloss=self.gloss,
            posture=posture.dominant.posture(),
            dominant=self.dominant,
            two_handed=two_handed,
            symmetry=symmetry,
            nondominant=posture.other.posture() if posture.other is not None else None,
            constellation=posture.constellation,
            movement=movement,
            manner=manner,
            where=self.where,
        )

    def compound_part(self, symmetry: SignSymmetry | None) -> Constraint:
        """The next part of a compound (after a top-level ``hamplus``): a change to its own
        posture and its movements. A part that writes its own symmetry operator is wrapped
        in :class:`Symmetrical` with it (both hands take part from there on); a part
        without one keeps the sign's."""
        plus = self.take()
        own = self.symmetry()
        if self.peek() is None:
            raise self.truncated("the posture of the next part after hamplus")
        part = [self.posture_change(plus, self.posture())]
        part.extend(self.actions(stop=()))
        body = _sequence(part)
        assert body is not None
        if own is None or own == symmetry:
            return body
        self.two_handed = True
        if own.alternating:
            body = _alternating(body)
        return Symmetrical(body, self.dominant, own.to_model(), where=plus.where)

    def symmetry(self) -> SignSymmetry | None:
        if not self.at("hamsymmlr", "hamsymmpar"):
            return None
        kind = "lr" if self.take().name == "hamsymmlr" else "par"
        planes = {"S"} if kind == "lr" else set()
        alternating = nonipsi = fingerplay = False
        while self.at("hamfingerstraightmod", "hamlargemod", "hamalternatingmotion", "hamnonipsi", "hamfingerplay", "hamsymmlr"):
            name = self.take().name
            if name == "hamlargemod":
                planes.add("T")
            elif name == "hamfingerstraightmod":
                planes.add("F")
            elif name == "hamalternatingmotion":
                alternating = True
            elif name == "hamnonipsi":
                nonipsi = True
            elif name == "hamfingerplay":
                fingerplay = True
            else:
                planes.add("S")
                kind = "lr"
        return SignSymmetry(kind, frozenset(planes) if kind == "lr" else frozenset(), alternating, nonipsi, fingerplay)

    # -- posture -------------------------------------------------------------------------
    def posture(self) -> _Posture:
        """One or more groups of hand features, single or paired for the two hands."""
        posture = _Posture(_Hand())
        start = self.pos
        while self.at_posture_group():
            if not self.at("hamparbegin"):
                _merge(posture.dominant, self.hand(allow_empty=False))
                continue
            first, second, contact = self.hand_pair()
            location = self.location() if self.at_location() else None
            if first.only_location and second.only_location and _on_hands(first.location, second.location):
                posture.constellation = HandConstellation(first.location, second.location, contact, location)
                continue
            posture.other = posture.other or _Hand()
            _merge(posture.dominant, first)
            _merge(posture.other, second)
            if contact is not None and posture.dominant.location is not None:
                posture.dominant.location = _with_contact(posture.dominant.location, contact)
            if location is not None:
                posture.dominant.location = location
        if self.pos == start:
            token = self.peek()
            if token is None:
                raise self.truncated("a hand shape, orientation or location")
            raise self.unexpected(token, "a hand shape, orientation or location")
        return posture

    def at_posture_group(self) -> bool:
        token = self.peek()
        if token is None:
            return False
        if token.name == "hamparbegin":
            following = self.peek(1)
            return following is not None and (
                following.category in _POSTURE_STARTS or following.name in ("hamnondominant", "hametc")
            )
        return token.category in _POSTURE_STARTS or token.name in ("hamnondominant", "hametc")

    def hand_pair(self) -> tuple[_Hand, _Hand, str | None]:
        opening = self.take()
        self.two_handed = True
        first = self.hand(allow_empty=False)
        if self.peek() is None:
            raise self.truncated("hamplus between the two hands")
        if not self.at("hamplus"):
            raise self.unexpected(self.tokens[self.pos], f"hamplus between the two hands of hamparbegin at position {opening.index}")
        self.take()
        if self.at("hamnomotion"):
            self.take()
            second = _Hand()
        else:
            second = self.hand(allow_empty=False)
        if self.peek() is not None and not self.at("hamparend"):
            raise self.unexpected(self.tokens[self.pos], f"hamparend to close hamparbegin at position {opening.index}")
        self.expect("hamparend", f"hamparbegin at position {opening.index}")
        contact = _CONTACTS[self.take().name] if self.at_category("contact") else None
        return first, second, contact

    def hand(self, allow_empty: bool) -> _Hand:
        hand = _Hand()
        start = self.pos
        if self.at("hamnondominant"):
            self.take()
            hand.nondominant = True
        hand.etc |= self.skip_etc()
        if self.at_category("handshape"):
            hand.shape = self.shape()
        elif self.at_shape_modifier():
            base = self.current.get("HandShape")
            if not isinstance(base, HandShape):
                raise self.unexpected(self.tokens[self.pos], "a hand shape before its modifier")
            hand.shape = self.shape_modifiers(base)
        hand.etc |= self.skip_etc()
        if self.at_category("extfinger"):
            hand.ext_finger = self.ext_finger()
        if self.at_category("palm"):
            hand.palm = self.palm()
        elif self.at("hamorirelative"):
            self.take()
        hand.etc |= self.skip_etc()
        if self.at_location():
            hand.location = self.location()
            if self.at_shape_modifier():
                hand.shape = self.bending_at_location(hand)
        hand.etc |= self.skip_etc()
        if self.pos == start and not allow_empty:
            token = self.peek()
            if token is None:
                raise self.truncated("a hand shape, orientation or location")
            raise self.unexpected(token, "a hand shape, orientation or location")
        return hand

    def bending_at_location(self, hand: _Hand) -> HandShape:
        """A finger bending (or thumb modifier) written after the location: the hand's
        shape as it is held there, bent so."""
        base = hand.shape or self.current.get("HandShape")
        if not isinstance(base, HandShape):
            raise self.unexpected(self.tokens[self.pos], "a hand shape before its bending")
        return self.shape_modifiers(base)

    def skip_etc(self) -> bool:
        seen = False
        while self.at("hametc"):
            self.take()
            seen = True
        return seen

    def at_shape_modifier(self) -> bool:
        token = self.peek()
        if token is None:
            return False
        if token.category == "finger":
            _, after = self.finger_run()
            return after is not None and after.category == "bending"
        return token.category in ("thumbmod", "bending")

    def shape(self) -> HandShape:
        shape = self.basic_shape()
        if self.at("hambetween") and self.peek(1) is not None and self.peek(1).category == "handshape":
            self.take()
            shape = replace(shape, between=self.basic_shape())
        return shape

    def basic_shape(self) -> HandShape:
        basic = self.take()
        return self.shape_modifiers(HandShape(basic=basic.name[3:], name=basic.name))

    def shape_modifiers(self, shape: HandShape) -> HandShape:
        while True:
            token = self.peek()
            if token is None:
                return shape
            if token.category == "thumbmod":
                self.take()
                shape = replace(shape, thumb=_THUMBS[token.name])
            elif token.category == "bending":
                self.take()
                shape = replace(shape, bending=_BENDINGS[token.name])
            elif token.category == "finger":
                fingers, after = self.finger_run()
                if after is not None and after.category == "bending":
                    self.pos += len(fingers)
                    bending = _BENDINGS[self.take().name]
                    shape = replace(shape, finger_bends=shape.finger_bends + (FingerBend(fingers, bending),))
                elif after is not None and after.category == "location-hand":
                    shape = replace(shape, contact=self.shape_contact())
                elif after is not None and after.name == "hambetween" and self.peek(len(fingers) + 1) is not None \
                        and self.peek(len(fingers) + 1).category == "finger":
                    shape = replace(shape, contact=self.shape_contact())
                elif after is not None and (after.category in _SITE_CATEGORIES or after.category in ("contact", "side")):
                    return shape
                else:
                    self.pos += len(fingers)
                    shape = replace(shape, extended=(shape.extended or ()) + fingers)
            else:
                return shape

    def shape_contact(self) -> tuple[str, ...]:
        """Digits touching inside a hand shape: fingers, a site (or hambetween), fingers."""
        fingers, _ = self.finger_run()
        self.pos += len(fingers)
        site = self.take().name[3:]
        partners, _ = self.finger_run()
        self.pos += len(partners)
        return fingers + (site,) + partners

    def finger_run(self) -> tuple[tuple[str, ...], Token | None]:
        fingers: list[str] = []
        ahead = 0
        while (token := self.peek(ahead)) is not None and token.category == "finger":
            fingers.append(_FINGER_OF[token.name])
            ahead += 1
        return tuple(fingers), self.peek(ahead)

    def ext_finger(self) -> Direction:
        first = self.take()
        direction = _direction(first.name, "hamextfinger")
        if self.at("hamorirelative"):
            self.take()
        if self.at_category("extfinger"):
            second = self.take()
            direction = self.between(direction, second, "hamextfinger", f"{first.name} {second.name}")
        if self.at("hambetween") and self.peek(1) is not None and self.peek(1).category == "extfinger":
            self.take()
            other = self.take()
            direction = self.between(direction, other, "hamextfinger", f"{direction.name} hambetween {other.name}")
        if self.at("hamorirelative"):
            self.take()
        return direction

    def palm(self) -> PalmOrientation:
        first = self.take()
        direction = _direction(first.name, "hampalm")
        if self.at("hambetween") and self.peek(1) is not None and self.peek(1).category == "palm":
            self.take()
            other = self.take()
            direction = self.between(direction, other, "hampalm", f"{first.name} hambetween {other.name}")
        relative = False
        if self.at("hamorirelative"):
            self.take()
            relative = True
        return PalmOrientation(direction.vector, direction.name, relative)

    # -- location ------------------------------------------------------------------------
    def at_location(self) -> bool:
        token = self.peek()
        if token is None:
            return False
        if token.category in _SITE_CATEGORIES or token.category in ("side", "finger", "contact"):
            return True
        return False

    def location(self) -> Location:
        contact = self.contacts()
        if not self.at_place():
            if contact is None:
                token = self.peek()
                raise self.truncated("a location") if token is None else self.unexpected(token, "a location")
            return BodySite("contact", proximity=contact)
        location: Location = self.place()
        if self.at("hambetween") and self.at_place(ahead=1):
            self.take()
            location = BetweenLocation(location, self.place())
        self.skip_etc()
        contact = self.contacts() or contact
        if contact is not None:
            location = _with_contact(location, contact)
        if self.at_contact_bracket():
            location = self.contact_bracket(location)
        return location

    def contacts(self) -> str | None:
        """A run of contact symbols (``hambehind hamtouch``): the contact the hand makes;
        ``behind`` (a side of the site, not a distance) only when it stands alone."""
        names: list[str] = []
        while self.at_category("contact"):
            names.append(_CONTACTS[self.take().name])
        made = [name for name in names if name != "behind"]
        return made[-1] if made else (names[-1] if names else None)

    def at_contact_bracket(self) -> bool:
        """Whether a bracket ``hamseqbegin contact hand-part… hamseqend`` follows: the part
        of the moving hand that makes the location's contact (HamNoSys 4)."""
        if not self.at("hamseqbegin"):
            return False
        contact = self.peek(1)
        if contact is None or contact.category != "contact":
            return False
        ahead = 2
        while (token := self.peek(ahead)) is not None and token.category in _HAND_PART_CATEGORIES:
            ahead += 1
        token = self.peek(ahead)
        return ahead > 2 and token is not None and token.name == "hamseqend"

    def contact_bracket(self, location: Location) -> Location:
        self.take()
        contact = self.contacts()
        assert contact is not None
        part = self.place()
        self.expect("hamseqend", "the contact bracket")
        return _with_hand_part(_with_contact(location, contact), part)

    def at_place(self, ahead: int = 0) -> bool:
        token = self.peek(ahead)
        return token is not None and (token.category in _SITE_CATEGORIES or token.category in ("side", "finger"))

    def place(self) -> BodySite:
        side = _side(self.take().name) if self.at_category("side") else None
        fingers: list[str] = []
        sites: list[str] = []
        while (token := self.peek()) is not None and (token.category in _SITE_CATEGORIES or token.category == "finger"):
            self.take()
            if token.category == "finger":
                fingers.append(_FINGER_OF[token.name])
            else:
                sites.append(token.name[3:])
        if self.at_category("side"):
            side = _side(self.take().name)
        if not sites and not fingers:
            token = self.peek()
            raise self.truncated("a location after the side") if token is None else self.unexpected(token, "a location after the side")
        site = ":".join(sites) if sites else "finger"
        return BodySite(site, side=side, finger=fingers[0] if fingers else None)

    # -- actions -------------------------------------------------------------------------
    def actions(self, stop: tuple[str, ...]) -> list[Constraint]:
        actions: list[Constraint] = []
        while (token := self.peek()) is not None and token.name not in stop:
            if token.category == "repeat":
                if not actions and token.name != "hamalternatingmotion" and not stop and self.touching():
                    actions.append(self.tap(token))
                if not actions:
                    raise self.unexpected(token, "a movement before the repetition")
                if token.name == "hamalternatingmotion":
                    self.take()
                    actions[-1] = _alternating(actions[-1])
                else:
                    if _repetition_depth(actions[-1]) >= MAX_NESTING:
                        raise _misplaced(self.gloss, token, f"more than {MAX_NESTING} repetitions of one movement")
                    actions[-1] = self.repetition(actions[-1], displaced=bool(stop))
                continue
            if actions and self.at_bracketed_repetition():
                actions[-1] = self.bracketed_repetition(actions[-1])
                continue
            if token.category in ("size", "manner"):
                following = self.peek(1)
                if following is not None and (following.name == "hamreplace" or following.category in _FEATURE_STARTS):
                    self.take()
                    unit = self.unit()
                    assert unit is not None
                    actions.append(_with_quality(unit, token.name))
                    continue
                if not actions:
                    raise self.unexpected(token, "a movement before its size or manner")
                self.take()
                actions[-1] = _with_quality(actions[-1], token.name)
                continue
            unit = self.unit()
            if unit is None:
                break
            actions.append(unit)
        return actions

    def repetition(self, child: Constraint, displaced: bool = False) -> Repetition:
        """The repetition symbol just ahead applied to ``child``. Inside a bracket
        (``displaced``), a straight movement right after it is the displacement of the
        passes: ``( move repeat move )``."""
        token = self.take()
        mode, count = _REPEATS[token.name]
        alternating = False
        if self.at("hamalternatingmotion"):
            self.take()
            alternating = True
        displacement = self.displacement() if displaced else None
        return Repetition(child, count=count, where=token.where, mode=mode, alternating=alternating, displacement=displacement)

    def displacement(self) -> Segment | None:
        token = self.peek()
        if token is None or token.category != "move-straight" or token.name.lower() in _LOCAL_MOVES:
            return None
        move = self.straight_move()
        assert isinstance(move, Dynamic)
        return move.segments[0]

    def at_bracketed_repetition(self) -> bool:
        """Whether a bracket that opens with a repetition follows (``move [ repeat move ]``)."""
        token, following = self.peek(), self.peek(1)
        return (
            token is not None and token.name in _OPENER_OF.values() and following is not None
            and following.category == "repeat" and following.name != "hamalternatingmotion"
        )  # fmt: skip

    def bracketed_repetition(self, child: Constraint) -> Repetition:
        """``move [ repeat move ]``: the movement before the bracket repeated, each pass
        displaced by the movement inside it."""
        opening = self.take()
        closing = next(close for close, open_ in _OPENER_OF.items() if open_ == opening.name)
        if _repetition_depth(child) >= MAX_NESTING:
            raise _misplaced(self.gloss, self.tokens[self.pos], f"more than {MAX_NESTING} repetitions of one movement")
        repetition = self.repetition(child, displaced=True)
        if repetition.displacement is None and not self.at(closing):
            raise self.unexpected(self.tokens[self.pos], f"a straight movement (the displacement) or {closing}")
        self.expect(closing, f"{opening.name} at position {opening.index}")
        return repetition

    def touching(self) -> bool:
        """Whether the hand is at a location it touches (a repetition may then repeat the contact)."""
        location = self.current.get("HandLocation")
        return isinstance(location, BodySite) and location.site != "contact" and location.proximity in _TOUCHES

    def tap(self, token: Token) -> Constraint:
        """A repeated contact with no movement before it (``chest touch repeat``): the hand
        leaves the site and touches it again, the unit the repetition repeats."""
        location = self.current["HandLocation"]
        assert isinstance(location, BodySite)
        away = Dynamic("HandLocation", (Segment(SegmentKind.LINEAR, end=replace(location, proximity="close"), where=token.where, manner="targetted"),), where=token.where)
        back = Dynamic("HandLocation", (Segment(SegmentKind.LINEAR, end=location, where=token.where, manner="targetted"),), where=token.where)
        return SequenceNode((away, back), where=token.where)

    def unit(self) -> Constraint | None:
        token = self.peek()
        assert token is not None
        category = token.category
        if category == "move-straight":
            return self.straight_move()
        if category == "move-circle":
            return self.circle()
        if category == "local-move":
            return self.local_move()
        if token.name == "hamreplace":
            return self.change_of_posture()
        if category in _FEATURE_STARTS or self.at_shape_modifier():
            # A new shape or orientation written without hamreplace changes the posture too.
            return self.posture_change(token, self.posture())
        if token.name == "hamseqbegin":
            return self.bracket("hamseqbegin", "hamseqend")
        if token.name == "hamfusionbegin":
            return self.bracket("hamfusionbegin", "hamfusionend")
        if token.name == "hamparbegin":
            return self.parallel()
        if self.at_location():
            location = self.location()
            self.current["HandLocation"] = location
            return Static("HandLocation", location, where=token.where)
        if token.name in ("hamplus", "hamparend", "hamseqend", "hamfusionend"):
            return None
        raise self.unexpected(token, "a movement, a change of posture, a location or a repetition")

    def enter(self, opening: Token) -> None:
        self.depth += 1
        if self.depth > MAX_NESTING:
            raise _misplaced(self.gloss, opening, f"brackets nested more than {MAX_NESTING} deep")

    def bracket(self, opening_name: str, closing_name: str) -> Constraint:
        opening = self.take()
        self.enter(opening)
        children = self.actions(stop=(closing_name,))
        context = f"{opening_name} at position {opening.index}"
        if self.peek() is not None and not self.at(closing_name):
            raise self.unexpected(self.tokens[self.pos], f"{closing_name} to close {context}")
        self.expect(closing_name, context)
        if not children:
            raise SpecError(f"sign {self.gloss!r}: empty {opening_name} … {closing_name} at position {opening.index}", opening.where)
        self.depth -= 1
        return SequenceNode(tuple(children), where=opening.where)

    def parallel(self) -> Constraint:
        opening = self.take()
        self.enter(opening)
        try:
            return self.parallel_parts(opening)
        finally:
            self.depth -= 1

    def parallel_parts(self, opening: Token) -> Constraint:
        before = dict(self.current)
        first = self.actions(stop=("hamparend", "hamplus"))
        context = f"hamparbegin at position {opening.index}"
        if self.at("hamplus"):
            self.take()
            self.two_handed = True
            after_first = self.current
            self.current = before
            second = self.actions(stop=("hamparend", "hamplus"))
            self.current = after_first
            if self.peek() is not None and not self.at("hamparend"):
                raise self.unexpected(self.tokens[self.pos], f"hamparend to close {context}")
            self.expect("hamparend", context)
            if not first or not second:
                raise SpecError(f"sign {self.gloss!r}: a hand of {context} has no movement", opening.where)
            return Parallel(
                (scoped_to(_sequence(first), self.dominant), scoped_to(_sequence(second), self.dominant.other)),
                where=opening.where,
            )
        if self.peek() is not None and not self.at("hamparend"):
            raise self.unexpected(self.tokens[self.pos], f"hamparend to close {context}")
        self.expect("hamparend", context)
        if not first:
            raise SpecError(f"sign {self.gloss!r}: empty hamparbegin … hamparend at position {opening.index}", opening.where)
        return first[0] if len(first) == 1 else Parallel(tuple(first), where=opening.where)

    def straight_move(self) -> Constraint:
        token = self.take()
        if token.name.lower() in _LOCAL_MOVES:
            return self.local_move(token)
        segment = Segment(SegmentKind.LINEAR, direction=_direction(token.name, "hammove"), where=token.where, manner="targetted")
        segment = self.movement_modifiers(segment, "move-straight")
        if segment.shape is not None:
            segment = replace(segment, kind=SegmentKind.CURVE)
        return Dynamic("HandLocation", (segment,), where=token.where)

    def circle(self) -> Constraint:
        token = self.take()
        segment = Segment(SegmentKind.CIRCLE, normal=_direction(token.name, "hamcircle"), where=token.where, manner="targetted")
        return Dynamic("HandLocation", (self.movement_modifiers(segment, "move-circle"),), where=token.where)

    def local_move(self, token: Token | None = None) -> Constraint:
        token = token or self.take()
        slot, kind = _LOCAL_MOVES[token.name.lower()]
        segment = Segment(kind, shape=token.name[3:], where=token.where, manner="targetted")
        return Dynamic(slot, (self.movement_modifiers(segment, "local-move"),), where=token.where)

    def movement_modifiers(self, segment: Segment, family: str) -> Segment:
        """Size, manner, path shape, clock, ellipse, between, contact and target of a movement."""
        clocks = 0
        while (token := self.peek()) is not None:
            name, category = token.name, token.category
            following = self.peek(1)
            if category == "size":
                segment = replace(segment, size=_SIZES[name])
            elif category == "manner":
                segment = replace(segment, manner=_MANNERS[name])
            elif category == "move-arc" and family == "move-straight" and segment.shape is None:
                segment = replace(segment, shape=name[3:])
            elif category == "clock" and family == "move-circle" and clocks < 2:
                key = "start" if clocks == 0 else "end"
                segment = replace(segment, modifiers=segment.modifiers + (f"{key}={name[len('hamclock'):]}",))
                clocks += 1
            elif category == "ellipse" and family in ("move-circle", "move-straight"):
                segment = replace(segment, modifiers=segment.modifiers + (f"ellipse={name[len('hamellipse'):]}",))
            elif name == "hambetween" and following is not None and following.category == family != "local-move" \
                    and following.name.lower() not in _LOCAL_MOVES:
                self.take()
                segment = self.halfway_movement(segment, self.take())
                continue
            elif name == "hamalternatingmotion":
                segment = replace(segment, modifiers=segment.modifiers + ("alternating",))
            elif category == "contact" and not self.at_place(ahead=1):
                segment = replace(segment, modifiers=segment.modifiers + (f"contact={_CONTACTS[name]}",))
            elif self.at_location():
                location = self.location()
                self.current["HandLocation"] = location
                segment = replace(segment, end=location)
                continue
            elif category in ("move-arc", "clock", "ellipse"):
                raise _misplaced(self.gloss, token, f"{name} cannot modify this movement")
            else:
                return segment
            self.take()
        return segment

    def halfway_movement(self, segment: Segment, other: Token) -> Segment:
        if segment.kind is SegmentKind.CIRCLE:
            assert segment.normal is not None
            return replace(segment, normal=self.between(segment.normal, other, "hamcircle", f"{segment.normal.name} hambetween {other.name}"))
        assert segment.direction is not None
        return replace(segment, direction=self.between(segment.direction, other, "hammove", f"{segment.direction.name} hambetween {other.name}"))

    def between(self, first: Direction, other: Token, prefix: str, name: str) -> Direction:
        """The direction halfway between ``first`` and the one ``other`` names."""
        halfway = _halfway(first, _direction(other.name, prefix), name)
        if halfway is None:
            raise _misplaced(self.gloss, other, f"{other.name} is opposite to {first.name}, so no direction lies halfway")
        return halfway

    def change_of_posture(self) -> Constraint:
        token = self.take()
        qualities = []
        while self.at_category("size", "manner"):
            qualities.append(self.take().name)
        if self.peek() is None:
            raise self.truncated("the new hand shape, orientation or location after hamreplace")
        if not self.at_posture_group():
            raise self.unexpected(self.tokens[self.pos], "the new hand shape, orientation or location after hamreplace")
        change = self.posture_change(token, self.posture())
        for quality in qualities:
            change = _with_quality(change, quality)
        return change

    def posture_change(self, token: Token, posture: _Posture) -> Constraint:
        """The change from the current posture to ``posture`` (one hand or both)."""
        dominant = self.changes(posture.dominant, token)
        if posture.constellation is not None:
            meeting = self.changes(_Hand(location=_meeting_site(posture.constellation)), token)
            if posture.other is None:
                # the hand's own new shape and orientation are the sign's (both hands' under
                # symmetry); only the move onto the other hand is the dominant hand's
                return _join(dominant, scoped_to(meeting, self.dominant) if meeting is not None else None) or _no_change(token)
            dominant = _join(dominant, meeting)
        if posture.other is None:
            return dominant or _no_change(token)
        other = self.changes(posture.other, token, keep=False)
        parts = [scoped_to(part, arm) for part, arm in ((dominant, self.dominant), (other, self.dominant.other)) if part is not None]
        return parts[0] if len(parts) == 1 else Parallel(tuple(parts), where=token.where)

    def changes(self, hand: _Hand, token: Token, keep: bool = True) -> Constraint | None:
        """One-segment dynamics from the current posture to the features ``hand`` names."""
        leaves: list[Constraint] = []
        for slot, value in _features(hand).items():
            if value is None:
                continue
            start = self.current.get(slot)
            segment = Segment(SegmentKind.LINEAR, start=start, end=value, where=token.where, manner="targetted")  # type: ignore[arg-type]
            leaves.append(Dynamic(slot, (segment,), where=token.where))
            if keep:
                self.current[slot] = value
        if not leaves:
            return None
        return leaves[0] if len(leaves) == 1 else Parallel(tuple(leaves), where=token.where)


def _repetition_depth(node: Constraint) -> int:
    depth = 0
    while isinstance(node, Repetition):
        node, depth = node.child, depth + 1
    return depth


def _features(hand: _Hand) -> dict[str, object]:
    return {
        "HandShape": hand.shape,
        "ExtFingerOrientation": hand.ext_finger,
        "PalmOrientation": hand.palm,
        "HandLocation": hand.location,
    }


def _meeting_site(constellation: HandConstellation) -> Location:
    """Where the dominant hand goes to form ``constellation`` from elsewhere: the other
    hand's site (its palm when none is named) at the contact, with the dominant hand's own
    site as the part of it that is there."""
    target = constellation.nondominant or BodySite("palm")
    if constellation.contact is not None:
        target = _with_contact(target, constellation.contact)
    if isinstance(constellation.dominant, BodySite):
        target = _with_hand_part(target, replace(constellation.dominant, proximity=None))
    return target


def _no_change(token: Token) -> Constraint:
    """A change of posture that names nothing new: the hand shape held (``etc``)."""
    return Dynamic("HandShape", (Segment(SegmentKind.LINEAR, where=token.where, modifiers=("etc",)),), where=token.where)


def _join(first: Constraint | None, second: Constraint | None) -> Constraint | None:
    if first is None or second is None:
        return first or second
    children = (first.children if isinstance(first, Parallel) else (first,)) + (second,)
    return Parallel(children, where=getattr(first, "where", None))


def _with_quality(node: Constraint, name: str) -> Constraint:
    """The same constraint with a size or manner given to every segment that has none."""
    if isinstance(node, Dynamic):
        if name in _SIZES:
            segments = tuple(s if s.size else replace(s, size=_SIZES[name]) for s in node.segments)
        else:
            segments = tuple(s if s.manner not in (None, "targetted") else replace(s, manner=_MANNERS[name]) for s in node.segments)
        return replace(node, segments=segments)
    if isinstance(node, (Parallel, SequenceNode)):
        return replace(node, children=tuple(_with_quality(child, name) for child in node.children))
    if isinstance(node, Static):
        return node
    return replace(node, child=_with_quality(node.child, name))


def _alternating(node: Constraint) -> Constraint:
    """The same constraint with the hands taking turns (``hamalternatingmotion`` after it)."""
    if isinstance(node, Repetition):
        return replace(node, alternating=True)
    if isinstance(node, Dynamic):
        segments = tuple(replace(s, modifiers=s.modifiers + ("alternating",)) for s in node.segments)
        return replace(node, segments=segments)
    if isinstance(node, (Parallel, SequenceNode)):
        return replace(node, children=tuple(_alternating(child) for child in node.children))
    if isinstance(node, Static):
        return node
    return replace(node, child=_alternating(node.child))


def _side(name: str) -> str:
    return name[3:]


def _on_hands(first: Location | None, second: Location | None) -> bool:
    """Whether both locations name parts of a hand or arm (a hand constellation)."""
    def on_hand(location: Location | None) -> bool:
        if not isinstance(location, BodySite):
            return False
        head = location.site.split(":")[0]
        table = vocabulary()
        symbol = table.lookup("ham" + head)
        return head == "finger" or (symbol is not None and symbol.category in ("location-hand", "location-arm"))

    return on_hand(first) and on_hand(second)


def _with_contact(location: Location, contact: str) -> Location:
    if isinstance(location, BodySite):
        return replace(location, proximity=contact)
    if isinstance(location, BetweenLocation):
        return replace(location, second=_with_contact(location.second, contact))
    return location


def _with_hand_part(location: Location, part: BodySite) -> Location:
    if isinstance(location, BodySite):
        return replace(location, hand_part=part)
    if isinstance(location, BetweenLocation):
        return replace(location, second=_with_hand_part(location.second, part))
    return location


def _merge(into: _Hand, part: _Hand) -> None:
    into.shape = part.shape or into.shape
    into.ext_finger = part.ext_finger or into.ext_finger
    into.palm = part.palm or into.palm
    into.location = part.location or into.location
    into.etc = into.etc or part.etc
    into.nondominant = into.nondominant or part.nondominant


def _sequence(actions: list[Constraint]) -> Constraint | None:
    if not actions:
        return None
    if len(actions) == 1:
        return actions[0]
    return SequenceNode(tuple(actions), where=getattr(actions[0], "where", None))


def scoped_to(node: Constraint | None, arm: Arm) -> Constraint:
    """The same constraint tree with every leaf restricted to ``arm``."""
    assert node is not None
    if isinstance(node, (Static, Dynamic)):
        return replace(node, scope=arm)
    if isinstance(node, (Parallel, SequenceNode)):
        return replace(node, children=tuple(scoped_to(child, arm) for child in node.children))
    return replace(node, child=scoped_to(node.child, arm))  # type: ignore[arg-type]
