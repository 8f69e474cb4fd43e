"""Analytic arm inverse kinematics with a natural, comfortable, collision-free swivel, vectorized.

Given wrist targets (and optionally global hand rotations), for every frame at once:

1. the clavicle turns the shoulder toward far reaches (seed 000, rule 3);
2. the elbow flexion follows from the law of cosines; a target out of reach is replaced
   by the nearest reachable point on the line from the shoulder, and the distance it
   fell short is reported (:mod:`motor.arm.chain`);
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

import numpy as np

from motor import quaternion as quat
from motor.arm.chain import ArmChain, ElbowCircle, arm_chain, clavicle_rotation, natural_swivel
from motor.arm.clearance import ArmSegments, arm_capsules, arm_segments, clearance
from motor.body.avatar import Avatar, check_side

#: Candidate swivels (radians): the whole circle in steps of :data:`SWIVEL_STEP`.
SWIVEL_STEP = np.deg2rad(10.0)
CANDIDATES = np.arange(-np.pi, np.pi - 1e-9, SWIVEL_STEP)
_COS, _SIN = np.cos(CANDIDATES), np.sin(CANDIDATES)
#: Cost weights: distance from the natural swivel (per radian), wrist deviation and
#: flexion as fractions of their limits, unachieved hand rotation (per radian squared,
#: saturating beyond :data:`RESIDUAL_SATURATION` radians: a hand rotation no swivel comes
#: near — e.g. halfway through turning the hand over — does not drag the elbow around).
SWIVEL_SCALE = 0.7
#: Farther than this from the natural swivel (radians) the elbow is forced, e.g. straight
#: up, the shoulder leaves its comfortable range: the cost then grows by
#: :data:`RANGE_WEIGHT` per radian squared beyond it.
SWIVEL_RANGE = np.radians(100.0)
RANGE_WEIGHT = 300.0
DEVIATION_WEIGHT = 1.5
FLEXION_WEIGHT = 0.4
RESIDUAL_WEIGHT = 5000.0
RESIDUAL_SATURATION = 0.25
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


@dataclass(frozen=True, eq=False)
class _Setup:
    """What every solve of the same targets shares: the shoulder girdle and elbow circles."""

    chain: ArmChain
    torso_q: np.ndarray
    clavicle_local: np.ndarray
    sc_global: np.ndarray
    circle: ElbowCircle
    targets: np.ndarray
    hands: np.ndarray | None
    body_frame: tuple[np.ndarray, np.ndarray] | None


def _setup(
    avatar: Avatar,
    side: str,
    wrist_targets: np.ndarray,
    hand_rotations: np.ndarray | None,
    torso_rotations: np.ndarray | None,
    torso_positions: np.ndarray | None,
) -> _Setup:
    chain = arm_chain(avatar, check_side(side))
    targets = np.asarray(wrist_targets, dtype=float).reshape(-1, 3)
    frames = targets.shape[0]
    upright = torso_rotations is None and torso_positions is None
    torso_q = np.broadcast_to(quat.IDENTITY, (frames, 4)) if torso_rotations is None else np.asarray(torso_rotations, float)
    torso_p = np.broadcast_to(chain.torso_joint_rest, (frames, 3)) if torso_positions is None else np.asarray(torso_positions, float)
    hands = None if hand_rotations is None else quat.normalize(np.asarray(hand_rotations, dtype=float).reshape(frames, 4))
    sc_position = torso_p + quat.rotate(torso_q, chain.sc_offset)
    clavicle_local = clavicle_rotation(chain, torso_q, sc_position, targets)
    sc_global = quat.multiply(torso_q, clavicle_local)
    shoulder = sc_position + quat.rotate(sc_global, chain.clavicle)
    body_frame = None if upright else (torso_q, torso_p - quat.rotate(torso_q, chain.torso_joint_rest))
    circle = ElbowCircle.of(chain, shoulder, targets, torso_q)
    return _Setup(chain, torso_q, clavicle_local, sc_global, circle, targets, hands, body_frame)


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
            round, within the limits.
        other: the other arm's capsules at the same instants, which this arm keeps clear
            of (when the swivel is searched, and in ``penetration``'s cost only).
        swivel_from: ``(n, 3)`` directions from which the given ``swivel`` is counted
            instead of the arm's own zero (:func:`swivel_of`): a nearby instant's zero.
    """
    setup = _setup(avatar, side, wrist_targets, hand_rotations, torso_rotations, torso_positions)
    circle = setup.circle
    if swivel is None:
        psi = _cheapest_swivel(avatar, setup, other)
    else:
        psi = np.broadcast_to(np.asarray(swivel, dtype=float), circle.radius.shape).copy()
        if swivel_from is not None:
            psi = psi + swivel_of(np.asarray(swivel_from, dtype=float), circle.down, circle.out)
    arm = _arm_at(setup.chain, circle, psi, setup.sc_global, setup.hands, twist_reference)
    depth = lambda: clearance(avatar, side, circle, arm.elbow[:, None], setup.body_frame)[1][:, 0]
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


