"""A deterministic sample of the real corpora renders; every failure says why."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from motor.sign_planning import SignPlanningError, plan_sign
from motor.signing import check_motion, realize_signs
from mura.sigml import parse_sigml

CORPORA = ("German_SL_DGS.sigml", "Indian_SL.sigml")
SAMPLE = 20  # signs per corpus, evenly spaced through it


@pytest.fixture(scope="module")
def sample(shared: Path):
    signs = []
    for name in CORPORA:
        result = parse_sigml((shared / "corpora" / "sigml" / name).read_bytes(), file=name)
        step = len(result.signs) // SAMPLE
        signs.extend(result.signs[::step][:SAMPLE])
    return signs


def test_sampled_signs_plan(avatar, sample):
    failures = []
    for sign in sample:
        try:
            plan_sign(avatar, sign)
        except SignPlanningError as error:
            failures.append(str(error))
            assert sign.gloss in str(error)
    assert len(failures) <= len(sample) // 100, failures


def test_sampled_sequence_is_clean(avatar, sample):
    signed = realize_signs(avatar, sample)
    assert [t.gloss for t in signed.timings] == [s.gloss for s in sample]
    check = check_motion(avatar, signed)
    assert check.non_finite == 0
    assert check.max_shortfall < 1e-3
    assert check.max_upper_arm_depth < 0.01
    starts = np.array([t.start for t in signed.timings])
    assert np.all(np.diff(starts) > 0.0)
