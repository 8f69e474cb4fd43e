"""Same input, same frames and weights; windows do not matter; blinks are deterministic per seed."""

from __future__ import annotations

import numpy as np
import pytest
from face_helpers import EXAMPLES

from agent.agent import Agent
from motor.face.blinks import BLOCK, DURATION, REFRACTORY, Blinks


@pytest.mark.parametrize("utterance", ["look_and_nod", "fig2_take_this_bar", "sign_here"])
def test_rendering_twice_gives_the_same_frames_and_weights(utterance):
    first, second = (Agent(avatar="max", tts="fake", fps=60).render(EXAMPLES / f"{utterance}.xml") for _ in range(2))
    assert np.array_equal(first.motion.rotations, second.motion.rotations)
    assert np.array_equal(first.motion.face_weights, second.motion.face_weights)


@pytest.mark.parametrize("window", [0.05, 0.37, 2.0])
def test_frame_windows_do_not_change_the_face(window):
    from dataclasses import replace

    whole = Agent(avatar="max", tts="fake", fps=60).render(EXAMPLES / "look_and_nod.xml")
    agent = Agent(avatar="max", tts="fake", fps=60)
    agent.config = replace(agent.config, offline_frame_window=window)
    windowed = agent.render(EXAMPLES / "look_and_nod.xml")
    assert np.array_equal(whole.motion.face_weights, windowed.motion.face_weights)
    # the same arithmetic in batches of other sizes: at most a last-bit difference
    np.testing.assert_allclose(whole.motion.rotations, windowed.motion.rotations, rtol=0.0, atol=1e-12)


@pytest.mark.parametrize("seed", [0, 1, 7, 12345])
def test_blinks_are_deterministic_and_at_a_natural_rate(seed):
    onsets = Blinks(seed).onsets(0.0, 600.0)
    assert np.array_equal(onsets, Blinks(seed).onsets(0.0, 600.0))
    assert 10.0 <= onsets.size / 10.0 <= 25.0  # per minute
    assert np.diff(onsets).min() >= REFRACTORY
    pieces = np.concatenate([Blinks(seed).onsets(a, b) for a, b in ((0.0, 123.4), (123.4, 600.0))])
    assert np.array_equal(np.unique(pieces), onsets)


def test_seeds_differ_and_chunk_boundaries_blink():
    assert not np.array_equal(Blinks(0).onsets(0.0, 60.0), Blinks(1).onsets(0.0, 60.0))
    blinks = Blinks(3)
    blinks.add_boundary(5.0)
    onsets = blinks.onsets(0.0, 20.0)
    boundary = onsets[np.argmin(np.abs(onsets - 5.05))]
    assert boundary == pytest.approx(5.05) and np.sort(np.abs(onsets - boundary))[1] >= REFRACTORY
    closed = blinks.sample(np.linspace(5.05, 5.05 + DURATION, 200))
    assert closed.max() == pytest.approx(1.0, abs=1e-3) and closed[0] == pytest.approx(0.0)


@pytest.mark.parametrize("seed", [0, 1, 7])
def test_windows_with_no_spontaneous_blink_sample_open_lids(seed):
    """A window whose random blocks drew no blink (an hour of speech meets some) gives open
    lids, not an error."""
    blinks = Blinks(seed)
    quiet = next(k for k in range(1, 100_000) if blinks._block(k).size == 0 and blinks._block(k - 1).size == 0)
    times = quiet * BLOCK + np.linspace(0.0, 0.5, 31)
    assert blinks.spontaneous(float(times[0]), float(times[-1])).size == 0
    assert np.all(blinks.sample(times) == 0.0)
