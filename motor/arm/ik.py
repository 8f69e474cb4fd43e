"""Analytic arm inverse kinematics with a natural elbow swivel (IKAN style), vectorized.

The arm chain is sternoclavicular → shoulder → elbow → wrist. Given wrist targets (and
optionally global hand rotations), for every frame at once:

1. the clavicle turns the shoulder toward far reaches (seed 000, rule 3);
2. the elbow flexion follows from the law of cosines (Tolani, Goswami & Badler); a target
   out of reach is replaced by the nearest reachable point on the line from the shoulder,
   and the distance it fell short is reported;
3. the elbow lies on the circle about the shoulder–wrist axis; its angle there, the
   *swivel*, is 0 with the elbow lowest (toward down-and-back) and positive as it rises
   outward. The natural swivel is the one the Soechting & Flanders sensorimotor model
   predicts (upper-arm elevation and yaw as linear functions of target distance, azimuth
   and elevation, as used by Koga et al.), projected onto the circle; then, as seed 000
   asks, it is corrected to spare the wrist (limited bending, especially side to side) and
   to keep the upper arm out of the torso when reaching across (the elbow is raised). The
   correction minimizes a smooth cost over candidate swivels around the natural one,
   refined by a parabola through the best three, so the arm varies continuously with the
   hand;
4. the hand rotation is solved at the same time: forearm twist (pronation) goes to the
   elbow joint, flexion and radial/ulnar deviation to the wrist, each clamped to the
   avatar's limits; what could not be achieved is reported as an angle.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from motor import quaternion as quat
from motor.body.avatar import Avatar, check_side

#: Reach (fraction of arm length from the resting shoulder) where the clavicle starts to
#: follow the hand, and where it reaches its limit.
_CLAVICLE_REACH = (0.65, 1.05)

#: Soechting & Flanders (1989) as used by Koga et al. (1994): degrees and centimetres of
#: a 60 cm arm. Upper-arm elevation from the vertical and yaw from straight ahead.
_ELEVATION = (-4.0, 1.10, 0.90)  # constant, per cm distance, per degree target elevation
_YAW = (13.2, 0.86, 0.11)  # constant, per degree azimuth, per degree target elevation
_MODEL_ARM_CM = 60.0

#: Candidate swivels around the natural one (radians) for the corrections.
_CANDIDATES = np.deg2rad(np.arange(-120.0, 120.1, 15.0))
#: A finer search around the best coarse candidate.
_FINE = np.deg2rad(np.arange(-7.5, 7.6, 3.75))
#: Cost weights: distance from the natural swivel (per radian), wrist deviation and
#: flexion as fractions of their limits, unachieved hand rotation (per radian), torso
#: penetration (per centimetre).
_SWIVEL_SCALE = 0.7
_DEVIATION_WEIGHT = 1.5
_FLEXION_WEIGHT = 0.4
_RESIDUAL_WEIGHT = 5000.0
_PENETRATION_WEIGHT = 50.0
#: Radius of the upper arm kept clear of the torso, as a fraction of arm length.
_ARM_RADIUS = 0.05
#: Points along the upper arm (fractions from shoulder to elbow) checked against the torso.
_ARM_SAMPLES = np.array([0.3, 0.45, 0.6, 0.75, 0.9, 1.0])


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
        penetration: ``(n,)`` how deep the upper arm (thickened by its radius) enters the
            torso, metres; nonzero only where no swivel keeps it out (e.g. reaching far
            across the body, which needs the trunk to turn).
    """

    rotations: np.ndarray
    shoulder: np.ndarray
    elbow: np.ndarray
    wrist: np.ndarray
    shortfall: np.ndarray
    elbow_flexion: np.ndarray
    swivel: np.ndarray
    orientation_error: np.ndarray
    penetration: np.ndarray


@dataclass(frozen=True, eq=False)
class _Chain:
    """Constants of one arm of one avatar."""

    side_sign: float
    upper: float
    fore: float
    clavicle: np.ndarray
    sc_offset: np.ndarray
    upper_rest: np.ndarray
    hinge_rest: np.ndarray
    fore_rest: np.ndarray
    pronation_axis: np.ndarray
    flexion_axis: np.ndarray
    deviation_axis: np.ndarray
    clavicle_max: float
    flexion_range: tuple[float, float]
    twist_range: tuple[float, float]
    wrist_flexion: tuple[float, float]
    wrist_deviation: tuple[float, float]
    torso_center: np.ndarray
    torso_axes: np.ndarray
    torso_heights: tuple[float, float]
    torso_joint_rest: np.ndarray


