"""Signs inside utterances: a sign behaviour, timed against speech like a gesture.

An utterance may carry a HamNoSys/SiGML sign as a behaviour (``<sign>`` in MURML). The
scheduler times it like a gesture (preparation, stroke spanning the affiliate,
retraction), and this module turns it into a :class:`motor.program.gesture.MotorProgram`: the
sign is planned on its own clock (:func:`motor.signing.planning.plan_sign`), its moves are
stretched or compressed uniformly onto the stroke interval the scheduler chose, a
transition leads into its first posture from wherever the hands are (lax, or targetted
into a static sign, seed 000 section 4.5) — without the citation form's initial hold: the
scheduler gives its stroke a visible onset as it does a gesture's —, and the hands retract to rest — or to the
interim rest when another gesture follows — after ``relax``. A sign is not repeated to
fill a long affiliate (its repetitions are its own); it is slowed, then holds its last
posture.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np

from motor.body.avatar import Avatar
from motor.body.conventions import ARMS, AVATAR_SIDE
from motor.program.fragment import PlanningError
from motor.program.gesture import (
    GestureDemands,
    MotorProgram,
    retraction_duration,
    retraction_lmp,
)
from motor.program.lmp import LMP, TimePegs
from motor.signing.lmp import Move, SignChannelLMP
from motor.signing.plan import SignPlan, SignPlanningError
from motor.signing.planning import plan_sign, without_initial_hold
from mura.model import BehaviorSpec

#: How many sign plans are kept (a chunk's signs are planned, then asked for again).
PLAN_CACHE = 16
#: Channels of one arm that a sign drives.
CHANNELS: tuple[str, ...] = ("wrist_position", "hand_rotation", "handshape")


class SignBehaviorPlanner:
    """Plans the sign behaviours of utterances on one avatar.

    Demands, preparation and planning each need the sign's plan, so the last few plans
    are kept, keyed by the sign object itself (behaviour ids repeat across utterances).
    """

    def __init__(self, avatar: Avatar) -> None:
        self.avatar = avatar
        self._plans: dict[int, tuple[object, SignPlan]] = {}

    def sign_plan(self, behavior: BehaviorSpec) -> SignPlan:
        """The sign's plan on its own clock; raises :class:`PlanningError` naming the behaviour."""
        sign = behavior.sign
        if sign is None:
            raise PlanningError(f"behaviour {behavior.id!r} carries no sign")
        return self._remembered(sign, lambda: without_initial_hold(plan_sign(self.avatar, sign)), behavior.id, (SignPlanningError,))

    def _remembered(self, source: object, plan: Callable[[], SignPlan], behavior_id: str, errors: tuple[type[Exception], ...]) -> SignPlan:
        """The plan of ``source`` (a sign object, kept by identity among the last
        :data:`PLAN_CACHE`), made by ``plan`` when not kept; ``errors`` it raises become a
        :class:`PlanningError` naming the behaviour."""
        kept = self._plans.get(id(source))
        if kept is not None and kept[0] is source:
            return kept[1]
        try:
            made = plan()
        except errors as error:
            raise PlanningError(f"behaviour {behavior_id!r}: {error}") from None
        if len(self._plans) >= PLAN_CACHE:
            self._plans.pop(next(iter(self._plans)))
        self._plans[id(source)] = (source, made)
        return made

    def first_wrists(self, behavior: BehaviorSpec) -> dict[str, np.ndarray]:
        """Where each hand the sign uses begins, metres (avatar frame)."""
        return {arm: pose.wrist for arm, pose in self.sign_plan(behavior).first.items()}

    def demands(self, behavior: BehaviorSpec) -> GestureDemands:
        """Arms, natural duration (the sign's own) and the preparation distance from rest."""
        plan = self.sign_plan(behavior)
        distance = max(
            (float(np.linalg.norm(wrist - self._rest(arm, "rest").wrist)) for arm, wrist in self.first_wrists(behavior).items()),
            default=0.0,
        )
        moving = not plan.static
        paths = {arm: np.concatenate([move.values for move in moves])
                 for (arm, channel), moves in plan.moves.items() if channel == "wrist_position" and moves}
        return GestureDemands(
            frozenset(plan.first), plan.duration if moving else 0.0, moving, False, distance,
            first_wrists={arm: tuple(pose.wrist) for arm, pose in plan.first.items()},
            last_wrists={arm: tuple(paths[arm][-1]) if arm in paths else tuple(pose.wrist) for arm, pose in plan.first.items()},
            stroke_distance=max((float(np.sum(np.linalg.norm(np.diff(path, axis=0), axis=1))) for path in paths.values()), default=0.0),
            manner="targetted" if plan.static else "lax",
        )

    def plan(self, behavior: BehaviorSpec, pegs: TimePegs, next_gesture_follows: bool = False) -> MotorProgram:
        """The sign's LMPs on ``pegs``: transition until ``stroke_start``, the sign's moves
        over ``[stroke_start, stroke_end]``, its last posture held until ``relax``, then
        the retraction."""
        plan = self.sign_plan(behavior)
        notes = [f"{behavior.id}: {warning}" for warning in plan.warnings]
        stroke_start = pegs.stroke_start
        stroke_end = max(pegs.stroke_end, stroke_start + 1e-3) if not plan.static else stroke_start
        scale = (stroke_end - stroke_start) / plan.duration if not plan.static else 1.0
        start = min(pegs.start, stroke_start - 1e-3)
        stroke = min(max(pegs.stroke, stroke_start), stroke_end)
        relax = max(pegs.relax, stroke_end)
        sign_pegs = TimePegs(start, stroke_start, stroke_start, stroke, stroke_end, relax, relax)
        transition = "targetted" if plan.static else "lax"
        posture = "interim_rest" if next_gesture_follows else "rest"
        lmps: list[LMP] = []
        retraction = 0.0
        for arm in (arm for arm in ARMS if arm in plan.first):
            last = plan.first[arm].wrist
            for channel in CHANNELS:
                moves = tuple(_placed(move, stroke_start, scale) for move in plan.moves.get((arm, channel), ()))
                lmps.append(SignChannelLMP((arm, channel), sign_pegs, plan.first[arm].channel(channel), moves, transition))
                if channel == "wrist_position" and moves:
                    last = moves[-1].values[-1]
            retraction = max(retraction, retraction_duration(float(np.linalg.norm(last - self._rest(arm, posture).wrist))))
        end = relax + retraction
        retract = TimePegs.movement(relax, end)
        lmps.extend(retraction_lmp(self.avatar, lmp.channel, retract, posture) for lmp in list(lmps))
        final = TimePegs(start, stroke_start, stroke_start, stroke, stroke_end, relax, end)
        return MotorProgram(behavior.id, tuple(lmps), tuple(notes), final, frozenset(plan.first))

    def _rest(self, arm: str, posture: str):
        return self.avatar.postures[posture][AVATAR_SIDE[arm]]


def _placed(move: Move, origin: float, scale: float) -> Move:
    """A move of the sign's own clock on the utterance clock, its timing scaled by ``scale``."""
    return replace(move, start=origin + scale * move.start, end=origin + scale * move.end)
