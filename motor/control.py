"""Motor control: the object the scheduler calls to plan, activate and sample gestures.

:class:`MotorControl` keeps one :class:`motor.program.lmp.ChannelTimeline` per channel of each
arm — wrist position, hand rotation, hand shape — holding every LMP activated so far.
Each :meth:`MotorControl.frames` call runs the per-frame order of seed 004 (Fig. 4) for
all frames of the window at once: first the externally formulated LMPs (wrist position,
wrist rotation) are sampled; where a hand reaches across the body the trunk turns toward
it (:mod:`motor.arm.reach_turn`) and the arms are solved in the trunk's frame; the wrists
are kept out of the torso and the hands a palm thickness apart (:mod:`motor.body.collision`);
then both arms' IK is solved (analytic, with the swivel track below) — and solved again
where the hands as the arms turned them would still meet (:mod:`motor.arm.arm_pair`); then the joint-space LMPs (hand
shape → finger joint rotations) are applied; then the neck module (:mod:`motor.neck`)
turns torso, shoulders, neck, head and eyes (composed onto the trunk's turn), and the
face module (:mod:`motor.face`) gives the frame's ARKit morph weights; every other joint
keeps its rest rotation and the root stands still at ``(0, root_height, 0)``.

Head and face: :meth:`MotorControl.plan` adds to each program the neck LMPs and face
tracks of the behaviour's head and face slots (MURML ``GazeDirection``, ``Neck`` …,
:mod:`motor.neck.planning`, :mod:`motor.face.planning`) or of its sign's non-manual tiers
(:mod:`motor.signing.nonmanual`); a gaze shift counts in the preparation time.
:meth:`MotorControl.speak` adds a chunk's lip-sync, the brow raise and a small head beat
on its accented words, and its boundary blink.

The elbow's swivel is a smooth function of time by construction: both arms' swivel
tracks and forearm twists live on a fixed grid of the utterance clock, every
:data:`motor.arm.swivel_track.SWIVEL_PERIOD` seconds (:mod:`motor.arm.swivel_track`).
Frames between grid points take the swivel by a Catmull-Rom spline (C¹) and the twist
from the grid (:meth:`motor.arm.swivel_track.SwivelGrid.sample`); wrist positions and
hand rotations are exact at every frame. Runs of identical channel values (holds, rest)
are solved once and repeated, which is exact.

A grid state depends on the state before it and on channel values up to
:data:`motor.arm.swivel_track.TRACK_REACH` grid points ahead, nothing else; so frames
depend only on their times and the activated LMPs, and sampling window after window
gives exactly the frames of one call over the whole span. The tracks start at the first
grid point asked for. Activating an LMP forgets the grid states that could see its start
— except those that frames already handed out used, which stay: the motion goes on from
where it was shown.

Frames and grid states are computed ahead of the window asked for
(:data:`FRAME_LOOKAHEAD`, :data:`motor.arm.swivel_track.SWIVEL_LOOKAHEAD`), so that short windows share the
fixed cost of one computation; activating an LMP forgets what was computed ahead from
where it can change things. While windows keep using up what was computed ahead with
nothing changing it, each computation looks :data:`LOOKAHEAD_GROWTH` times as far ahead
as the one before (up to :data:`MAX_FRAME_LOOKAHEAD`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from motor import quaternion as quat
from motor.arm.arm_pair import ArmPair, separation_margin
from motor.arm.ik import swivel_of, swivel_zeros
from motor.arm.reach_turn import TURN_JOINTS, trunk_turn, turned
from motor.arm.swivel_track import SWIVEL_PERIOD, TRACK_REACH, SwivelGrid
from motor.face.arkit import FACE_NAMES
from motor.face.control import FaceControl
from motor.face.planning import plan_face
from motor.neck.control import NeckControl
from motor.neck import gaze as neck_gaze
from motor.neck.lexemes import head_lexeme
from motor.neck.planning import NeckPlanner
from motor.body.avatar import Avatar
from motor.body.conventions import ARMS, AVATAR_SIDE
from motor.body.collision import hand_push_out_of_torso, kept_out_of_torso, separate_hands
from motor.hand.shape import hand_rotations
from motor.held_runs import HeldRuns
from motor.motion import Motion
from motor.program.fragment import first_location
from motor.program.gesture import (
    GestureDemands,
    MotorProgram,
    Planner,
    rest_handshape,
    retraction_duration,
    retraction_lmp,
)
from motor.program.lmp import (
    LMP,
    ChannelState,
    ChannelTimeline,
    TimePegs,
)
from motor.signing.behavior import SignBehaviorPlanner
from motor.signing.lmp import SignChannelLMP
from motor.signing.nonmanual import plan_nonmanuals
from motor.signing.track_batch import activate_in_turn, sample_tracks
from motor.trajectory.spline import fitts_duration
from motor.verbs.behavior import VerbBehaviorPlanner
from mura.model import BehaviorSpec
from tts.speech import SpeechTiming

#: The channels of one arm, in sampling order (externally formulated ones first).
ARM_CHANNELS: tuple[str, ...] = ("wrist_position", "hand_rotation", "handshape")
#: How far back (s) from the start of the latest window the LMP history is kept; covers
#: the swivel grid's margin.
HISTORY = 1.0
#: LMPs that lost control are dropped once a channel has this many of them (or all but
#: its last): each drop computes the channel's state where its history now starts (about
#: 1 ms for the arm channels), so dropping several at a time spares that work — streamed
#: 0.1 s windows about 5 % faster at 8 than at 2 — while memory stays flat all the same
#: (a channel keeps at most this many spent LMPs, some 40 kB each).
FORGET_BATCH = 8
#: How far past a window's start frames are computed ahead, seconds: later windows are
#: then served from them until an activation changes what they would be.
FRAME_LOOKAHEAD = 2.0
#: Each time the frames computed ahead are used up with nothing activated that changed
#: them, the next computation looks :data:`LOOKAHEAD_GROWTH` times as far ahead, up to
#: :data:`MAX_FRAME_LOOKAHEAD` seconds: a stream of short windows over activated programs
#: then pays the fixed cost of a computation (about 9 ms) a few times, not every
#: :data:`FRAME_LOOKAHEAD` seconds. Twofold, not more: where programs keep being activated
#: (the scheduler's chunks) what was computed ahead past the next activation is thrown
#: away (rendering the example utterances in 0.1 s windows: 1.3 frames computed per frame
#: handed out at twofold, 2.7 at fourfold). Memory: frames × joints × 32 bytes (16 s at
#: 60 fps, 55 joints: 1.7 MB). A computation looks no further than
#: :data:`FRAME_LOOKAHEAD` past the end of the arms' last activated LMP, and the look-ahead
#: then starts over (:meth:`MotorControl._lookahead_frames`): streaming the bench's
#: 37.5 s utterance in 0.1 s windows solved 2,760 frames for 2,250 shown, now 2,279.
LOOKAHEAD_GROWTH = 2.0
MAX_FRAME_LOOKAHEAD = 16.0
#: Frames solved in one pass: a long span is solved this many frames at a time, which
#: gives the same frames (they depend only on their times and the activated LMPs, module
#: docstring) with per-frame arrays that stay in the CPU's cache.
FRAME_CHUNK = 2048
#: Frame times are ``k / fps``; a time within this of a frame counts as on it.
_FRAME_TOLERANCE = 1e-9
#: Module of a channel that is not an arm's: its LMPs go to the neck or the face.
_NONMANUAL = ("neck", "face")
#: The head beat on an accented vowel starts this long before it and ends this long after, s.
BEAT_LEAD, BEAT_TAIL = 0.15, 0.2
#: Fitts' law ``T = FITTS_SCALE · ln(FITTS_AMPLITUDE · A + 1)`` (motor.trajectory.spline), inverted
#: to express a gaze shift's time as the wrist distance the scheduler times preparations from.
FITTS_SCALE, FITTS_AMPLITUDE = 0.24, 100.0
#: Nothing of a chunk's face shows earlier than this before its speech onset, s (the
#: articulation's lead-in: a pause, the anticipation and the dominance's reach).
SPEECH_REACH = 1.0


class MotorControl:
    """Plans gestures into motor programs and renders the activated programs as frames.

    Implements the scheduler's motor contract (``blackboard.planning.MotorControl``)
    structurally. Times are seconds on the utterance clock; ``fps`` frames per second.
    """

    def __init__(self, avatar: Avatar, fps: float = 60.0, face_seed: int = 0) -> None:
        if not fps > 0:
            raise ValueError(f"fps must be positive, got {fps}")
        self.avatar = avatar
        self.fps = float(fps)
        self.planner = Planner(avatar)
        self.signs = SignBehaviorPlanner(avatar)
        self.verbs = VerbBehaviorPlanner(avatar)
        self.neck = NeckControl(avatar, self.palm_centres)
        self.neck_planner = NeckPlanner(self.neck)
        self.face = FaceControl(face_seed)
        self._palm_offset = {arm: _palm_offset(avatar, AVATAR_SIDE[arm]) for arm in ARMS}
        self._initial = self._rest_states()
        self._lmps: dict[tuple[str, str], list[LMP]] = {channel: [] for channel in self._initial}
        self._timelines: dict[tuple[str, str], ChannelTimeline] = {}
        self._pending: dict[tuple[str, str], list[LMP]] = {channel: [] for channel in self._initial}
        self._grid = SwivelGrid(avatar)
        self._committed = -(10**9)  # last grid index that frames handed out used
        self._ahead: tuple[int, np.ndarray, np.ndarray] | None = None  # first frame index, rotations, face weights
        self._lookahead = FRAME_LOOKAHEAD  # seconds the next computation looks ahead
        self._next_frame = 0  # the frame after the last one handed out
        self._parents = tuple(int(p) for p in avatar.parents)
        self._forget_from = -math.inf  # no arm LMP loses control before this horizon (s)
        self._arms = ArmPair(avatar, self.fps, self._grid)
        self._last_hand = {arm: HeldRuns() for arm in ARMS}
        self._arm_joints = {arm: avatar.arm_joints(AVATAR_SIDE[arm]) for arm in ARMS}
        self._hand_joints = {arm: avatar.hand_joints(AVATAR_SIDE[arm]) for arm in ARMS}
        self._trunk_joints = np.array([avatar.joint_index(name) for name in TURN_JOINTS])
        rest = np.zeros((avatar.joint_count, 4))
        rest[:, 3] = 1.0
        self._rest_rotations = rest
        self._root = np.array([0.0, avatar.root_height, 0.0])

    def _rest_states(self) -> dict[tuple[str, str], ChannelState]:
        states = {}
        for arm in ARMS:
            rest = self.avatar.postures["rest"][AVATAR_SIDE[arm]]
            states[(arm, "wrist_position")] = ChannelState.at_rest(rest.wrist)
            states[(arm, "hand_rotation")] = ChannelState.at_rest(rest.hand_rotation, rotation=True)
            states[(arm, "handshape")] = ChannelState.at_rest(rest_handshape())
        return states

    # -- planning -----------------------------------------------------------------------

    def demands(self, behavior: BehaviorSpec) -> GestureDemands:
        """Arms, natural stroke duration and preparation distance of ``behavior``."""
        if behavior.spatial is not None:
            return self.verbs.demands(behavior)
        if behavior.sign is not None:
            return self.signs.demands(behavior)
        return self.planner.demands(behavior)

    def preparation_distances(self, behavior: BehaviorSpec, at_time: float) -> dict[str, float]:
        """Per arm, metres from where the wrist will be at ``at_time`` (given the programs
        activated so far) to the start of the stroke; arms the stroke leaves free are absent.

        A behaviour that shifts the gaze (:mod:`motor.neck.planning`) adds ``"gaze"``: the
        wrist distance whose Fitts' law time is the time eyes and head need to get on the
        target, so that the scheduler, which times preparations from distances, leaves them
        that time before the stroke."""
        if behavior.spatial is not None:
            targets = self.verbs.first_wrists(behavior)
        elif behavior.sign is not None:
            targets = self.signs.first_wrists(behavior)
        else:
            fragment = self.planner.fragment(behavior)
            targets = {arm: first_location(fragment, arm) for arm in ARMS}
        distances = {
            arm: float(np.linalg.norm(target - self.timeline((arm, "wrist_position")).state(at_time).value))
            for arm, target in targets.items() if target is not None
        }
        gaze = self.neck_planner.preparation(behavior.id, behavior.gesture.constraints, at_time) if behavior.gesture is not None else 0.0
        if gaze > 0.0:
            distances["gaze"] = float(np.expm1(gaze / FITTS_SCALE) / FITTS_AMPLITUDE)
        return distances

    def preparation_duration(self, behavior: BehaviorSpec, at_time: float) -> float:
        """Fitts' law time (s) from where the arms will be at ``at_time`` (given the
        programs activated so far) to the start of the stroke; the slowest arm counts, or
        the gaze shift the behaviour asks for when longer."""
        return max((float(fitts_duration(d)) for d in self.preparation_distances(behavior, at_time).values()), default=0.0)

    def plan(
        self, behavior: BehaviorSpec, pegs: TimePegs, *, repetitions: int = 1, next_gesture_follows: bool = False
    ) -> MotorProgram:
        """The motor program performing ``behavior`` on ``pegs`` (see :mod:`motor.program.gesture`;
        a sign behaviour: :mod:`motor.signing.behavior`; pointing and indicating verbs:
        :mod:`motor.verbs.behavior`)."""
        if behavior.spatial is not None:
            program = self.verbs.plan(behavior, pegs, next_gesture_follows)
        elif behavior.sign is not None:
            program = self.signs.plan(behavior, pegs, next_gesture_follows)
        else:
            states = {arm: self.timeline((arm, "wrist_position")).state(pegs.start) for arm in ARMS}
            program = self.planner.plan(behavior, pegs, repetitions, next_gesture_follows, start_states=states)
        return self._with_head_and_face(behavior, program)

    def _with_head_and_face(self, behavior: BehaviorSpec, program: MotorProgram) -> MotorProgram:
        """``program`` with the neck LMPs and face tracks of ``behavior`` added (module docstring)."""
        pegs = program.pegs
        if behavior.sign is not None:
            sign = behavior.sign
            dominant = sign.dominant.side
            nonmanual = plan_nonmanuals(self.avatar, sign.gloss, sign.nonmanual, pegs.start, pegs.stroke_start, pegs.stroke_end,
                                        self.palm_centres, dominant, sign.where)  # fmt: skip
            lmps, notes = nonmanual.lmps, nonmanual.warnings
        else:
            tree = behavior.gesture.constraints if behavior.gesture is not None else None
            neck = self.neck_planner.plan(behavior.id, tree, pegs)
            face = plan_face(behavior.id, tree, pegs)
            lmps, notes = [*neck.lmps, *face.tracks], [*neck.warnings, *face.warnings]
        if not lmps and not notes:
            return program
        return replace(program, lmps=(*program.lmps, *lmps), warnings=(*program.warnings, *notes))

    def speak(self, speech: SpeechTiming, onset: float, accents: Sequence[tuple[float, float]] = ()) -> tuple[str, ...]:
        """Lip-sync of a chunk's speech starting at ``onset`` (seconds), a brow raise and a
        head beat (unless a head lexeme already moves the head then) on each accented span
        ``(start, end)``, a blink at its end
        (:meth:`motor.face.control.FaceControl.speak`); call it before frames at ``onset``
        are sampled. Returns what was done instead of something asked, said once."""
        self._forget_ahead_from(onset - SPEECH_REACH)
        notes, peaks = self.face.speak(speech, onset, accents)
        for peak in peaks:
            if not self.neck.head_moves(peak):
                self._forget_ahead_from(self.neck.activate(head_lexeme("BEAT", peak - BEAT_LEAD, peak + BEAT_TAIL)))
        return notes

    def palm_centres(self, arm: str, times: np.ndarray) -> np.ndarray:
        """Where the palm of ``arm`` is asked to be at sorted ``times`` (metres): the wrist
        channel, kept out of the torso, moved by the hand rotation to the palm's centre
        (what gaze follows: the trunk's turn and the hands' separation, a few
        centimetres at most, are left out)."""
        wrists = kept_out_of_torso(self.avatar, _sample(self.timeline((arm, "wrist_position")), times))
        hands = quat.normalize(_sample(self.timeline((arm, "hand_rotation")), times))
        return wrists + quat.rotate(hands, self._palm_offset[arm])

    # -- execution ----------------------------------------------------------------------

    def activate(self, program: MotorProgram) -> None:
        """Hand the program's LMPs to their channels; each starts itself at its start peg."""
        for lmp in program.lmps:
            channel = tuple(lmp.channel)
            if channel not in self._lmps and channel[0] not in _NONMANUAL:
                raise ValueError(f"program {program.behavior!r}: no channel {channel} on this avatar")
        for lmp in program.lmps:
            channel = tuple(lmp.channel)
            if channel[0] in _NONMANUAL:
                module = self.neck if channel[0] == "neck" else self.face
                self._forget_ahead_from(module.activate(lmp))
                continue
            self._lmps[channel].append(lmp)
            self._pending[channel].append(lmp)
            self._changed(channel, lmp.pegs.start)

    def _changed(self, channel: tuple[str, str], since: float) -> None:
        """The channel's values from ``since`` on are no longer known: forget the grid
        states that could see them (:data:`TRACK_REACH` grid points before; earlier values
        are unchanged: an LMP only takes control at its start), except those that frames
        already handed out used, and the frames computed ahead from those states on."""
        self._forget_from = -math.inf
        first = max(math.floor(since / SWIVEL_PERIOD - _FRAME_TOLERANCE) - TRACK_REACH, self._committed + 1)
        self._grid.forget_from(first)
        # a frame's swivel is interpolated from grid points up to two periods after it, and
        # its hands' separation depends on the frames up to a margin after it
        self._forget_ahead_from((first - 2) * SWIVEL_PERIOD - separation_margin(self.fps) / self.fps)

    def _forget_ahead_from(self, since: float) -> None:
        """Drop the frames computed ahead from time ``since`` on (something changes them)."""
        if self._ahead is None:
            return
        held, rotations, faces = self._ahead
        kept = max(0, math.ceil(since * self.fps - _FRAME_TOLERANCE) - held)
        if kept < rotations.shape[0]:
            self._lookahead = FRAME_LOOKAHEAD
        self._ahead = (held, rotations[:kept], faces[:kept]) if kept else None

    def timeline(self, channel: tuple[str, str]) -> ChannelTimeline:
        """The channel's timeline of everything activated so far (built on demand; LMPs
        starting no earlier than every one before them are appended to it)."""
        pending = self._pending[channel]
        if not pending and channel in self._timelines:
            return self._timelines[channel]
        built = self._timelines.get(channel)
        if built is not None and all(a.pegs.start <= b.pegs.start for a, b in zip(built.lmps[-1:] + tuple(pending), pending)):
            built = _extended(built, pending)
        elif all(isinstance(lmp, SignChannelLMP) for lmp in self._lmps[channel]) and _in_order(self._lmps[channel]):
            built = _extended(ChannelTimeline(channel, self._initial[channel], (), (), np.empty(0)), self._lmps[channel])
        else:
            built = ChannelTimeline.build(channel, self._lmps[channel], self._initial[channel])
        self._timelines[channel] = built
        pending.clear()
        return built

    def busy_until(self, arm: str) -> float:
        """When the arm's last activated LMP ends (retraction included); 0 if never used."""
        if arm not in ARMS:
            raise ValueError(f"arm must be one of {ARMS}, got {arm!r}")
        return max((lmp.pegs.end for name in ARM_CHANNELS for lmp in self._lmps[(arm, name)]), default=0.0)

    def interrupt(self, at_time: float) -> None:
        """Stop every gesture at ``at_time``: LMPs starting later are dropped and each arm
        that is away from rest retracts from where it is then, in Fitts' law time; the
        gaze goes back to rest and head and face movements not yet begun are dropped."""
        self.neck.interrupt(at_time, neck_gaze.gaze(self.avatar, neck_gaze.rest(self.avatar), at_time, returning=True))
        self.face.interrupt(at_time)
        self._forget_ahead_from(at_time)
        for arm in ARMS:
            channels = [(arm, name) for name in ARM_CHANNELS]
            if not any(lmp.pegs.end > at_time for channel in channels for lmp in self._lmps[channel]):
                continue
            wrist = self.timeline((arm, "wrist_position")).state(at_time).value
            rest = self.avatar.postures["rest"][AVATAR_SIDE[arm]]
            pegs = TimePegs.movement(at_time, at_time + retraction_duration(float(np.linalg.norm(wrist - rest.wrist))))
            for channel in channels:
                kept = [lmp for lmp in self._lmps[channel] if lmp.pegs.start < at_time]
                self._lmps[channel] = [*kept, retraction_lmp(self.avatar, channel, pegs, "rest")]
                self._timelines.pop(channel, None)
                self._pending[channel].clear()
                self._changed(channel, at_time)

    def frame_times(self, start: float, end: float) -> np.ndarray:
        """Frame times ``k / fps`` in ``[start, end)``."""
        first = math.ceil(start * self.fps - _FRAME_TOLERANCE)
        stop = math.ceil(end * self.fps - _FRAME_TOLERANCE)
        return np.arange(first, max(first, stop)) / self.fps

    def frames(self, start: float, end: float) -> Motion:
        """Frames at times ``k / fps`` in ``[start, end)`` from everything activated so far."""
        times = self.frame_times(start, end)
        count = times.size
        first = math.ceil(start * self.fps - _FRAME_TOLERANCE)
        rotations, face = self._rotations_ahead(first, count)
        if count:
            self._committed = max(self._committed, self._grid_span(times)[1])
            self._next_frame = first + count
            self._forget_before(float(times[0]) - HISTORY)
        if count and not np.isfinite(rotations).all():
            bad = float(times[np.argmax(~np.all(np.isfinite(rotations), axis=(1, 2)))])
            raise FloatingPointError(f"non-finite joint rotation at t = {bad:.4f} s")
        return Motion(
            fps=self.fps,
            joint_names=self.avatar.joint_names,
            parents=self._parents,
            offsets=np.asarray(self.avatar.offsets),
            rotations=rotations,
            root_translation=np.repeat(self._root[None], count, axis=0),
            start_time=float(times[0]) if count else float(start),
            face_names=FACE_NAMES,
            face_weights=face,
        )

    def _rotations_ahead(self, first: int, count: int) -> tuple[np.ndarray, np.ndarray]:
        """Joint rotations and face weights of frames ``first … first + count − 1``: from the
        frames computed ahead when they hold them, else computed now with the frames
        after them (:meth:`_lookahead_frames`; arms, then neck and face)."""
        if count and self._ahead is not None:
            held, rotations, faces = self._ahead
            if held <= first and first + count <= held + rotations.shape[0]:
                return rotations[first - held : first - held + count].copy(), faces[first - held : first - held + count].copy()
        if count == 0:
            return np.empty((0, self.avatar.joint_count, 4)), np.empty((0, len(FACE_NAMES)))
        if self._ahead is not None and self._ahead[0] <= first <= self._ahead[0] + self._ahead[1].shape[0]:
            self._lookahead = min(LOOKAHEAD_GROWTH * self._lookahead, MAX_FRAME_LOOKAHEAD)  # used up, unchanged: look further
        ahead = self._lookahead_frames(first)
        if ahead < math.ceil(self._lookahead * self.fps):  # the arms come to rest: the look-ahead starts over
            self._lookahead = FRAME_LOOKAHEAD
        total = max(count, ahead)
        times = np.arange(first, first + total) / self.fps
        rotations = self.neck.pose(times, self._rotations(times))
        faces = self.face.weights(times)
        if total == count:  # nothing ahead to keep
            self._ahead = None
            return rotations, faces
        self._ahead = (first, rotations, faces)
        return rotations[:count].copy(), faces[:count].copy()

    def _lookahead_frames(self, first: int) -> int:
        """How many frames from frame ``first`` on a computation makes: :attr:`_lookahead`
        seconds' worth, or, where the arms' last activated LMP ends sooner, up to
        :data:`FRAME_LOOKAHEAD` past that end (and at least that long). A stream that ends
        there — an utterance rendered to its end — would otherwise pay for up to
        :data:`MAX_FRAME_LOOKAHEAD` seconds that nobody asks for."""
        ahead = math.ceil(self._lookahead * self.fps)
        busy = max(self.busy_until(arm) for arm in ARMS) + FRAME_LOOKAHEAD
        until = math.ceil(busy * self.fps - _FRAME_TOLERANCE) - first
        return ahead if until >= ahead else max(until, math.ceil(FRAME_LOOKAHEAD * self.fps))

    def _rotations(self, times: np.ndarray) -> np.ndarray:
        """Joint rotations ``(n, J, 4)`` at frame times ``times`` (module docstring: the
        per-frame order), solved :data:`FRAME_CHUNK` frames at a time; the hands'
        separation of these frames is kept, for frames computed again after an activation
        to go on from it (:meth:`motor.arm.arm_pair.ArmPair.hold`)."""
        if times.size == 0:
            return np.empty((0, self.avatar.joint_count, 4))
        solved = [self._solve_frames(times[start : start + FRAME_CHUNK], continued=start == 0) for start in range(0, times.size, FRAME_CHUNK)]
        self._arms.hold(int(round(times[0] * self.fps)), np.concatenate([part[3] for part in solved]))
        return np.concatenate([part[0] for part in solved]) if len(solved) > 1 else solved[0][0]

    def _solve_frames(self, times: np.ndarray, continued: bool = False) -> tuple[np.ndarray, dict[str, np.ndarray], np.ndarray, np.ndarray]:
        """Joint rotations ``(n, J, 4)`` at sorted frame times ``times`` (``k / fps``), the
        wrist positions each arm was given ``(n, 3)`` (the trunk's frame), the trunk's yaw
        ``(n,)`` and the hands' separation ``(n, 3)`` (:meth:`motor.arm.arm_pair.ArmPair.solve`; with
        ``continued`` they go on from the frames shown). The arms' inputs are worked out over the frames
        around them too (:meth:`_separation_frames`), as the hands' separation at a frame
        depends on the frames around it."""
        frames, pick = self._separation_frames(times)
        first, last = self._grid_span(frames)
        plan = self._grid.plan(first, last)
        if plan is None:
            values, yaw = self._channel_inputs(frames)
        else:
            # the frames and the grid points still to solve, sampled in one pass
            grid = self._grid.times(plan[0], plan[1])
            merged = np.concatenate([frames, grid])
            order = np.argsort(merged, kind="stable")
            back = np.empty_like(order)
            back[order] = np.arange(order.size)
            sampled, yaw = self._channel_inputs(merged[order])
            values = {arm: tuple(v[back[: frames.size]] for v in pair) for arm, pair in sampled.items()}
            self._grid.solve(*plan, self._kept_apart({arm: tuple(v[back[frames.size :]] for v in pair) for arm, pair in sampled.items()}), _turning(yaw[back[frames.size :]]))
            yaw = yaw[back[: frames.size]]
        rotations = np.empty((times.size, self.avatar.joint_count, 4))
        rotations[:] = self._rest_rotations
        turn = turned(self.avatar, yaw[pick])
        if turn is not None:
            rotations[:, self._trunk_joints] = turn.local_rotations()
        given, arms, separation = self._arms.solve(values, first, last, frames, pick, self._next_frame if continued else None)
        for arm in ARMS:
            side = AVATAR_SIDE[arm]
            rotations[:, self._arm_joints[arm]] = arms[arm]
            params = _sample(self.timeline((arm, "handshape")), times)
            rotations[:, self._hand_joints[arm]] = self._last_hand[arm].apply(
                lambda rows, side=side: hand_rotations(self.avatar, side, rows), params
            )
        return rotations, given, yaw[pick], separation

    def _separation_frames(self, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The frame times the hands' separation at sorted frame times ``times`` depends
        on — from :func:`motor.arm.arm_pair.separation_margin` frames before the first (not before frame 0)
        to as many after the last — and where ``times`` lie among them. ValueError for
        times that are not frames ``k / fps``."""
        index = np.rint(np.asarray(times, dtype=float) * self.fps)
        if times.size == 0:
            return np.zeros(0), np.zeros(0, dtype=int)
        if np.max(np.abs(index / self.fps - times)) > _FRAME_TOLERANCE:
            raise ValueError(f"times must be frame times k / {self.fps:g} s")
        margin = separation_margin(self.fps)
        low = max(int(index[0]) - margin, min(int(index[0]), 0))
        return np.arange(low, int(index[-1]) + margin + 1) / self.fps, index.astype(int) - low

    def wrist_targets(self, times: np.ndarray) -> dict[str, np.ndarray]:
        """Per arm, the wrist positions ``(n, 3)`` (avatar frame) the IK is given at sorted
        frame times ``times``: the wrist channel's, the hands a palm thickness apart (as
        asked, and as the arms turn them) and kept out of the torso."""
        _, wrists, yaw, _ = self._solve_frames(np.asarray(times, dtype=float))
        turn = turned(self.avatar, yaw)
        return wrists if turn is None else {arm: turn.from_trunk(points) for arm, points in wrists.items()}

    def _channel_inputs(self, times: np.ndarray) -> tuple[dict[str, tuple[np.ndarray, np.ndarray]], np.ndarray]:
        """Per arm, the wrist channel's positions and the hand channel's rotations at
        sorted ``times``, carried into the frame of the trunk turned where a hand reaches
        across the body (:mod:`motor.arm.reach_turn`), and the trunk's yaw ``(n,)``."""
        values = {arm: (_sample(self.timeline((arm, "wrist_position")), times), _sample(self.timeline((arm, "hand_rotation")), times)) for arm in ARMS}
        turn = trunk_turn(self.avatar, values["left"][0], values["right"][0])
        if turn is None:
            return values, np.zeros(times.size)
        return {arm: (turn.to_trunk(wrists), turn.hands_to_trunk(hands)) for arm, (wrists, hands) in values.items()}, turn.yaw

    def _kept_apart(self, values: dict[str, tuple[np.ndarray, np.ndarray]]) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Channel inputs (:meth:`_channel_inputs`) with the hands a palm thickness apart,
        instant by instant, and the wrists and hands kept out of the torso (a path between
        targets may cut through it; :mod:`motor.body.collision`): what the swivel's grid
        points are solved for."""
        (left, left_hands), (right, right_hands) = values["left"], values["right"]
        left, right = separate_hands(self.avatar, left, right, left_hands, right_hands)
        return {
            arm: (kept_out_of_torso(self.avatar, wrists) + hand_push_out_of_torso(self.avatar, AVATAR_SIDE[arm], wrists, hands), hands)
            for arm, (wrists, hands) in (("left", (left, left_hands)), ("right", (right, right_hands)))
        }

    def _arm_inputs(self, times: np.ndarray) -> tuple[dict[str, tuple[np.ndarray, np.ndarray]], np.ndarray | None]:
        """Per arm, the wrist positions and hand rotations the swivel's grid is solved for
        at sorted ``times``, in the trunk's frame (:meth:`_kept_apart`), and the trunk's
        yaw there (None where it never turns)."""
        values, yaw = self._channel_inputs(times)
        return self._kept_apart(values), _turning(yaw)

    def _forget_before(self, horizon: float) -> None:
        """Drop LMPs that lost control before ``horizon`` (module docstring)."""
        if horizon >= self._forget_from:
            self._forget_arm_lmps_before(horizon)
        self.neck.forget_before(horizon)
        self.face.forget_before(horizon)
        self._grid.forget_before(math.floor(horizon / SWIVEL_PERIOD) - 2)

    def _forget_arm_lmps_before(self, horizon: float) -> None:
        """The arm channels' part of :meth:`_forget_before`; notes the earliest horizon at
        which one of them will have :data:`FORGET_BATCH` LMPs (or all but its last) to
        drop, so that windows before it skip this."""
        for channel in self._lmps:
            timeline = self.timeline(channel)
            keep = int(np.searchsorted(timeline.starts, horizon, side="right")) - 1
            if keep <= 0:
                continue
            start = float(timeline.starts[keep])
            state = timeline.realizations[keep - 1].state(start)
            initial = ChannelState(np.asarray(state.value, dtype=float), np.asarray(state.velocity, dtype=float), start)
            self._timelines[channel] = ChannelTimeline(
                channel, initial, timeline.lmps[keep:], timeline.realizations[keep:], timeline.starts[keep:]
            )
            self._initial[channel] = initial
            self._lmps[channel] = list(timeline.lmps[keep:])
        self._forget_from = min(
            (float(starts[min(FORGET_BATCH, starts.size - 1)]) for starts in (self.timeline(c).starts for c in self._lmps) if starts.size > 1),
            default=math.inf,
        )

    def swivel(self, arm: str, times: np.ndarray) -> np.ndarray:
        """The arm's swivel (radians) at sorted ``times``, from the grid's track."""
        if times.size == 0:
            return np.zeros(0)
        first, last = self._grid_span(times)
        plan = self._grid.plan(first, last)
        if plan is not None:
            self._grid.solve(*plan, *self._arm_inputs(self._grid.times(plan[0], plan[1])))
        swivel = self._grid.sample(arm, times, first, last)[0]
        return swivel[:, 0] + swivel_of(swivel[:, 1:], *swivel_zeros(self.avatar, AVATAR_SIDE[arm], self._arm_inputs(times)[0][arm][0]))

    @staticmethod
    def _grid_span(times: np.ndarray) -> tuple[int, int]:
        """First and last grid index the swivel interpolation at sorted ``times`` needs."""
        first = math.floor(times[0] / SWIVEL_PERIOD + _FRAME_TOLERANCE) - 1
        last = math.floor(times[-1] / SWIVEL_PERIOD + _FRAME_TOLERANCE) + 2
        return first, last

    def warnings(self) -> tuple[str, ...]:
        """What the LMPs changed when they activated (a squeezed preparation, a slowed
        stroke), channel by channel in time order."""
        return tuple(w for channel in self._lmps for w in self.timeline(channel).warnings)

    def activated(self) -> dict[tuple[str, str], tuple[LMP, ...]]:
        """The LMPs activated on every channel so far."""
        return {channel: tuple(lmps) for channel, lmps in self._lmps.items()}


def _turning(yaw: np.ndarray) -> np.ndarray | None:
    """The trunk's yaw ``(n,)`` (radians), None where it never turns."""
    return yaw if np.any(yaw != 0.0) else None


