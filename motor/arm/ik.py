"""Analytic arm inverse kinematics with a natural, comfortable, collision-free swivel, vectorized.

Given wrist targets (and optionally global hand rotations), for every frame at once:

1. the clavicle turns the shoulder toward far reaches (seed 000, rule 3);
2. the elbow flexion follows from the law of cosines; a target out of reach is replaced
   by the nearest reachable point on the line from the shoulder (eased short of full
   stretch), and the distance it fell short is reported (:mod:`motor.arm.chain`);
3. the elbow's swivel is either given (the motor control's smooth swivel track,
   :mod:`motor.arm.swivel`) or, for a single posture, the cheapest of
   :data:`CANDIDATES` refined by a parabola. The cost (:func:`swivel_costs`, the same
   one the track minimizes over time) adds to the distance from the natural swivel
   (Soechting & Flanders) the wrist's load — bending as fractions of its limits,
   especially side to side, and any hand rotation the limits leave unachieved, as seed
   000 asks — and the arm's clearance from the body and the other arm
   (:mod:`motor.arm.clearance`);
4. the hand rotation is solved at the same time: forearm twist (pronation) goes to the
   elbow joint, flexion and radial/ulnar deviation to the wrist, each clamped to the
   avatar's limits; what could not be achieved is reported as an angle. Given a
   reference — a nearby instant's twist and what the hand wanted there — the twist is
   the reference's plus the change since, so it never wraps from one limit to the other
   when the hand asks for more than the forearm can give.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from motor import quaternion as quat
from motor.arm.chain import ArmChain, ArmPlacement, ElbowCircle, natural_swivel, place_arm
from motor.arm.clearance import ArmSegments, arm_capsules, arm_segments, clearance
from motor.arm.cheapest_swivel import cheapest_reach, cheapest_swivel
from motor.arm.swivel_cost import CANDIDATES, SWIVEL_STEP, beyond_penalties, body_penalties, candidate_costs, candidate_elbows, wrist_state
from motor.arm.upright_placement import upright_placement
from motor.body.avatar import Avatar
from motor.body.distance import components

#: Swing (radians) between forearm and hand up to which the hand's twist about the
#: forearm is taken as fully defined (:func:`twist_certainty`).
SURE_SWING = np.radians(60.0)


@dataclass(frozen=True, eq=False)
class ArmSolution:
    """The solved arm for ``n`` frames.

    Attributes:
        rotations: ``(n, 4, 4)`` local rotations of sternoclavicular, shoulder, elbow, wrist.
        shoulder, elbow, wrist: ``(n, 3)`` joint positions reached, avatar frame, metres.
        shortfall: ``(n,)`` distance from the reached wrist to the target, metres (0 when
            reachable).
        elbow_flexion: ``(n,)`` radians, 0 = straight.
        swivel: ``(n,)`` swivel angle used, radians.
        orientation_error: ``(n,)`` angle between the requested and the reached hand
            rotation, radians (0 without a hand-rotation target).
        twist: ``(n,)`` forearm twist (pronation) given to the elbow, radians within the
            limits; ``wanted_twist`` the twist the hand asked for, in (-π, π], and
            ``twist_certainty`` how well defined that is, 1 … 0 (:func:`twist_certainty`).
        penetration: ``(n,)`` how deep the upper arm or forearm enters the body's volumes,
            metres (computed when first read); nonzero only where no swivel keeps the arm
            out (e.g. reaching far across the body, which needs the trunk to turn).
    """

    rotations: np.ndarray
    shoulder: np.ndarray
    elbow: np.ndarray
    wrist: np.ndarray
    shortfall: np.ndarray
    elbow_flexion: np.ndarray
    swivel: np.ndarray
    orientation_error: np.ndarray
    twist: np.ndarray
    wanted_twist: np.ndarray
    twist_certainty: np.ndarray
    depth: Callable[[], np.ndarray] = field(repr=False)

    @functools.cached_property
    def penetration(self) -> np.ndarray:
        return self.depth()

    def segments(self, hand_rotations: np.ndarray, avatar: Avatar, side: str) -> ArmSegments:
        """The arm's posed capsules (the obstacles of the other arm)."""
        return arm_segments(arm_capsules(avatar, side), self.shoulder, self.elbow, self.wrist, hand_rotations)


