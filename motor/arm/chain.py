"""The arm as a chain: its constants per avatar, the clavicle, the elbow circle and the
natural swivel (seeds 000 and 004).

The chain is sternoclavicular → shoulder → elbow → wrist. Once the wrist is placed, the
elbow flexion follows from the law of cosines (Tolani, Goswami & Badler) and the elbow
lies on a circle about the shoulder–wrist axis; its angle there, the *swivel*, is 0 with
the elbow lowest (toward down-and-back; for a raised arm, toward the front) and positive
as it rises outward. The natural
swivel is the one the Soechting & Flanders sensorimotor model predicts (upper-arm
elevation and yaw as linear functions of target distance, azimuth and elevation, as used
by Koga et al.), projected onto the circle.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from motor import quaternion as quat
from motor.arm.reach_turn import turned
from motor.body.avatar import Avatar, check_side

#: Reach (fraction of arm length from the resting shoulder) where the clavicle starts to
#: follow the hand, and where it reaches its limit.
CLAVICLE_REACH = (0.65, 1.05)

#: Soechting & Flanders (1989) as used by Koga et al. (1994): degrees and centimetres of
#: a 60 cm arm. Upper-arm elevation from the vertical and yaw from straight ahead.
ELEVATION_MODEL = (-4.0, 1.10, 0.90)  # constant, per cm distance, per degree target elevation
YAW_MODEL = (13.2, 0.86, 0.11)  # constant, per degree azimuth, per degree target elevation
MODEL_ARM_CM = 60.0
#: Direction (avatar frame) toward which swivel 0 points the elbow: down and back, blended
#: into forward as the arm rises (its axis' upward component from the first value to
#: the second), so that the reference is never near the arm's axis where a hand goes
#: (the blend is degenerate only for a hand raised behind the head).
DOWN_BACK = np.array([0.0, -1.0, -0.5]) / np.sqrt(1.25)
RAISED = (0.2, 0.7)
#: Within twice this (m) of the straight arm's reach the wrist eases toward a point this
#: much short of it: at full stretch the elbow's bend, and with it the elbow's speed,
#: changes without bound as the wrist comes back (a pop), and a clamped reach is a step in
#: the wrist's speed.
REACH_EASE = 0.015


@dataclass(frozen=True, eq=False)
class ArmChain:
    """Constants of one arm of one avatar (lengths metres, angles radians, axes unit
    vectors in the avatar frame at rest)."""

    side: str
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
    torso_joint_rest: np.ndarray


@functools.lru_cache(maxsize=32)
def arm_chain(avatar: Avatar, side: str) -> ArmChain:
    """The arm's constants, computed once per avatar and side (avatars are immutable)."""
    sc, shoulder, elbow, wrist = avatar.arm_joints(check_side(side))
    upper_rest = quat.normalize(avatar.offsets[elbow])
    hand = avatar.hand_frames[side]
    return ArmChain(
        side=side,
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
        torso_joint_rest=avatar.rest_positions[avatar.parents[sc]],
    )


def _turned(torso_q: np.ndarray | None, vectors: np.ndarray) -> np.ndarray:
    """Vectors given in the upper spine's frame, in the avatar frame (``torso_q`` None:
    the spine upright, at rest)."""
    return vectors if torso_q is None else quat.rotate(torso_q, vectors)


