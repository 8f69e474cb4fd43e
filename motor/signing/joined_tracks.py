"""Sign tracks joined end to end, sampled in one pass.

A sequence of signs puts thousands of :class:`motor.signing.lmp.SignTrack` on each channel;
sampled one by one, each costs a few dozen small numpy calls, most of the time their
overhead. :class:`JoinedTracks` holds the arrays of many tracks one after another and finds
every sample's move and segment among its track's alone in one compiled loop
(:mod:`motor.signing.track_kernels`), so that each number is computed as the track's own
:meth:`motor.signing.lmp.SignTrack.sample` computes it. Its tracks one by one are
:class:`BatchedTrack`, which sample through it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from motor import quaternion as quat
from motor.program.lmp import ChannelState
from motor.signing.lmp import NEGLIGIBLE, SignTrack, manner_tables, track_state
from motor.signing.track_kernels import segments


@dataclass(frozen=True, eq=False)
class JoinedTracks:
    """``n`` sign tracks of one kind (rotations or vectors) one after another.

    Attributes:
        rotation: the values are quaternions.
        initial: ``(n, D)`` each track's value before its first move.
        move_base, value_base: ``(n + 1,)`` where each track's moves and values begin.
        starts, ends, manners: ``(M,)`` the moves' seconds and rows of
            :func:`motor.signing.lmp.manner_tables`.
        values: ``(V, D)``; keys: ``(V,)`` each value's key within its track
            (``2 · move + fraction of the way``).
        first, last: ``(M,)`` each move's first and last value (rows of ``values``).
    """

    rotation: bool
    initial: np.ndarray
    move_base: np.ndarray
    value_base: np.ndarray
    starts: np.ndarray
    ends: np.ndarray
    manners: np.ndarray
    values: np.ndarray
    keys: np.ndarray
    first: np.ndarray
    last: np.ndarray

    @classmethod
    def of(cls, tracks: Sequence[SignTrack]) -> JoinedTracks:
        """The tracks (all rotations or all vectors) joined."""
        moves = np.array([track.starts.size for track in tracks])
        sizes = np.array([track.values.shape[0] for track in tracks])
        move_base = np.concatenate([[0], np.cumsum(moves)])
        value_base = np.concatenate([[0], np.cumsum(sizes)])
        offsets = np.repeat(value_base[:-1], moves)
        return cls(
            tracks[0].rotation, np.stack([track.initial for track in tracks]), move_base, value_base,
            np.concatenate([track.starts for track in tracks]), np.concatenate([track.ends for track in tracks]),
            np.concatenate([track.manners for track in tracks]), np.concatenate([track.values for track in tracks]),
            np.concatenate([track.keys for track in tracks]), np.concatenate([track.first for track in tracks]) + offsets,
            np.concatenate([track.last for track in tracks]) + offsets,
        )  # fmt: skip

    def sample(self, owner: np.ndarray, times: np.ndarray) -> np.ndarray:
        """Values at ``times`` of the tracks ``owner`` ``(n,)``: what each track's own
        ``sample`` gives for its times."""
        t = np.asarray(times, dtype=float)
        index, fraction = segments(
            owner, t, self.move_base, self.value_base, self.starts, self.ends, self.manners, manner_tables(), self.keys, self.first, self.last,
            NEGLIGIBLE,
        )  # fmt: skip
        before = index < 0
        index[before] = 0
        if self.rotation:
            out = quat.slerp(self.values[index], self.values[index + 1], fraction)
        else:
            out = self.values[index] + fraction[:, None] * (self.values[index + 1] - self.values[index])
        if np.any(before):
            out[before] = self.initial[owner[before]]
        return out

    def replaced(self, parts: dict[int, SignTrack]) -> JoinedTracks:
        """These tracks with those at the keys of ``parts`` replaced by the values."""
        if not parts:
            return self
        order = sorted(parts)
        moves, sizes = np.diff(self.move_base), np.diff(self.value_base)
        offsets = np.repeat(self.value_base[:-1], moves)
        local_first, local_last = self.first - offsets, self.last - offsets
        moves[order] = [parts[i].starts.size for i in order]
        sizes[order] = [parts[i].values.shape[0] for i in order]
        move_base = np.concatenate([[0], np.cumsum(moves)])
        value_base = np.concatenate([[0], np.cumsum(sizes)])
        offsets = np.repeat(value_base[:-1], moves)

        def spliced(array: np.ndarray, base: np.ndarray, new: list[np.ndarray]) -> np.ndarray:
            pieces, at = [], 0
            for i, piece in zip(order, new):
                pieces += [array[base[at] : base[i]], piece]
                at = i + 1
            return np.concatenate([*pieces, array[base[at] :]])

        def per_move(name: str, array: np.ndarray) -> np.ndarray:
            return spliced(array, self.move_base, [getattr(parts[i], name) for i in order])

        initial = self.initial.copy()
        initial[order] = [parts[i].initial for i in order]
        return JoinedTracks(
            self.rotation, initial, move_base, value_base, per_move("starts", self.starts), per_move("ends", self.ends),
            per_move("manners", self.manners), spliced(self.values, self.value_base, [parts[i].values for i in order]),
            spliced(self.keys, self.value_base, [parts[i].keys for i in order]), per_move("first", local_first) + offsets,
            per_move("last", local_last) + offsets,
        )  # fmt: skip

    def tracks(self) -> list[BatchedTrack]:
        """Each track, sampled through these."""
        return [BatchedTrack(self, index) for index in range(self.initial.shape[0])]

    def alone(self, index: int) -> SignTrack:
        """The ``index``-th track on its own (its arrays views of these)."""
        m, m_end = self.move_base[index : index + 2].tolist()
        v, v_end = self.value_base[index : index + 2].tolist()
        return SignTrack(
            self.rotation, self.initial[index], self.starts[m:m_end], self.ends[m:m_end], self.manners[m:m_end], self.values[v:v_end],
            self.keys[v:v_end], self.first[m:m_end] - v, self.last[m:m_end] - v,
        )  # fmt: skip


class BatchedTrack:
    """A sign track that is part of a :class:`JoinedTracks` (``batch``, the ``index``-th),
    sampled through it: what the track on its own (:meth:`JoinedTracks.alone`) gives.
    Thousands are made at once, so it holds no arrays of its own."""

    __slots__ = ("batch", "index")
    warnings: tuple[str, ...] = ()

    def __init__(self, batch: JoinedTracks, index: int) -> None:
        self.batch = batch
        self.index = index

    @property
    def rotation(self) -> bool:
        return self.batch.rotation

    @property
    def initial(self) -> np.ndarray:
        return self.batch.initial[self.index]

    def sample(self, times: np.ndarray) -> np.ndarray:
        t = np.asarray(times, dtype=float)
        return self.batch.sample(np.full(t.size, self.index), t)

    def state(self, time: float) -> ChannelState:
        """Value and velocity (angular velocity for rotations) looking back from ``time``."""
        return track_state(self, time)
