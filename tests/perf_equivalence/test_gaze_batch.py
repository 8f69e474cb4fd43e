"""A gaze timeline's shifts sampled in one pass (:func:`motor.neck.gaze.sample_shifts`)
give the very numbers of sampling each shift on its own with the plain numpy steps
(``plain_gaze.py``), whichever shifts and frames share the pass."""

from __future__ import annotations

import numpy as np
import pytest
from plain_gaze import sample, sample_timeline

from motor.body.avatar import load_avatar
from motor.neck.gaze import direction, gaze, gaze_target, listener, point, rest_state, sample_shifts
from motor.program.lmp import ChannelState

#: When each shift of the table starts, seconds.
STARTS = 0.3 + 0.7 * np.arange(8)


def _hands(arm: str, times: np.ndarray) -> np.ndarray:
    """A palm circling in front of the chest (synthetic), the left one mirrored."""
    t = np.asarray(times, dtype=float)
    side = 1.0 if arm == "right" else -1.0
    return np.column_stack([side * (-0.2 + 0.1 * np.cos(3.0 * t)), 0.1 + 0.1 * np.sin(3.0 * t), 0.35 + 0.0 * t])


def _shifts(avatar_name: str) -> list:
    """Shifts activated one after another, each from where the one before left the gaze:
    fixed points, a direction, the listener, a moving hand, a head target, a head share,
    and the same point twice (a shift of no amplitude)."""
    avatar = load_avatar(avatar_name)
    targets = [
        dict(target=point([-0.35, 0.05, 0.55])),
        dict(target=direction(avatar, np.array([0.6, 0.0, 1.0]))),
        dict(target=listener(avatar)),
        dict(target=gaze_target(avatar, "RightHand", _hands)),
        dict(target=point([0.3, 0.05, 0.55]), head=point([0.0, 0.55, 1.2])),
        dict(target=point([0.3, 0.05, 0.55]), head_share=1.0),
        dict(target=point([0.3, 0.05, 0.55]), head_share=1.0),
        dict(target=gaze_target(avatar, "Hands", _hands), head_share=0.5),
    ]
    state = ChannelState(rest_state(avatar), np.zeros(6), 0.0)
    shifts = []
    for start, kwargs in zip(STARTS, targets, strict=True):
        target = kwargs.pop("target")
        if shifts:
            value = sample_shifts(shifts[-1:], np.zeros(1, dtype=np.int64), np.array([start]))[0]
            state = ChannelState(value, np.zeros(6), float(start))
        else:
            state = ChannelState(state.value, state.velocity, float(start))
        shifts.append(gaze(avatar, target, float(start), **kwargs).activate(state))
    return shifts


def _windows() -> dict[str, np.ndarray]:
    starts, end = STARTS, STARTS[-1] + 1.0
    frames = np.arange(np.ceil(starts[0] * 60.0), np.floor(end * 60.0)) / 60.0
    return {
        "all frames at 60 fps": frames,
        "25 fps": np.arange(np.ceil(starts[0] * 25.0), np.floor(end * 25.0)) / 25.0,
        "one frame": frames[100:101],
        "no frame": frames[:0],
        "each shift's last tenth": frames[np.isin(np.searchsorted(starts, frames, side="right") - 1, np.arange(starts.size)) & (((frames - starts[0]) % 0.7) > 0.63)],
        "at the shifts' starts": starts.copy(),
        "just before the next shift": starts[1:] - 1e-9,
        "a NaN time last": np.append(frames[:50], np.nan),
    }


@pytest.mark.parametrize("avatar_name", ["max", "kim"])
@pytest.mark.parametrize("window", list(_windows()))
def test_one_pass_gives_each_shifts_own_numbers(avatar_name, window):
    shifts = _shifts(avatar_name)
    times = _windows()[window]
    owner = np.searchsorted(STARTS, times, side="right") - 1
    assert np.all(owner >= 0)
    together = sample_shifts(shifts, owner, times)
    assert together.shape == (times.size, 6)
    np.testing.assert_array_equal(together, sample_timeline(shifts, owner, times))
    for index, shift in enumerate(shifts):  # and one shift alone, as a gaze state asks it
        rows = owner == index
        if np.any(rows):
            np.testing.assert_array_equal(shift.sample(times[rows]), sample(shift, times[rows]))


def test_a_fixed_goal_is_held_exactly_once_the_shift_is_over():
    first = _shifts("max")[0]
    after = np.array([first.time + first.duration, first.time + first.duration + 0.1])
    held = sample_shifts([first], np.zeros(2, dtype=np.int64), after)
    np.testing.assert_array_equal(held, np.tile(np.concatenate(first._goal_at_start), (2, 1)))


def test_the_shifts_really_move_the_gaze():
    """The table's shifts are not all alike: the comparison above can fail."""
    shifts = _shifts("max")
    times = _windows()["all frames at 60 fps"]
    values = sample_shifts(shifts, np.searchsorted(STARTS, times, side="right") - 1, times)
    assert np.ptp(values[:, 0]) > 0.3 and np.ptp(values[:, 3]) > 0.2
