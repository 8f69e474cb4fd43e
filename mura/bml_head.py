"""BML head, gaze and face behaviours as the head slots MURML uses, for the neck and face
modules of ``motor/`` to perform.

* ``<head lexeme repetition>`` is a ``Neck`` value (``NOD``, ``SHAKE``, ``TILT``: the
  neck module's lexemes, where ``TILT`` tilts to the right); ``repetition="n"`` repeats
  the lexeme's swings n times, as a MURML ``<repetition>`` around it does.
* ``<gaze target>`` is a ``GazeDirection`` target in ``pointTo`` mode: a place of the
  lexicon's scene, or a name the gaze model knows (``Listener``, ``RightHand``, …; an
  unknown name makes the motor warn and look at the listener).
* ``<faceLexeme lexeme>`` is a ``FaceExpression`` value (the BML core lexemes
  ``RAISE_BROWS``, ``FROWN``, ``SMILE``, … as the face module names them).

What BML lets these behaviours say and mura does not perform is said once per behaviour
as a warning: ``amount`` other than 1 (a lexeme keeps its own amplitude) and ``influence``
(the eye–head split follows the size of the shift, as people's does).
"""

from __future__ import annotations

from collections.abc import Callable

from lxml import etree

from mura.bml_sync import number
from mura.constraints import Constraint, Repetition, Static
from mura.errors import SourceLocation
from mura.lexicon import GestureLexicon
from mura.murml_constraints import ConstraintReader
from mura.values import Symbol
from mura.xml_source import XmlSource

#: BML behaviour kind → the MURML slot it fills.
HEAD_SLOTS: dict[str, str] = {"head": "Neck", "gaze": "GazeDirection", "faceLexeme": "FaceExpression"}
#: The scope of every head slot (MURML's ``scope="head"``).
HEAD_SCOPE = "head"

#: ``warn(kind, message, attribute)``: how the BML reader is told what is not performed.
Warn = Callable[[str, str, str], None]


def head_constraint(
    source: XmlSource, element: etree._Element, kind: str, behavior_id: str, lexicon: GestureLexicon, warn: Warn
) -> Constraint:
    """The constraint tree performing the BML behaviour ``element`` of ``kind`` (a key of
    :data:`HEAD_SLOTS`) read from ``source``; its numbers were checked by the BML reader."""
    where = source.where(element)
    slot = HEAD_SLOTS[kind]
    if kind == "gaze":
        leaf = _gaze(source, slot, element.get("target", "").strip(), where, lexicon)
    else:
        leaf = Static(slot, Symbol(element.get("lexeme", "").strip()), HEAD_SCOPE, None, where)
    _say_what_is_not_performed(element, behavior_id, warn)
    count = int(number(element.get("repetition", "1")) or 1)
    return Repetition(leaf, count, where) if count > 1 else leaf


def _gaze(source: XmlSource, slot: str, target: str, where: SourceLocation, lexicon: GestureLexicon) -> Static:
    """A gaze target: a scene place read as MURML reads ``$place`` (its unit and grid
    names), or a name for the gaze model."""
    name = target.removeprefix("$")
    if name not in lexicon.scene:
        return Static(slot, Symbol(name), HEAD_SCOPE, "pointTo", where)
    element = etree.Element("static", slot=slot, value=f"${name}", mode="pointTo", scope=HEAD_SCOPE)
    reader = ConstraintReader(source, "m", lexicon.scene, {}, where, lexicon.symbols)
    place = reader.read(element, None)
    if not isinstance(place, Static):
        raise TypeError(f"a <static> read as {type(place).__name__}")
    return Static(place.slot, place.value, HEAD_SCOPE, "pointTo", where)


def _say_what_is_not_performed(element: etree._Element, behavior_id: str, warn: Warn) -> None:
    amount = element.get("amount")
    if amount is not None and number(amount) != 1.0:
        warn("NOT_PERFORMED", f"{behavior_id!r}: amount {amount} is not performed; the lexeme keeps its own amplitude", "amount")
    influence = element.get("influence")
    if influence is not None:
        warn("NOT_PERFORMED", f"{behavior_id!r}: influence {influence} is not performed; eyes and head share the shift by its size", "influence")
