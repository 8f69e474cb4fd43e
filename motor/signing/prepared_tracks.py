"""The tracks of a channel's sign LMPs, made ahead of their activation all at once.

Activated one by one, a sign LMP of a keyframe channel (hand rotation, hand shape) copies
the track of its template (:meth:`motor.signing.lmp.SignChannelLMP.realize`) and sets where
and when it starts; a wrist LMP takes the chain traced ahead for it
(:class:`motor.signing.lmp.TracedChain`). For the thousands of LMPs of a sequence of signs,
each is a few dozen small numpy calls. :func:`prepare` makes every template and traced
track of a channel's LMPs as one :class:`PreparedTracks` in a few vectorized steps — a
rotation channel's both ways, for a start in the hemisphere of the sign's first value and
for one in the other — and :meth:`PreparedTracks.activated` gives the tracks of
activations from given values at given times, each number as the LMP's own ``realize``
makes it. An LMP that neither way fits (a wrist whose chain was traced from elsewhere, a
transition left no time, a value not finite) is left to its own ``realize``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from motor.program.lmp import ROTATION_CHANNELS
from motor.signing.lmp import MANNER_ROWS, SignChannelLMP, even_fractions
from motor.signing.joined_tracks import JoinedTracks
from motor.trajectory.biocontrol import profile

#: A dot product this small next to the sum of its products' sizes has its sign computed
#: again as the LMP computes it (``a @ b``): summed in another order, it might differ.
_UNSURE = 1e-9
_ENDS = (np.zeros(1), np.ones(1))


@dataclass(frozen=True, eq=False)
class PreparedTracks:
    """The tracks of ``n`` sign LMPs of one channel but for where and when each starts.

    Attributes:
        rotation: the channel's values are quaternions.
        traced: ``(n,)`` the LMP's track is its traced chain, made from ``chain_here`` at
            ``chain_time`` (``(n, D)``, ``(n,)``; NaN for the others).
        template: ``(n,)`` the LMP's track is its template's (a keyframe channel).
        firsts: ``(n, D)`` each sign's first value; ``ready``: ``(n,)`` seconds it is reached.
        layout: the joined tracks (:class:`motor.signing.joined_tracks.JoinedTracks`) with each
            template's first value as given (``initial`` and the transitions' starts to be set).
        flipped: ``(V, D)`` the layout's values for rotation templates started in the other
            hemisphere: the first value and the moves negated, the way points kept.
    """

    rotation: bool
    traced: np.ndarray
    template: np.ndarray
    chain_here: np.ndarray
    chain_time: np.ndarray
    firsts: np.ndarray
    ready: np.ndarray
    layout: JoinedTracks
    flipped: np.ndarray

    def activated(self, heres: np.ndarray, times: np.ndarray) -> tuple[JoinedTracks, np.ndarray]:
        """The tracks of the LMPs activated from ``heres`` ``(n, D)`` at ``times`` ``(n,)``
        seconds, and which LMPs' tracks they are (the others' rows hold nothing of use:
        their own ``realize`` makes them)."""
        fits = self.traced & (times == self.chain_time) & (heres == self.chain_here).all(axis=1)
        keyframed = self.template & ~fits & (self.ready > times) & np.isfinite(heres).all(axis=1)
        layout = self.layout
        chosen = np.flatnonzero(keyframed)
        values, starts = layout.values, layout.starts
        if chosen.size:
            if self.rotation:
                flips = keyframed & opposite_hemisphere(heres, self.firsts)
                values = np.where(np.repeat(flips, np.diff(layout.value_base))[:, None], self.flipped, values)
            else:
                values = values.copy()
            starts = starts.copy()
            values[layout.value_base[chosen]] = heres[chosen]
            starts[layout.move_base[chosen]] = times[chosen]
        batch = JoinedTracks(
            layout.rotation, heres.copy(), layout.move_base, layout.value_base, starts, layout.ends, layout.manners, values, layout.keys,
            layout.first, layout.last,
        )  # fmt: skip
        return batch, fits | keyframed


def opposite_hemisphere(values: np.ndarray, firsts: np.ndarray) -> np.ndarray:
    """Whether each row of ``values`` has a negative dot product with the row of ``firsts``,
    as ``value @ first < 0`` decides it (rows near a right angle computed that way)."""
    return _dots(values, firsts) < 0.0


def _dots(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Rows' dot products whose signs are those of ``a[i] @ b[i]``."""
    dots = np.einsum("ij,ij->i", a, b)
    for row in np.flatnonzero(~(np.abs(dots) > _UNSURE * np.einsum("ij,ij->i", np.abs(a), np.abs(b)))):
        dots[row] = a[row] @ b[row]
    return dots


