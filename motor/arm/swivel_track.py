"""Both arms' swivel tracks on a fixed grid of the utterance clock.

Every :data:`SWIVEL_PERIOD` seconds each candidate swivel of each arm gets the IK's cost
(natural swivel, wrist comfort, clearance from the body: :func:`motor.arm.ik.track_costs`;
the clearance is the least the candidate keeps there and half a period before and after,
for a fast stroke can take the arm into the body between two grid points) and a swivel track walks through the candidates, a bounded step from one grid point to
the next, toward what costs least now and :data:`motor.arm.swivel.HORIZON` grid points
ahead (:func:`motor.arm.swivel.smooth_swivels`). The track's steps follow the turn of
the swivel's zero from grid point to grid point, so that a track that stays put keeps
the elbow where it was whatever the arm's elevation. The right arm's track is found
first; the left arm's keeps clear of the right arm where that track puts it at the same
grid point (a cost of the point itself, not of the look ahead). Then both are found again,
the right keeping clear of where the left's first track puts it, the left of the right's
second, where the left arm's first track still comes near the right one's (hands crossing
over): the right elbow no longer takes the only room the left one had. Each of the four tracks goes on from its own state
at the grid point before (the first tracks' are kept beside the second's), so the tracks
still depend on nothing but those states and the channel values ahead; where the arms
keep apart and the second tracks stand where the first do, the second are the first. The forearm twist is
carried along the grid too (:func:`twist_track`): it never wraps from one limit to the
other.

A grid state depends on the state before it and on channel values up to
:data:`TRACK_REACH` grid points ahead, nothing else. States are kept as columns of
arrays, grid index ``first`` onward, contiguous.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from motor.arm.ik import CANDIDATES, track_costs
from motor.arm.swivel import HORIZON, SwivelState, smooth_swivels
from motor.arm.swivel_cost import turn_remainder
from motor.body.avatar import Avatar
from motor.body.conventions import ARMS, AVATAR_SIDE
from motor.kernel_types import READ1, READ2, WRITE1, WRITE2

#: Period of the grid, seconds.
SWIVEL_PERIOD = 0.125
#: How many grid points a batch solves at least: short windows then share one batch.
SWIVEL_LOOKAHEAD = 20
#: How many grid points ahead a grid state depends on channel values: the horizon's, and
#: half a period beyond its last point (the clearance half way, :func:`track_costs`).
TRACK_REACH = HORIZON + 1
#: How much less of a twist the hand asks for must be left unachieved before the forearm
#: turns over to the other side of its range (radians), and how fast it turns over
#: (radians per grid point).
TWIST_HYSTERESIS = math.radians(90.0)
TWIST_STEP = math.radians(60.0)
#: How far the wrist's flexion and deviation may move per grid point where the hand's
#: way is only partly defined (radians).
WRIST_STEP = math.radians(40.0)
#: The columns kept per arm and grid point: the track's candidate (unwrapped step count)
#: and swivel (radians, unwrapped), how far the swivel's zero turned since the grid point
#: before, the direction of swivel 0 (3 columns), the forearm twist, the twist the hand
#: wanted there (radians, in (-π, π]), the wrist's flexion and deviation, and the first
#: track's candidate and swivel (module docstring).
_COLUMNS = ("cell", "swivel", "turn", "zero_x", "zero_y", "zero_z", "twist", "wanted", "flexion", "deviation", "first_cell", "first_swivel")


@dataclass
class _Arm:
    """One arm's grid states, a row per grid point (columns :data:`_COLUMNS`)."""

    rows: np.ndarray

    def state(self, row: int) -> tuple[SwivelState, tuple[float, float, float], SwivelState]:
        """The track's state, the twist, flexion and deviation, and the first track's state at a row."""
        values = self.rows[row]
        return (
            SwivelState(int(values[0]), float(values[1])),
            (float(values[6]), float(values[8]), float(values[9])),
            SwivelState(int(values[10]), float(values[11])),
        )