def solve_arm(
    avatar: Avatar,
    side: str,
    wrist_targets: np.ndarray,
    hand_rotations: np.ndarray | None = None,
    swivel: np.ndarray | None = None,
    torso_rotations: np.ndarray | None = None,
    torso_positions: np.ndarray | None = None,
    twist_reference: np.ndarray | None = None,
    other: ArmSegments | None = None,
    swivel_from: np.ndarray | None = None,
) -> ArmSolution:
    """Solve one arm for ``n`` frames at once.

    Args:
        wrist_targets: ``(n, 3)`` wrist positions in the avatar frame (root at origin), metres.
        hand_rotations: ``(n, 4)`` global hand rotations to reach, or None to keep the hand
            in line with the forearm.
        swivel: ``(n,)`` swivel angles (radians) to use instead of the cheapest one.
        torso_rotations: ``(n, 4)`` global rotation of the clavicles' parent joint (the
            upper spine), identity if None; the body's volumes turn with it.
        torso_positions: ``(n, 3)`` global position of that joint, its rest position if None.
        twist_reference: ``(n, 2)`` forearm twist of a nearby instant and the twist the hand
            asked for there (radians): the twist is the reference's plus the change the
            hand asks for since (the shorter way round), within the limits — so it never
            wraps from one limit to the other. None: the hand's twist, the shorter way
            round, within the limits. Two more columns, the wrist's flexion and deviation
            there (radians), make the wrist keep to them as far as the hand's own way is
            undefined (``twist_certainty`` below 1: the hand points far off the forearm,
            where the wrist that comes nearest to it jumps from one limit to the other).
        other: the other arm's capsules at the same instants, which this arm keeps clear
            of (when the swivel is searched, and in ``penetration``'s cost only).
        swivel_from: ``(n, 3)`` directions from which the given ``swivel`` is counted
            instead of the arm's own zero (:func:`swivel_of`): a nearby instant's zero.
    """
    setup = place_arm(avatar, side, wrist_targets, hand_rotations, torso_rotations, torso_positions)
    circle = setup.circle
    if swivel is None:
        psi = cheapest_swivel(avatar, setup, other)
    else:
        psi = np.broadcast_to(np.asarray(swivel, dtype=float), circle.radius.shape).copy()
        if swivel_from is not None:
            psi = psi + swivel_of(np.asarray(swivel_from, dtype=float), circle.down, circle.out)
    arm = _arm_at(setup.chain, circle, psi, setup.sc_global, setup.hands, twist_reference)
    depth = lambda: _body_depth(avatar, setup, arm.elbow)
    return ArmSolution(
        rotations=np.stack((setup.clavicle_local, arm.shoulder_local, arm.elbow_local, arm.wrist_local), axis=1),
        shoulder=circle.shoulder,
        elbow=arm.elbow,
        wrist=circle.wrist,
        shortfall=circle.shortfall,
        elbow_flexion=circle.flexion,
        swivel=psi,
        orientation_error=arm.residual,
        twist=arm.twist,
        wanted_twist=arm.wanted_twist,
        twist_certainty=arm.certainty,
        depth=depth,
    )


class ArmReach(NamedTuple):
    """What a reach check reads of :func:`solve_arm`'s solution, for ``n`` frames: the
    wrist positions reached ``(n, 3)``, how far each falls short of its target and how
    deep the arm enters the body at the cheapest swivel ``(n,)``, metres."""

    wrist: np.ndarray
    shortfall: np.ndarray
    penetration: np.ndarray