@functools.lru_cache(maxsize=32)
def _chain(avatar: Avatar, side: str) -> _Chain:
    """The arm's constants, computed once per avatar and side (avatars are immutable)."""
    sc, shoulder, elbow, wrist = avatar.arm_joints(side)
    upper_rest = quat.normalize(avatar.offsets[elbow])
    hand = avatar.hand_frames[side]
    radius = _ARM_RADIUS * avatar.arm_length(side)
    torso = avatar.torso
    return _Chain(
        side_sign=1.0 if side == "l" else -1.0,
        upper=float(np.linalg.norm(avatar.offsets[elbow])),
        fore=float(np.linalg.norm(avatar.offsets[wrist])),
        clavicle=avatar.offsets[shoulder],
        sc_offset=avatar.offsets[sc],
        upper_rest=upper_rest,
        hinge_rest=quat.normalize(quat.cross(upper_rest, [0.0, 0.0, 1.0])),
        fore_rest=quat.normalize(avatar.offsets[wrist]),
        pronation_axis=hand.twist_axis,
        flexion_axis=hand.bend_axis,
        deviation_axis=hand.splay_axis,
        clavicle_max=avatar.limit(f"{side}_sternoclavicular", "swing")[1],
        flexion_range=avatar.limit(f"{side}_elbow", "flexion"),
        twist_range=avatar.limit(f"{side}_elbow", "twist"),
        wrist_flexion=avatar.limit(f"{side}_wrist", "flexion"),
        wrist_deviation=avatar.limit(f"{side}_wrist", "deviation"),
        torso_center=torso.center,
        torso_axes=np.array([torso.half_width + radius, torso.half_depth + radius]),
        torso_heights=(torso.bottom, torso.top),
        torso_joint_rest=avatar.rest_positions[avatar.parents[sc]],
    )


def solve_arm(
    avatar: Avatar,
    side: str,
    wrist_targets: np.ndarray,
    hand_rotations: np.ndarray | None = None,
    swivel: np.ndarray | None = None,
    torso_rotations: np.ndarray | None = None,
    torso_positions: np.ndarray | None = None,
) -> ArmSolution:
    """Solve one arm for ``n`` frames at once.

    Args:
        wrist_targets: ``(n, 3)`` wrist positions in the avatar frame (root at origin), metres.
        hand_rotations: ``(n, 4)`` global hand rotations to reach, or None to keep the hand
            in line with the forearm.
        swivel: ``(n,)`` swivel angles (radians) to use instead of the natural swivel.
        torso_rotations: ``(n, 4)`` global rotation of the clavicles' parent joint (the
            upper spine), identity if None.
        torso_positions: ``(n, 3)`` global position of that joint, its rest position if None.
    """
    chain = _chain(avatar, check_side(side))
    targets = np.asarray(wrist_targets, dtype=float).reshape(-1, 3)
    frames = targets.shape[0]
    torso_q = np.broadcast_to(quat.IDENTITY, (frames, 4)) if torso_rotations is None else np.asarray(torso_rotations, float)
    torso_p = np.broadcast_to(chain.torso_joint_rest, (frames, 3)) if torso_positions is None else np.asarray(torso_positions, float)
    hands = None if hand_rotations is None else quat.normalize(np.asarray(hand_rotations, dtype=float).reshape(frames, 4))

    sc_position = torso_p + quat.rotate(torso_q, chain.sc_offset)
    clavicle_local = _clavicle(chain, torso_q, sc_position, targets)
    sc_global = quat.multiply(torso_q, clavicle_local)
    shoulder = sc_position + quat.rotate(sc_global, chain.clavicle)
    circle = _Circle.of(chain, shoulder, targets, torso_q)

    if swivel is None:
        natural = _natural_swivel(chain, circle, shoulder, targets, torso_q)
        psi = _corrected_swivel(chain, circle, natural, sc_global, hands, torso_q, torso_p)
    else:
        psi = np.broadcast_to(np.asarray(swivel, dtype=float), (frames,)).copy()
    arm = _arm_at(chain, circle, psi, sc_global, hands)
    return ArmSolution(
        rotations=np.stack((clavicle_local, arm.shoulder_local, arm.elbow_local, arm.wrist_local), axis=1),
        shoulder=shoulder,
        elbow=arm.elbow,
        wrist=circle.wrist,
        shortfall=circle.shortfall,
        elbow_flexion=circle.flexion,
        swivel=psi,
        orientation_error=arm.residual,
        penetration=_torso_penetration(chain, shoulder, arm.elbow, torso_q, torso_p),
    )


