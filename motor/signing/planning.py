"""A sign planned into timed hand moves (seed 000, sections 4.1–4.6).

:func:`plan_sign` turns a :class:`mura.signs.Sign` into a :class:`SignPlan`: for each
hand, the first posture (wrist, global hand rotation, hand parameters) and the sign's
moves on its own clock ``[0, duration]``, one :class:`motor.signing.lmp.Move` per channel.
The sign's postures and movement are compiled into hand moves by
:class:`motor.signing.sign_compiler.SignCompiler` (where the hands go, two hands,
movements, repetition: that module says how); this one keeps them clear of the body and
within reach, retimes them, and plans many signs at once.

**Body.** Wrist positions inside the torso's elliptic cylinder (grown by
:data:`motor.body.collision.TORSO_MARGIN`), or behind it, are first eased out of it as the
motor control eases every frame (:func:`motor.body.collision.kept_out_of_torso`: continuous across the torso's
top and bottom, where a push onto the front surface alone would make a path step out by
the torso's depth in one sample), then cleared as paths (:func:`motor.signing.reach.clear_paths`,
whose pushes are shared smoothly along each hand's moves so that a circle or a line keeps
its shape); positions beyond the arm's reach are pulled in, positions too
near the shoulder step around its front, and positions so far across the body that the
IK reports the upper arm in the torso step back toward the arm's side
(:func:`motor.signing.reach.within_reach`); a wrist whose hand (its collision capsule, in the
hand's rotation there) would still enter the torso moves forward by what the hand needs
(:func:`motor.signing.hand_clearance.hands_clear_of_torso`); midpoints are checked where that
opened long chords (:func:`motor.signing.reach.clear_paths`). A warning names every sign whose paths were changed. The upper arm
is otherwise kept out of the torso by the IK's swivel (:mod:`motor.arm.ik`). Moves whose
final paths (cleared, and travelled in law time) need more time than they were given within
their manner's speed budget are then slowed, the sign's clock warped with them
(:mod:`motor.signing.retiming`; a warning says by how much).

**Many signs at once.** :func:`plan_signs` plans a collection in passes: every sign is
compiled into hand moves, and the costly geometry the signs ask for (arm poses for sites on
the other hand, wrist-to-site offsets) is computed for all of them together in vectorized
rounds (:class:`motor.signing.hand_geometry.HandGeometry`, which also remembers hand
rotations, shapes, rest locations and the stopping lengths of paths for the collection);
then the wrist offsets of all moves, then every move's wrist path and every wrist kept out
of the torso in one pass (:func:`motor.signing.layout.placed`), then the reach of every distinct wrist position
of the collection (:func:`motor.signing.reach.within_reach_all`), then the timing lengths
of all wrist moves for the retiming (:func:`motor.signing.retiming.timing_lengths`); the
garbage collector waits meanwhile (:mod:`motor.signing.collector`). The plans are those of planning each sign alone, bit
for bit (``tests/signing_speed``, ``tests/perf_equivalence/test_planning_fast_paths.py``).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace
from functools import partial
from typing import TypeVar

from motor.body.avatar import Avatar
from motor.signing.collector import collector_paused
from motor.signing.hand_geometry import GeometryPending, HandGeometry
from motor.signing.layout import Layout, placed
from motor.signing.orientations import written_orientations
from motor.signing.plan import SignPlan, SignPlanningError
from motor.signing.reach import within_reach_all
from motor.signing.retiming import retimed_all
from motor.signing.hand_placement import NEUTRAL_FINGERS
from motor.signing.sign_compiler import INITIAL_HOLD, SignCompiler
from mura.errors import SpecError
from mura.signs import Sign

_Result = TypeVar("_Result")


def plan_sign(avatar: Avatar, sign: Sign) -> SignPlan:
    """The sign's hand moves on its own clock; raises :class:`SignPlanningError` with the
    gloss and the reason when it cannot be realized."""
    (result,) = plan_signs(avatar, [sign])
    if isinstance(result, SignPlanningError):
        raise result
    return result


def plan_signs(avatar: Avatar, signs: Sequence[Sign], memoize: bool = True) -> list[SignPlan | SignPlanningError]:
    """Each sign's plan, or the error saying why it cannot be realized, in order.

    Planning many signs at once is faster: the hand geometry the signs share (rotations,
    hand shapes, locations, site offsets, arm poses) is computed once for the collection
    (:class:`motor.signing.hand_geometry.HandGeometry`; ``memoize=False`` computes it
    afresh every time, the plain path the tests compare with), and the reach of every
    wrist position of all the signs is checked in one vectorized IK call per arm."""
    with collector_paused():
        geometry = HandGeometry(avatar, memoize)
        compiled = _compile_all(geometry, signs)
        geometry.prefetch_site_offsets([r for c in compiled if isinstance(c, SignCompiler) for r in c.palm_offset_requests()])
        drafts = _plan_all(avatar, compiled) if memoize else [c if isinstance(c, SignPlanningError) else _attempt(c.sign, c.plan) for c in compiled]
        return retimed_all(within_reach_all(avatar, drafts), batched=memoize)


def without_initial_hold(plan: SignPlan) -> SignPlan:
    """The plan with its moves begun at once instead of after :data:`motor.signing.sign_compiler.INITIAL_HOLD` (a sign
    inside an utterance, whose stroke the scheduler times like a gesture's); a static
    plan, or one whose moves begin sooner, as it is."""
    starts = [move.start for moves in plan.moves.values() for move in moves]
    if plan.static or not starts or min(starts) < INITIAL_HOLD - 1e-9:
        return plan
    moves = {key: tuple(move.shifted(-INITIAL_HOLD) for move in channel) for key, channel in plan.moves.items()}
    return replace(plan, duration=plan.duration - INITIAL_HOLD, moves=moves)


def _compile_all(geometry: HandGeometry, signs: Sequence[Sign]) -> list[SignCompiler | SignPlanningError]:
    """Every sign compiled into hand moves, in rounds: a sign that asks for an arm pose or
    a site offset not yet known is set aside, the round's requests of all signs are
    computed in one vectorized pass, and the signs set aside are compiled again (a sign
    asking for k such answers in turn takes k + 1 rounds; offsets asked together, and an
    arm pose with the wrist offset it needs, count as one). The rotations of the hand
    orientations the signs write are computed first, all at once
    (:mod:`motor.signing.orientations`)."""
    compiled: list[SignCompiler | SignPlanningError | None] = [None] * len(signs)
    waiting = list(range(len(signs)))
    geometry.prefetch_rotations(*written_orientations(signs, [NEUTRAL_FINGERS], [(1.0, 0.0, 0.0)]))
    geometry.deferring = geometry.memoize
    try:
        while waiting:
            again = []
            for index in waiting:
                sign = signs[index]
                try:
                    compiled[index] = _attempt(sign, lambda: SignCompiler(geometry, sign).compile_sign())
                except GeometryPending:
                    again.append(index)
            if not geometry.resolve_pending():
                geometry.deferring = False  # nothing noted: the next round computes as asked
            waiting = again
    finally:
        geometry.deferring = False
    return [c for c in compiled if c is not None]  # every sign is compiled once no sign waits


def _attempt(sign: Sign, work: Callable[[], _Result]) -> _Result | SignPlanningError:
    """What ``work`` gives, or the planning error naming the sign."""
    try:
        return work()
    except SignPlanningError as error:
        return error
    except (SpecError, ValueError, KeyError) as error:
        return SignPlanningError(f"sign {sign.gloss!r}: {error}")

def _plan_all(avatar: Avatar, compiled: Sequence[SignCompiler | SignPlanningError]) -> list[SignPlan | SignPlanningError]:
    """The plan of every compiled sign (:meth:`SignCompiler.plan`), the wrists of all of
    them kept out of the torso in one pass; a sign whose layout fails is planned alone,
    where it fails with its own error."""
    layouts: dict[int, Layout] = {}
    for index, sign in enumerate(compiled):
        if isinstance(sign, SignCompiler):
            layout = _attempt(sign.sign, sign.layout)
            if isinstance(layout, Layout):
                layouts[index] = layout
    wrists = dict(zip(layouts, placed(avatar, list(layouts.values()))))
    return [
        c if isinstance(c, SignPlanningError)
        else _attempt(c.sign, partial(c.plan_from, wrists[index])) if index in wrists
        else _attempt(c.sign, c.plan)
        for index, c in enumerate(compiled)
    ]  # fmt: skip