def arm_reach(
    avatar: Avatar, side: str, wrist_targets: np.ndarray, hand_rotations: np.ndarray | None = None, with_depth: bool = True
) -> ArmReach:
    """:func:`solve_arm`'s ``wrist``, ``shortfall`` and ``penetration`` (the same numbers)
    without the joint rotations and the hand's twist, which a reach check does not read:
    planning checks a quarter of a million wrist positions of a corpus this way.

    The wrist reached and the shortfall come from the arm's placement alone; only the
    penetration needs the cheapest swivel's search. A check that does not read it passes
    ``with_depth=False``: the search is skipped and ``penetration`` is NaN (not measured)."""
    setup, natural = upright_placement(avatar, side, wrist_targets, hand_rotations)
    if not with_depth:
        return ArmReach(setup.circle.wrist, setup.circle.shortfall, np.full(len(natural), np.nan))
    _, _, depth = cheapest_reach(avatar, setup, natural)
    return ArmReach(setup.circle.wrist, setup.circle.shortfall, depth)


def _body_depth(avatar: Avatar, setup: ArmPlacement, elbow: np.ndarray) -> np.ndarray:
    """How deep (m) the arm placed at ``setup`` with its elbows at ``elbow (n, 3)`` enters the body ``(n,)``."""
    circle = setup.circle
    elbows = tuple(c[:, None] for c in components(elbow))
    return clearance(avatar, setup.chain.side, circle.shoulder, circle.wrist, elbows, setup.body_frame, carried_frames=setup.carried_frames)[1][:, 0]


def swivel_costs(
    avatar: Avatar,
    side: str,
    wrist_targets: np.ndarray,
    hand_rotations: np.ndarray | None = None,
    other: ArmSegments | None = None,
) -> np.ndarray:
    """The cost ``(n, K)`` of every candidate swivel (:data:`CANDIDATES`,
    :mod:`motor.arm.swivel_cost`) at each of ``n`` wrist targets (and hand rotations), the
    other arm's capsules kept clear of."""
    setup = place_arm(avatar, side, wrist_targets, hand_rotations)
    natural = natural_swivel(setup.chain, setup.circle, setup.targets, setup.torso_q)
    return candidate_costs(avatar, setup, natural, other)


@dataclass(frozen=True, eq=False)
class TrackCosts:
    """A swivel track's view of ``m`` consecutive instants (:func:`track_costs`).

    Attributes:
        costs: ``(m, K)`` costs of the candidates (:data:`CANDIDATES`).
        turns: ``(m,)`` radians: how far the swivel's zero turned since the instant before
            (:func:`swivel_of`): an elbow that keeps its place as well as the moving circle
            allows changes its swivel by this much.
        zeros: ``(m, 3)`` direction of swivel 0 at each instant.
        placement, natural: the arm's placement and natural swivel there.
    """

    costs: np.ndarray
    turns: np.ndarray
    zeros: np.ndarray
    placement: ArmPlacement
    natural: np.ndarray

    def pose(self, swivels: np.ndarray) -> tuple[np.ndarray, ...]:
        """At the first ``n`` instants with the given ``swivels (n,)``: the elbow positions
        ``(n, 3)``, the forearm twist the hand asks for (radians, in (-π, π]), how well
        defined it is (:func:`twist_certainty`'s 1 … 0) and the wrist's flexion and
        deviation within their limits (radians) — as :func:`solve_arm` gives them where
        the twist is within its limits, from vectors alone."""
        rows = self.placement.take(np.arange(len(swivels)))
        chain = rows.chain
        elbow, radial = candidate_elbows(rows, np.cos(swivels)[:, None], np.sin(swivels)[:, None])
        flexion, deviation, twist, swing = (value[:, 0] for value in wrist_state(rows, elbow, radial))
        return (
            np.stack([c[:, 0] for c in elbow], axis=1),
            twist,
            np.minimum(np.maximum(2.0 - swing / SURE_SWING, 0.0), 1.0),
            np.minimum(np.maximum(flexion, chain.wrist_flexion[0]), chain.wrist_flexion[1]),
            np.minimum(np.maximum(deviation, chain.wrist_deviation[0]), chain.wrist_deviation[1]),
        )

    def segments(self, avatar: Avatar, side: str, elbow: np.ndarray) -> ArmSegments:
        """The arm's capsules at the first ``n`` instants, elbows at ``elbow (n, 3)``."""
        rows = self.placement.take(np.arange(len(elbow)))
        return arm_segments(arm_capsules(avatar, side), rows.circle.shoulder, elbow, rows.circle.wrist, rows.hands)

    def near_other(self, avatar: Avatar, other: ArmSegments) -> np.ndarray:
        """The costs ``(n, K)`` of keeping clear of the other arm's capsules at the first
        ``n`` instants (``other``'s length), alone."""
        rows = np.arange(len(other.upper[0]))
        return candidate_costs(avatar, self.placement.take(rows), self.natural[rows], other, own=False)


