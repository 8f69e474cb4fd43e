"""Sign tracks sampled and activated many at once as :mod:`motor.signing.track_batch` did
before its tracks were prepared and joined per channel (issue 19): each realization's
arrays joined on every call, each LMP realized on its own from a guess, one guessing
round, then a pass in order. The plain path ``test_track_batch.py`` holds the joined
tracks to, bit for bit. Not used by mura itself."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from motor import quaternion as quat
from motor.signing.lmp import NEGLIGIBLE, SignChannelLMP, SignTrack, manner_tables


def sample_tracks(realizations: Sequence[object], owner: np.ndarray, times: np.ndarray) -> np.ndarray | None:
    """Values at sorted ``times`` of ``realizations[owner]`` (``owner`` ``(n,)``, indices
    into ``realizations``, non-decreasing), all in one pass: what each realization's
    ``sample`` gives for its times, when all are sign tracks of one kind; else None.

    The tracks' arrays are joined; a move or value is found by the pair (track, time) or
    (track, key) — complex numbers, which numpy orders lexicographically — so that every
    number is computed as the track's own :meth:`SignTrack.sample` computes it."""
    if not realizations or not all(type(r) is SignTrack for r in realizations):
        return None
    rotation = realizations[0].rotation
    if any(r.rotation != rotation for r in realizations):
        return None
    moves = np.array([r.starts.size for r in realizations])
    sizes = np.array([r.values.shape[0] for r in realizations])
    move_base = np.concatenate([[0], np.cumsum(moves)[:-1]])
    value_base = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    starts = np.concatenate([r.starts for r in realizations])
    ends = np.concatenate([r.ends for r in realizations])
    manners = np.concatenate([r.manners for r in realizations])
    tables = manner_tables()
    values = np.concatenate([r.values for r in realizations])
    keys = np.concatenate([r.keys for r in realizations])
    first = np.concatenate([r.first for r in realizations]) + np.repeat(value_base, moves)
    last = np.concatenate([r.last for r in realizations]) + np.repeat(value_base, moves)
    t = np.asarray(times, dtype=float)
    tracks = owner.astype(float)
    found = np.searchsorted(np.repeat(np.arange(len(realizations), dtype=float), moves) + 1j * starts, tracks + 1j * t, side="right") - 1
    local = found - move_base[owner]
    before = local < 0
    move = np.maximum(local, 0)
    row = move_base[owner] + move
    u = np.clip((t - starts[row]) / (ends[row] - starts[row]), 0.0, 1.0)
    position = u * (tables.shape[1] - 1)
    low = np.minimum(position.astype(int), tables.shape[1] - 2)
    weight = position - low
    s = (1.0 - weight) * tables[manners[row], low] + weight * tables[manners[row], low + 1]
    wanted = 2.0 * move + s
    index = np.searchsorted(np.repeat(np.arange(len(realizations), dtype=float), sizes) + 1j * keys, tracks + 1j * wanted, side="right") - 1
    index = np.clip(index, first[row], last[row] - 1)
    width = keys[index + 1] - keys[index]
    fraction = np.clip((wanted - keys[index]) / np.where(width > NEGLIGIBLE, width, 1.0), 0.0, 1.0)
    if rotation:
        out = quat.slerp(values[index], values[index + 1], fraction)
    else:
        out = values[index] + fraction[:, None] * (values[index + 1] - values[index])
    if np.any(before):
        out[before] = np.stack([realizations[i].initial for i in owner[before]])
    return out


#: Rounds that correct the guessed activation values of :func:`activate_in_turn` before
#: its pass in order.
GUESS_ROUNDS = 1


def activate_in_turn(lmps: Sequence[SignChannelLMP], here: np.ndarray, time: float) -> list[SignTrack]:
    """The tracks of sign LMPs of one channel activated one after another, as
    :meth:`motor.program.lmp.ChannelTimeline.build` activates them: the first at ``time``
    from ``here``, each next at its start from the value the track before has then.

    Each activation's value is first guessed: the value the previous LMP's track has at
    its start when that track is made from a guess of its own value (:data:`GUESS_ROUNDS`
    times, after which most guesses are exact), all tracks sampled at once (:func:`sample_tracks`). Then the LMPs
    are taken in order: an activation whose guess is the value the track before gives
    keeps its track; any other is made again from that value, and the value after it is
    sampled anew. The result is the sequential one, with most of its work in vectorized
    passes."""
    starts = [lmp.pegs.start for lmp in lmps]
    guesses = [here] + [_last_value(lmp) for lmp in lmps[:-1]]
    tracks = [lmps[0].realize(here, time)] + [lmp.realize(guess, start) for lmp, guess, start in zip(lmps[1:], guesses[1:], starts[1:])]
    for _ in range(GUESS_ROUNDS):
        sampled = _values_at(tracks[:-1], starts[1:])
        if sampled is None:
            break
        for i in range(1, len(lmps)):
            if not np.array_equal(sampled[i - 1], guesses[i]):
                guesses[i] = sampled[i - 1]
                tracks[i] = lmps[i].realize(guesses[i], starts[i])
    sampled = _values_at(tracks[:-1], starts[1:])
    fresh = False  # the track before was made again after the values were sampled
    for i in range(1, len(lmps)):
        value = tracks[i - 1].sample(np.array([starts[i]]))[0] if fresh or sampled is None else sampled[i - 1]
        fresh = not np.array_equal(value, guesses[i])
        if fresh:
            tracks[i] = lmps[i].realize(value, starts[i])
    return tracks


def _last_value(lmp: SignChannelLMP) -> np.ndarray:
    """Where the channel is when ``lmp`` is done, about (a guess, exact for most)."""
    if lmp.traced is not None:
        return lmp.traced.values[-1][-1]
    return np.asarray(lmp.moves[-1].values[-1] if lmp.moves else lmp.first, dtype=float)


def _values_at(tracks: Sequence[SignTrack], times: Sequence[float]) -> np.ndarray | None:
    """Each track's value at its time, all at once (the values its own ``sample`` gives)."""
    if not tracks:
        return np.empty((0, 0))
    return sample_tracks(tracks, np.arange(len(tracks)), np.asarray(times, dtype=float))
