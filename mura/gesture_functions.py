"""Gestures asked for by communicative function, resolved through a lexicon.

One entry point for every language that calls lexicon functions — MURML's
``<function name=… ><param name=… value=…/></function>`` and BML: :func:`function_gesture`
binds the call's parameters (with the entry's defaults), fills the ``$param``
placeholders of the entry's form and reads it into a constraint tree. Errors inside the
entry are reported at the call, naming the place in the lexicon too.
"""

from __future__ import annotations

from collections.abc import Mapping

from mura.errors import SourceLocation, SpecError
from mura.expansion import check_movements
from mura.lexicon import GestureLexicon, LexiconEntry, SceneLocation, bind_params
from mura.limits import DEFAULT_LIMITS, Limits
from mura.model import FunctionCall, Gesture
from mura.murml_constraints import ConstraintReader, arm_or_none


def function_gesture(
    lexicon: GestureLexicon,
    call: FunctionCall,
    scope: str | None = None,
    scene: Mapping[str, SceneLocation] | None = None,
    gesture_id: str | None = None,
    where: SourceLocation | None = None,
    limits: Limits = DEFAULT_LIMITS,
) -> Gesture:
    """The gesture ``call`` asks for.

    Args:
        lexicon: where the function is looked up (its scene and symbol table apply).
        call: the function's name, the parameters given and where the call is written.
        scope: the arm the caller gives (``right_arm``/``left_arm``), None for the entry's.
        scene: places known at the call (the utterance's own scene over the lexicon's);
            the lexicon's scene when None.
        gesture_id, where: the gesture's id and place, for the result.
        limits: what the gesture may ask for (its movements once repetitions expand, lengths).

    Raises:
        SpecError: an unknown function, a missing or unknown parameter, or a problem in
            the entry's form — located at the call.
    """
    entry = lexicon.entry(call.name)
    if entry is None:
        known = ", ".join(lexicon.functions) or "none"
        raise SpecError(f"unknown gesture function {call.name!r} (the lexicon has: {known})", call.where)
    try:
        bound = bind_params(entry, call.params)
    except ValueError as error:
        raise SpecError(str(error), call.where) from None
    places = scene if scene is not None else lexicon.scene
    reader = ConstraintReader(entry.source, entry.unit, places, bound, call.where, lexicon.symbols, limits)
    own = arm_or_none(reader.fill(entry.scope)) if entry.scope else None
    tree = reader.read(entry.form, own or arm_or_none(scope))
    identity = gesture_id or entry.name or call.name
    check_movements(tree, limits, f"gesture {identity!r}", where or call.where)
    return Gesture(identity, tree, call, scope, where or call.where)


def check_entry(lexicon: GestureLexicon, entry: LexiconEntry, limits: Limits = DEFAULT_LIMITS) -> list[SpecError]:
    """The problems of one entry read as a call would read it: defaults bound, required
    parameters left as written (so only what does not depend on them is checked)."""
    bound = {name: default for name, default in entry.params.items() if default is not None}
    reader = ConstraintReader(entry.source, entry.unit, lexicon.scene, bound, None, lexicon.symbols, limits)
    try:
        reader.read(entry.form, arm_or_none(entry.scope))
    except SpecError as error:
        if _depends_on_required(error, entry):
            return []
        return [error]
    return []


def _depends_on_required(error: SpecError, entry: LexiconEntry) -> bool:
    required = [name for name, default in entry.params.items() if default is None]
    return any(f"${name}" in error.message for name in required)
