"""The motor core's compiled kernels, loaded before the first frame is due.

numba compiles each kernel (:mod:`motor.quaternion`'s products,
:mod:`motor.body.distance`'s signed distances, :mod:`motor.body.collision`'s and
:mod:`motor.body.torso_push`'s torso push, :mod:`motor.body.hands_parting`'s hands kept apart, :mod:`motor.arm.clearance`'s
arm-against-body loop, :mod:`motor.arm.other_arm_clearance`'s arm-against-the-other-arm
loop, :mod:`motor.arm.swivel_cost`'s wrist state and candidate costs,
:mod:`motor.arm.swivel`'s value tables and walk, :mod:`motor.arm.swivel_track`'s twist and
wrist tracks and samples, :mod:`motor.arm.cheapest_swivel`'s pruned search,
:mod:`motor.arm.given_swivel`'s arm posed at a swivel, :mod:`motor.hand.shape`'s hand joint
rotations, :mod:`motor.signing.path_batch`'s trace of a move within its hull,
:mod:`motor.signing.law_time`'s law time of many paths, :mod:`motor.signing.retiming`'s
law factors, :mod:`motor.signing.repeats`' repeated postures,
:mod:`motor.signing.reach_steps`' steps of the reach check and
:mod:`motor.signing.track_kernels`' samples of joined sign tracks,
:mod:`motor.program.keyframe_sampling`'s keyframe realizations,
:mod:`motor.trajectory.spline_positions`' wrist splines, :mod:`motor.neck.posing`'s
head, neck and eyes and :mod:`motor.neck.shift_sampling`'s gaze shifts) once per checkout and
caches it on disk
(``__pycache__``): several seconds the very first time.
Each kernel states its signature, so a process loads it from the cache when it imports
the kernel's module — about 0.7 s in all, most of it numba's own start — never in the
middle of an utterance: a realizer has them once it has imported the motor.
:func:`warm_up` imports them all and runs each once, and computes the tables that depend
on the model's constants alone — the manners' time profiles
(:func:`motor.trajectory.biocontrol.load_profiles`: eight ODE integrations, about 0.3 s) —
so that neither falls in the middle of the first utterance or sign: a live agent calls it
when it opens its scheduler, the speed benches before they time anything. The seconds it
returns are what that cost in this process, near zero when done already.
"""

from __future__ import annotations

import time

from motor import quaternion
from motor.arm import cheapest_swivel, clearance, given_swivel, other_arm_clearance, swivel, swivel_cost, swivel_track, upright_placement
from motor.body import collision, distance, hands_parting, torso_push
from motor.hand import shape
from motor.neck import posing, shift_sampling
from motor.program import keyframe_sampling
from motor.signing import law_time, path_batch, reach, reach_steps, repeats, retiming, spreading, track_kernels
from motor.trajectory import biocontrol, spline_positions


def warm_up() -> float:
    """Load (compiling where no cache holds them) every compiled kernel and compute the
    manners' time profiles; returns the seconds it took."""
    started = time.perf_counter()
    for module in (quaternion, distance, collision, torso_push, hands_parting, clearance, other_arm_clearance, swivel, swivel_track, swivel_cost, cheapest_swivel, given_swivel, upright_placement, shape, path_batch, law_time, retiming, spreading, repeats, reach_steps, reach, track_kernels, keyframe_sampling, spline_positions, posing, shift_sampling):
        module.load_kernels()
    biocontrol.load_profiles()
    return time.perf_counter() - started
