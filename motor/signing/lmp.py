"""Sign LMPs: a hand channel moving through timed moves, each along a manner profile.

Seed 000 (sections 4.5, 4.6) times every movement of a sign by the biocontrol manner
tables and interpolates the posture between its ends: the position linearly *along the
path by distance*, the orientation by slerp, the hand shape by its joint parameters. A
:class:`Move` is one such movement of one channel: its values along the way (a polyline
of positions, a chain of quaternions or of hand-parameter vectors) over ``[start, end]``
seconds, and the manner whose table ``f: [0, 1] → [0, 1]`` maps the time fraction to the
fraction of the way travelled. Between moves the channel holds.

:class:`SignChannelLMP` carries the moves of one channel for one sign and plugs into
:class:`motor.program.lmp.ChannelTimeline` like any LMP: at activation (its ``start`` peg, the end
of the previous sign) it adds the *transition* from wherever the channel is to the
sign's first value, in the transition manner (lax between signs, targetted into a static
sign, seed 000). A channel still moving at activation (a gesture's retraction the sign
takes over) keeps its velocity, faded out by the sign's first posture as the keyframe
LMPs fade theirs (:mod:`motor.program.lmp`).

A wrist path of three or more points is traced along a C² curve rather than the
polyline, so that the hand does not turn a corner at speed (:func:`smooth_path`): a
transition passes through its way points (they keep it clear of the torso) along the
interpolating spline; a sign's move follows the clamped B-spline whose control polygon is
the move's polyline, which starts and ends on it and stays within its convex hull (and so
within the reach the planner checked at the points, where an interpolating curve would
bulge past them). Both are cut at reversals (:data:`REVERSAL_ANGLE`),
where the polyline's corner stays and the hand stops: the move is split there into moves
that each run from rest to rest, each piece taking time ∝ √(its length) so that all
pieces peak at the same acceleration (:func:`stopping_times`). Every move starts and
stops at rest with zero acceleration (the manner profiles,
:mod:`motor.trajectory.biocontrol`), so a reversal is a stop, never a step in velocity.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from functools import cache

import numpy as np
from scipy.interpolate import BSpline
from scipy.ndimage import gaussian_filter1d

from motor import quaternion as quat
from motor.program.lmp import ROTATION_CHANNELS, Channel, ChannelState, Realization, TimePegs, incoming_blend
from motor.trajectory.biocontrol import MANNERS, profile
from motor.trajectory.power_law import EXPONENT, clamped_curvature, path_spline
from motor.trajectory.spline import HOLD_LENGTH, turning_angles

#: Turning angle (radians) at which a wrist path reverses: the hand stops there. Sharper
#: than the utterances' cusp (:data:`motor.trajectory.spline.CUSP_ANGLE`), because a
#: sign's path kept clear of the torso zigzags by up to ~135° between its checked points,
#: which the B-spline within them rounds; a back-and-forth repetition turns by ~180°.
REVERSAL_ANGLE = np.radians(150.0)
#: Arc length (metres, a Gaussian's standard deviation) over which the curvature that
#: times a wrist move is smoothed: the speed cannot change faster than the hand accelerates.
#: At 8 mm a bend entered at 1.5 m/s changed the speed within ~10 ms (steps of the
#: velocity beyond 30 m/s² in 1 of 4 signs); 2 cm halves those and keeps an ellipse's slowing.
LAW_SMOOTHING = 0.02
#: Points per chord with which a wrist path is traced along its spline.
PATH_DENSITY = 12
#: Speed (units of the channel per second) below which an activation state counts as at
#: rest: the differences that estimate a held channel's velocity leave ~1e-12.
STILL = 1e-6
#: Step of the differences that estimate a channel's velocity, seconds.
_STEP = 1e-4
#: A length (m) or a width between keys (channel units) below which it counts as none.
NEGLIGIBLE = 1e-12
_FLOAT64 = np.dtype(np.float64)


@dataclass(frozen=True, eq=False)
class Move:
    """One timed movement of a channel.

    Attributes:
        start, end: seconds (``end > start``).
        manner: a :data:`motor.trajectory.biocontrol.MANNERS` name, the time profile of the move.
        values: ``(m, D)`` values along the way, ``m ≥ 2``: positions of a path (metres,
            travelled by distance), or quaternions / hand parameters at evenly spaced
            fractions of the way.
    """

    start: float
    end: float
    manner: str
    values: np.ndarray

    def __post_init__(self) -> None:
        values = np.asarray(self.values, dtype=float)
        if values.ndim != 2 or values.shape[0] < 2 or not np.isfinite(values).all():  # the method: no wrapper, for 30,000 moves a corpus
            raise ValueError(f"move values must be finite (m ≥ 2, D), got shape {values.shape}")
        _check_span(self.start, self.end)
        profile(self.manner)
        object.__setattr__(self, "values", values)

    @classmethod
    def many(cls, moves: Sequence[tuple[float, float, str, np.ndarray]]) -> list[Move]:
        """The moves ``(start, end, manner, values)`` as the constructor makes them, or the
        constructor's error for the first it refuses; when all of them pass its checks, as
        float arrays, their values are checked finite together (a collection of signs
        makes some 23,000 moves, each check a few numpy calls)."""
        if not _passing(moves):
            return [cls(*move) for move in moves]
        for manner in {manner for _, _, manner, _ in moves}:
            profile(manner)  # computed once, as the constructor would have it
        return [_unchecked(*move) for move in moves]

    def shifted(self, offset: float) -> Move:
        """The same move ``offset`` seconds later (its values, already checked, shared)."""
        moved = _unchecked(self.start + offset, self.end + offset, self.manner, self.values)
        _check_span(moved.start, moved.end)
        return moved


def _unchecked(start: float, end: float, manner: str, values: np.ndarray) -> Move:
    """A :class:`Move` of values its caller has checked, as the constructor would keep them."""
    move = object.__new__(Move)
    move.__dict__.update(start=start, end=end, manner=manner, values=values)
    return move


def _passing(moves: Sequence[tuple[float, float, str, np.ndarray]]) -> bool:
    """Whether each move's values are a float array the constructor keeps as it is and all
    the checks of :meth:`Move.__post_init__` pass."""
    for start, end, manner, values in moves:
        if not (type(values) is np.ndarray and values.dtype == _FLOAT64 and values.ndim == 2 and values.shape[0] >= 2 and end > start and manner in MANNERS):
            return False
    return not moves or bool(np.isfinite(np.concatenate([values for *_, values in moves], axis=None)).all())


def _check_span(start: float, end: float) -> None:
    if not end > start:
        raise ValueError(f"move must end after it starts, got [{start}, {end}]")


def _through(piece: np.ndarray) -> np.ndarray:
    """The interpolating C² spline through ``piece``, densely, without its first point."""
    spline = path_spline(piece)
    fractions = np.linspace(0.0, 1.0, PATH_DENSITY + 1)[1:]
    dense = spline((spline.x[:-1, None] + np.diff(spline.x)[:, None] * fractions).ravel())
    dense[PATH_DENSITY - 1 :: PATH_DENSITY] = piece[1:]
    return dense


def _within(piece: np.ndarray) -> np.ndarray:
    """The clamped B-spline (cubic, quadratic for three points) with control polygon
    ``piece``, densely, without its first point."""
    degree = min(3, piece.shape[0] - 1)
    interior = piece.shape[0] - degree - 1
    knots = np.concatenate([np.zeros(degree + 1), np.arange(1, interior + 1) / (interior + 1), np.ones(degree + 1)])
    curve = BSpline(knots, piece, degree)
    dense = curve(np.linspace(0.0, 1.0, PATH_DENSITY * (piece.shape[0] - 1) + 1)[1:])
    dense[-1] = piece[-1]
    return dense


def smooth_pieces(points: np.ndarray, through: bool) -> list[np.ndarray]:
    """A wrist path ``(m, 3)`` traced densely (:data:`PATH_DENSITY` points per chord) along
    the interpolating spline through its points (``through``) or the B-spline within their
    hull (module docstring), cut at reversals into pieces (each ``(k ≥ 2, 3)``, starting
    where the previous one ends); repeated points are dropped. A path of fewer than three
    distinct points is one piece, as it is."""
    keep = np.concatenate([[True], np.linalg.norm(np.diff(points, axis=0), axis=1) > HOLD_LENGTH])
    p = points[keep]
    if p.shape[0] < 3:
        return [points]
    cuts = np.concatenate([[0], np.flatnonzero(turning_angles(p) >= REVERSAL_ANGLE) + 1, [p.shape[0] - 1]])
    pieces = []
    for first, last in zip(cuts[:-1], cuts[1:]):
        piece = p[first : last + 1]
        traced = piece[1:] if piece.shape[0] < 3 else _through(piece) if through else _within(piece)
        pieces.append(np.concatenate([piece[:1], traced]))
    return pieces


def smooth_path(points: np.ndarray, through: bool) -> np.ndarray:
    """The pieces of :func:`smooth_pieces` joined into one path."""
    pieces = smooth_pieces(points, through)
    return np.concatenate([pieces[0], *(piece[1:] for piece in pieces[1:])])


def stopping_times(lengths: np.ndarray, start: float, end: float) -> np.ndarray:
    """Where a movement over ``[start, end]`` that stops at each reversal of its path (pieces
    of ``lengths`` metres, each from rest to rest in the move's manner) is at rest: the
    ``(k + 1,)`` piece boundaries. Each piece takes time ∝ √length, so every piece peaks at
    the same acceleration (``length / time²`` is the same)."""
    weights = np.sqrt(np.maximum(lengths, 0.0)) + NEGLIGIBLE
    return start + (end - start) * np.concatenate([[0.0], np.cumsum(weights) / weights.sum()])


def stopping_length(points: np.ndarray) -> float:
    """The straight length (metres) a rest-to-rest movement of the same duration and peak
    acceleration would travel as the path ``points`` stopping at each reversal
    (:func:`stopping_times`): ``(Σ √lengthᵢ)²``, the path length when it has no reversal."""
    lengths = [polyline_length(piece) for piece in smooth_pieces(points, through=False)]
    return float(np.sum(np.sqrt(lengths)) ** 2)


def polyline_length(polyline: np.ndarray) -> float:
    """Length (m) of a polyline ``(k, 3)``: its chords' lengths summed, with the arithmetic
    of ``np.linalg.norm(np.diff(polyline, axis=0), axis=1).sum()`` without its wrappers
    (a collection of signs measures thousands)."""
    steps = polyline[1:] - polyline[:-1]
    return float(np.sqrt(np.add.reduce(steps * steps, axis=1)).sum())


def _stopping_at_reversals(move: Move, through: bool) -> list[Move]:
    """A wrist move traced along its smooth path, split where the path reverses into moves
    that each start and stop at rest (a reversal at speed is a step in velocity)."""
    pieces = smooth_pieces(move.values, through)
    lengths = np.array([polyline_length(piece) for piece in pieces])
    times = stopping_times(lengths, move.start, move.end)
    return [replace(move, start=float(a), end=float(b), values=piece) for a, b, piece in zip(times[:-1], times[1:], pieces)]


def law_fractions(points: np.ndarray) -> np.ndarray:
    """Fraction of the *law time* ``τ = ∫ R̃^{−β} ds`` (β = 1/3) at each point of a dense
    path ``(m, 3)``: a move that advances in law time along its manner profile goes at
    speed ∝ R̃^{1/3} — the power law — wherever the profile is flat, and slows into tight
    bends. ``R̃`` is the radius of curvature at each point (turning angle over the mean of
    the adjacent chords), softly clamped (:func:`motor.trajectory.power_law.clamped_curvature`),
    its logarithm smoothed over :data:`LAW_SMOOTHING` metres of arc."""
    chords = np.linalg.norm(np.diff(points, axis=0), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(chords)])
    if arc[-1] < NEGLIGIBLE:
        return np.linspace(0.0, 1.0, points.shape[0])
    curvature = np.zeros(points.shape[0])
    if points.shape[0] > 2:
        spans = np.maximum(0.5 * (chords[:-1] + chords[1:]), NEGLIGIBLE)
        curvature[1:-1] = turning_angles(points) / spans
    curvature[0], curvature[-1] = curvature[min(1, curvature.size - 1)], curvature[max(curvature.size - 2, 0)]
    log_curvature = np.log(clamped_curvature(curvature))
    step = min(LAW_SMOOTHING / 4.0, float(arc[-1]) / 8.0)
    grid = np.linspace(0.0, float(arc[-1]), int(np.ceil(float(arc[-1]) / step)) + 1)
    # on a path much shorter than the smoothing the curvature is flat: a kernel of a few
    # times the grid does the same, where one of LAW_SMOOTHING / step points would not fit in memory
    sigma = min(LAW_SMOOTHING / (grid[1] - grid[0]), 4.0 * grid.size)
    smooth = gaussian_filter1d(np.interp(grid, arc, log_curvature), sigma, mode="nearest")
    density = np.exp(EXPONENT * np.interp(arc, grid, smooth))
    tau = np.concatenate([[0.0], np.cumsum(0.5 * (density[1:] + density[:-1]) * chords)])
    return tau / tau[-1]


def path_fractions(values: np.ndarray, by_distance: bool) -> np.ndarray:
    """Fraction of the way ``(m,)`` at each value: by law time (positions,
    :func:`law_fractions`) or evenly."""
    if not by_distance:
        return np.linspace(0.0, 1.0, values.shape[0])
    return law_fractions(values)


@dataclass(frozen=True, eq=False)
class SignTrack:
    """A realized channel: moves with their profiles, holds between, sampled at once.

    The moves' values are flattened into one array; each value's *key* is
    ``2 · move + fraction of the way`` (strictly increasing), so one ``searchsorted``
    finds every sample's segment in every move. ``manners`` are the moves' rows in
    :func:`manner_tables`.
    """

    rotation: bool
    initial: np.ndarray
    starts: np.ndarray
    ends: np.ndarray
    manners: np.ndarray
    values: np.ndarray
    keys: np.ndarray
    first: np.ndarray
    last: np.ndarray
    warnings: tuple[str, ...] = ()

    @classmethod
    def traced(cls, initial: np.ndarray, chain: TracedChain) -> SignTrack:
        """The wrist track of a chain traced ahead: what :meth:`of` makes of the same moves."""
        return cls.keyed(False, initial, chain.starts, chain.ends, chain.manners, chain.values, chain.fractions)

    @classmethod
    def of(cls, rotation: bool, initial: np.ndarray, moves: list[Move], by_distance: bool) -> SignTrack:
        return cls.keyed(
            rotation, initial, np.array([m.start for m in moves]), np.array([m.end for m in moves]), [m.manner for m in moves],
            [m.values for m in moves], [path_fractions(m.values, by_distance) for m in moves],
        )  # fmt: skip

    @classmethod
    def keyed(
        cls, rotation: bool, initial: np.ndarray, starts: np.ndarray, ends: np.ndarray, manners: Sequence[str],
        values: Sequence[np.ndarray], fractions: Sequence[np.ndarray] | None,
    ) -> SignTrack:  # fmt: skip
        """The track of moves given by their times, manners, values and fractions of the way
        (None: even fractions)."""
        if fractions is None:
            keys, first, last = _even_layout(tuple(v.shape[0] for v in values))
        else:
            keys, first, last = _layout([f.shape[0] for f in fractions], fractions)
        return cls(
            rotation=rotation,
            initial=initial,
            starts=starts,
            ends=ends,
            manners=np.array([MANNER_ROWS[manner] for manner in manners]),
            values=np.concatenate(values),
            keys=keys,
            first=first,
            last=last,
        )

    def sample(self, times: np.ndarray) -> np.ndarray:
        t = np.asarray(times, dtype=float)
        owner = self.starts.searchsorted(t, side="right") - 1
        before = owner < 0
        move = np.maximum(owner, 0)
        start = self.starts[move]
        u = np.minimum(np.maximum((t - start) / (self.ends[move] - start), 0.0), 1.0)
        # the move's time profile, read from its table (linear interpolation)
        tables = manner_tables()
        position = u * (tables.shape[1] - 1)
        low = np.minimum(position.astype(int), tables.shape[1] - 2)
        weight = position - low
        rows = self.manners[move]
        s = (1.0 - weight) * tables[rows, low] + weight * tables[rows, low + 1]
        # the segment of the move's values that fraction s of the way falls in
        wanted = 2.0 * move + s
        index = np.minimum(np.maximum(self.keys.searchsorted(wanted, side="right") - 1, self.first[move]), self.last[move] - 1)
        low_key = self.keys[index]
        width = self.keys[index + 1] - low_key
        local = np.minimum(np.maximum((wanted - low_key) / np.where(width > NEGLIGIBLE, width, 1.0), 0.0), 1.0)
        a, b = self.values[index], self.values[index + 1]
        out = quat.slerp(a, b, local) if self.rotation else a + local[:, None] * (b - a)
        if before.any():
            out[before] = self.initial
        return out

    def state(self, time: float) -> ChannelState:
        """Value and velocity (angular velocity for rotations) looking back from ``time``."""
        return track_state(self, time)


@dataclass(frozen=True, eq=False)
class _Carried:
    """A track plus the velocity it was activated with, faded out over the transition:
    ``v · τ (1 − τ/T)²`` (:func:`motor.program.lmp.incoming_blend`; τ seconds since
    activation, T the transition's length), added to a vector channel and left-multiplied
    as a rotation vector onto a rotation channel. Position and velocity are continuous at
    the activation; the blend and its rate are zero from the sign's first posture on."""

    track: SignTrack
    velocity: np.ndarray
    time: float
    window: float

    @property
    def rotation(self) -> bool:
        return self.track.rotation

    @property
    def warnings(self) -> tuple[str, ...]:
        return self.track.warnings

    def sample(self, times: np.ndarray) -> np.ndarray:
        planned = self.track.sample(times)
        weight, _ = incoming_blend(times, self.time, self.window)
        if self.rotation:
            return quat.multiply(quat.from_rotation_vector(weight[:, None] * self.velocity), planned)
        return planned + weight[:, None] * self.velocity

    def state(self, time: float) -> ChannelState:
        return track_state(self, time)


def track_state(track: Realization, time: float) -> ChannelState:
    """Value and velocity (angular velocity for rotations) of a sign ``track`` (its
    ``rotation`` tells its kind) looking back from ``time``."""
    v = track.sample(np.array([time - 2 * _STEP, time - _STEP, time]))
    if track.rotation:
        one, two = quat.to_rotation_vector(quat.multiply(v[2], quat.conjugate(v[1::-1])))
        velocity = (4.0 * one - two) / (2.0 * _STEP)
    else:
        velocity = (3.0 * v[2] - 4.0 * v[1] + v[0]) / (2.0 * _STEP)
    return ChannelState(v[2], velocity, float(time))


#: Row of each manner in :func:`manner_tables`.
MANNER_ROWS: dict[str, int] = {name: row for row, name in enumerate(MANNERS)}


@cache
def manner_tables() -> np.ndarray:
    """The tables ``f: [0, 1] → [0, 1]`` of every manner (:data:`MANNER_ROWS`), one per row."""
    return np.stack([profile(name).fractions for name in MANNERS])


@dataclass(frozen=True, eq=False)
class TracedChain:
    """A wrist channel's moves as its activation would make them, traced ahead for many
    signs at once (:mod:`motor.signing.path_batch`): the transition from ``here`` starting
    at ``time`` and the sign's moves, each split at reversals, with the law-time fractions
    of their values. Used only when the activation state is exactly ``(here, time)``.

    Attributes:
        time: seconds, the activation the transition was traced from.
        here: ``(3,)`` metres, the wrist position it was traced from.
        starts, ends: ``(k,)`` seconds of each move of the chain.
        manners: the moves' manners.
        values: each move's dense path ``(m, 3)``.
        fractions: each move's fraction of the way at its values ``(m,)``.
    """

    time: float
    here: np.ndarray
    starts: np.ndarray
    ends: np.ndarray
    manners: tuple[str, ...]
    values: tuple[np.ndarray, ...]
    fractions: tuple[np.ndarray, ...]

    def fits(self, here: np.ndarray, time: float) -> bool:
        return time == self.time and np.array_equal(here, self.here)


@dataclass(frozen=True, eq=False)
class SignChannelLMP:
    """The moves of one channel during one sign, after a transition into it.

    Attributes:
        channel: ``(arm, "wrist_position" | "hand_rotation" | "handshape")``.
        pegs: ``start`` = the transition begins, ``ready`` = the sign's first posture is
            reached, ``stroke_start``/``stroke_end`` = the sign's movement, ``end``.
        first: the sign's first value on this channel, reached at ``ready``.
        moves: the sign's moves on the utterance clock, in order, inside
            ``[ready, end]``.
        transition: the manner of the transition.
        via: ``(k, D)`` values the transition passes through on its way (a wrist path
            kept clear of the torso), or None for the direct way.
        traced: the wrist chain traced ahead for the activation state expected, or None;
            any other state is activated the plain way.
        via_fractions: ``(k,)`` fractions of the way, strictly increasing within (0, 1),
            at which a channel moved by even fractions (hand rotation, hand shape) passes
            its ``via`` values — those at which the wrist passes its own way points, so
            that the hand turns along the wrist's transition as the transition was
            planned (kept clear of the torso with these turns) — or None: evenly.
    """

    channel: Channel
    pegs: TimePegs
    first: np.ndarray
    moves: tuple[Move, ...] = ()
    transition: str = "lax"
    via: np.ndarray | None = None
    traced: TracedChain | None = None
    via_fractions: np.ndarray | None = None
    _templates: dict[bool, _Template] = field(default_factory=dict, init=False, repr=False)

    def __post_init__(self) -> None:
        if not self.pegs.ready > self.pegs.start:
            raise ValueError(f"{self.channel}: the transition needs time (start {self.pegs.start}, ready {self.pegs.ready})")
        if self.via_fractions is not None:
            fractions = np.asarray(self.via_fractions, dtype=float)
            count = 0 if self.via is None else np.asarray(self.via).shape[0]
            if fractions.shape != (count,) or not (np.all(np.diff(fractions) > 0.0) and fractions.min(initial=0.5) > 0.0 and fractions.max(initial=0.5) < 1.0):
                raise ValueError(f"{self.channel}: via_fractions must be {count} strictly increasing fractions within (0, 1), got {fractions}")
        previous = self.pegs.ready
        for move in self.moves:
            if move.start < previous - 1e-9:
                raise ValueError(f"{self.channel}: moves overlap or start before ready at {move.start:.4f} s")
            previous = move.end

    def activate(self, state: ChannelState) -> SignTrack | _Carried:
        """The track from ``state``; a channel still moving (a retraction the sign takes
        over) carries its velocity into the transition (:class:`_Carried`), so the hand
        does not stop dead in one frame."""
        track = self.realize(np.asarray(state.value, dtype=float), state.time)
        velocity = np.asarray(state.velocity, dtype=float)
        if np.max(np.abs(velocity), initial=0.0) <= STILL or not self.pegs.ready > state.time:
            return track
        return _Carried(track, velocity, state.time, self.pegs.ready - state.time)

    def realize(self, here: np.ndarray, time: float) -> SignTrack:
        """The track of an activation at ``time`` seconds with the channel at ``here``
        (only the state's value and time matter, not its velocity)."""
        rotation = self.channel[1] in ROTATION_CHANNELS
        if self.traced is not None and self.traced.fits(here, time):
            return SignTrack.traced(here, self.traced)
        first = np.asarray(self.first, dtype=float)
        flip = bool(rotation and here @ first < 0.0)
        if flip:
            first = -first
        by_distance = self.channel[1] == "wrist_position"
        if not by_distance and self.pegs.ready > time and np.isfinite(here).all():
            return self._template(rotation, flip, first).track(here, time)
        way = np.stack([here, first] if self.via is None else [here, *np.asarray(self.via, dtype=float), first])
        transition = Move(time, self.pegs.ready, self.transition, way)
        chain = _stopping_at_reversals(transition, through=True) if by_distance else [transition]
        previous = first
        for move in self.moves:
            if rotation:
                move = replace(move, values=quat.continuous(np.concatenate([previous[None], move.values]))[1:])
            if by_distance:
                chain.extend(_stopping_at_reversals(move, through=False))
            else:
                chain.append(move)
            previous = chain[-1].values[-1]
        if by_distance or self.via_fractions is None:
            return SignTrack.of(rotation, here, chain, by_distance)
        return SignTrack.keyed(
            rotation, here, np.array([m.start for m in chain]), np.array([m.end for m in chain]), [m.manner for m in chain],
            [m.values for m in chain], self._key_fractions(),
        )  # fmt: skip

    def _key_fractions(self) -> list[np.ndarray]:
        """Fractions of the way at the values of the transition (through :attr:`via` at
        :attr:`via_fractions`) and of each move (even)."""
        assert self.via_fractions is not None
        transition = np.concatenate([[0.0], np.asarray(self.via_fractions, dtype=float), [1.0]])
        return [transition, *(even_fractions(m.values.shape[0]) for m in self.moves)]

    def _template(self, rotation: bool, flip: bool, first: np.ndarray) -> _Template:
        """The track of a channel moved by even fractions of its values (hand rotation, hand
        shape) but for where it starts, made once per sign of ``first``: the transition to
        ``first`` (through :attr:`via`), then the moves (rotations kept in the hemisphere of
        the value before them), as the chain of :class:`Move` would make it."""
        templates = self._templates
        if flip not in templates:
            for manner in (self.transition, *(m.manner for m in self.moves)):
                profile(manner)  # an unknown manner: the error a Move gives
            way = np.array([first, first] if self.via is None else [first, *np.asarray(self.via, dtype=float), first])
            values = [way]
            for move in self.moves:
                values.append(quat.continuous(np.concatenate([values[-1][-1:], move.values]))[1:] if rotation else move.values)
            templates[flip] = _Template(SignTrack.keyed(
                rotation, first, np.array([self.pegs.start, *(m.start for m in self.moves)]), np.array([self.pegs.ready, *(m.end for m in self.moves)]),
                [self.transition, *(m.manner for m in self.moves)], values, None if self.via_fractions is None else self._key_fractions(),
            ))  # fmt: skip
        return templates[flip]


@dataclass(frozen=True, eq=False)
class _Template:
    """A keyframe channel's track with the place and time it starts left open."""

    base: SignTrack

    def track(self, here: np.ndarray, time: float) -> SignTrack:
        values = self.base.values.copy()
        values[0] = here
        starts = self.base.starts.copy()
        starts[0] = time
        base = self.base
        return SignTrack(base.rotation, here, starts, base.ends, base.manners, values, base.keys, base.first, base.last, base.warnings)


def _layout(sizes: Sequence[int], fractions: Sequence[np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A track's keys (``2 · move + fraction``) and each move's first and last value."""
    sizes = np.array(sizes)
    first = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    return np.concatenate([2.0 * i + f for i, f in enumerate(fractions)]), first, first + sizes - 1


@cache
def even_fractions(count: int) -> np.ndarray:
    """``count`` even fractions of the way from 0 to 1 (``np.linspace``; read-only, shared)."""
    fractions = np.linspace(0.0, 1.0, count)
    fractions.flags.writeable = False
    return fractions


@cache
def _even_layout(sizes: tuple[int, ...]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_layout` of moves of ``sizes`` values at even fractions (read-only, shared)."""
    arrays = _layout(sizes, [even_fractions(size) for size in sizes])
    for array in arrays:
        array.flags.writeable = False
    return arrays