def clavicle_rotation(chain: ArmChain, torso_q: np.ndarray | None, sc_position: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """Local sternoclavicular rotation ``(n, 4)`` turning the shoulder toward a far reach
    (seed 000): a smooth function of the target, so it never jumps. ``torso_q``: the
    upper spine's global rotation ``(n, 4)``, None when upright."""
    clavicle = _turned(torso_q, chain.clavicle)
    reach = targets - (sc_position + clavicle)
    distance = quat.norm(reach)
    low, high = CLAVICLE_REACH
    t = np.minimum(np.maximum((distance / (chain.upper + chain.fore) - low) / (high - low), 0.0), 1.0)
    amount = t * t * (3.0 - 2.0 * t)
    axis = quat.cross(clavicle, reach)
    axis_norm = quat.norm(axis)
    # the shoulder moves across the clavicle toward the reach; fade out only when the
    # reach runs almost along the clavicle (no defined direction to move in)
    sine = axis_norm / np.maximum(quat.norm(clavicle) * distance, 1e-12)
    across = np.minimum(np.maximum(sine / 0.3, 0.0), 1.0)
    axis = axis / np.maximum(axis_norm, 1e-12)[:, None]
    world = quat.from_axis_angle(axis, chain.clavicle_max * amount * across)
    return world if torso_q is None else quat.multiply(quat.conjugate(torso_q), quat.multiply(world, torso_q))


@dataclass(frozen=True, eq=False)
class ElbowCircle:
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
    def of(chain: ArmChain, shoulder: np.ndarray, targets: np.ndarray, torso_q: np.ndarray | None) -> ElbowCircle:
        """The circles for wrist ``targets (n, 3)``; a target out of reach is replaced by
        the nearest reachable point on the line from the shoulder — eased in within
        :data:`REACH_EASE` of the arm's length, which it never quite reaches (:func:`short_of`)."""
        upper, fore = chain.upper, chain.fore
        reach = targets - shoulder
        distance = quat.norm(reach)
        fallback = _turned(torso_q, np.array([0.0, -1.0, 0.0]))
        axis = np.where(distance[:, None] > 1e-9, reach / np.maximum(distance, 1e-12)[:, None], fallback)
        reached = np.maximum(short_of(distance, farthest_reach(chain)), nearest_reach(chain))
        cos_flexion = (reached**2 - upper**2 - fore**2) / (2.0 * upper * fore)
        flexion = np.arccos(np.minimum(np.maximum(cos_flexion, -1.0), 1.0))
        cos_shoulder = np.minimum(np.maximum((upper**2 + reached**2 - fore**2) / (2.0 * upper * reached), -1.0), 1.0)
        up = _turned(torso_q, np.array([0.0, 1.0, 0.0]))
        raised = np.minimum(np.maximum((np.sum(axis * up, axis=-1, keepdims=True) - RAISED[0]) / (RAISED[1] - RAISED[0]), 0.0), 1.0)
        raised = raised * raised * (3.0 - 2.0 * raised)
        reference = (1.0 - raised) * _turned(torso_q, DOWN_BACK) + raised * _turned(torso_q, np.array([0.0, 0.0, 1.0]))
        down = reference - np.sum(reference * axis, axis=-1, keepdims=True) * axis
        down_norm = np.linalg.norm(down, axis=-1, keepdims=True)
        sideways = _turned(torso_q, np.array([chain.side_sign, 0.0, 0.0]))
        down = np.where(down_norm > 1e-6, down / np.maximum(down_norm, 1e-12), quat.cross(axis, sideways))
        out = chain.side_sign * quat.cross(axis, down)
        return ElbowCircle(
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

    def take(self, rows: np.ndarray) -> ElbowCircle:
        """The circles of the frames selected by a boolean mask or indices."""
        return ElbowCircle(**{name: getattr(self, name)[rows] for name in self.__dataclass_fields__})

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


def farthest_reach(chain: ArmChain) -> float:
    """Shoulder-to-wrist distance (m) of the arm stretched as far as its elbow goes."""
    upper, fore = chain.upper, chain.fore
    return float(np.sqrt(upper**2 + fore**2 + 2.0 * upper * fore * np.cos(chain.flexion_range[0])))


def nearest_reach(chain: ArmChain) -> float:
    """Shoulder-to-wrist distance (m) of the arm bent as far as its elbow goes."""
    upper, fore = chain.upper, chain.fore
    return float(np.sqrt(upper**2 + fore**2 + 2.0 * upper * fore * np.cos(chain.flexion_range[1])))


def exact_reach(chain: ArmChain) -> float:
    """The farthest shoulder-to-wrist distance (m) the arm reaches exactly, where its reach
    starts to ease (:func:`short_of`): what planners place their paths within, so that
    the arm follows them as planned."""
    return farthest_reach(chain) - 2.0 * REACH_EASE


def short_of(distance: np.ndarray, farthest: float) -> np.ndarray:
    """Shoulder-to-wrist distances kept short of ``farthest``: unchanged up to
    ``farthest - 2 REACH_EASE``, beyond it rising with a C² ease (tanh: equal in value,
    slope and curvature at the knee) toward ``farthest - REACH_EASE``."""
    knee = farthest - 2.0 * REACH_EASE
    beyond = np.maximum(distance - knee, 0.0)
    return np.where(distance > knee, knee + REACH_EASE * np.tanh(beyond / REACH_EASE), distance)


def natural_swivel(chain: ArmChain, circle: ElbowCircle, targets: np.ndarray, torso_q: np.ndarray | None) -> np.ndarray:
    """Swivel (radians) of the elbow the Soechting & Flanders model predicts for each target."""
    shoulder = circle.shoulder
    local = targets - shoulder if torso_q is None else quat.rotate(quat.conjugate(torso_q), targets - shoulder)
    lateral = chain.side_sign * local[:, 0]
    distance_cm = quat.norm(local) / (chain.upper + chain.fore) * MODEL_ARM_CM
    target_elevation = np.degrees(np.arctan2(local[:, 1], np.hypot(lateral, local[:, 2])))
    azimuth = np.degrees(np.arctan2(lateral, local[:, 2]))
    elevation = np.radians(np.minimum(np.maximum(ELEVATION_MODEL[0] + ELEVATION_MODEL[1] * distance_cm + ELEVATION_MODEL[2] * target_elevation, 0.0), 170.0))
    yaw = np.radians(YAW_MODEL[0] + YAW_MODEL[1] * azimuth + YAW_MODEL[2] * target_elevation)
    upper_dir = np.stack(
        (chain.side_sign * np.sin(elevation) * np.sin(yaw), -np.cos(elevation), np.sin(elevation) * np.cos(yaw)), axis=-1
    )
    predicted = shoulder + chain.upper * _turned(torso_q, upper_dir)
    offset = predicted - circle.center
    return np.arctan2(np.sum(offset * circle.out, axis=-1), np.sum(offset * circle.down, axis=-1))


@dataclass(frozen=True, eq=False)
class ArmPlacement:
    """What every solve of the same targets shares: the shoulder girdle and elbow circles.

    ``torso_q (n, 4)`` is the clavicles' parent's global rotation (None: upright, at
    rest); ``body_frame`` (rotation
    ``(n, 4)``, translation ``(n, 3)``) carries the body's rest geometry to where it is,
    None when the torso stands upright at rest; ``carried_frames`` do so for the volumes
    that stay with the hips or turn with only part of the thoracic spine when the arm is
    solved in the frame of a trunk turned toward a reach
    (:meth:`motor.arm.reach_turn.TrunkTurn.carried_frames`), None when it is not turned."""

    chain: ArmChain
    torso_q: np.ndarray | None
    clavicle_local: np.ndarray
    sc_global: np.ndarray
    circle: ElbowCircle
    targets: np.ndarray
    hands: np.ndarray | None
    body_frame: tuple[np.ndarray, np.ndarray] | None
    carried_frames: tuple[tuple[np.ndarray, np.ndarray], ...] | None = None

    def take(self, rows: np.ndarray) -> ArmPlacement:
        """The placements of the selected frames."""
        frame = None if self.body_frame is None else (self.body_frame[0][rows], self.body_frame[1][rows])
        carried = None if self.carried_frames is None else tuple((r[rows], t[rows]) for r, t in self.carried_frames)
        return ArmPlacement(
            self.chain, None if self.torso_q is None else self.torso_q[rows], self.clavicle_local[rows], self.sc_global[rows], self.circle.take(rows),
            self.targets[rows], None if self.hands is None else self.hands[rows], frame, carried,
        )  # fmt: skip


def place_arm(
    avatar: Avatar,
    side: str,
    wrist_targets: np.ndarray,
    hand_rotations: np.ndarray | None = None,
    torso_rotations: np.ndarray | None = None,
    torso_positions: np.ndarray | None = None,
    trunk_yaw: np.ndarray | None = None,
) -> ArmPlacement:
    """The clavicle, shoulder and elbow circle for wrist targets ``(n, 3)`` (see
    :func:`motor.arm.ik.solve_arm` for the arguments); ``trunk_yaw (n,)`` (radians), the
    turn of the trunk in whose frame the targets are given (:mod:`motor.arm.reach_turn`),
    places the volumes that stay with the hips."""
    chain = arm_chain(avatar, check_side(side))
    targets = np.asarray(wrist_targets, dtype=float).reshape(-1, 3)
    frames = targets.shape[0]
    hands = None if hand_rotations is None else quat.normalize(np.asarray(hand_rotations, dtype=float).reshape(frames, 4))
    if torso_rotations is None and torso_positions is None:
        torso_q, body_frame = None, None
        sc_position = np.broadcast_to(chain.torso_joint_rest + chain.sc_offset, (frames, 3))
    else:
        torso_q = np.broadcast_to(quat.IDENTITY, (frames, 4)) if torso_rotations is None else np.asarray(torso_rotations, float)
        torso_p = np.broadcast_to(chain.torso_joint_rest, (frames, 3)) if torso_positions is None else np.asarray(torso_positions, float)
        sc_position = torso_p + quat.rotate(torso_q, chain.sc_offset)
        body_frame = (torso_q, torso_p - quat.rotate(torso_q, chain.torso_joint_rest))
    clavicle_local = clavicle_rotation(chain, torso_q, sc_position, targets)
    sc_global = clavicle_local if torso_q is None else quat.multiply(torso_q, clavicle_local)
    shoulder = sc_position + quat.rotate(sc_global, chain.clavicle)
    circle = ElbowCircle.of(chain, shoulder, targets, torso_q)
    return ArmPlacement(chain, torso_q, clavicle_local, sc_global, circle, targets, hands, body_frame, carried_frames(avatar, trunk_yaw))


def carried_frames(avatar: Avatar, trunk_yaw: np.ndarray | None) -> tuple[tuple[np.ndarray, np.ndarray], ...] | None:
    """Where the volumes that do not turn with the whole trunk are, seen from a trunk
    turned by ``trunk_yaw (n,)`` radians (:meth:`motor.arm.reach_turn.TrunkTurn.carried_frames`);
    None where the trunk is not turned."""
    turn = None if trunk_yaw is None else turned(avatar, np.asarray(trunk_yaw, dtype=float))
    return None if turn is None else turn.carried_frames()
