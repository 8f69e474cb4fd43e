"""Sign tracks many at once: sampled in one pass, activated one after another in
vectorized rounds.

A sequence of signs puts thousands of :class:`motor.signing.lmp.SignChannelLMP` on each
channel. Activated and sampled one by one, each costs a few dozen small numpy calls, and
the calls' overhead is most of the time. :func:`activate_in_turn` makes the tracks
:meth:`motor.program.lmp.ChannelTimeline.build` makes, as parts of one
:class:`motor.signing.joined_tracks.JoinedTracks`; :func:`sample_tracks` samples a run of
them through it. ``tests/perf_equivalence/test_path_batch.py`` and
``tests/perf_equivalence/test_track_batch.py`` pin both to the one-by-one results.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from motor.signing.joined_tracks import BatchedTrack, JoinedTracks
from motor.signing.lmp import SignChannelLMP, SignTrack
from motor.signing.prepared_tracks import prepare


def sample_tracks(realizations: Sequence[object], owner: np.ndarray, times: np.ndarray) -> np.ndarray | None:
    """Values at sorted ``times`` of ``realizations[owner]`` (``owner`` ``(n,)``, indices
    into ``realizations``, non-decreasing), all in one pass: what each realization's
    ``sample`` gives for its times, when all are sign tracks of one kind; else None.

    A run of tracks activated together is sampled through their batch; others are joined first."""
    if not realizations or not all(type(r) is SignTrack or type(r) is BatchedTrack for r in realizations):
        return None
    rotation = realizations[0].rotation
    if any(r.rotation != rotation for r in realizations):
        return None
    first = realizations[0]
    if type(first) is BatchedTrack and all(type(r) is BatchedTrack and r.batch is first.batch and r.index == first.index + k for k, r in enumerate(realizations)):
        return first.batch.sample(owner + first.index, times)
    return JoinedTracks.of([r.batch.alone(r.index) if type(r) is BatchedTrack else r for r in realizations]).sample(owner, times)


#: Rounds of guessed activation values checked at once before the LMPs whose guesses are
#: still wrong are activated one after another.
GUESS_ROUNDS = 3


def activate_in_turn(lmps: Sequence[SignChannelLMP], here: np.ndarray, time: float) -> list[SignTrack] | list[BatchedTrack]:
    """The tracks of sign LMPs of one channel activated one after another, as
    :meth:`motor.program.lmp.ChannelTimeline.build` activates them: the first at ``time``
    from ``here``, each next at its start from the value the track before has then.

    Each activation's value is guessed: at first where the LMP before ends, then what the
    tracks made from the guesses give, all of them made and sampled at once
    (:mod:`motor.signing.prepared_tracks`) — for a rotation, negated where a guess started
    the track before in the wrong hemisphere — for :data:`GUESS_ROUNDS` rounds or until
    every guess is the value the track before gives: then the tracks are the sequential
    ones. From the first guess still wrong on, the LMPs are taken in order, each made again
    from the value the track before gives. Most of the work is in vectorized passes."""
    here = np.asarray(here, dtype=float)
    prepared = prepare(lmps)
    count = len(lmps)
    starts = np.array([lmp.pegs.start for lmp in lmps], dtype=float)
    times = starts.copy()
    times[0] = time
    guesses = [here] + [_last_value(lmp) for lmp in lmps[:-1]]
    if prepared is None or any(guess.shape != here.shape for guess in guesses) or here.shape != prepared.firsts.shape[1:]:
        return _in_order(lmps, here, time)
    heres = np.array(guesses)
    for attempt in range(GUESS_ROUNDS):
        batch, fits = prepared.activated(heres, times)
        own = {int(i): lmps[i].realize(heres[i], float(times[i])) for i in np.flatnonzero(~fits)}
        values = _next_values(batch, fits, own, starts)
        wrong = np.flatnonzero(~(values == heres[1:]).all(axis=1)) + 1
        if wrong.size == 0 or attempt == GUESS_ROUNDS - 1:
            break
        if prepared.rotation:
            values = _chosen(values, _next_values(*prepared.activated(-heres, times), dict.fromkeys(own), starts, values), heres)
        heres = np.concatenate([heres[:1], values])
    tracks: list[SignTrack | None] = [own.get(i) for i in range(count)]
    fresh = False  # the track before was made again after the values were sampled
    for i in range(int(wrong[0]) if wrong.size else count, count):
        value = tracks[i - 1].sample(starts[i : i + 1])[0] if fresh else values[i - 1]
        fresh = not np.array_equal(value, heres[i])
        if fresh:
            tracks[i] = lmps[i].realize(value, float(starts[i]))
    return batch.replaced({i: track for i, track in enumerate(tracks) if track is not None}).tracks()


def _next_values(batch: JoinedTracks, fits: np.ndarray, own: dict[int, SignTrack | None], starts: np.ndarray, otherwise: np.ndarray | None = None) -> np.ndarray:
    """Each track's value at the next LMP's start: the batch's where it ``fits``, else the
    LMP's own track's (``otherwise``'s row where it has none)."""
    values = np.empty((starts.size - 1, batch.values.shape[1]))
    rows = np.flatnonzero(fits[:-1])
    values[rows] = batch.sample(rows, starts[rows + 1])
    for i, track in own.items():
        if i < starts.size - 1:
            values[i] = otherwise[i] if track is None else track.sample(starts[i + 1 : i + 2])[0]
    return values


def _chosen(values: np.ndarray, negated: np.ndarray, heres: np.ndarray) -> np.ndarray:
    """The next activation values of a rotation channel, whose values' signs chain from
    each activation to the next: ``values`` ``(n - 1, 4)`` are the tracks' values at the
    next starts made from the guesses ``heres`` ``(n, 4)``, ``negated`` from their
    negations. Taken in order from the first LMP (whose activation value is given), each
    value, nearer a guess or its negation, tells which of the LMP's values to take next."""
    nearer = (np.einsum("ij,ij->i", values, heres[1:]) < 0.0).tolist()
    negated_nearer = (np.einsum("ij,ij->i", negated, heres[1:]) < 0.0).tolist()
    other = [False] * len(nearer)  # the LMP's activation value is nearer its guess's negation
    for i in range(len(nearer) - 1):
        other[i + 1] = negated_nearer[i] if other[i] else nearer[i]
    return np.where(np.array(other)[:, None], negated, values)


def _in_order(lmps: Sequence[SignChannelLMP], here: np.ndarray, time: float) -> list[SignTrack]:
    """The tracks made one after another, each from the value the track before has at its start."""
    tracks = [lmps[0].realize(here, time)]
    for lmp in lmps[1:]:
        tracks.append(lmp.realize(tracks[-1].sample(np.array([lmp.pegs.start]))[0], lmp.pegs.start))
    return tracks


def _last_value(lmp: SignChannelLMP) -> np.ndarray:
    """Where the channel is when ``lmp`` is done, about (a guess, exact for most)."""
    if lmp.traced is not None:
        return lmp.traced.values[-1][-1]
    return np.asarray(lmp.moves[-1].values[-1] if lmp.moves else lmp.first, dtype=float)