def _clavicle(chain: _Chain, torso_q: np.ndarray, sc_position: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """Local sternoclavicular rotation turning the shoulder toward a far reach (seed 000)."""
    clavicle = quat.rotate(torso_q, chain.clavicle)
    reach = targets - (sc_position + clavicle)
    distance = quat.norm(reach)
    low, high = _CLAVICLE_REACH
    t = np.clip((distance / (chain.upper + chain.fore) - low) / (high - low), 0.0, 1.0)
    amount = t * t * (3.0 - 2.0 * t)
    axis = quat.cross(clavicle, reach)
    axis_norm = quat.norm(axis)
    # the shoulder moves across the clavicle toward the reach; fade out only when the
    # reach runs almost along the clavicle (no defined direction to move in)
    sine = axis_norm / np.maximum(quat.norm(clavicle) * distance, 1e-12)
    across = np.clip(sine / 0.3, 0.0, 1.0)
    axis = axis / np.maximum(axis_norm, 1e-12)[:, None]
    world = quat.from_axis_angle(axis, chain.clavicle_max * amount * across)
    return quat.multiply(quat.conjugate(torso_q), quat.multiply(world, torso_q))


@dataclass(frozen=True, eq=False)
class _Circle:
    """The elbow circle of each frame: centre, radius, in-plane basis; and the reach."""

    shoulder: np.ndarray
    axis: np.ndarray
    center: np.ndarray
    radius: np.ndarray
    down: np.ndarray
    out: np.ndarray
    wrist: np.ndarray
    shortfall: np.ndarray
    flexion: np.ndarray

    @staticmethod
    def of(chain: _Chain, shoulder: np.ndarray, targets: np.ndarray, torso_q: np.ndarray) -> _Circle:
        upper, fore = chain.upper, chain.fore
        reach = targets - shoulder
        distance = quat.norm(reach)
        fallback = quat.rotate(torso_q, np.array([0.0, -1.0, 0.0]))
        axis = np.where(distance[:, None] > 1e-9, reach / np.maximum(distance, 1e-12)[:, None], fallback)
        low, high = chain.flexion_range
        nearest = np.sqrt(upper**2 + fore**2 + 2.0 * upper * fore * np.cos(high))
        farthest = np.sqrt(upper**2 + fore**2 + 2.0 * upper * fore * np.cos(low))
        reached = np.clip(distance, nearest, farthest)
        cos_flexion = (reached**2 - upper**2 - fore**2) / (2.0 * upper * fore)
        flexion = np.arccos(np.clip(cos_flexion, -1.0, 1.0))
        cos_shoulder = np.clip((upper**2 + reached**2 - fore**2) / (2.0 * upper * reached), -1.0, 1.0)
        reference = quat.rotate(torso_q, quat.normalize(np.array([0.0, -1.0, -0.5])))
        down = reference - np.sum(reference * axis, axis=-1, keepdims=True) * axis
        down_norm = np.linalg.norm(down, axis=-1, keepdims=True)
        sideways = quat.rotate(torso_q, np.array([chain.side_sign, 0.0, 0.0]))
        down = np.where(down_norm > 1e-6, down / np.maximum(down_norm, 1e-12), quat.cross(axis, sideways))
        out = chain.side_sign * quat.cross(axis, down)
        return _Circle(
            shoulder=shoulder,
            axis=axis,
            center=shoulder + axis * (upper * cos_shoulder)[:, None],
            radius=upper * np.sqrt(1.0 - cos_shoulder**2),
            down=down,
            out=out,
            wrist=shoulder + axis * reached[:, None],
            shortfall=np.abs(distance - reached),
            flexion=flexion,
        )

    def take(self, mask: np.ndarray) -> _Circle:
        """The circles of the frames selected by a boolean mask."""
        return _Circle(**{name: getattr(self, name)[mask] for name in self.__dataclass_fields__})

    def elbow(self, psi: np.ndarray, direction: np.ndarray | None = None) -> np.ndarray:
        """Elbow positions ``(n, ..., 3)`` at swivels ``psi (n, ...)`` (their
        :meth:`direction`, when known, spares computing it again)."""
        at = (slice(None),) + (None,) * (psi.ndim - 1)
        radial = self.direction(psi) if direction is None else direction
        return self.center[at] + radial * self.radius[at][..., None]

    def direction(self, psi: np.ndarray) -> np.ndarray:
        """Unit direction from the circle's centre to the elbow at swivel ``psi (n, ...)``."""
        cos, sin = np.cos(psi)[..., None], np.sin(psi)[..., None]
        shape = (slice(None),) + (None,) * (psi.ndim - 1)
        return self.down[shape] * cos + self.out[shape] * sin


def _natural_swivel(chain: _Chain, circle: _Circle, shoulder: np.ndarray, targets: np.ndarray, torso_q: np.ndarray) -> np.ndarray:
    """Swivel of the elbow the Soechting & Flanders model predicts for each target."""
    local = quat.rotate(quat.conjugate(torso_q), targets - shoulder)
    lateral = chain.side_sign * local[:, 0]
    distance_cm = quat.norm(local) / (chain.upper + chain.fore) * _MODEL_ARM_CM
    target_elevation = np.degrees(np.arctan2(local[:, 1], np.hypot(lateral, local[:, 2])))
    azimuth = np.degrees(np.arctan2(lateral, local[:, 2]))
    elevation = np.radians(np.clip(_ELEVATION[0] + _ELEVATION[1] * distance_cm + _ELEVATION[2] * target_elevation, 0.0, 170.0))
    yaw = np.radians(_YAW[0] + _YAW[1] * azimuth + _YAW[2] * target_elevation)
    upper_dir = np.stack(
        (chain.side_sign * np.sin(elevation) * np.sin(yaw), -np.cos(elevation), np.sin(elevation) * np.cos(yaw)), axis=-1
    )
    predicted = shoulder + chain.upper * quat.rotate(torso_q, upper_dir)
    offset = predicted - circle.center
    return np.arctan2(np.sum(offset * circle.out, axis=-1), np.sum(offset * circle.down, axis=-1))


@dataclass(frozen=True, eq=False)
class _Arm:
    elbow: np.ndarray
    shoulder_local: np.ndarray
    elbow_local: np.ndarray
    wrist_local: np.ndarray
    residual: np.ndarray
    deviation: np.ndarray
    wrist_flexion: np.ndarray


def _arm_at(chain: _Chain, circle: _Circle, psi: np.ndarray, sc_global: np.ndarray, hands: np.ndarray | None) -> _Arm:
    """Joint rotations of the arm at swivel ``psi (n, ...)`` (extra axes broadcast)."""
    extra = (None,) * (psi.ndim - 1)
    at = (slice(None),) + extra
    radial = circle.direction(psi)
    elbow = circle.elbow(psi)
    upper_dir = quat.normalize(elbow - circle.shoulder[at])
    hinge = quat.normalize(quat.cross(radial, np.broadcast_to(circle.axis[at], radial.shape)))
    rest = np.stack((chain.upper_rest, chain.hinge_rest, quat.cross(chain.upper_rest, chain.hinge_rest)), axis=-1)
    target = np.stack((upper_dir, hinge, quat.cross(upper_dir, hinge)), axis=-1)
    shoulder_global = quat.from_frames(rest, target)
    sc = np.broadcast_to(sc_global[at], shoulder_global.shape)
    shoulder_local = quat.multiply(quat.conjugate(sc), shoulder_global)
    bend = quat.from_axis_angle(chain.hinge_rest, np.broadcast_to(circle.flexion[at], psi.shape))
    forearm = quat.multiply(shoulder_global, bend)
    zeros = np.zeros(psi.shape)
    if hands is None:
        identity = np.broadcast_to(quat.IDENTITY, psi.shape + (4,))
        return _Arm(elbow, shoulder_local, bend, identity.copy(), zeros, zeros, zeros)
    hand = np.broadcast_to(hands[at], forearm.shape)
    relative = quat.multiply(quat.conjugate(forearm), hand)
    _, negative_twist = quat.swing_twist(quat.conjugate(relative), chain.pronation_axis)
    twist = np.clip(-negative_twist, *chain.twist_range)
    elbow_local = quat.multiply(bend, quat.from_axis_angle(chain.pronation_axis, twist))
    wanted = quat.multiply(quat.conjugate(quat.multiply(shoulder_global, elbow_local)), hand)
    swing, _ = quat.swing_twist(wanted, chain.pronation_axis)
    rotvec = quat.to_rotation_vector(swing)
    flexion = np.sum(rotvec * chain.flexion_axis, axis=-1)
    deviation = np.sum(rotvec * chain.deviation_axis, axis=-1)
    flexion_c = np.clip(flexion, *chain.wrist_flexion)
    deviation_c = np.clip(deviation, *chain.wrist_deviation)
    wrist_local = quat.from_rotation_vector(flexion_c[..., None] * chain.flexion_axis + deviation_c[..., None] * chain.deviation_axis)
    reached = quat.multiply(quat.multiply(shoulder_global, elbow_local), wrist_local)
    residual = quat.angle_between(reached, hand)
    return _Arm(elbow, shoulder_local, elbow_local, wrist_local, residual, deviation, flexion)


def _corrected_swivel(
    chain: _Chain,
    circle: _Circle,
    natural: np.ndarray,
    sc_global: np.ndarray,
    hands: np.ndarray | None,
    torso_q: np.ndarray,
    torso_p: np.ndarray,
) -> np.ndarray:
    """The natural swivel moved to spare the wrist and keep the upper arm out of the torso.

    Without a hand rotation only frames whose natural swivel puts the upper arm into the
    torso need the search (elsewhere the natural swivel is already the optimum).
    """
    if hands is None:
        elbow = circle.elbow(natural[:, None])
        needed = _torso_penetration(chain, circle.shoulder, elbow, torso_q, torso_p)[:, 0] > 0.0
    else:
        needed = np.ones(len(natural), dtype=bool)
    if not np.any(needed):
        return natural
    sub = (
        circle.take(needed),
        natural[needed],
        sc_global[needed],
        None if hands is None else hands[needed],
        torso_q[needed],
        torso_p[needed],
    )
    coarse = _best_candidate(chain, sub[0], sub[1][:, None] + _CANDIDATES, *sub[1:])
    fine = _best_candidate(chain, sub[0], coarse[:, None] + _FINE, *sub[1:])
    swivel = natural.copy()
    swivel[needed] = fine
    return swivel


def _best_candidate(
    chain: _Chain,
    circle: _Circle,
    candidates: np.ndarray,
    natural: np.ndarray,
    sc_global: np.ndarray,
    hands: np.ndarray | None,
    torso_q: np.ndarray,
    torso_p: np.ndarray,
) -> np.ndarray:
    """The cheapest of evenly spaced candidate swivels ``(n, K)``, refined by a parabola."""
    cost = _cost(chain, circle, candidates, natural, sc_global, hands, torso_q, torso_p)
    rows = np.arange(len(natural))
    winner = np.argmin(cost, axis=1)
    best = np.clip(winner, 1, candidates.shape[1] - 2)
    left, middle, right = cost[rows, best - 1], cost[rows, best], cost[rows, best + 1]
    curvature = left - 2.0 * middle + right
    step = np.where(curvature > 1e-12, 0.5 * (left - right) / np.where(curvature > 1e-12, curvature, 1.0), 0.0)
    spacing = candidates[:, 1] - candidates[:, 0]
    refined = candidates[rows, best] + np.clip(step, -1.0, 1.0) * spacing
    # keep the refinement only where it does not make things worse
    refined_cost = _cost(chain, circle, refined[:, None], natural, sc_global, hands, torso_q, torso_p)[:, 0]
    return np.where(refined_cost <= cost[rows, winner], refined, candidates[rows, winner])


def _cost(
    chain: _Chain,
    circle: _Circle,
    psi: np.ndarray,
    natural: np.ndarray,
    sc_global: np.ndarray,
    hands: np.ndarray | None,
    torso_q: np.ndarray,
    torso_p: np.ndarray,
) -> np.ndarray:
    cost = ((psi - natural[:, None]) / _SWIVEL_SCALE) ** 2
    if hands is None:
        elbow = circle.elbow(psi)
    else:
        radial = circle.direction(psi)
        elbow = circle.elbow(psi, radial)
        deviation, flexion, residual = _wrist_load(chain, circle, radial, elbow, hands)
        deviation = deviation / np.where(deviation >= 0, chain.wrist_deviation[1], -chain.wrist_deviation[0])
        flexion = flexion / np.where(flexion >= 0, chain.wrist_flexion[1], -chain.wrist_flexion[0])
        cost = cost + _DEVIATION_WEIGHT * deviation**2 + _FLEXION_WEIGHT * flexion**2 + _RESIDUAL_WEIGHT * residual**2
    depth = _torso_penetration(chain, circle.shoulder, elbow, torso_q, torso_p)
    return cost + _PENETRATION_WEIGHT * (100.0 * depth) ** 2


def _wrist_load(
    chain: _Chain, circle: _Circle, radial: np.ndarray, elbow: np.ndarray, hands: np.ndarray
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
    angle = np.arctan2(sine, np.sum(seen_from_hand * chain.fore_rest, axis=-1))
    rotvec = axis * (angle / np.maximum(sine, 1e-12))[..., None]
    flexion = rotvec @ chain.flexion_axis
    deviation = rotvec @ chain.deviation_axis
    swing = quat.from_rotation_vector(rotvec)
    wanted_hinge = quat.rotate(quat.multiply(hand, quat.conjugate(swing)), chain.hinge_rest)
    hinge = quat.normalize(quat.cross(radial, circle.axis[:, None, :]))
    twist_axis = forearm * float(chain.pronation_axis @ chain.fore_rest)
    twist = np.arctan2(np.sum(quat.cross(hinge, wanted_hinge) * twist_axis, axis=-1), np.sum(hinge * wanted_hinge, axis=-1))
    excess = lambda value, limits: value - np.clip(value, *limits)
    residual = np.sqrt(
        excess(flexion, chain.wrist_flexion) ** 2 + excess(deviation, chain.wrist_deviation) ** 2 + excess(twist, chain.twist_range) ** 2
    )
    return deviation, flexion, residual


def _torso_penetration(chain: _Chain, shoulder: np.ndarray, elbow: np.ndarray, torso_q: np.ndarray, torso_p: np.ndarray) -> np.ndarray:
    """How deep (metres) the upper arm, thickened by its radius, reaches into the torso.

    The torso is the avatar's elliptic cylinder, carried by the upper-spine joint.
    ``elbow (n, ...)`` may carry extra axes after the frame axis.
    """
    extra = (None,) * (elbow.ndim - 2)
    at = (slice(None),) + extra
    if np.all(torso_q == quat.IDENTITY):
        # an upright torso: rotating by the identity changes nothing; the same arithmetic
        # one coordinate at a time, samples along the arm first, on contiguous arrays
        samples = _ARM_SAMPLES.reshape((-1,) + (1,) * (elbow.ndim - 1))
        x, y, z = (
            shoulder[at + (c,)] + samples * (elbow[..., c] - shoulder[at + (c,)]) - torso_p[at + (c,)] + chain.torso_joint_rest[c]
            for c in range(3)
        )
    else:
        points = shoulder[at][..., None, :] + _ARM_SAMPLES[:, None] * (elbow - shoulder[at])[..., None, :]
        inverse = quat.conjugate(torso_q)[at][..., None, :]
        local = np.moveaxis(quat.rotate(inverse, points - torso_p[at][..., None, :]) + chain.torso_joint_rest, -2, 0)
        x, y, z = local[..., 0], local[..., 1], local[..., 2]
    dx = (x - chain.torso_center[0]) / chain.torso_axes[0]
    dz = (z - chain.torso_center[2]) / chain.torso_axes[1]
    inside = np.sqrt(dx**2 + dz**2)
    within = (y > chain.torso_heights[0]) & (y < chain.torso_heights[1])
    depth = np.where(within, np.clip(1.0 - inside, 0.0, None) * chain.torso_axes.min(), 0.0)
    return depth.max(axis=0)
