"""Sign moves keep within their speed budget once their paths are final, on one clock.

A table of real signs (every 40th sign of both SiGML corpora, planned on the reference
avatar) and written signs whose large or curved movements need more than their manner's
table time; the properties hold for every plan.
"""

from __future__ import annotations

import numpy as np
import pytest
from signing_helpers import CORPORA, sign_of

from motor.signing.lmp import Move
from motor.signing import planning
from motor.signing.plan import HandPose, SignPlan
from motor.signing.planning import plan_signs
from motor.signing.retiming import law_factor, needed_duration, retimed
from mura.sigml import parse_sigml
from mura.signs import Sign

STRIDE = 40
HAND = "hamflathand hamextfingero hampalmd"
WRITTEN = {
    "large arc": f"{HAND} hamshoulders hammoveu hamarcl hamlargemod",
    "large circle": f"{HAND} hamchest hamcircleo hamlargemod",
    "across and back": f"{HAND} hamshoulders hamlrat hammovel hamlargemod hamrepeatreverse",
}


@pytest.fixture(scope="module")
def table(sigml_corpora) -> list[Sign]:
    signs = [sign for name in CORPORA for sign in parse_sigml(sigml_corpora[name], file=name).signs[::STRIDE]]
    return signs + [sign_of(symbols, gloss) for gloss, symbols in WRITTEN.items()]


@pytest.fixture(scope="module")
def plans(avatar, table) -> list[SignPlan]:
    return [plan for plan in plan_signs(avatar, table) if isinstance(plan, SignPlan)]


def wrist_moves(plan: SignPlan):
    return [move for (arm, channel), moves in plan.moves.items() if channel == "wrist_position" for move in moves]


def test_the_table_has_slowed_moves(plans):
    assert len(plans) > 50
    assert any("slowed to keep the wrist within its speed budget" in w for p in plans for w in p.warnings)


def test_every_wrist_move_has_the_time_its_final_path_needs(plans):
    for plan in plans:
        for move in wrist_moves(plan):
            assert move.end - move.start >= needed_duration(move) * (1.0 - 1e-9), plan.gloss


def test_moves_stay_in_order_within_the_sign(plans):
    for plan in plans:
        for moves in plan.moves.values():
            assert all(a.end <= b.start + 1e-9 for a, b in zip(moves[:-1], moves[1:])), plan.gloss
            assert all(0.0 <= m.start < m.end <= plan.duration + 1e-9 for m in moves), plan.gloss


@pytest.fixture(scope="module")
def unretimed(avatar, table) -> list[SignPlan]:
    """The same table planned with the retiming left out."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(planning, "retimed_all", lambda drafts, batched=True: drafts)
        return [plan for plan in plan_signs(avatar, table) if isinstance(plan, SignPlan)]


def test_boundaries_that_met_still_meet(unretimed):
    """Every channel's moves are on one warped clock: moves that started or ended
    together (a hand's turn or shape change with its wrist move) still do, in order."""
    for plan in unretimed:
        again = retimed(plan)
        before = np.array([t for moves in plan.moves.values() for m in moves for t in (m.start, m.end)])
        after = np.array([t for moves in again.moves.values() for m in moves for t in (m.start, m.end)])
        order = np.argsort(before, kind="stable")
        assert np.all(np.diff(after[order]) >= -1e-12), plan.gloss
        same = np.diff(before[order]) == 0.0
        assert np.all(np.diff(after[order])[same] == 0.0), plan.gloss


def _line_move(length: float, start: float, end: float) -> Move:
    return Move(start, end, "targetted", np.linspace([0.0, 0.3, 0.3], [length, 0.3, 0.3], 5))


@pytest.mark.parametrize("length", [0.05, 0.2, 0.6])
def test_a_straight_move_travels_evenly_and_is_stretched_only_when_it_must(length):
    move = _line_move(length, 0.0, 0.4)
    assert law_factor(move.values) == pytest.approx(1.0)
    hand = {"right": HandPose(move.values[0], np.array([0.0, 0.0, 0.0, 1.0]), np.zeros(3))}
    plan = SignPlan("line", 0.4, hand, {("right", "wrist_position"): (move,)}, static=False)
    again = retimed(plan)
    if needed_duration(move) <= 0.4:
        assert again is plan
    else:
        (slowed,) = again.moves[("right", "wrist_position")]
        assert slowed.end == pytest.approx(needed_duration(move)) and again.duration == pytest.approx(slowed.end)
        assert any("slowed" in w for w in again.warnings)


def test_a_path_with_a_tight_bend_goes_faster_along_its_straights():
    bend = np.array([[0.0, 0.3, 0.3], [0.1, 0.3, 0.3], [0.2, 0.3, 0.3], [0.21, 0.31, 0.3], [0.21, 0.4, 0.3], [0.21, 0.5, 0.3]])
    assert law_factor(bend) > 1.05
