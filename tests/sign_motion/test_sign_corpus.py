"""A deterministic sample of the real corpora renders; every failure says why."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from motor.signing.plan import SignPlan, SignPlanningError
from motor.signing.planning import plan_signs
from motor.body.conventions import ARMS
from motor.signing.sequence import check_motion, prepare_signs, realize_prepared, realize_signs
from mura.sigml import parse_sigml

CORPORA = ("German_SL_DGS.sigml", "Indian_SL.sigml")
SAMPLE = 20  # signs per corpus, evenly spaced through it


SIGN_ELEMENT = re.compile(rb"<(hns_sign|hamgestural_sign)\b.*?</\1>", re.DOTALL)


@pytest.fixture(scope="module")
def sample(shared: Path):
    """Every n-th sign element of each corpus (parsing a whole corpus takes seconds)."""
    signs = []
    for name in CORPORA:
        elements = [m.group(0) for m in SIGN_ELEMENT.finditer((shared / "corpora" / "sigml" / name).read_bytes())]
        chosen = elements[:: len(elements) // SAMPLE][:SAMPLE]
        result = parse_sigml(b"<sigml>" + b"".join(chosen) + b"</sigml>", file=name)
        assert result.total == SAMPLE
        signs.extend(result.signs)
    return signs


@pytest.fixture(scope="module")
def planned(avatar, sample):
    return plan_signs(avatar, sample)


def test_sampled_signs_plan(sample, planned):
    failures = [result for result in planned if isinstance(result, SignPlanningError)]
    for sign, result in zip(sample, planned):
        if isinstance(result, SignPlanningError):
            assert sign.gloss in str(result)
    assert len(failures) <= len(sample) // 100, [str(f) for f in failures]


def test_sampled_sequence_is_clean(avatar, sample, planned):
    plans = [result for result in planned if isinstance(result, SignPlan)]
    signed = realize_signs(avatar, plans)
    assert [t.gloss for t in signed.timings] == [p.gloss for p in plans]
    check = check_motion(avatar, signed)
    assert check.non_finite == 0
    assert check.max_shortfall < 1e-3
    assert check.max_upper_arm_depth < 0.01
    starts = np.array([t.start for t in signed.timings])
    assert np.all(np.diff(starts) > 0.0)


@pytest.mark.parametrize(("sizes", "alone"), [((1,) * 40, 0), ((1,) * 40, 17), ((3, 1, 5, 2), 2), ((40,), 0)], ids=["signs one by one", "one by one, 18th", "sequences of several", "one sequence"])
def test_signs_prepared_together_are_prepared_as_alone(avatar, planned, sizes, alone):
    """Sequences prepared in one batch (:func:`prepare_signs`: their transitions' ways,
    stopping and timing lengths, traced chains and hand turns worked out together) get,
    bit for bit, what the sequence prepared on its own gets, and :func:`realize_prepared`
    the very frames of :func:`realize_signs`."""
    plans = [result for result in planned if isinstance(result, SignPlan)]
    starts = np.cumsum((0,) + sizes)
    sequences = [plans[a:b] for a, b in zip(starts, starts[1:]) if a < len(plans)]
    together = prepare_signs(avatar, sequences)
    (own,) = prepare_signs(avatar, [sequences[alone]])
    batched = together[alone]
    assert [len(p.legs) for p in together] == [len(sequence) + 1 for sequence in sequences]
    assert batched.spans == own.spans and batched.manners == own.manners
    for arm in ARMS:
        assert all(np.array_equal(a[arm], b[arm]) for a, b in zip(batched.ways, own.ways))
        for a, b in zip(batched.traced, own.traced):
            assert (a[arm].time, a[arm].manners) == (b[arm].time, b[arm].manners)
            assert np.array_equal(a[arm].here, b[arm].here) and np.array_equal(a[arm].starts, b[arm].starts) and np.array_equal(a[arm].ends, b[arm].ends)
            assert all(np.array_equal(x, y) for x, y in zip(a[arm].values + a[arm].fractions, b[arm].values + b[arm].fractions))
        for a, b in zip(batched.turns, own.turns):
            assert all((x is None and y is None) or np.array_equal(x, y) for x, y in zip(a[arm], b[arm]))
    if len(sequences[alone]) <= 3:
        prepared = realize_prepared(avatar, batched).motion.rotations
        assert np.array_equal(prepared, realize_signs(avatar, sequences[alone]).motion.rotations)