def prepare(lmps: Sequence[SignChannelLMP]) -> PreparedTracks | None:
    """The templates and traced tracks of sign LMPs of one channel, joined; None when
    their values are not all of one width."""
    channel = lmps[0].channel
    rotation = channel[1] in ROTATION_CHANNELS
    keyframes = channel[1] != "wrist_position"
    starts: list[float] = []
    ends: list[float] = []
    manners: list[str] = []
    values: list[np.ndarray] = []
    fractions: list[np.ndarray] = []
    counts: list[int] = []  # values of each move
    moves: list[int] = []  # of each LMP
    way_rows: list[int] = []  # of each template
    kinds: list[int] = []  # of each LMP: 0 none, 1 traced, 2 template
    firsts = [np.asarray(lmp.first, dtype=float) for lmp in lmps]
    if len({first.shape for first in firsts}) != 1 or firsts[0].ndim != 1:
        return None
    width = firsts[0].size
    nowhere = np.full(width, np.nan)
    chain_here: list[np.ndarray] = []
    chain_time: list[float] = []
    for lmp, first in zip(lmps, firsts):
        chain = lmp.traced
        if chain is not None and chain.here.shape == (width,):
            kinds.append(1)
            chain_here.append(chain.here)
            chain_time.append(chain.time)
            starts += chain.starts.tolist()
            ends += chain.ends.tolist()
            manners += chain.manners
            values += chain.values
            fractions += chain.fractions
            counts += [fraction.shape[0] for fraction in chain.fractions]
            moves.append(len(chain.values))
            continue
        chain_here.append(nowhere)
        chain_time.append(np.nan)
        if chain is not None or not keyframes:
            kinds.append(0)
            moves.append(0)
            continue
        kinds.append(2)
        via = lmp.via
        if via is None:
            way_rows.append(2)
            values += (first[None], first[None])
        else:
            via = np.asarray(via, dtype=float)
            way_rows.append(2 + via.shape[0])
            values += (first[None], via, first[None])
        starts.append(lmp.pegs.start)
        ends.append(lmp.pegs.ready)
        manners.append(lmp.transition)
        counts.append(way_rows[-1])
        if lmp.via_fractions is None:
            fractions.append(even_fractions(way_rows[-1]))
        else:
            fractions += (_ENDS[0], np.asarray(lmp.via_fractions, dtype=float), _ENDS[1])
        for move in lmp.moves:
            starts.append(move.start)
            ends.append(move.end)
            manners.append(move.manner)
            values.append(move.values)
            counts.append(move.values.shape[0])
            fractions.append(even_fractions(counts[-1]))
        moves.append(1 + len(lmp.moves))
    try:
        joined = np.concatenate(values) if values else np.empty((0, width))
    except ValueError:  # values of other widths
        return None
    if joined.ndim != 2 or joined.shape != (sum(counts), width):
        return None
    kind = np.array(kinds)
    traced, template = kind == 1, kind == 2
    for manner in set(manners):
        profile(manner)  # an unknown manner: the error a Move gives
    sizes = np.array(counts, dtype=int)
    move_base = np.concatenate([[0], np.cumsum(moves)]).astype(int)
    owner = np.repeat(np.arange(len(lmps)), moves)
    in_track = np.arange(owner.size) - move_base[owner]
    first_row = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(int)
    value_base = np.concatenate([[0], np.cumsum(sizes)])[move_base]
    keys = np.repeat(2.0 * in_track, sizes) + (np.concatenate(fractions) if fractions else np.empty(0))
    kept = flipped = joined
    if rotation:
        kept, flipped = _continued(joined, np.repeat(template[owner] & (in_track > 0), sizes))
        last_way = value_base[:-1][template] + np.array(way_rows, dtype=int) - 1
        flipped[last_way] = -flipped[last_way]
        flipped[value_base[:-1][template]] = flipped[last_way]
    layout = JoinedTracks(
        rotation, np.empty((len(lmps), width)), move_base, value_base, np.array(starts, dtype=float), np.array(ends, dtype=float),
        np.array([MANNER_ROWS[manner] for manner in manners], dtype=int), kept, keys, first_row, first_row + sizes - 1,
    )  # fmt: skip
    ready = np.array([lmp.pegs.ready for lmp in lmps], dtype=float)
    return PreparedTracks(rotation, traced, template, np.array(chain_here), np.array(chain_time), np.array(firsts), ready, layout, flipped)


def _continued(values: np.ndarray, chained: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``values`` with the ``chained`` rows' signs flipped as :func:`motor.quaternion.continuous`
    flips them along each run of chained rows, which continues the row before the run: as
    given, and with that row negated (the rows before the runs are kept as they are).

    Each row's sign is the one before's times the sign of the rows' dot product (a dot of
    exactly zero keeps the row as it is, whatever the row before)."""
    rows = np.flatnonzero(chained)
    kept, flipped = values.copy(), values.copy()
    if rows.size == 0:
        return kept, flipped
    dots = _dots(values[rows], values[rows - 1])
    starts = np.ones(rows.size, dtype=bool)
    starts[1:] = rows[1:] != rows[:-1] + 1
    zero = dots == 0.0
    negative = dots < 0.0
    anchor = np.maximum.accumulate(np.where(starts | zero, np.arange(rows.size), 0))
    counted = np.cumsum(negative)
    odd = (counted - counted[anchor] + negative[anchor]) % 2 == 1
    kept[rows] = np.where(odd[:, None], -values[rows], values[rows])
    flipped[rows] = np.where((odd != ~zero[anchor])[:, None], -values[rows], values[rows])
    return kept, flipped
