"""The fast sign-planning paths give the plans of the plain ones, bit for bit.

Planning a collection shares hand geometry between its signs (memoized, computed in
vectorized rounds) and checks the reach of all their wrist positions at once, each distinct
position once. The plain path plans each sign alone with nothing remembered
(``memoize=False``). Both must give equal plans: the same durations, moves, values and
warnings, and the same errors.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from motor.signing.plan import SignPlan, SignPlanningError
from motor.signing.planning import plan_signs
from mura.signs import Sign
from mura.values import BodySite


def plain(avatar, signs: list[Sign]) -> list[SignPlan | SignPlanningError]:
    """Each sign planned alone, every piece of geometry computed afresh."""
    return [plan_signs(avatar, [sign], memoize=False)[0] for sign in signs]


def assert_same_plan(fast: SignPlan | SignPlanningError, slow: SignPlan | SignPlanningError) -> None:
    if isinstance(slow, SignPlanningError):
        assert isinstance(fast, SignPlanningError) and str(fast) == str(slow)
        return
    assert isinstance(fast, SignPlan), str(fast)
    assert (fast.gloss, fast.duration, fast.static, fast.warnings) == (slow.gloss, slow.duration, slow.static, slow.warnings)
    assert repr(fast.nonmanual) == repr(slow.nonmanual)
    assert fast.first.keys() == slow.first.keys()
    for arm, pose in slow.first.items():
        for name in ("wrist_position", "hand_rotation", "handshape"):
            assert np.array_equal(fast.first[arm].channel(name), pose.channel(name)), (fast.gloss, arm, name)
    assert fast.moves.keys() == slow.moves.keys()
    for key, moves in slow.moves.items():
        assert len(fast.moves[key]) == len(moves), (fast.gloss, key)
        for a, b in zip(fast.moves[key], moves):
            assert (a.start, a.end, a.manner) == (b.start, b.end, b.manner), (fast.gloss, key)
            assert a.values.shape == b.values.shape and a.values.tobytes() == b.values.tobytes(), (fast.gloss, key)


@pytest.fixture(scope="module")
def parts(corpus_sample, written_signs) -> dict[str, list[Sign]]:
    """Real signs, written signs, and a sign whose location no avatar has (an error)."""
    broken = replace(written_signs[0], gloss="unknown site")
    broken = replace(broken, posture=replace(broken.posture, location=BodySite("elsewhere")))
    return {"corpus sample": corpus_sample, "written": written_signs, "error": [broken]}


@pytest.fixture(scope="module")
def table(parts) -> list[Sign]:
    return [sign for signs in parts.values() for sign in signs]


@pytest.fixture(scope="module")
def fast_and_plain(avatar, table):
    return plan_signs(avatar, table), plain(avatar, table)


def differences(fast: list, slow: list) -> list[str]:
    """What differs between two lists of plans, one line per sign."""
    found = []
    for a, b in zip(fast, slow):
        try:
            assert_same_plan(a, b)
        except AssertionError as error:
            found.append(f"{getattr(b, 'gloss', b)}: {error}")
    return found


def test_table_covers_what_the_fast_paths_share(table, fast_and_plain):
    """The table holds two-handed signs, constellations, hands at the other hand, and an error."""
    fast, _ = fast_and_plain
    plans = [p for p in fast if isinstance(p, SignPlan)]
    assert len(fast) == len(table) and len(plans) >= len(table) - 1
    assert any(len(p.arms) == 2 for p in plans)
    assert sum(s.constellation is not None for s in table) >= 4
    assert any(isinstance(p, SignPlanningError) and "unknown site" in str(p) for p in fast)
    assert any("moved within reach" in w for p in plans for w in p.warnings)


@pytest.mark.parametrize("part", ["corpus sample", "written", "error"])
def test_collection_plans_equal_plain_plans(part, parts, table, fast_and_plain):
    fast, slow = fast_and_plain
    start = sum(len(signs) for name, signs in parts.items() if list(parts).index(name) < list(parts).index(part))
    rows = slice(start, start + len(parts[part]))
    assert differences(fast[rows], slow[rows]) == []


def test_order_of_the_collection_does_not_change_a_plan(avatar, table, fast_and_plain):
    fast, _ = fast_and_plain
    assert differences(plan_signs(avatar, table[::-1])[::-1], fast) == []


@pytest.mark.parametrize("missing", ["palm", "elbow"])
def test_an_avatar_without_a_site_fails_sign_by_sign_as_the_plain_path(avatar, written_signs, missing):
    """The vectorized geometry passes fail for a whole group when the avatar lacks a site;
    each sign then fails alone, with the plain path's error, and the others still plan."""
    sites = {name: site for name, site in avatar.sites.items() if not name.endswith(f"_{missing}")}
    lacking = replace(avatar, sites=sites)
    fast, slow = plan_signs(lacking, written_signs), plain(lacking, written_signs)
    assert differences(fast, slow) == []
    errors = [p for p in fast if isinstance(p, SignPlanningError)]
    assert errors and all(missing in str(e) for e in errors)
    if missing == "elbow":
        assert len(errors) < len(fast)