def track_costs(
    avatar: Avatar,
    side: str,
    wrist_targets: np.ndarray,
    hand_rotations: np.ndarray,
    trunk_yaw: np.ndarray | None = None,
    midway: tuple[np.ndarray, np.ndarray, np.ndarray | None] | None = None,
) -> TrackCosts:
    """Swivel costs at ``m`` consecutive instants for a track, from wrist targets and hand
    rotations ``(m + 1, ...)`` that include the instant before (for the first turn of the
    swivel's zero), given in the frame of the trunk turned by ``trunk_yaw`` ``(m + 1,)``
    (radians, None: not turned). Runs of identical instants are measured once. The
    candidates beyond the window pay for going into the body too
    (:func:`motor.arm.swivel_cost.beyond_penalties`): the track may be carried there.

    ``midway``: the wrist targets, hand rotations and trunk yaw half way from each of
    those instants to the next ``(m + 1, ...)``. A candidate then pays the clearance
    penalty of the deeper of its instant and the two half-way ones around it, its elbow
    held there (:func:`midway_penalties`): a fast stroke can take the arm deeper into
    the body between two instants than at either."""
    placement, natural = _placed(avatar, side, wrist_targets, hand_rotations, trunk_yaw)
    circle = placement.circle
    turns = swivel_of(circle.down[:-1], circle.down[1:], circle.out[1:])
    rows = placement.take(slice(1, None))
    natural = natural[1:]
    keys = [rows.targets, rows.hands] + ([] if trunk_yaw is None else [np.asarray(trunk_yaw, dtype=float)[1:, None]])
    nearby = None
    if midway is not None:
        nearby = midway_penalties(avatar, side, placement, *midway, trunk_yaw)
        half = np.concatenate([midway[0], midway[1]] + ([] if midway[2] is None else [np.asarray(midway[2], dtype=float)[:, None]]), axis=1)
        keys += [half[:-1], half[1:]]
    values = np.concatenate(keys, axis=1)
    starts = np.concatenate([[0], np.flatnonzero(np.any(values[1:] != values[:-1], axis=1)) + 1])
    distinct = rows.take(starts)
    unique = candidate_costs(avatar, distinct, natural[starts], nearby=None if nearby is None else nearby[starts])
    unique = unique + beyond_penalties(avatar, distinct, natural[starts])
    costs = np.repeat(unique, np.diff(np.append(starts, len(values))), axis=0)
    return TrackCosts(costs, turns, circle.down[1:], rows, natural)