class SwivelGrid:
    """The grid states of both arms from grid index :attr:`first` on (none when empty)."""

    def __init__(self, avatar: Avatar) -> None:
        self.avatar = avatar
        self.first = 0
        self._arms = {arm: _Arm(np.empty((0, len(_COLUMNS)))) for arm in ARMS}

    @property
    def count(self) -> int:
        return self._arms[ARMS[0]].rows.shape[0]

    @property
    def last(self) -> int:
        """The last grid index known (``first - 1`` when none is)."""
        return self.first + self.count - 1

    def plan(self, first: int, last: int) -> tuple[int, int, bool] | None:
        """Which grid states to solve so that every index in ``[first, last]`` is known:
        None if all are, else the first and last index to solve and whether the tracks
        start afresh there. They go on from the last known state, :data:`SWIVEL_LOOKAHEAD`
        points at a time; they start afresh at ``first`` — forgetting what is known — when
        nothing before it is known."""
        if self.count and self.first <= first and last <= self.last:
            return None
        if not self.count or first < self.first:
            return first, max(last, first + SWIVEL_LOOKAHEAD - 1), True
        start = self.last + 1
        return start, max(last, start + SWIVEL_LOOKAHEAD - 1), False

    def times(self, start: int, end: int) -> np.ndarray:
        """The times whose channel values :meth:`solve` needs for ``start … end``: the grid
        points from the one before ``start`` to :data:`HORIZON` after ``end``, each
        followed by the instant half way to the next."""
        return np.arange(2 * (start - 1), 2 * (end + HORIZON) + 2) * (0.5 * SWIVEL_PERIOD)

    def solve(self, start: int, end: int, fresh: bool, inputs: dict[str, tuple[np.ndarray, np.ndarray]], trunk_yaw: np.ndarray | None = None) -> None:
        """Grid states ``start … end`` of both arms (module docstring) from the arms' wrist
        positions and hand rotations at :meth:`times` (grid points and the instants half
        way between them, alternately), given in the frame of the trunk turned by
        ``trunk_yaw`` there (radians, None: not turned)."""
        if fresh:
            self.first = start
            for arm in ARMS:
                self._arms[arm].rows = self._arms[arm].rows[:0]
        count = end - start + 1
        before = {arm: None if fresh else self._arms[arm].state(-1) for arm in ARMS}
        grid_yaw, half_yaw = (None, None) if trunk_yaw is None else (trunk_yaw[::2], trunk_yaw[1::2])
        costs = {
            arm: track_costs(self.avatar, AVATAR_SIDE[arm], wrists[::2], hands[::2], grid_yaw, (wrists[1::2], hands[1::2], half_yaw))
            for arm, (wrists, hands) in inputs.items()
        }
        first, first_poses, crowded = self._tracks(costs, {arm: None if state is None else state[2] for arm, state in before.items()}, None)
        again = {arm: None if state is None else state[0] for arm, state in before.items()}
        if crowded or any(state is not None and state[0] != state[2] for state in before.values()):
            tracks, poses, _ = self._tracks(costs, again, first_poses[ARMS[-1]][0])
        else:
            tracks, poses = first, first_poses
        for arm in ARMS:
            side = AVATAR_SIDE[arm]
            cells, swivels = tracks[arm]
            _, wanted, certainty, flexion, deviation = poses[arm]
            limits = self.avatar.limit(f"{side}_elbow", "twist")
            twists = twist_track(wanted, certainty, None if before[arm] is None else before[arm][1][0], limits)
            wrist = wrist_track(np.stack([flexion, deviation], axis=1), certainty, None if before[arm] is None else before[arm][1][1:])
            rows = np.column_stack([cells, swivels, costs[arm].turns[:count], costs[arm].zeros[:count], twists, wanted, wrist, *first[arm]])
            self._arms[arm].rows = np.concatenate([self._arms[arm].rows, rows])

    def _tracks(self, costs: dict, before: dict[str, SwivelState | None], left: np.ndarray | None) -> tuple[dict, dict, bool]:
        """Both arms' tracks and poses, in turn: the right arm's keeping clear of the left
        arm's elbows at ``left (n, 3)`` (None: of nothing), the left arm's of the right's
        track; and whether the left arm's track still comes near the right one's (its
        chosen swivels pay for it somewhere)."""
        tracks, poses = {}, {}
        last = ARMS[-1]
        other = None if left is None else costs[last].segments(self.avatar, AVATAR_SIDE[last], left)
        crowded = False
        for arm in ARMS:
            now = None if other is None else costs[arm].near_other(self.avatar, other)
            near = now is not None and bool(np.any(now))
            tracks[arm], poses[arm] = self._track(costs[arm], before[arm], now if near else None)
            if near and arm == last:
                cells = tracks[arm][0] % now.shape[1]
                crowded = bool(np.any(np.take_along_axis(now, cells[: now.shape[0], None], axis=1) > 0.0))
            other = costs[arm].segments(self.avatar, AVATAR_SIDE[arm], poses[arm][0])
        return tracks, poses, crowded

    @staticmethod
    def _track(costs, before, now: np.ndarray | None) -> tuple[tuple[np.ndarray, np.ndarray], tuple[np.ndarray, ...]]:
        """One arm's track (candidates, swivels) and its pose there (:meth:`TrackCosts.pose`)."""
        track = smooth_swivels(costs.costs, CANDIDATES, before, HORIZON, now, costs.turns)
        return track, costs.pose(track[1])

    def forget_from(self, index: int) -> None:
        """Drop the states of grid indices ``index`` and later."""
        keep = max(0, index - self.first)
        for arm in ARMS:
            self._arms[arm].rows = self._arms[arm].rows[:keep]

    def forget_before(self, index: int) -> None:
        """Drop the states of grid indices before ``index`` (the last one always stays: the
        tracks go on from it)."""
        drop = min(max(0, index - self.first), self.count - 1)
        if drop <= 0:
            return
        self.first += drop
        for arm in ARMS:
            self._arms[arm].rows = self._arms[arm].rows[drop:]

    def sample(self, arm: str, times: np.ndarray, first: int, last: int) -> tuple[np.ndarray, np.ndarray]:
        """The arm's swivel at sorted ``times`` (whose grid span is ``first … last``) as
        ``(n, 4)``: a Catmull-Rom spline through the four grid swivels around each time,
        each carried to the grid point at or before it (undoing the turns of the zero
        between them), and that grid point's direction of swivel 0, from which the swivel
        is counted (so that between grid points the elbow keeps to the track however the
        arm's zero turns); and the forearm twist's reference ``(n, 2)``: the grid's twist
        and the twist the hand wanted there, and the wrist's flexion and deviation, all
        linear between grid points (the wanted twist the shorter way round)."""
        rows = np.ascontiguousarray(self._arms[arm].rows[first - self.first : last - self.first + 1])
        positions = np.ascontiguousarray(times / SWIVEL_PERIOD, dtype=float)
        swivel, reference = np.empty((positions.size, 4)), np.empty((positions.size, 4))
        _sampled_rows(rows, positions, first, swivel, reference)
        return swivel, reference


