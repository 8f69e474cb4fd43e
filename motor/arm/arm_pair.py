"""Both arms solved frame by frame with the hands kept a palm thickness apart.

The motor control samples the channels' wrist positions and hand rotations (in the
trunk's frame), then :meth:`ArmPair.solve` keeps each hand out of the torso, the hands a
palm thickness apart as asked (:func:`motor.body.collision.hand_separation`) and the
wrists out of the torso, solves both arms' IK on the swivel grid
(:func:`motor.arm.given_swivel.arm_rotations`), and where the hands as the arms turned
them would still meet looks again, moving the wrists apart and solving again. Every
separation is eased in and out over time (:mod:`motor.body.hands_apart`), so a frame's
separation depends on the channel values :func:`separation_margin` frames either side;
frames that go on from frames already shown go on from the separation worked out for
them then (:meth:`ArmPair.hold`). Positions are metres, times seconds.
"""

from __future__ import annotations

import math

import numpy as np

from motor import quaternion as quat
from motor.arm.given_swivel import arm_rotations
from motor.arm.swivel_track import SwivelGrid
from motor.body.avatar import Avatar
from motor.body.collision import hand_push_out_of_torso, hand_separation, hands_may_meet, kept_out_of_torso
from motor.body.conventions import ARMS, AVATAR_SIDE
from motor.body.hands_apart import eased_separation, reach_frames
from motor.held_runs import HeldRuns

#: How much nearer (m) than the palm thickness the hands as the arms turned them may come
#: (:meth:`ArmPair.solve`): they are left alone while they overlap less than
#: that (skin gives; moving the wrists for it would cost a movement that starts from a
#: contact its minimum-jerk start) and never overlap more than that and
#: :data:`motor.body.hands_parting.HAND_BAND` together (5 mm).
REACHED_ALLOWANCE = 0.003
#: Most times, frame by frame, the hands as the arms turned them are moved apart and the
#: arms solved again, to find how far apart the wrists must move (solving again turns the
#: hands anew; :meth:`ArmPair._reached_separation`).
HANDS_APART_ROUNDS = 3
#: Most times the hands as the arms turned them are looked at, each separation found
#: eased in and out over time and the arms solved again: a later look takes up what the
#: one before left — its easing (where the way the hands part turns over), or hands the
#: arms turn anew as the wrists move (SHUT-OR-CLOSED1's crossed index fingers, which the
#: joint limits turn about 100° from the plan: two looks left them 2.7 cm into each
#: other, three 0.1 cm; go-with-you's palms, on max, 0.6 cm into each other after three
#: looks, 0.5 after four). Looks stop once one finds
#: nothing more than :data:`LOOK_TOLERANCE` to do. Each look widens the frames a frame's
#: separation depends on by :func:`motor.body.hands_apart.reach_frames`
#: (:func:`separation_margin`), which every window computes: five looks cost signs a
#: tenth of their synthesis speed, each look about 4 %.
HANDS_APART_LOOKS = 4
#: A look that asks no wrist to move more than this (m, along any axis) is the last one.
LOOK_TOLERANCE = 5e-4
#: Largest acceleration (m/s²) with which the wrists go over from the hands' separation
#: worked out for frames before an activation to the one worked out after it
#: (:meth:`ArmPair._go_on_from_shown`): 0.27 m/s of velocity change per frame at 60 fps,
#: half a speed step; at 12 m/s² `sign_here`'s hands stayed 1.03 cm into each other for a frame.
CROSSFADE_ACCELERATION = 16.0


