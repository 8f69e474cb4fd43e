"""The hands' separation eased over time (motor.body.hands_apart), on synthetic per-frame
separations: at least what each frame needs, no speed step, nothing far from a need, and
the same values whatever window the frames are computed in."""

from __future__ import annotations

import numpy as np
import pytest

from motor.body.hands_apart import eased_separation, reach_frames

FPS = 60.0


def _needs(kind: str) -> np.ndarray:
    """Synthetic per-frame separations (m), 240 frames: what a frame-by-frame look at the
    hands asks for in typical cases."""
    needs = np.zeros((240, 3))
    frames = np.arange(240)
    if kind == "switch on":  # a path enters the contact: 2.6 cm from one frame to the next, held
        needs[100:140, 0] = 0.026
    elif kind == "one frame":  # a single frame's need
        needs[120] = [0.02, 0.005, -0.004]
    elif kind == "growing":  # a need that grows and falls, with a dip in the middle
        needs[80:160, 0] = 0.015 * np.sin(np.pi * (frames[80:160] - 80) / 80) + 0.005 * (frames[80:160] % 7 == 0)
        needs[80:160, 1] = 0.004
    elif kind == "flickering":  # on and off from frame to frame, as per-frame looks switch
        needs[90:150:2, 0] = 0.012
        needs[91:150:2, 2] = -0.008
    elif kind == "two runs":
        needs[40:60, 0] = 0.01
        needs[150:200, 0] = 0.02
        needs[150:200, 1] = -0.01
    return needs


KINDS = ["switch on", "one frame", "growing", "flickering", "two runs"]


@pytest.mark.parametrize("kind", KINDS)
def test_each_frame_gets_at_least_its_separation(kind):
    needs = _needs(kind)
    eased = eased_separation(needs, FPS)
    positive, negative = needs > 0.0, needs < 0.0
    assert np.all(eased[positive] >= needs[positive] - 1e-15)
    assert np.all(eased[negative] <= needs[negative] + 1e-15)
    # along each frame's own separation, the wrists move at least as far
    length = np.linalg.norm(needs, axis=1)
    asked = length > 0.0
    along = np.einsum("ij,ij->i", eased[asked], needs[asked]) / length[asked]
    assert np.all(along >= length[asked] - 1e-15)


@pytest.mark.parametrize("kind", KINDS)
def test_the_separation_adds_no_speed_step(kind):
    """At most 0.07 m/s of velocity change per frame and 0.25 m/s of speed for separations
    up to 2.6 cm, switched on from one frame to the next (a speed step is 0.5 m/s in one
    frame)."""
    eased = eased_separation(_needs(kind), FPS)
    velocity = np.diff(eased, axis=0) * FPS
    assert np.max(np.linalg.norm(velocity, axis=1)) < 0.25
    assert np.max(np.linalg.norm(np.diff(velocity, axis=0), axis=1)) < 0.07


@pytest.mark.parametrize("kind", KINDS)
def test_frames_far_from_any_need_are_not_moved(kind):
    needs = _needs(kind)
    asked = np.flatnonzero(np.any(needs != 0.0, axis=1))
    distance = np.min(np.abs(np.arange(len(needs))[:, None] - asked[None, :]), axis=1)
    eased = eased_separation(needs, FPS)
    assert np.all(eased[distance > reach_frames(FPS)] == 0.0)
    assert np.all(np.any(eased[distance <= reach_frames(FPS) - 1] != 0.0, axis=1))


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("window", [1, 7, 50])
def test_windows_with_their_margins_give_the_values_of_one_call(kind, window):
    needs = _needs(kind)
    whole = eased_separation(needs, FPS)
    reach = reach_frames(FPS)
    for start in range(reach, len(needs) - reach - window, window):
        part = eased_separation(needs[start - reach : start + window + reach], FPS)[reach : reach + window]
        assert np.array_equal(part, whole[start : start + window])


@pytest.mark.parametrize("fps", [25.0, 60.0, 240.0])
def test_the_ramp_lasts_the_same_time_at_any_frame_rate(fps):
    """A need switched on at 1 s is eased in from 0.8 s whatever the frame rate."""
    count = int(2 * fps)
    needs = np.zeros((count, 3))
    needs[int(fps) :, 0] = 0.02
    eased = eased_separation(needs, fps)
    first = np.flatnonzero(eased[:, 0] > 0.0)[0] / fps
    assert first == pytest.approx(1.0 - 0.2, abs=1.5 / fps)
    assert eased[int(fps), 0] == pytest.approx(0.02)
