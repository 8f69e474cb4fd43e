"""Signs realized by the motor core: SiGML/HamNoSys signs in a row → :class:`Motion`.

Each sign is planned on its own clock (:func:`motor.signing.planning.plan_sign`) and placed
on the utterance clock one after the other: the avatar stands in its ``rest`` posture for
:data:`REST_LEAD` seconds, each sign begins with a *transition* from wherever the hands
are to its first posture — lax, or targetted into a static sign (seed 000, 4.5) — lasting
the longer of :func:`motor.trajectory.biocontrol.movement_duration` and Fitts' law for the distance
the wrists travel, then performs its moves; after the last sign the hands return to rest
along the lax profile in :func:`motor.program.gesture.retraction_duration` and stay there for
:data:`REST_TAIL` seconds. A hand a sign does not use goes back to rest during that sign.

The wrist paths of every transition and move of the sequence are worked out first
(:func:`prepare_signs`: the transitions kept clear of the body and in reach, timed, traced
in one batch by :mod:`motor.signing.path_batch`, for many sequences at once when a corpus
is rendered sign by sign) and handed to the sign LMPs
(:class:`motor.signing.lmp.SignChannelLMP`, one per channel of each arm and sign),
activated on :class:`motor.control.MotorControl`, which samples them and solves
both arms (analytic IK with a smooth swivel track that keeps the arms clear of the body
and of each other, :mod:`motor.control`) and hands for every frame. Each sign's
non-manual tiers (head, eye gaze, torso, shoulders, eyebrows, eyelids, nose, mouth
gestures and mouth pictures) are activated with it, timed by its transition and movement
(:mod:`motor.signing.nonmanual`), so the motion carries the head and eyes and the face's
morph weights too.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from functools import cache

import numpy as np

from motor import quaternion as quat
from motor.arm.hand_turn import takes_long_way, turn_ways
from motor.body.avatar import Avatar
from motor.body.conventions import ARMS, AVATAR_SIDE
from motor.body.collision import joint_placement, posed_capsule, to_rest
from motor.body.distance import capsule_distance
from motor.body.kinematics import Pose, forward_kinematics
from motor.control import MotorControl
from motor.motion import Motion
from motor.program.gesture import rest_handshape, retraction_duration
from motor.program.lmp import LMP, TimePegs
from motor.signing.collector import collector_paused
from motor.signing.lmp import PATH_DENSITY, Move, SignChannelLMP, TracedChain
from motor.signing.nonmanual import plan_nonmanuals
from motor.signing.path_batch import stopping_lengths, trace_chains
from motor.signing.plan import HandPose, SignPlan
from motor.signing.planning import plan_sign
from motor.signing.reach import clear_paths
from motor.signing.retiming import timing_lengths
from motor.trajectory.biocontrol import movement_duration, shortest_duration
from motor.trajectory.spline import fitts_duration
from mura.signs import Sign

#: Standing at rest before the first sign and after the last, seconds.
REST_LEAD = 0.3
REST_TAIL = 0.3
#: Spacing (m) and least number of the interior points of a transition's wrist path,
#: which are checked against the torso and the arm's reach.
TRANSITION_SPACING = 0.03
MIN_TRANSITION_POINTS = 4
#: Interior keys of a hand turning the long way round (:mod:`motor.arm.hand_turn`) where
#: its wrist gives no way points to turn along: each step then stays below half a turn.
LONG_WAY_KEYS = 3
#: Channels of one arm that a sign drives.
CHANNELS: tuple[str, ...] = ("wrist_position", "hand_rotation", "handshape")


@dataclass(frozen=True)
class SignTiming:
    """When a sign happens on the utterance clock, seconds: its transition starts at
    ``start``, its first posture is reached at ``ready`` and its movement ends at ``end``."""

    gloss: str
    start: float
    ready: float
    end: float
    nonmanual: tuple[str, ...] = ()


@dataclass(frozen=True, eq=False)
class SignedMotion:
    """Signs realized as a :class:`Motion`, with their timing and what planning noted."""

    motion: Motion
    timings: tuple[SignTiming, ...]
    warnings: tuple[str, ...]
    control: MotorControl = field(repr=False)

    @property
    def duration(self) -> float:
        return self.motion.duration


@dataclass(frozen=True, eq=False)
class SignProgram:
    """The LMPs of one sign, in the form :meth:`MotorControl.activate` takes."""

    behavior: str
    lmps: tuple[LMP, ...]


def realize_signs(avatar: Avatar, signs: Iterable[Sign | SignPlan], fps: float = 25.0) -> SignedMotion:
    """Signs (or their plans) one after another as one motion at ``fps`` frames/s; the
    garbage collector waits meanwhile (:mod:`motor.signing.collector`).

    Raises :class:`motor.signing.planning.SignPlanningError` for a sign that cannot be
    planned (plan signs first with :func:`plan_sign` to skip such signs one by one).
    """
    plans = [item if isinstance(item, SignPlan) else plan_sign(avatar, item) for item in signs]
    with collector_paused():
        return _realized(avatar, prepare_signs(avatar, [plans])[0], fps)


@dataclass(frozen=True, eq=False)
class PreparedSigns:
    """Planned signs to realize one after another (:func:`realize_prepared`), with all
    their wrist paths worked out. Per leg (one per sign, then the way back to rest):
    where the hands are before its transition and after it (``legs``), the transition's
    interior wrist points per arm (``ways``, :func:`_transition_ways`), its manner, its
    traced wrist chain per arm (the transition, then the sign's moves:
    :func:`motor.signing.path_batch.trace_chains`) and the hand's turns
    (:func:`_hand_turns`); per sign, when its transition starts, its first posture is
    reached and it ends (``spans``, seconds; last, the retraction: start, arrival,
    arrival), and its moves on that clock."""

    plans: tuple[SignPlan, ...]
    legs: tuple[tuple[dict[str, HandPose], dict[str, HandPose]], ...]
    ways: tuple[dict[str, np.ndarray], ...]
    manners: tuple[str, ...]
    spans: tuple[tuple[float, float, float], ...]
    moves: tuple[dict[tuple[str, str], tuple[Move, ...]], ...]
    traced: tuple[dict[str, TracedChain], ...]
    turns: tuple[dict[str, tuple[np.ndarray | None, np.ndarray | None]], ...]


def prepare_signs(avatar: Avatar, sequences: Sequence[Sequence[SignPlan]]) -> list[PreparedSigns]:
    """Each sequence of planned signs with its wrist paths worked out, those of all the
    sequences in one batch per step: the transitions' ways kept outside the torso and
    within reach, the paths' stopping and timing lengths, the chains traced, the hands'
    turns. Every step works path by path, so each sequence gets, bit for bit, what it gets
    alone; a corpus rendered sign by sign shares the steps' fixed cost (transition ways
    of signs in sixteens: 7.0 → 1.6 ms a sign)."""
    rest = {arm: _rest_pose(avatar, arm) for arm in ARMS}
    legs = [_legs(plans, rest) for plans in sequences]
    flat_ways = _transition_ways(avatar, [leg for own in legs for leg in own])
    leg_ways = iter(flat_ways)
    ways = [[next(leg_ways) for _ in own] for own in legs]
    paths = [[{arm: _way_path(before[arm], after[arm], way[arm]) for arm in ARMS} for (before, after), way in zip(own, own_ways)] for own, own_ways in zip(legs, ways)]
    stopping = iter(stopping_lengths([leg[arm] for own in paths for leg in own[:-1] for arm in ARMS]))
    last = iter(timing_lengths([own[-1][arm] for own in paths for arm in ARMS]))
    manners = [["targetted" if plan.static else "lax" for plan in plans] + ["lax"] for plans in sequences]
    spans = [_spans(plans, own, stopping, [next(last) for _ in ARMS], kinds) for plans, own, kinds in zip(sequences, legs, manners)]
    moves = [
        [{(arm, channel): tuple(m.shifted(ready) for m in plan.moves.get((arm, channel), ())) for arm in ARMS for channel in CHANNELS}
         for plan, (_, ready, _) in zip(plans, times)]
        for plans, times in zip(sequences, spans)
    ]  # fmt: skip
    # every wrist transition and move of every sequence traced in one batch (motor.signing.path_batch)
    chains = iter(trace_chains(
        [(start, ready, manner, leg[arm]) for times, kinds, own in zip(spans, manners, paths)
         for (start, ready, _), manner, leg in zip(times, kinds, own) for arm in ARMS],
        [sign.get((arm, "wrist_position"), ()) for signs in moves for sign in [*signs, {}] for arm in ARMS],
    ))  # fmt: skip
    traced = [[{arm: next(chains) for arm in ARMS} for _ in own] for own in legs]
    flat_turns = iter(_hand_turns(avatar, [leg for own in legs for leg in own], flat_ways, [chain for own in traced for chain in own]))
    return [
        PreparedSigns(tuple(plans), tuple(own), tuple(way), tuple(kinds), tuple(times), tuple(signs), tuple(chain), tuple(next(flat_turns) for _ in own))
        for plans, own, way, kinds, times, signs, chain in zip(sequences, legs, ways, manners, spans, moves, traced)
    ]  # fmt: skip


def realize_prepared(avatar: Avatar, prepared: PreparedSigns, fps: float = 25.0) -> SignedMotion:
    """:func:`realize_signs` of signs prepared by :func:`prepare_signs`: the same motion."""
    with collector_paused():
        return _realized(avatar, prepared, fps)


def _realized(avatar: Avatar, prepared: PreparedSigns, fps: float) -> SignedMotion:
    """:func:`realize_signs` of prepared signs: their LMPs activated and their frames made."""
    control = MotorControl(avatar, fps)
    plans, legs, ways, spans, manners, moves, traced, turns = (
        prepared.plans, prepared.legs, prepared.ways, prepared.spans, prepared.manners, prepared.moves, prepared.traced, prepared.turns
    )  # fmt: skip
    rest = legs[-1][1]
    clock, back = spans[-1][0], spans[-1][1] - spans[-1][0]
    timings: list[SignTiming] = []
    warnings: list[str] = []
    for plan, (_, targets), way, chain, turn, (start, ready, end), manner, sign in zip(plans, legs, ways, traced, turns, spans, manners, moves):
        pegs = TimePegs(start, ready, ready, ready + 0.5 * plan.duration, end, end, end)
        lmps = [
            SignChannelLMP(
                (arm, channel), pegs, targets[arm].channel(channel), sign[(arm, channel)], manner,
                *_transition_keys(channel, way[arm], chain[arm], turn[arm]),
            )
            for arm in ARMS for channel in CHANNELS
        ]  # fmt: skip
        nonmanual = plan_nonmanuals(avatar, plan.gloss, plan.nonmanual, start, ready, end, control.palm_centres)
        control.activate(SignProgram(plan.gloss, (*lmps, *nonmanual.lmps)))
        timings.append(SignTiming(plan.gloss, start, ready, end, tuple(sorted(plan.nonmanual))))
        warnings.extend(plan.warnings)
        warnings.extend(nonmanual.warnings)
    retract = TimePegs.movement(clock, clock + back)
    control.activate(SignProgram("rest", tuple(
        SignChannelLMP(
            (arm, channel), retract, rest[arm].channel(channel), (), "lax",
            *_transition_keys(channel, ways[-1][arm], traced[-1][arm], turns[-1][arm]),
        )
        for arm in ARMS for channel in CHANNELS
    )))  # fmt: skip
    motion = control.frames(0.0, clock + back + REST_TAIL)
    return SignedMotion(motion, tuple(timings), tuple(warnings), control)


def _legs(plans: Sequence[SignPlan], rest: dict[str, HandPose]) -> list[tuple[dict[str, HandPose], dict[str, HandPose]]]:
    """Per sign, where the hands are before its transition and its first postures (a hand
    the sign does not use goes to rest); and last, from the last sign back to ``rest``."""
    here = dict(rest)
    legs = []
    for plan in plans:
        targets = {arm: plan.first.get(arm, rest[arm]) for arm in ARMS}
        legs.append((dict(here), targets))
        here = {arm: _last_pose(plan, arm, targets[arm]) for arm in ARMS}
    legs.append((dict(here), rest))
    return legs


def _spans(
    plans: Sequence[SignPlan],
    legs: Sequence[tuple[dict[str, HandPose], dict[str, HandPose]]],
    stopping: Iterator[float],
    last: Sequence[float],
    manners: Sequence[str],
) -> list[tuple[float, float, float]]:
    """Per sign, when its transition starts, when its first posture is reached and when it
    ends (seconds), one after another from :data:`REST_LEAD`; and last, the retraction to
    rest (start, arrival, arrival). The transitions, in their ``manners``, take their
    times from the ``stopping`` lengths of their wrist paths, arm by arm
    (:func:`_transition_time`; :func:`motor.signing.path_batch.stopping_lengths`); the
    retraction takes at least what its way, travelled in law time, needs within the lax
    budget (its ``last`` timing lengths per arm,
    :func:`motor.signing.retiming.timing_lengths`: a way around the body from behind the
    head is long and bent)."""
    clock = REST_LEAD
    spans = []
    for plan, (before, targets), manner in zip(plans, legs, manners):
        ready = clock + _transition_time(before, targets, [next(stopping) for _ in ARMS], manner)
        spans.append((clock, ready, ready + plan.duration))
        clock = ready + plan.duration
    before, rest = legs[-1]
    back = max(retraction_duration(float(np.linalg.norm(before[arm].wrist - rest[arm].wrist))) for arm in ARMS)
    back = max(back, max(shortest_duration(length, "lax") for length in last))
    spans.append((clock, clock + back, clock + back))
    return spans


def _rest_pose(avatar: Avatar, arm: str) -> HandPose:
    posture = avatar.postures["rest"][AVATAR_SIDE[arm]]
    return HandPose(np.asarray(posture.wrist, dtype=float), np.asarray(posture.hand_rotation, dtype=float), rest_handshape())


def _last_pose(plan: SignPlan, arm: str, first: HandPose) -> HandPose:
    values = {}
    for channel in CHANNELS:
        moves = plan.moves.get((arm, channel), ())
        values[channel] = moves[-1].values[-1] if moves else first.channel(channel)
    return HandPose(values["wrist_position"], values["hand_rotation"], values["handshape"])


def _transition_ways(
    avatar: Avatar, legs: Sequence[tuple[dict[str, HandPose], dict[str, HandPose]]]
) -> list[dict[str, np.ndarray]]:
    """Interior points of every straight wrist transition, one every
    :data:`TRANSITION_SPACING` metres, kept outside the torso and within reach
    (:func:`motor.signing.planning.clear_paths`; a transition is not a path the sign chose)."""
    ways: list[dict[str, np.ndarray]] = [{} for _ in legs]
    for arm in ARMS:
        starts = np.array([before[arm].wrist for before, _ in legs])
        steps = np.array([after[arm].wrist for _, after in legs]) - starts
        distances = [float(np.linalg.norm(step)) for step in steps]
        counts = np.array([max(MIN_TRANSITION_POINTS, int(np.ceil(distance / TRANSITION_SPACING))) + 2 for distance in distances])
        fractions = np.concatenate([_even_fractions(int(count)) for count in counts])
        leg = np.repeat(np.arange(len(legs)), counts)
        points = starts[leg] + fractions[:, None] * steps[leg]
        # the hand's turn between the leg's two rotations (the way _transition_keys turns it)
        turns = turn_ways(
            avatar, AVATAR_SIDE[arm], [before[arm].rotation for before, _ in legs], [after[arm].rotation for _, after in legs], [_even_fractions(int(count)) for count in counts]
        )
        split = np.cumsum(counts)[:-1]
        cleared, _ = clear_paths(avatar, arm, np.split(points, split), np.split(turns, split), keep_ends=True, across=False)
        for way, path in zip(ways, cleared):
            way[arm] = path[1:-1]
    return ways


def _transition_keys(
    channel: str, way: np.ndarray, traced: TracedChain, turn: tuple[np.ndarray | None, np.ndarray | None]
) -> tuple[np.ndarray | None, TracedChain | None, np.ndarray | None]:
    """The ``via``, ``traced`` and ``via_fractions`` of one channel's transition: the wrist
    passes its way points (along its traced chain), the hand turns through ``turn``
    (:func:`_hand_turns`), the hand shape changes evenly."""
    if channel == "wrist_position":
        return way, traced, None
    if channel == "hand_rotation":
        return turn[0], None, turn[1]
    return None, None, None


def _hand_turns(
    avatar: Avatar, legs: Sequence[tuple[dict[str, HandPose], dict[str, HandPose]]], ways: Sequence[dict[str, np.ndarray]], traced: Sequence[dict[str, TracedChain]]
) -> list[dict[str, tuple[np.ndarray | None, np.ndarray | None]]]:
    """Per leg and arm, the hand rotations the hand turns through in the transition and
    the fractions of the way at which it reaches them (None, None: it turns as a slerp
    between the two ends). The hand turns through the turns its way was kept clear of
    the torso with (:func:`_transition_ways`: the hand's turn between the two postures,
    :func:`motor.arm.hand_turn.turn_way`, at the way points' even fractions), each reached
    when the wrist reaches its way point (:func:`_way_fractions`); a way whose wrist stops
    on the way (a reversal) or whose points the trace merged changes evenly — a hand
    turning the long way round then through :data:`LONG_WAY_KEYS` keys, as a slerp
    between the two ends would take the short way. The turns of all legs are computed
    together, per arm (:func:`motor.arm.hand_turn.turn_ways`)."""
    turns: list[dict[str, tuple[np.ndarray | None, np.ndarray | None]]] = [{} for _ in legs]
    for arm in ARMS:
        side = AVATAR_SIDE[arm]
        asked = []  # (leg, the turn's fractions, the way's fractions)
        for index, ((before, after), way, chain) in enumerate(zip(legs, ways, traced)):
            points = way[arm].shape[0]
            fractions = None if points == 0 else _way_fractions(chain[arm], points)
            if fractions is not None:
                asked.append((index, _even_fractions(points + 2)[1:-1], fractions))
            elif takes_long_way(avatar, side, before[arm].rotation, after[arm].rotation):
                asked.append((index, _even_fractions(LONG_WAY_KEYS + 2)[1:-1], None))
            else:
                turns[index][arm] = (None, None)
        rows = turn_ways(
            avatar, side, [legs[index][0][arm].rotation for index, _, _ in asked], [legs[index][1][arm].rotation for index, _, _ in asked], [part for _, part, _ in asked]
        )
        for (index, _, fractions), turn in zip(asked, np.split(rows, np.cumsum([len(part) for _, part, _ in asked])[:-1])):
            turns[index][arm] = (turn, fractions)
    return turns


def _way_fractions(traced: TracedChain, count: int) -> np.ndarray | None:
    """Fractions of the transition's way (its law time, as the wrist travels it) at which
    the wrist passes the ``count`` interior way points; None unless the transition is
    one piece traced :data:`motor.signing.lmp.PATH_DENSITY` points per chord (no
    reversal, no way point dropped), or if the fractions do not rise strictly."""
    # a transition split at a reversal begins with a piece through fewer way points
    if not traced.values or traced.values[0].shape[0] != 1 + PATH_DENSITY * (count + 1):
        return None
    fractions = traced.fractions[0][PATH_DENSITY : PATH_DENSITY * (count + 1) : PATH_DENSITY]
    if fractions.shape != (count,) or not (np.all(np.diff(fractions) > 0.0) and fractions[0] > 0.0 and fractions[-1] < 1.0):
        return None
    return fractions


def _way_path(before: HandPose, after: HandPose, way: np.ndarray) -> np.ndarray:
    """A wrist transition's path ``(k + 2, 3)``: from ``before`` through ``way`` to ``after``."""
    return np.concatenate([before.wrist[None], way.reshape(-1, 3), after.wrist[None]])


@cache
def _even_fractions(count: int) -> np.ndarray:
    """``count`` evenly spaced fractions from 0 to 1 (read-only, shared)."""
    fractions = np.linspace(0.0, 1.0, count)
    fractions.flags.writeable = False
    return fractions


def _transition_time(here: dict[str, HandPose], targets: dict[str, HandPose], stopping: Sequence[float], manner: str) -> float:
    """Lax straight movement time, or Fitts' law for the farthest wrist, or the least time
    the wrists' ways need within the speed budget of ``manner`` (their ``stopping``
    lengths, metres: :func:`motor.signing.lmp.stopping_length`), whichever is longest."""
    distance = max(float(np.linalg.norm(targets[arm].wrist - here[arm].wrist)) for arm in ARMS)
    budgeted = max(shortest_duration(length, manner) for length in stopping)
    return max(movement_duration("straight", "lax"), float(fitts_duration(distance)), budgeted)


@dataclass(frozen=True)
class MotionCheck:
    """Body checks of a rendered motion.

    Attributes:
        frames: frames checked.
        non_finite: frames with a NaN or infinite rotation.
        max_shortfall: largest distance (m) between a wrist reached (forward kinematics)
            and the wrist position the sign asked for.
        max_upper_arm_depth: deepest overlap (m) of either upper arm's capsule with the
            trunk's volumes as posed (:func:`upper_arm_depths`).
    """

    frames: int
    non_finite: int
    max_shortfall: float
    max_upper_arm_depth: float


def upper_arm_depths(avatar: Avatar, pose: Pose) -> dict[str, np.ndarray]:
    """Per arm, per frame of ``pose`` (forward kinematics' global joint poses): how deep
    (m) the upper arm's capsule (the avatar's collision volume, posed) is inside the
    trunk's volumes (a torso, and a chest where the avatar has one), each where its joint
    carries it — the trunk turns toward a hand reaching across the body, and the volumes
    with it; 0 outside. The depth is the signed distance's
    (:func:`motor.body.distance.capsule_distance`), which the swivel search keeps within
    a few millimetres where arms merely touch."""
    placed = lambda joint: joint_placement(avatar, pose.positions, pose.orientations, joint)
    trunk = [(volume, placed(volume.joint)) for volume in avatar.collision.trunk()]
    depths = {}
    for arm in ARMS:
        upper = avatar.collision.arm(AVATAR_SIDE[arm], "upper_arm")
        ends = posed_capsule(upper, *placed(upper.joint))
        depth = np.zeros(pose.positions.shape[0])
        for volume, placement in trunk:
            a, b = (to_rest(*placement, end) for end in ends)
            depth = np.maximum(depth, -capsule_distance(volume, a, b, upper.radius))
        depths[arm] = depth
    return depths


def frame_faults(avatar: Avatar, signed: SignedMotion) -> dict[str, np.ndarray]:
    """Per frame: ``non_finite`` (bool), ``shortfall`` (m between the wrist reached by
    forward kinematics and the wrist the arm was given — the sign's, kept out of the torso
    and the hands a palm thickness apart — worse arm) and ``upper_arm_depth`` (m,
    worse arm, see :func:`upper_arm_depths`)."""
    motion = signed.motion
    finite = np.all(np.isfinite(motion.rotations), axis=(1, 2))
    pose = forward_kinematics(avatar, np.where(np.isfinite(motion.rotations), motion.rotations, quat.IDENTITY))
    shortfall = np.zeros(motion.frame_count)
    asked = signed.control.wrist_targets(motion.times)
    for arm in ARMS:
        wrist = avatar.arm_joints(AVATAR_SIDE[arm])[3]
        shortfall = np.maximum(shortfall, np.linalg.norm(pose.positions[:, wrist] - asked[arm], axis=1))
    depths = upper_arm_depths(avatar, pose)
    return {"non_finite": ~finite, "shortfall": shortfall, "upper_arm_depth": np.maximum(*depths.values())}


def check_motion(avatar: Avatar, signed: SignedMotion) -> MotionCheck:
    """NaN, reach and torso checks of every frame, by forward kinematics (no root offset)."""
    faults = frame_faults(avatar, signed)
    return MotionCheck(
        signed.motion.frame_count,
        int(faults["non_finite"].sum()),
        float(np.max(faults["shortfall"], initial=0.0)),
        float(np.max(faults["upper_arm_depth"], initial=0.0)),
    )