def _in_order(lmps: Sequence[LMP]) -> bool:
    return all(a.pegs.start <= b.pegs.start for a, b in zip(lmps, lmps[1:]))


def _extended(timeline: ChannelTimeline, lmps: Sequence[LMP]) -> ChannelTimeline:
    """``timeline`` extended by ``lmps`` (in start order) one after another
    (:meth:`ChannelTimeline.extended`); sign LMPs all at once
    (:func:`motor.signing.track_batch.activate_in_turn`, the same tracks)."""
    if len(lmps) < 2 or not all(isinstance(lmp, SignChannelLMP) for lmp in lmps):
        for lmp in lmps:
            timeline = timeline.extended(lmp)
        return timeline
    start = lmps[0].pegs.start
    if timeline.starts.size and start < timeline.starts[-1]:
        raise ValueError(f"{timeline.channel}: an LMP starting at {start} cannot follow one starting at {timeline.starts[-1]}")
    here = timeline.realizations[-1].state(start).value if timeline.realizations else timeline.initial.value
    tracks = activate_in_turn(lmps, np.asarray(here, dtype=float), start)
    starts = np.append(timeline.starts, [float(lmp.pegs.start) for lmp in lmps])
    return ChannelTimeline(timeline.channel, timeline.initial, (*timeline.lmps, *lmps), (*timeline.realizations, *tracks), starts)