def midway_penalties(
    avatar: Avatar,
    side: str,
    placement: ArmPlacement,
    targets: np.ndarray,
    hands: np.ndarray,
    trunk_yaw: np.ndarray | None,
    grid_yaw: np.ndarray | None,
) -> np.ndarray:
    """For instants ``1 … m`` of ``placement`` (``m + 1`` instants, the trunk turned by
    ``grid_yaw`` there), each candidate's clearance penalty from the body ``(m, K)`` at
    the half-way instants before and after it (wrist targets ``(m + 1, 3)``, hand
    rotations ``(m + 1, 4)`` and trunk yaw half way after each instant), the deeper of
    the two. The elbow is held where the candidate puts it: carried to the half-way
    instant's circle as :func:`swivel_of` carries it, to the nearest candidate there.
    A half-way instant the same as the instants on either side adds nothing to theirs
    and is not measured (0)."""
    grid = np.concatenate([placement.targets, placement.hands] + ([] if grid_yaw is None else [np.asarray(grid_yaw, dtype=float)[:, None]]), axis=1)
    half = np.concatenate([targets, hands] + ([] if trunk_yaw is None else [np.asarray(trunk_yaw, dtype=float)[:, None]]), axis=1)
    following = np.concatenate([grid[1:], grid[-1:]])
    moving = np.flatnonzero(np.any(half != grid, axis=1) | np.any(half != following, axis=1))
    count = len(CANDIDATES)
    penalties = np.zeros((len(half), count))
    down, out = placement.circle.down.copy(), placement.circle.out.copy()
    if moving.size:
        between, natural = _placed(avatar, side, targets[moving], hands[moving], None if trunk_yaw is None else np.asarray(trunk_yaw, dtype=float)[moving])
        penalties[moving] = body_penalties(avatar, between, natural)
        down[moving], out[moving] = between.circle.down, between.circle.out
    circle = placement.circle
    # an elbow at swivel ψ of instant i is at ψ + forward half way after it, at ψ − back half way before it
    forward = swivel_of(circle.down[1:], down[1:], out[1:])
    back = swivel_of(down[:-1], circle.down[1:], circle.out[1:])
    cells = np.arange(count)[None, :]
    after = np.take_along_axis(penalties[1:], (cells + np.rint(forward / SWIVEL_STEP).astype(np.int64)[:, None]) % count, axis=1)
    before = np.take_along_axis(penalties[:-1], (cells - np.rint(back / SWIVEL_STEP).astype(np.int64)[:, None]) % count, axis=1)
    return np.maximum(before, after)