def swivel_costs(
    avatar: Avatar,
    side: str,
    wrist_targets: np.ndarray,
    hand_rotations: np.ndarray | None = None,
    other: ArmSegments | None = None,
    offsets: np.ndarray | None = None,
) -> np.ndarray:
    """The cost ``(n, K)`` of every candidate swivel at each of ``n`` wrist targets (and
    hand rotations), the other arm's capsules kept clear of: the candidates are
    :data:`CANDIDATES` turned by ``offsets (n,)`` radians (0 if None)."""
    setup = _setup(avatar, side, wrist_targets, hand_rotations, None, None)
    natural = natural_swivel(setup.chain, setup.circle, setup.targets, setup.torso_q)
    if offsets is None:
        return _cost(avatar, setup, _COS, _SIN, CANDIDATES, natural, other)
    psi = CANDIDATES + np.asarray(offsets, dtype=float)[:, None]
    return _cost(avatar, setup, np.cos(psi), np.sin(psi), psi, natural, other)


def other_arm_costs(
    avatar: Avatar, side: str, wrist_targets: np.ndarray, other: ArmSegments, offsets: np.ndarray | None = None
) -> np.ndarray:
    """The part ``(n, K)`` of :func:`swivel_costs` that keeps clear of the other arm, alone."""
    setup = _setup(avatar, side, wrist_targets, None, None, None)
    circle = setup.circle
    psi = CANDIDATES if offsets is None else CANDIDATES + np.asarray(offsets, dtype=float)[:, None]
    radial = circle.down[:, None, :] * np.cos(psi)[..., None] + circle.out[:, None, :] * np.sin(psi)[..., None]
    elbow = circle.center[:, None, :] + radial * circle.radius[:, None, None]
    return clearance(avatar, side, circle, elbow, None, other, body=False)[0]


