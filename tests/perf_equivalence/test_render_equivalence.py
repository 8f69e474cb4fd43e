"""Optimizing motion synthesis must not change what it produces.

Every example utterance and a few published MURML files are rendered offline through
:class:`agent.agent.Agent` (fake speech, 60 fps) and compared with golden records made
before the optimizations (``golden_cases.py``): the same number of frames from the same
start, every frame's rotations (through fixed random projections), every tenth frame in
full, and the timeline, each within 1e-6 — a bound far above floating-point reordering
(≈ 1e-12) and far below any visible change (1e-6 rad).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from golden_cases import GOLDEN, portable_timeline, record, render, sources

TOLERANCE = 1e-6
CASES = sources()


def _close(actual, expected, where: str) -> None:
    """Equal JSON values, numbers within :data:`TOLERANCE`; raises naming the first
    difference. Keys added to the timeline since the golden record are not compared."""
    if isinstance(expected, dict):
        missing = sorted(set(expected) - set(actual)) if isinstance(actual, dict) else "all"
        assert not missing, f"{where}: keys {missing} missing"
        for key in expected:
            _close(actual[key], expected[key], f"{where}.{key}")
    elif isinstance(expected, list):
        assert isinstance(actual, list) and len(actual) == len(expected), f"{where}: length differs"
        for index, (a, e) in enumerate(zip(actual, expected)):
            _close(a, e, f"{where}[{index}]")
    elif isinstance(expected, float) and not isinstance(expected, bool):
        assert isinstance(actual, (int, float)) and math.isclose(actual, expected, rel_tol=0.0, abs_tol=TOLERANCE), f"{where}: {actual} != {expected}"
    else:
        assert actual == expected, f"{where}: {actual!r} != {expected!r}"


@pytest.fixture(scope="module", params=sorted(CASES))
def rendered(request):
    name = request.param
    golden = GOLDEN / f"{name}.npz"
    if not golden.is_file():
        pytest.fail(f"no golden record {golden.name}; generate it from known-good code with golden_cases.py")
    performance = render(CASES[name])
    with np.load(golden) as stored:
        expected = dict(stored)
    return name, performance, record(performance), expected


def test_same_frames(rendered):
    name, _, actual, expected = rendered
    assert int(actual["frame_count"]) == int(expected["frame_count"]), name
    assert float(actual["start_time"]) == pytest.approx(float(expected["start_time"]), abs=TOLERANCE)


@pytest.mark.parametrize("key", ["projected", "sampled", "root"])
def test_same_rotations(rendered, key):
    name, _, actual, expected = rendered
    assert actual[key].shape == expected[key].shape, f"{name}: {key} shape"
    difference = float(np.max(np.abs(actual[key] - expected[key]), initial=0.0))
    assert difference <= TOLERANCE, f"{name}: {key} differs by {difference:.3g}"


def test_same_timeline(rendered):
    name, performance, _, _ = rendered
    expected = json.loads((GOLDEN / f"{name}.timeline.json").read_text())
    actual = portable_timeline(performance.timeline)
    _close(actual, expected, f"{name} timeline")


def test_a_changed_frame_is_caught(rendered):
    """The comparison can fail: one rotation moved by 1e-5 shows in the projections."""
    _, performance, actual, _ = rendered
    changed = np.array(performance.motion.rotations, dtype=float)
    changed[changed.shape[0] // 2, changed.shape[1] // 2, 0] += 1e-5
    moved = changed.reshape(changed.shape[0], -1) @ np.random.default_rng(20240611).standard_normal((changed[0].size, 3))
    assert np.max(np.abs(moved - actual["projected"])) > TOLERANCE
