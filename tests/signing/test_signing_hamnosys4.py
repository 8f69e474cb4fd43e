"""HamNoSys 4 constructs beyond the visible corpora, each with signs written for the test.

Contact brackets naming the hand part (``site [touch part]``, also inside a two-handed
split location), compound signs whose parts carry their own symmetry operator, repetitions
with a displacement (``( move repeat move )`` and ``move [ repeat move ]``), a finger
bending written after the location, a repeated contact with no movement, runs of contact
symbols, and ``hamneutralspace`` as either hand's location. Malformed variants are still
refused one by one, naming the symbol and its position.
"""

from __future__ import annotations

import numpy as np
import pytest
from signing_helpers import sign_of

from motor.signing.plan import SignPlan
from motor.signing.planning import plan_signs
from mura.constraints import Dynamic, Parallel, Repetition, Sequence, Static, Symmetrical, iter_leaves
from mura.errors import SpecError
from mura.values import BodySite, HandShape

HAND = "hamflathand hamextfingero hampalmd"


def _plan(avatar, symbols: str) -> SignPlan:
    (plan,) = plan_signs(avatar, [sign_of(symbols)])
    assert isinstance(plan, SignPlan), plan
    return plan


@pytest.mark.parametrize(
    ("symbols", "part"),
    [
        (f"{HAND} hamchest hamseqbegin hamtouch hamthumb hamfingertip hamseqend hammoveo", BodySite("fingertip", finger="thumb")),
        (f"{HAND} hamchin hamseqbegin hamclose hamhandback hamseqend", BodySite("handback")),
        (f"{HAND} hamnose hamseqbegin hamtouch hamfingertip hamthumb hamseqend", BodySite("fingertip", finger="thumb")),
    ],
)
def test_contact_bracket_names_the_touching_hand_part(symbols: str, part: BodySite) -> None:
    location = sign_of(symbols).posture.location
    assert isinstance(location, BodySite)
    assert location.hand_part == part
    assert location.proximity in ("touch", "close")


@pytest.mark.parametrize(
    "symbols",
    [
        f"{HAND} hamparbegin hamchest hamseqbegin hamtouch hamthumb hamfingertip hamseqend hamplus hamstomach hamparend hammoveo",
        f"{HAND} hamparbegin hamchest hamplus hamstomach hamseqbegin hamtouch hampalm hamseqend hamparend",
        f"{HAND} hamparbegin hamlrat hamchest hamseqbegin hamclose hamindexfinger hamfingerside hamseqend hamplus hamlrat hamchest hamparend",
    ],
)
def test_contact_bracket_inside_a_split_location(avatar, symbols: str) -> None:
    sign = sign_of(symbols)
    assert sign.two_handed and sign.nondominant is not None
    parts = [loc.hand_part for loc in (sign.posture.location, sign.nondominant.location) if isinstance(loc, BodySite)]
    assert any(part is not None for part in parts)
    _plan(avatar, symbols)


def test_a_bracket_with_more_than_a_hand_part_stays_a_movement() -> None:
    sign = sign_of(f"{HAND} hamlowerarm hamseqbegin hamtouch hammovedo hamseqend")
    assert sign.posture.location == BodySite("lowerarm")
    assert isinstance(sign.movement, Sequence)


@pytest.mark.parametrize(
    ("symbols", "first", "second"),
    [
        (f"hamsymmlr {HAND} hamchest hammoveo hamplus hamsymmpar hamfist hamextfingero hampalmd hamstomach hammoved", "lr", "par"),
        (f"{HAND} hamchest hammoveo hamplus hamsymmlr hamfist hamextfingero hampalmd hamstomach hammoved", None, "lr"),
        (f"hamsymmpar {HAND} hamchest hammoveo hamplus hamsymmlr hamalternatingmotion hamfist hamextfingero hampalmd hammoved", "par", "lr"),
    ],
)
def test_compound_parts_carry_their_own_symmetry(avatar, symbols: str, first: str | None, second: str) -> None:
    sign = sign_of(symbols)
    assert (sign.symmetry.kind if sign.symmetry else None) == first
    assert sign.two_handed
    (part,) = [node for node in sign.movement.children if isinstance(node, Symmetrical)]
    assert (part.symmetry.name == "par") == (second == "par")
    plan = _plan(avatar, symbols)
    left = plan.moves[("left", "wrist_position")]
    assert left and max(np.ptp(move.values, axis=0).max() for move in left) > 0.02  # the other hand moves in its part


def test_a_part_repeating_the_signs_symmetry_is_not_wrapped() -> None:
    sign = sign_of(f"hamsymmlr {HAND} hamchest hammoveo hamplus hamsymmlr hamfist hamextfingero hampalmd hammoved")
    assert not any(isinstance(node, Symmetrical) for node in sign.movement.children)