def swivel_zeros(avatar: Avatar, side: str, wrist_targets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The directions ``(n, 3)`` of swivel 0 and of swivel π/2 for wrist targets ``(n, 3)``
    (the elbow circle's in-plane axes; the zero turns with the arm's elevation,
    :mod:`motor.arm.chain`)."""
    circle = _setup(avatar, side, wrist_targets, None, None, None).circle
    return circle.down, circle.out


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
    twist = np.clip(wanted, *chain.twist_range)
    if reference is not None:
        # the reference's twist, plus the change the hand asks for since the reference
        # (none where the hand points so far off the forearm that its twist means little)
        reference = np.asarray(reference, dtype=float).reshape(-1, 2)
        more = (wanted - reference[:, 1] + np.pi) % (2.0 * np.pi) - np.pi
        twist = np.clip(reference[:, 0] + certainty * more, *chain.twist_range)
    elbow_local = quat.multiply(bend, quat.from_axis_angle(chain.pronation_axis, twist))
    rest_of_hand = quat.multiply(quat.conjugate(quat.multiply(shoulder_global, elbow_local)), hands)
    swing, _ = quat.swing_twist(rest_of_hand, chain.pronation_axis)
    rotvec = quat.to_rotation_vector(swing)
    flexion = np.clip(_dot(rotvec, chain.flexion_axis), *chain.wrist_flexion)
    deviation = np.clip(_dot(rotvec, chain.deviation_axis), *chain.wrist_deviation)
    wrist_local = quat.from_rotation_vector(flexion[..., None] * chain.flexion_axis + deviation[..., None] * chain.deviation_axis)
    reached = quat.multiply(quat.multiply(shoulder_global, elbow_local), wrist_local)
    residual = quat.angle_between(reached, hands)
    return _Arm(elbow, shoulder_local, elbow_local, wrist_local, residual, twist, wanted, certainty)


def twist_certainty(swing: np.ndarray) -> np.ndarray:
    """How well the hand's twist about the forearm is defined, 1 … 0, from the swing
    ``(n, 4)`` that takes the forearm's axis onto the hand's: fully up to
    :data:`SURE_SWING`, not at all from twice that on (at a half-turn swing the twist is
    undefined: any tiny change of the hand turns it around)."""
    angle = 2.0 * np.arccos(np.clip(np.abs(swing[..., 3]), 0.0, 1.0))
    return np.clip(2.0 - angle / SURE_SWING, 0.0, 1.0)


def _dot(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Dot products over the last axis, element by element (the same rounding whatever
    the batch: frames must not depend on how many are computed at once)."""
    return u[..., 0] * v[..., 0] + u[..., 1] * v[..., 1] + u[..., 2] * v[..., 2]


def _cheapest_swivel(avatar: Avatar, setup: _Setup, other: ArmSegments | None) -> np.ndarray:
    """The cheapest swivel of each frame on its own: the best candidate refined by a
    parabola through it and its neighbours. Without a hand rotation and where the natural
    swivel is clear of the body and the other arm, it is the natural swivel itself."""
    natural = natural_swivel(setup.chain, setup.circle, setup.targets, setup.torso_q)
    if setup.hands is None:
        free = _cost(avatar, setup, np.cos(natural)[:, None], np.sin(natural)[:, None], natural[:, None], natural, other)[:, 0]
        needed = free > 0.0
    else:
        needed = np.ones(len(natural), dtype=bool)
    if not np.any(needed):
        return natural
    rows = np.flatnonzero(needed)
    sub = _subset(setup, rows)
    other_rows = None if other is None else other.take(rows)
    cost = _cost(avatar, sub, _COS, _SIN, CANDIDATES, natural[rows], other_rows)
    best = np.argmin(cost, axis=1)
    index = np.arange(len(rows))
    count = len(CANDIDATES)
    left, middle, right = cost[index, (best - 1) % count], cost[index, best], cost[index, (best + 1) % count]
    offset = parabola_offset(left, middle, right)
    refined = CANDIDATES[best] + offset * SWIVEL_STEP
    refined_cost = _cost(avatar, sub, np.cos(refined)[:, None], np.sin(refined)[:, None], refined[:, None], natural[rows], other_rows)[:, 0]
    swivel = natural.copy()
    swivel[rows] = np.where(refined_cost <= middle, refined, CANDIDATES[best])
    return swivel


def parabola_offset(left: np.ndarray, middle: np.ndarray, right: np.ndarray) -> np.ndarray:
    """Where (in steps, within ±½) the parabola through three evenly spaced costs is lowest."""
    curvature = left - 2.0 * middle + right
    step = 0.5 * (left - right) / np.where(curvature > 1e-12, curvature, 1.0)
    return np.where(curvature > 1e-12, np.clip(step, -0.5, 0.5), 0.0)


def _subset(setup: _Setup, rows: np.ndarray) -> _Setup:
    pick = lambda a: None if a is None else a[rows]
    frame = None if setup.body_frame is None else (setup.body_frame[0][rows], setup.body_frame[1][rows])
    return _Setup(
        setup.chain, setup.torso_q[rows], setup.clavicle_local[rows], setup.sc_global[rows], setup.circle.take(rows),
        setup.targets[rows], pick(setup.hands), frame,
    )  # fmt: skip


def _cost(
    avatar: Avatar, setup: _Setup, cos: np.ndarray, sin: np.ndarray, psi: np.ndarray, natural: np.ndarray, other: ArmSegments | None
) -> np.ndarray:
    """Cost ``(n, K)`` of swivels ``psi`` (``(K,)`` shared or ``(n, K)``, with their cosines
    and sines) — the module docstring's terms."""
    circle, chain = setup.circle, setup.chain
    away = np.abs((psi - natural[:, None] + np.pi) % (2.0 * np.pi) - np.pi)
    beyond = np.maximum(away - SWIVEL_RANGE, 0.0)
    cost = (away / SWIVEL_SCALE) ** 2 + RANGE_WEIGHT * beyond * beyond
    radial = circle.down[:, None, :] * cos[..., None] + circle.out[:, None, :] * sin[..., None]
    elbow = circle.center[:, None, :] + radial * circle.radius[:, None, None]
    if setup.hands is not None:
        deviation, flexion, residual = _wrist_load(chain, circle, radial, elbow, setup.hands)
        deviation = deviation / np.where(deviation >= 0, chain.wrist_deviation[1], -chain.wrist_deviation[0])
        flexion = flexion / np.where(flexion >= 0, chain.wrist_flexion[1], -chain.wrist_flexion[0])
        unreached = residual * residual
        cost = cost + DEVIATION_WEIGHT * deviation**2 + FLEXION_WEIGHT * flexion**2 + RESIDUAL_WEIGHT * unreached / (1.0 + unreached / RESIDUAL_SATURATION**2)
    penalty, _ = clearance(avatar, chain.side, circle, elbow, setup.body_frame, other)
    return cost + penalty


def _wrist_load(
    chain: ArmChain, circle: ElbowCircle, radial: np.ndarray, elbow: np.ndarray, hands: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Wrist deviation and flexion a hand rotation needs with the elbow at ``elbow
    (n, K, 3)``, in ``radial`` directions from the circle's centre, and an
    estimate of the rotation left unachieved by the joint limits (radians).

    The same quantities :func:`_arm_at` computes, from vectors alone (no rotation
    matrices): the wrist's swing is the rotation taking the forearm axis, seen from the
    hand, onto the hand's long axis; the forearm twist is what turns the elbow hinge onto
    where the hand rotation, undone by that swing, wants it.
    """
    hand = hands[:, None, :]
    forearm = (circle.wrist[:, None, :] - elbow) / chain.fore
    seen_from_hand = quat.rotate(quat.conjugate(hand), forearm)
    axis = quat.cross(seen_from_hand, chain.fore_rest)
    sine = quat.norm(axis)
    angle = np.arctan2(sine, _dot(seen_from_hand, chain.fore_rest))
    rotvec = axis * (angle / np.maximum(sine, 1e-12))[..., None]
    flexion = _dot(rotvec, chain.flexion_axis)
    deviation = _dot(rotvec, chain.deviation_axis)
    swing = quat.from_rotation_vector(rotvec)
    wanted_hinge = quat.rotate(quat.multiply(hand, quat.conjugate(swing)), chain.hinge_rest)
    hinge = quat.normalize(quat.cross(radial, circle.axis[:, None, :]))
    twist_axis = forearm * float(chain.pronation_axis @ chain.fore_rest)
    twist = np.arctan2(_dot(quat.cross(hinge, wanted_hinge), twist_axis), _dot(hinge, wanted_hinge))
    excess = lambda value, limits: value - np.clip(value, *limits)
    residual = np.sqrt(
        excess(flexion, chain.wrist_flexion) ** 2 + excess(deviation, chain.wrist_deviation) ** 2 + excess(twist, chain.twist_range) ** 2
    )
    return deviation, flexion, residual