def twist_track(wanted: np.ndarray, certainty: np.ndarray, previous: float | None, limits: tuple[float, float]) -> np.ndarray:
    """The forearm twist along grid points (radians, within the limits).

    At each grid point the hand asks for a twist, known up to whole turns; it is taken on
    the turn nearest the previous grid point's twist and clamped to the limits — unless
    the other way round leaves at least :data:`TWIST_HYSTERESIS` less of it unachieved,
    when the forearm turns over to that side instead. The twist then moves toward its
    target by at most :data:`TWIST_STEP` per grid point, so turning over takes several
    frames instead of one, and only as far as the hand's twist is defined (``certainty``,
    :func:`motor.arm.ik.twist_certainty`). The first grid point, without a previous one,
    takes the shortest turn."""
    start = 0.0 if previous is None else float(previous)
    return _twists(np.ascontiguousarray(wanted, dtype=float), np.ascontiguousarray(certainty, dtype=float), start, previous is None, float(limits[0]), float(limits[1]))


def wrist_track(targets: np.ndarray, certainty: np.ndarray, previous: tuple[float, float] | None) -> np.ndarray:
    """The wrist's flexion and deviation along grid points ``(m, 2)``: each moves toward
    its target (within the limits, from the hand rotation) by at most
    :data:`WRIST_STEP`, and only as far as the hand's way is defined (``certainty``); so
    where the hand points so far off the forearm that the nearest wrist jumps from one
    limit to the other, the wrist stays where it was. Without a previous grid point the
    first takes its target."""
    here = np.array(targets[0] if previous is None else previous, dtype=float)
    return _wrist_steps(np.ascontiguousarray(targets, dtype=float), np.ascontiguousarray(certainty, dtype=float), here)