class ArmPair:
    """Both arms of ``avatar`` at ``fps`` frames per second, on the swivel ``grid``: their
    joint rotations with the hands kept apart (:meth:`solve`)."""

    def __init__(self, avatar: Avatar, fps: float, grid: SwivelGrid) -> None:
        self.avatar = avatar
        self.fps = fps
        self._grid = grid
        self._last = {arm: HeldRuns() for arm in ARMS}
        self._held: tuple[int, np.ndarray] | None = None  # first frame, hands' separation of the frames computed last

    def hold(self, first: int, separation: np.ndarray) -> None:
        """Keep the hands' separation ``(n, 3)`` worked out for frames ``first`` onward (the
        frames computed last), for frames computed again to go on from it."""
        self._held = (first, separation)

    def solve(
        self, values: dict[str, tuple[np.ndarray, np.ndarray]], first: int, last: int, frames: np.ndarray, pick: np.ndarray, shown: int | None
    ) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray], np.ndarray]:
        """Per arm, the wrist positions the IK is given and the arm's joint rotations at
        the frames ``pick`` among ``frames``, from the channels' wrist positions and hand rotations
        ``values`` (the trunk's frame).

        The hands are kept a palm thickness apart — as asked
        (:func:`motor.body.collision.hand_separation` with the asked hand rotations),
        then, where the hands as the arms turned them (not quite as asked, where the joint
        limits fall short) would still come into each other, again with those rotations,
        a few millimetres less strictly (:data:`REACHED_ALLOWANCE`), and the arms solved
        again, up to :data:`HANDS_APART_ROUNDS` times — each separation eased in and out
        over time (:func:`motor.body.hands_apart.eased_separation`: it grows before the
        hands would meet, instead of within one frame) and the wrists then kept out of the
        torso. Where the hands may meet nowhere among ``frames``, only the frames ``pick``
        are solved. Also returns the separation at ``pick`` ``(n, 3)`` (the left wrist's
        move; the right one's is its opposite). ``shown``: the frame after the last one
        handed out, where ``frames`` go on from the frames shown (else None); frames
        about to be shown then go on from the separation worked out for them before
        (:meth:`_go_on_from_shown`, :meth:`hold`)."""
        values = self._hands_out_of_torso(values)
        (left, left_hands), (right, right_hands) = values["left"], values["right"]
        offset = eased_separation(hand_separation(self.avatar, left, right, left_hands, right_hands), self.fps)
        placed = {"left": left + offset, "right": right - offset}
        wrists = {arm: kept_out_of_torso(self.avatar, placed[arm]) for arm in ARMS}
        meeting = hands_may_meet(self.avatar, wrists["left"], wrists["right"])
        solved = pick if not np.any(meeting) else np.arange(frames.size)
        rows, arms = {}, {}
        for arm in ARMS:
            swivel, twist = self._grid.sample(arm, frames[solved], first, last)
            rows[arm] = np.concatenate([wrists[arm][solved], values[arm][1][solved], swivel, twist], axis=1)
            arms[arm] = self._last[arm].apply(lambda rows, side=AVATAR_SIDE[arm]: _solve_rows(self.avatar, side, rows), rows[arm])
        if solved is not pick:
            self._look_again(placed, rows, arms)
            rows, arms = {arm: rows[arm][pick] for arm in ARMS}, {arm: arms[arm][pick] for arm in ARMS}
        separation = placed["left"][pick] - left[pick]
        if shown is not None:
            self._go_on_from_shown(int(round(frames[pick[0]] * self.fps)), shown, separation, {arm: values[arm][0][pick] for arm in ARMS}, rows, arms)
        return {arm: rows[arm][:, :3] for arm in ARMS}, arms, separation

    def _hands_out_of_torso(self, values: dict[str, tuple[np.ndarray, np.ndarray]]) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Channel inputs of consecutive frames with each wrist moved as far as its hand,
        in the asked rotation, needs to stay out of the torso
        (:func:`motor.body.collision.hand_push_out_of_torso`, measured where the torso
        leaves the wrist), that push eased in and out over time as the hands' separation is
        (:func:`motor.body.hands_apart.eased_separation`: a hand turning into the body on
        its way down to rest needs centimetres within a few frames, which pushed at once
        would step the wrist's velocity)."""
        out = {}
        for arm, (wrists, hands) in values.items():
            push = hand_push_out_of_torso(self.avatar, AVATAR_SIDE[arm], wrists, hands)
            out[arm] = (wrists + eased_separation(push, self.fps), hands) if np.any(push) else (wrists, hands)
        return out

    def _look_again(self, placed: dict[str, np.ndarray], rows: dict[str, np.ndarray], arms: dict[str, np.ndarray]) -> None:
        """The looks at the hands as the arms turned them (:meth:`solve`): moves
        ``placed`` (before the torso) and ``rows`` and solves ``arms`` again, in place."""
        for _ in range(HANDS_APART_LOOKS):
            needs = self._reached_separation(placed, rows, arms)
            if not np.any(np.abs(needs) > LOOK_TOLERANCE):
                break
            more = eased_separation(needs, self.fps)
            moved = np.flatnonzero(np.any(more != 0.0, axis=1))
            for arm, sign in (("left", 1.0), ("right", -1.0)):
                placed[arm][moved] += sign * more[moved]
                rows[arm][moved, :3] = kept_out_of_torso(self.avatar, placed[arm][moved])
                arms[arm][moved] = self._solved(arm, rows[arm][moved])

    def _go_on_from_shown(
        self, start: int, shown: int, separation: np.ndarray, channel: dict[str, np.ndarray], rows: dict[str, np.ndarray], arms: dict[str, np.ndarray]
    ) -> None:
        """Frames from ``start`` on whose hands' separation ``(n, 3)`` (the left wrist's;
        the right one's is its opposite) differs from the one worked out for them before,
        when frames up to ``start`` have been shown (``shown`` is the frame after the last
        one handed out): an LMP activated since then changed
        what lies ahead, which the shown frames could not anticipate. The separation then
        goes over from the one before to the new one (C², :func:`_smootherstep`) instead
        of jumping, as fast as :data:`CROSSFADE_ACCELERATION` allows (the hands are apart
        as they should be the sooner), within :func:`motor.body.hands_apart.reach_frames`
        frames; ``separation``, ``rows`` (from the channel's wrists ``channel``) and
        ``arms`` are changed in place."""
        if self._held is None or start != shown:
            return
        held_from, held = self._held
        skip = start - held_from
        count = min(reach_frames(self.fps), held.shape[0] - skip, separation.shape[0])
        if skip < 0 or count <= 0:
            return
        before, after = held[skip : skip + count], separation[:count].copy()
        if np.array_equal(before, after):
            return
        gap = float(np.max(np.linalg.norm(after - before, axis=1)))
        frames = min(count, math.ceil(self.fps * math.sqrt(_SMOOTHERSTEP_CURVATURE * gap / CROSSFADE_ACCELERATION)))
        share = _smootherstep(np.arange(1, frames + 1) / (frames + 1))[:, None]
        separation[:frames] = before[:frames] + share * (after[:frames] - before[:frames])
        changed = np.flatnonzero(np.any(separation[:count] != after, axis=1))
        for arm, sign in (("left", 1.0), ("right", -1.0)):
            rows[arm][changed, :3] = kept_out_of_torso(self.avatar, channel[arm][changed] + sign * separation[changed])
            arms[arm][changed] = self._solved(arm, rows[arm][changed])

    def _reached_separation(self, placed: dict[str, np.ndarray], rows: dict[str, np.ndarray], arms: dict[str, np.ndarray]) -> np.ndarray:
        """How far ``(n, 3)`` the left wrist placed at ``placed["left"]`` (before the torso;
        the right one the other way) must move for the hands as the arms turn them
        (``arms``: joint rotations solved from ``rows``) to come no nearer than the palm
        thickness less :data:`REACHED_ALLOWANCE` where the torso then leaves the wrists
        (its push may carry one hand into the other): found frame by frame, moving the wrists
        and solving the arms again up to :data:`HANDS_APART_ROUNDS` times, as solving again
        turns the hands anew. Only the frames where the hands may meet are looked at."""
        total = np.zeros((rows["left"].shape[0], 3))
        near = np.flatnonzero(hands_may_meet(self.avatar, rows["left"][:, :3], rows["right"][:, :3]))
        turned_arms = {arm: arms[arm][near] for arm in ARMS}
        trial = {arm: rows[arm][near] for arm in ARMS}
        for _ in range(HANDS_APART_ROUNDS):
            if near.size == 0:
                break
            reached = {arm: _chain_rotation(turned_arms[arm]) for arm in ARMS}
            # measured where the torso leaves the wrists (it may push one into the other)
            more = hand_separation(self.avatar, trial["left"][:, :3], trial["right"][:, :3], reached["left"], reached["right"], REACHED_ALLOWANCE)
            moved = np.any(more != 0.0, axis=1)
            if not np.any(moved):
                break
            near, more = near[moved], more[moved]
            total[near] += more
            for arm, sign in (("left", 1.0), ("right", -1.0)):
                trial[arm] = trial[arm][moved]
                trial[arm][:, :3] = kept_out_of_torso(self.avatar, placed[arm][near] + sign * total[near])
                turned_arms[arm] = self._solved(arm, trial[arm])
        return total

    def _solved(self, arm: str, rows: np.ndarray) -> np.ndarray:
        """The arm's joint rotations ``(n, 4, 4)`` for IK input rows (:func:`_solve_rows`)."""
        side = AVATAR_SIDE[arm]
        return HeldRuns().apply(lambda rows: _solve_rows(self.avatar, side, rows), rows)


def _solve_rows(avatar: Avatar, side: str, rows: np.ndarray) -> np.ndarray:
    """Arm joint rotations ``(n, 4, 4)`` from rows of wrist, hand rotation, swivel, the
    swivel's zero and the twist's reference (:meth:`motor.control.MotorControl._rotations`): the
    compiled :func:`motor.arm.given_swivel.arm_rotations`, as the trunk's frame is upright."""
    return arm_rotations(avatar, side, rows[:, :3], rows[:, 3:7], rows[:, 7], rows[:, 8:11], rows[:, 11:15])


def separation_margin(fps: float) -> int:
    """Frames either side of a frame whose channel values its hands' separation depends
    on at ``fps``: the reach of each eased separation (:func:`motor.body.hands_apart.reach_frames`),
    once for the look as asked and once per look as the arms turned the hands."""
    return (1 + HANDS_APART_LOOKS) * reach_frames(fps)


#: Largest second derivative of :func:`_smootherstep` on [0, 1] (10 / √3).
_SMOOTHERSTEP_CURVATURE = 10.0 / math.sqrt(3.0)


def _smootherstep(u: np.ndarray) -> np.ndarray:
    """0 at 0, 1 at 1, with zero slope and curvature at both ends (C²)."""
    return u * u * u * (u * (6.0 * u - 15.0) + 10.0)


def _chain_rotation(local: np.ndarray) -> np.ndarray:
    """Global rotations ``(n, 4)`` of the last of a chain's local rotations ``(n, k, 4)``
    below an unturned parent (the trunk's frame)."""
    total = local[:, 0]
    for index in range(1, local.shape[1]):
        total = quat.multiply(total, local[:, index])
    return total
