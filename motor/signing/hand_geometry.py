"""The hand geometry that sign planning asks for again and again, memoized per avatar.

Planning a collection of signs asks many times for the same few things, each of which
depends only on the avatar and on a hand's values: the global hand rotation of an
extended-finger direction and a palm direction, the joint parameters of a hand shape,
the point a location names on the body at rest, the offset from the wrist to a site of
the hand in a rotation and shape, and the whole-body pose with one arm holding a hand
posture (IK and forward kinematics); and, though it is no hand's, the stopping length of
a path that a sign's moves take (a corpus repeats many). :class:`HandGeometry` computes each once per
planning run and hands the same (read-only) arrays back afterwards; with
``memoize=False`` it computes every answer afresh, which is how the tests check that the
memo changes nothing.

Keys are the exact values asked for (the bytes of float arrays, the frozen symbol values
of :mod:`mura.values`), so a remembered answer is the one the computation gives for
those inputs, bit for bit. Errors are not remembered: asking again raises again.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Iterable, Sequence
from typing import TypeVar

import numpy as np

from motor.arm.hand_orientation import hand_rotations_from_vectors
from motor.arm.ik import solve_arm
from motor.body.avatar import Avatar
from motor.body.kinematics import Pose, forward_kinematics, identity_rotations
from motor.body.locations import resolve_location, site_points
from motor.hand.shape import hand_rotations, handshape_params
from motor.signing.lmp import stopping_length
from motor.signing.path_batch import stopping_length_of
from mura.errors import SpecError
from mura.values import BodySite, HandShape, Location

_Value = TypeVar("_Value")
_UNKNOWN = object()
_FLOAT64 = np.dtype(np.float64)


class GeometryPending(Exception):
    """Raised by a deferring :class:`HandGeometry` asked for an arm pose or a site offset
    it does not know yet: the request is kept for :meth:`HandGeometry.resolve_pending`."""


class HandGeometry:
    """Memoized hand geometry of one avatar (module docstring); units metres, quaternions
    scalar-last. Not shared between avatars: make one per avatar and planning run.

    With ``deferring`` set, the two costly answers (:meth:`site_offset`, :meth:`arm_pose`)
    are not computed one by one: an unknown one is noted and :class:`GeometryPending`
    raised, so that a caller planning many signs can set aside the signs that asked,
    compute all the noted answers in one vectorized pass (:meth:`resolve_pending`) and
    plan those signs again."""

    def __init__(self, avatar: Avatar, memoize: bool = True) -> None:
        self.avatar = avatar
        self.memoize = memoize
        self.deferring = False
        self._memo: dict[Hashable, object] = {}
        self._pending_offsets: list[tuple[str, BodySite, np.ndarray, np.ndarray]] = []
        self._pending_poses: dict[Hashable, tuple[str, np.ndarray, np.ndarray, np.ndarray]] = {}
        self._pending_palm_poses: list[tuple[np.ndarray, Hashable, tuple[str, np.ndarray, np.ndarray]]] = []
        self._alone: set[Hashable] = set()
        #: Site offsets by the id of the request tuple asked (:meth:`site_offsets`), with the
        #: tuple itself, which keeps the id from being reused while the entry lasts.
        self._answers: dict[int, tuple[tuple[str, BodySite, np.ndarray, np.ndarray], np.ndarray]] = {}

    def _unknown(self, key: Hashable) -> bool:
        """Whether a memoizing geometry neither knows ``key`` nor has given up computing it
        with others (:attr:`_alone`): a deferring caller then notes it for the next round."""
        return self.memoize and key not in self._memo and key not in self._alone

    def _recall(self, key: Hashable, compute: Callable[[], _Value]) -> _Value:
        if not self.memoize:
            return compute()
        value = self._memo.get(key, _UNKNOWN)
        if value is _UNKNOWN:
            value = compute()
            if isinstance(value, np.ndarray):
                value.setflags(write=False)
            self._memo[key] = value
        return value  # type: ignore[return-value]

    def rotation(self, side: str, fingers: np.ndarray, palm: np.ndarray) -> np.ndarray:
        """Global hand rotation ``(4,)`` of the hand on ``side`` (``"l"``/``"r"``) whose
        extended fingers point along ``fingers`` ``(3,)`` with the palm toward ``palm``."""
        return self._recall(
            ("rotation", side, key_bytes(fingers), key_bytes(palm)),
            lambda: hand_rotations_from_vectors(self.avatar, side, fingers[None], palm[None])[0],
        )

    def prefetch_rotations(self, fingers: np.ndarray, palms: np.ndarray) -> None:
        """Compute the :meth:`rotation` of every row pair of ``fingers`` and ``palms``
        ``(n, 3)`` not yet known, on both sides, in one vectorized pass per side (a
        collection of signs writes a few thousand pairs); every operation of
        :func:`~motor.arm.hand_orientation.hand_rotations_from_vectors` is row by row, so
        the answers are those of :meth:`rotation`, bit for bit. A pass that fails (a zero
        vector) leaves its pairs to be computed when asked. Does nothing without ``memoize``."""
        if not self.memoize:
            return
        for side in ("l", "r"):
            wanted = {}
            for finger, palm in zip(fingers, palms):
                key = ("rotation", side, finger.tobytes(), palm.tobytes())
                if key not in self._memo:
                    wanted[key] = (finger, palm)
            if not wanted:
                continue
            try:
                rotations = hand_rotations_from_vectors(self.avatar, side, np.array([f for f, _ in wanted.values()]), np.array([p for _, p in wanted.values()]))
            except ValueError:
                continue
            rotations.setflags(write=False)
            self._memo.update(zip(wanted, rotations))

    def params(self, shape: HandShape) -> np.ndarray:
        """Joint parameters of a hand shape (:func:`motor.hand.shape.handshape_params`)."""
        return self._recall(("params", shape), lambda: handshape_params(shape))

    def location(self, location: Location, side: str) -> np.ndarray:
        """The point ``(3,)`` m a location names for the hand on ``side``, body at rest."""
        return self._recall(("location", location, side), lambda: resolve_location(self.avatar, location, side))

    def arm_length(self) -> float:
        """The straight right arm's length (m), the unit of a sign's movement sizes."""
        return self._recall(("arm length",), lambda: self.avatar.arm_length("r"))

    def stopping_length(self, path: np.ndarray) -> float:
        """:func:`motor.signing.lmp.stopping_length` of a wrist or palm path ``(m, 3)``, m
        (:func:`motor.signing.path_batch.stopping_length_of` when memoizing: the same number)."""
        if not self.memoize:
            return stopping_length(path)
        return self._recall(("stopping length", path.shape, key_bytes(path)), lambda: stopping_length_of(path))

    def site_offset(self, side: str, site: BodySite, rotation: np.ndarray, params: np.ndarray) -> np.ndarray:
        """From the wrist to ``site`` of the hand on ``side`` ``(3,)`` m, for the hand's
        global ``rotation`` ``(4,)`` and shape ``params``, the rest of the body at rest."""
        key = _offset_key(side, site, rotation, params)
        if self.deferring and self._unknown(key):
            self._pending_offsets.append((side, site, rotation, params))
            raise GeometryPending(key)
        return self._recall(key, lambda: self._site_offset(side, site, rotation, params))

    def site_offsets(self, requests: Sequence[tuple[str, BodySite, np.ndarray, np.ndarray]]) -> list[np.ndarray]:
        """The :meth:`site_offset` of each ``(side, site, rotation, params)``, in order;
        when memoizing, a request that is the very same tuple as one answered before (a
        sign asks for one posture's offset again and again; :meth:`prefetch_site_offsets`
        answers a collection's) is answered as then, without making its key again."""
        if not self.memoize:
            return [self.site_offset(*request) for request in requests]
        answers = self._answers
        offsets = []
        for request in requests:
            known = answers.get(id(request))
            if known is None or known[0] is not request:
                known = answers[id(request)] = (request, self.site_offset(*request))
            offsets.append(known[1])
        return offsets

    def expect_site_offsets(self, requests: Sequence[tuple[str, BodySite, np.ndarray, np.ndarray]]) -> None:
        """Note the :meth:`site_offset` of each ``(side, site, rotation, params)`` a caller
        is about to ask for: when deferring, every one not yet known is computed by the
        next :meth:`resolve_pending` (the first one asked for still raises
        :class:`GeometryPending`), so that a sign needing several independent offsets, or
        an arm pose beside them, is set aside for one round, not one round each."""
        if not (self.memoize and self.deferring):
            return
        for side, site, rotation, params in requests:
            key = _offset_key(side, site, rotation, params)
            if self._unknown(key):
                self._pending_offsets.append((side, site, rotation, params))

    def _site_offset(self, side: str, site: BodySite, rotation: np.ndarray, params: np.ndarray) -> np.ndarray:
        avatar = self.avatar
        wrist_joint = avatar.joint_index(f"{side}_wrist")
        rotations = identity_rotations(avatar, 1)
        rotations[0, wrist_joint] = rotation
        rotations[0, avatar.hand_joints(side)] = self.finger_rotations(side, params)
        pose = forward_kinematics(avatar, rotations)
        return resolve_location(avatar, site, "l" if side == "r" else "r", pose) - pose.positions[0, wrist_joint]

    def prefetch_site_offsets(self, requests: Sequence[tuple[str, BodySite, np.ndarray, np.ndarray]]) -> None:
        """Compute the :meth:`site_offset` of every ``(side, site, rotation, params)``
        not yet known in one forward-kinematics pass per side and site (a collection of
        signs asks for thousands); each row's arithmetic is that of :meth:`site_offset`,
        so the answers are the same, bit for bit. A request that is the very same tuple as
        one before (a sign asks for one posture's offset again and again) is looked at once,
        and its answer kept for :meth:`site_offsets`. Does nothing without ``memoize``."""
        if not self.memoize:
            return
        missing: dict[tuple[str, BodySite], dict[Hashable, tuple[np.ndarray, np.ndarray]]] = {}
        keys: dict[int, tuple[tuple[str, BodySite, np.ndarray, np.ndarray], Hashable]] = {}  # by the ids of the requests, as :attr:`_answers`
        for request in requests:
            if id(request) in keys:
                continue
            side, site, rotation, params = request
            key = _offset_key(side, site, rotation, params)
            keys[id(request)] = (request, key)
            if key not in self._memo:
                missing.setdefault((side, site), {})[key] = (rotation, params)
        for (side, site), wanted in missing.items():
            try:
                offsets = self._site_offsets(side, site, wanted.values())
            except (SpecError, ValueError, KeyError):
                self._alone.update(wanted)  # asked again, each is computed alone and raises there
                continue
            offsets.setflags(write=False)
            self._memo.update(zip(wanted, offsets))
        for identity, (request, key) in keys.items():
            offset = self._memo.get(key)
            if offset is not None:  # else its pass failed: asked again, it is computed alone
                self._answers[identity] = (request, offset)

    def _site_offsets(self, side: str, site: BodySite, postures: Iterable[tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
        avatar = self.avatar
        postures = list(postures)
        wrist_joint = avatar.joint_index(f"{side}_wrist")
        rotations = identity_rotations(avatar, len(postures))
        rotations[:, wrist_joint] = [rotation for rotation, _ in postures]
        rotations[:, avatar.hand_joints(side)] = [self.finger_rotations(side, params) for _, params in postures]
        pose = forward_kinematics(avatar, rotations)
        return site_points(avatar, site, "l" if side == "r" else "r", pose) - pose.positions[:, wrist_joint]

    def finger_rotations(self, side: str, params: np.ndarray) -> np.ndarray:
        """Local rotations ``(17, 4)`` of the hand's joints for the shape ``params``
        (:func:`motor.hand.shape.hand_rotations` of one row)."""
        return self._recall(
            ("fingers", side, key_bytes(params)),
            lambda: hand_rotations(self.avatar, side, np.asarray(params, dtype=float)[None])[0],
        )

    def arm_pose(self, side: str, wrist: np.ndarray, rotation: np.ndarray, params: np.ndarray) -> Pose:
        """The whole body, one frame, with the arm on ``side`` reaching ``wrist`` ``(3,)``
        with the hand in ``rotation`` ``(4,)`` and shape ``params``; rest elsewhere."""
        key = _pose_key(side, wrist, rotation, params)
        if self.deferring and self._unknown(key):
            self._pending_poses[key] = (side, wrist, rotation, params)
            raise GeometryPending(key)
        return self._recall(key, lambda: self._arm_pose(side, wrist, rotation, params))

    def palm_pose(self, side: str, palm: np.ndarray, offset: tuple[str, BodySite, np.ndarray, np.ndarray], rotation: np.ndarray, params: np.ndarray) -> Pose:
        """:meth:`arm_pose` of the hand in ``rotation`` ``(4,)`` and shape ``params`` with
        the wrist at ``palm`` ``(3,)`` less the :meth:`site_offset` of ``offset`` (``(side,
        site, rotation, params)``, the request the caller's offsets share). When deferring
        and the offset is not known yet, both are noted at once: :meth:`resolve_pending`
        computes the offset first, then the pose at the wrist it gives (the same
        subtraction), so that a sign waits one round for both, not two."""
        key = _offset_key(*offset)
        if self.deferring and self._unknown(key):
            self._pending_offsets.append(offset)
            self._pending_palm_poses.append((palm, key, (side, rotation, params)))
            raise GeometryPending(key)
        return self.arm_pose(side, palm - self.site_offset(*offset), rotation, params)

    def resolve_pending(self) -> bool:
        """Compute every noted site offset and arm pose: one forward-kinematics pass per
        side and site for the offsets (:meth:`prefetch_site_offsets`), one IK and one
        forward-kinematics pass per side for the poses; each row's arithmetic is that of
        the one-by-one computation, so the answers are the same, bit for bit. A pass that
        fails (an avatar without the site, say) leaves its requests to be computed one by
        one when asked again, where each raises for its own sign. Returns whether
        anything was noted."""
        noted = bool(self._pending_offsets or self._pending_poses)
        self.prefetch_site_offsets(self._pending_offsets)
        self._pending_offsets = []
        for palm, offset_key, (side, rotation, params) in self._pending_palm_poses:
            offset = self._memo.get(offset_key)
            if offset is not None:  # else its pass failed: the sign asks again and fails alone
                wrist = palm - offset
                key = _pose_key(side, wrist, rotation, params)
                if self._unknown(key):
                    self._pending_poses[key] = (side, wrist, rotation, params)
        self._pending_palm_poses = []
        by_side: dict[str, dict[Hashable, tuple[str, np.ndarray, np.ndarray, np.ndarray]]] = {}
        for key, request in self._pending_poses.items():
            by_side.setdefault(request[0], {})[key] = request
        self._pending_poses = {}
        avatar = self.avatar
        for side, wanted in by_side.items():
            requests = list(wanted.values())
            try:
                solution = solve_arm(avatar, side, np.array([r[1] for r in requests]), np.array([r[2] for r in requests]))
                rotations = identity_rotations(avatar, len(requests))
                rotations[:, avatar.arm_joints(side)] = solution.rotations
                rotations[:, avatar.hand_joints(side)] = [self.finger_rotations(side, r[3]) for r in requests]
            except (SpecError, ValueError, KeyError):
                self._alone.update(wanted)
                continue
            pose = forward_kinematics(avatar, rotations)
            for index, key in enumerate(wanted):
                self._memo[key] = Pose(pose.positions[index : index + 1], pose.orientations[index : index + 1])
        return noted

    def _arm_pose(self, side: str, wrist: np.ndarray, rotation: np.ndarray, params: np.ndarray) -> Pose:
        avatar = self.avatar
        solution = solve_arm(avatar, side, wrist[None], rotation[None])
        rotations = identity_rotations(avatar, 1)
        rotations[0, avatar.arm_joints(side)] = solution.rotations[0]
        rotations[0, avatar.hand_joints(side)] = self.finger_rotations(side, params)
        return forward_kinematics(avatar, rotations)


def _offset_key(side: str, site: BodySite, rotation: np.ndarray, params: np.ndarray) -> tuple:
    """The memo key of a :meth:`HandGeometry.site_offset`."""
    return ("offset", side, site, key_bytes(rotation), key_bytes(params))


def _pose_key(side: str, wrist: np.ndarray, rotation: np.ndarray, params: np.ndarray) -> tuple:
    """The memo key of a :meth:`HandGeometry.arm_pose`."""
    return ("arm_pose", side, key_bytes(wrist), key_bytes(rotation), key_bytes(params))


def key_bytes(values: np.ndarray) -> bytes:
    """The bytes of ``values`` as float64: a memo key that matches the very same values."""
    if type(values) is np.ndarray and values.dtype == _FLOAT64:  # most keys: skip the conversion
        return values.tobytes()
    return np.asarray(values, dtype=float).tobytes()