@numba.njit([WRITE1(READ1, READ1, numba.float64, numba.boolean, numba.float64, numba.float64)], cache=True, error_model="numpy")
def _twists(wanted, certainty, previous, fresh, low, high):  # noqa: ANN001, ANN202
    """:func:`twist_track`'s steps from ``previous`` (``fresh``: from none), one grid point
    at a time (each depends on the one before); the whole turn nearest is ``rint``'s, ties
    to even as Python's ``round``."""
    turn = 2.0 * math.pi
    twists = np.empty(wanted.size)
    here = previous
    for i in range(wanted.size):
        value = wanted[i]
        if i == 0 and fresh:
            here = low if value < low else high if value > high else value
            twists[0] = here
            continue
        value += turn * np.rint((here - value) / turn)
        other = value - turn if value > high else value + turn
        short = value - high if value > high else low - value if value < low else 0.0
        other_short = other - high if other > high else low - other if other < low else 0.0
        if short > other_short + TWIST_HYSTERESIS:
            value = other
        step = (low if value < low else high if value > high else value) - here
        here += certainty[i] * (-TWIST_STEP if step < -TWIST_STEP else TWIST_STEP if step > TWIST_STEP else step)
        twists[i] = here
    return twists


@numba.njit([WRITE2(READ2, READ1, READ1)], cache=True, error_model="numpy")
def _wrist_steps(targets, certainty, start):  # noqa: ANN001, ANN202
    """:func:`wrist_track`'s steps from ``start (2,)``, one grid point at a time."""
    track = np.empty(targets.shape)
    flexion, deviation = start[0], start[1]
    for i in range(targets.shape[0]):
        step = targets[i, 0] - flexion
        flexion += certainty[i] * (-WRIST_STEP if step < -WRIST_STEP else WRIST_STEP if step > WRIST_STEP else step)
        step = targets[i, 1] - deviation
        deviation += certainty[i] * (-WRIST_STEP if step < -WRIST_STEP else WRIST_STEP if step > WRIST_STEP else step)
        track[i, 0], track[i, 1] = flexion, deviation
    return track


@numba.njit(cache=True, error_model="numpy", inline="always")
def _catmull_rom(p0, p1, p2, p3, u):  # noqa: ANN001, ANN202
    """The Catmull-Rom spline through ``p0 … p3`` (at grid points −1 … 2) at ``u`` in [0, 1)."""
    return p1 + 0.5 * u * ((p2 - p0) + u * ((2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) + u * (3.0 * (p1 - p2) + p3 - p0)))


@numba.njit([numba.void(READ2, READ1, numba.int64, WRITE2, WRITE2)], cache=True, error_model="numpy")
def _sampled_rows(rows, positions, first, swivel, reference):  # noqa: ANN001, ANN202
    """:meth:`SwivelGrid.sample` per time: ``positions`` are the times in grid periods,
    ``rows`` the grid states from index ``first`` on; the arithmetic of numpy's whole-array
    steps it replaced, in their order (``tests/perf_equivalence/plain_swivel.py``)."""
    for i in range(positions.size):
        at = int(math.floor(positions[i] + 1e-9)) - first
        if at < 1 or at + 2 >= rows.shape[0]:
            raise IndexError("a time outside the grid states given")
        u = positions[i] - float(at + first)
        turn, after = rows[at, 2], rows[at + 1, 2]
        p0, p1, p2 = rows[at - 1, 1] + turn, rows[at, 1], rows[at + 1, 1] - after
        p3 = rows[at + 2, 1] - after - rows[at + 2, 2]
        swivel[i, 0] = _catmull_rom(p0, p1, p2, p3, u)
        swivel[i, 1], swivel[i, 2], swivel[i, 3] = rows[at, 3], rows[at, 4], rows[at, 5]
        twist, wanted = rows[at, 6], rows[at, 7]
        change = turn_remainder(rows[at + 1, 7] - wanted + np.pi) - np.pi
        reference[i, 0] = twist + u * (rows[at + 1, 6] - twist)
        reference[i, 1] = wanted + u * change
        reference[i, 2] = rows[at, 8] + u * (rows[at + 1, 8] - rows[at, 8])
        reference[i, 3] = rows[at, 9] + u * (rows[at + 1, 9] - rows[at, 9])


def load_kernels() -> None:
    """Run this module's compiled loops once (they load when the module is imported):
    :func:`motor.compiled.warm_up`."""
    _twists(np.zeros(2), np.ones(2), 0.0, True, -1.0, 1.0)
    _wrist_steps(np.zeros((2, 2)), np.ones(2), np.zeros(2))
    _sampled_rows(np.zeros((4, len(_COLUMNS))), np.array([1.5]), 0, np.empty((1, 4)), np.empty((1, 4)))