def _sample(timeline: ChannelTimeline, times: np.ndarray) -> np.ndarray:
    """A timeline's values at ``times``: only the realizations in control there are asked."""
    value = np.asarray(timeline.initial.value, dtype=float)
    out = np.empty((times.size, value.size))
    out[:] = value
    if not timeline.realizations or times.size == 0:
        return out
    owner = np.searchsorted(timeline.starts, times, side="right") - 1
    first, last = int(owner[0]), int(owner[-1])
    lo = int(np.searchsorted(owner, 0, side="left"))
    if lo < times.size:  # sign tracks: all in one pass
        values = sample_tracks(timeline.realizations[max(first, 0) : last + 1], owner[lo:] - max(first, 0), times[lo:])
        if values is not None:
            out[lo:] = values
            return out
    for index in range(max(first, 0), last + 1):
        lo = np.searchsorted(owner, index, side="left")
        hi = np.searchsorted(owner, index, side="right")
        if hi > lo:
            out[lo:hi] = timeline.realizations[index].sample(times[lo:hi])
    return out


def _palm_offset(avatar: Avatar, side: str) -> np.ndarray:
    """From the wrist to the palm's centre at rest (halfway to the middle finger's base), metres."""
    wrist = avatar.rest_positions[avatar.joint_index(f"{side}_wrist")]
    return 0.5 * (avatar.rest_positions[avatar.joint_index(f"{side}_middle1")] - wrist)