def swivel_zeros(avatar: Avatar, side: str, wrist_targets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The directions ``(n, 3)`` of swivel 0 and of swivel π/2 for wrist targets ``(n, 3)``
    (the elbow circle's in-plane axes; the zero turns with the arm's elevation,
    :mod:`motor.arm.chain`)."""
    circle = upright_placement(avatar, side, wrist_targets)[0].circle
    return circle.down, circle.out


def _placed(avatar: Avatar, side: str, wrist_targets: np.ndarray, hand_rotations: np.ndarray, trunk_yaw: np.ndarray | None) -> tuple[ArmPlacement, np.ndarray]:
    """The arm placed for wrist targets ``(n, 3)`` and hand rotations ``(n, 4)`` given in
    the frame of the trunk turned by ``trunk_yaw (n,)`` (:func:`motor.arm.chain.place_arm`),
    and the natural swivels there ``(n,)``: by the compiled :func:`upright_placement`
    where the trunk is not turned (the same numbers)."""
    if trunk_yaw is None:
        return upright_placement(avatar, side, wrist_targets, hand_rotations)
    placement = place_arm(avatar, side, wrist_targets, hand_rotations, trunk_yaw=trunk_yaw)
    return placement, natural_swivel(placement.chain, placement.circle, placement.targets, placement.torso_q)


def swivel_of(direction: np.ndarray, zero: np.ndarray, quarter: np.ndarray) -> np.ndarray:
    """The swivel (radians) at which a circle with in-plane axes ``zero``, ``quarter``
    ``(n, 3)`` points nearest ``direction (n, 3)``: carrying an elbow direction from one
    circle to the next this way keeps the elbow where it was as well as the circle allows."""
    return np.arctan2(_dot(direction, quarter), _dot(direction, zero))


@dataclass(frozen=True, eq=False)
class _Arm:
    elbow: np.ndarray
    shoulder_local: np.ndarray
    elbow_local: np.ndarray
    wrist_local: np.ndarray
    residual: np.ndarray
    twist: np.ndarray
    wanted_twist: np.ndarray
    certainty: np.ndarray


def _arm_at(
    chain: ArmChain, circle: ElbowCircle, psi: np.ndarray, sc_global: np.ndarray, hands: np.ndarray | None, reference: np.ndarray | None
) -> _Arm:
    """Joint rotations of the arm at swivel ``psi (n,)``."""
    radial = circle.direction(psi)
    elbow = circle.elbow(psi, radial)
    upper_dir = quat.normalize(elbow - circle.shoulder)
    hinge = quat.normalize(quat.cross(radial, circle.axis))
    rest = np.stack((chain.upper_rest, chain.hinge_rest, quat.cross(chain.upper_rest, chain.hinge_rest)), axis=-1)
    target = np.stack((upper_dir, hinge, quat.cross(upper_dir, hinge)), axis=-1)
    shoulder_global = quat.from_frames(rest, target)
    shoulder_local = quat.multiply(quat.conjugate(sc_global), shoulder_global)
    bend = quat.from_axis_angle(chain.hinge_rest, circle.flexion)
    forearm = quat.multiply(shoulder_global, bend)
    zeros = np.zeros(psi.shape)
    if hands is None:
        identity = np.broadcast_to(quat.IDENTITY, psi.shape + (4,))
        return _Arm(elbow, shoulder_local, bend, identity.copy(), zeros, zeros, zeros, np.ones(psi.shape))
    relative = quat.multiply(quat.conjugate(forearm), hands)
    swing, negative_twist = quat.swing_twist(quat.conjugate(relative), chain.pronation_axis)
    wanted = -negative_twist
    certainty = twist_certainty(swing)
    twist = np.minimum(np.maximum(wanted, chain.twist_range[0]), chain.twist_range[1])
    if reference is not None:
        # the reference's twist, plus the change the hand asks for since the reference
        # (none where the hand points so far off the forearm that its twist means little)
        reference = np.asarray(reference, dtype=float)
        more = (wanted - reference[:, 1] + np.pi) % (2.0 * np.pi) - np.pi
        twist = np.minimum(np.maximum(reference[:, 0] + certainty * more, chain.twist_range[0]), chain.twist_range[1])
    elbow_local = quat.multiply(bend, quat.from_axis_angle(chain.pronation_axis, twist))
    rest_of_hand = quat.multiply(quat.conjugate(quat.multiply(shoulder_global, elbow_local)), hands)
    swing, _ = quat.swing_twist(rest_of_hand, chain.pronation_axis)
    rotvec = quat.to_rotation_vector(swing)
    flexion = np.minimum(np.maximum(_dot(rotvec, chain.flexion_axis), chain.wrist_flexion[0]), chain.wrist_flexion[1])
    deviation = np.minimum(np.maximum(_dot(rotvec, chain.deviation_axis), chain.wrist_deviation[0]), chain.wrist_deviation[1])
    if reference is not None and reference.shape[1] == 4:
        # the wrist, too, keeps to its reference where the hand's way is undefined
        flexion = reference[:, 2] + certainty * (flexion - reference[:, 2])
        deviation = reference[:, 3] + certainty * (deviation - reference[:, 3])
    wrist_local = quat.from_rotation_vector(flexion[..., None] * chain.flexion_axis + deviation[..., None] * chain.deviation_axis)
    reached = quat.multiply(quat.multiply(shoulder_global, elbow_local), wrist_local)
    residual = quat.angle_between(reached, hands)
    return _Arm(elbow, shoulder_local, elbow_local, wrist_local, residual, twist, wanted, certainty)


def twist_certainty(swing: np.ndarray) -> np.ndarray:
    """How well the hand's twist about the forearm is defined, 1 … 0, from the swing
    ``(n, 4)`` that takes the forearm's axis onto the hand's: fully up to
    :data:`SURE_SWING`, not at all from twice that on (at a half-turn swing the twist is
    undefined: any tiny change of the hand turns it around)."""
    angle = 2.0 * np.arccos(np.minimum(np.maximum(np.abs(swing[..., 3]), 0.0), 1.0))
    return np.minimum(np.maximum(2.0 - angle / SURE_SWING, 0.0), 1.0)


def _dot(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Dot products over the last axis, element by element (the same rounding whatever
    the batch: frames must not depend on how many are computed at once)."""
    return u[..., 0] * v[..., 0] + u[..., 1] * v[..., 1] + u[..., 2] * v[..., 2]