@pytest.mark.parametrize(
    "symbols",
    [
        f"{HAND} hamchest hamparbegin hammover hamrepeatfromstartseveral hammoved hamparend",
        f"{HAND} hamchest hammover hamseqbegin hamrepeatfromstartseveral hammoved hamseqend",
        f"{HAND} hamchest hammover hamparbegin hamrepeatfromstartseveral hammoved hamparend",
    ],
)
def test_repetition_with_displacement(avatar, symbols: str) -> None:
    movement = sign_of(symbols).movement
    assert isinstance(movement, Repetition)
    assert movement.count == 3 and movement.displacement is not None
    assert movement.displacement.direction.vector == (0.0, -1.0, 0.0)
    plan = _plan(avatar, symbols)
    strokes = [move for move in plan.moves[("right", "wrist_position")] if move.manner != "lax"]
    starts = np.array([move.values[0, 1] for move in strokes])
    assert len(starts) == 3 and np.all(np.diff(starts) < -0.03)  # each pass starts lower


def test_repetition_without_displacement_repeats_in_place(avatar) -> None:
    plan = _plan(avatar, f"{HAND} hamchest hammover hamrepeatfromstartseveral")
    strokes = [move for move in plan.moves[("right", "wrist_position")] if move.manner != "lax"]
    starts = np.array([move.values[0] for move in strokes])
    # in place to within a centimetre: the chest pushes these passes forward by up to
    # 12 cm, and clearing spreads each point's push over SPREAD metres of the hand's arc,
    # so passes with different neighbours (the first has the start posture on one side
    # only) are pushed up to 9 mm differently
    assert np.all(np.linalg.norm(starts - starts[0], axis=1) < 0.01)


def test_bracketed_repetition_needs_a_displacement_or_the_bracket_end() -> None:
    with pytest.raises(SpecError, match=r"hamcircleo at position 7"):
        sign_of(f"{HAND} hamchest hammover hamseqbegin hamrepeatfromstart hamcircleo hamseqend")


@pytest.mark.parametrize(
    ("symbols", "bending"),
    [
        ("hamfinger2 hamfingerbendmod hamextfingerui hampalmu hamear hamfingerstraightmod hamclose hammoved", "straight"),
        ("hamfinger2 hamthumbacrossmod hamextfingeru hampalmu hamlrat hamlips hamdoublebent hamcircleui hamclose", "dblbent"),
    ],
)
def test_finger_bending_after_the_location(avatar, symbols: str, bending: str) -> None:
    sign = sign_of(symbols)
    assert isinstance(sign.posture.shape, HandShape) and sign.posture.shape.bending == bending
    assert isinstance(sign.posture.location, BodySite)
    _plan(avatar, symbols)


def test_repeated_contact_taps(avatar) -> None:
    symbols = "hamfist hamthumboutmod hamextfingeril hampalml hamshouldertop hamlrat hambehind hamtouch hamrepeatfromstart"
    sign = sign_of(symbols)
    assert sign.posture.location == BodySite("shouldertop", side="lrat", proximity="touch")
    assert isinstance(sign.movement, Repetition) and isinstance(sign.movement.child, Sequence)
    plan = _plan(avatar, symbols)
    wrist = np.concatenate([move.values for move in plan.moves[("right", "wrist_position")]])
    away = np.linalg.norm(wrist - wrist[0], axis=1)
    assert away.max() > 0.01 and np.sum(np.diff((away < 0.005).astype(int)) == 1) >= 1  # leaves and comes back


def test_repetition_without_movement_or_contact_is_refused() -> None:
    with pytest.raises(SpecError, match=r"hamrepeatfromstart at position 4: expected a movement before the repetition"):
        sign_of(f"{HAND} hamchest hamrepeatfromstart")


@pytest.mark.parametrize(
    ("symbols", "proximity"),
    [(f"{HAND} hamchest hambehind hamtouch", "touch"), (f"{HAND} hamchest hambehind", "behind"), (f"{HAND} hamchest hamclose hamtouch", "touch")],
)
def test_runs_of_contact_symbols(symbols: str, proximity: str) -> None:
    location = sign_of(symbols).posture.location
    assert isinstance(location, BodySite) and location.site == "chest" and location.proximity == proximity


@pytest.mark.parametrize(
    "symbols",
    [
        f"{HAND} hamparbegin hamchest hamplus hamneutralspace hamparend hammoveo",
        f"{HAND} hamneutralspace hammoveo",
        f"hamsymmlr {HAND} hamneutralspace hamcircleo",
    ],
)
def test_neutral_space_is_a_location_of_either_hand(avatar, symbols: str) -> None:
    plan = _plan(avatar, symbols)
    assert plan.duration > 0


def test_static_leaves_of_new_constructs_keep_their_slots() -> None:
    sign = sign_of(f"hamsymmlr {HAND} hamchest hamparbegin hammover hamrepeatfromstart hammoved hamparend hamplus hamsymmpar hamfist hammoveo")
    slots = {leaf.slot for leaf in iter_leaves(sign.to_constraint()) if isinstance(leaf, (Static, Dynamic))}
    assert slots <= {"HandShape", "ExtFingerOrientation", "PalmOrientation", "HandLocation"}
    assert not isinstance(sign.movement, Parallel)
