"""A sign with movement holds its first posture briefly before moving (citation form);
inside an utterance it begins at once (the scheduler times its stroke like a gesture's).

A table of written signs: straight, circular, repeated and two-handed movements, a
hand-shape change, and a static sign.
"""

from __future__ import annotations

import pytest
from signing_helpers import sign_of

from motor.signing.plan import SignPlan
from motor.signing.planning import plan_signs, without_initial_hold
from motor.signing.sign_compiler import INITIAL_HOLD

HAND = "hamflathand hamextfingero hampalmd"
MOVING = {
    "straight": f"{HAND} hamchest hammoveu",
    "circle": f"{HAND} hamchest hamcircleo",
    "repeated": f"{HAND} hamchest hammover hamrepeatfromstart",
    "two hands": f"hamsymmlr {HAND} hamshoulders hamlrat hammoved",
    "shape change": f"{HAND} hamchest hamreplace hamfist",
}
STATIC = f"{HAND} hamchest"


@pytest.fixture(scope="module")
def plans(avatar) -> dict[str, SignPlan]:
    signs = [sign_of(symbols, gloss) for gloss, symbols in {**MOVING, "static": STATIC}.items()]
    planned = plan_signs(avatar, signs)
    assert all(isinstance(plan, SignPlan) for plan in planned), planned
    return {sign.gloss: plan for sign, plan in zip(signs, planned)}


def starts(plan: SignPlan) -> list[float]:
    return [move.start for moves in plan.moves.values() for move in moves]


@pytest.mark.parametrize("gloss", list(MOVING))
def test_a_moving_sign_holds_its_first_posture_first(plans, gloss):
    plan = plans[gloss]
    assert min(starts(plan)) == pytest.approx(INITIAL_HOLD)


@pytest.mark.parametrize("gloss", list(MOVING))
def test_inside_an_utterance_the_sign_moves_at_once(plans, gloss):
    plan, alone = without_initial_hold(plans[gloss]), plans[gloss]
    assert min(starts(plan)) == pytest.approx(0.0)
    assert plan.duration == pytest.approx(alone.duration - INITIAL_HOLD)
    shifted = sorted(starts(plan))
    assert shifted == pytest.approx([start - INITIAL_HOLD for start in sorted(starts(alone))])


def test_a_static_sign_is_a_hold_either_way(plans):
    plan = plans["static"]
    assert plan.static and without_initial_hold(plan) is plan
