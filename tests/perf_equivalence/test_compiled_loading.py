"""The compiled kernels load when their modules are imported, each with the one signature
it states, and take what callers pass them — read-only views (broadcasts), strided and
non-float inputs — without another compilation, which an utterance would wait for."""

from __future__ import annotations

import numpy as np
import pytest

from motor import quaternion as quat
from motor.arm import candidate_clearance, cheapest_swivel, given_swivel, other_arm_clearance, swivel, swivel_cost, swivel_track, upright_placement
from motor.body import collision, distance, hands_parting, torso_push
from motor.body.avatar import load_avatar
from motor.hand import shape
from motor.neck import posing, shift_sampling
from motor.program import keyframe_sampling
from motor.signing import law_time, path_batch, reach, reach_steps, repeats, retiming, spreading, track_kernels
from motor.compiled import warm_up
from motor.trajectory import biocontrol, spline_positions

LOOPS = [
    (quat, "_multiply_rows"), (quat, "_rotate_rows"), (quat, "_cross_rows"), (quat, "_normalize_rows"),
    (distance, "_closest_loop"), (distance, "_segments_loop"), (distance, "_point_segment_loop"), (distance, "_volume_loop"),
    (candidate_clearance, "clearance_rows"), (candidate_clearance, "charge_trunk"), (swivel, "_cost_to_go"),
    (swivel_cost, "_wrist_rows"), (swivel_cost, "_cost_rows"), (cheapest_swivel, "_cheapest_rows"), (path_batch, "_traced"), (path_batch, "_cut_at_reversals"),
    (given_swivel, "_posed_rows"), (shape, "_hand_rows"),
    (law_time, "_chords_and_arcs"), (law_time, "_chord_sums"), (law_time, "_turning_cosines"), (law_time, "_curvature_and_grids"),
    (law_time, "_kernel_exponents"), (law_time, "_smoothed"), (law_time, "_law_time"), (retiming, "_law_factors"), (path_batch, "_root_sums"),
    (spreading, "_near_pairs"), (spreading, "_add_weighted"), (reach, "_shift_rows"), (repeats, "_group_rows"),
    (reach_steps, "_probe_rows"), (reach_steps, "_step_rows"),
    (upright_placement, "_clavicle_rows"), (upright_placement, "_circle_rows"), (upright_placement, "_swivel_sides"),
    (swivel, "_walk"), (swivel_track, "_twists"), (swivel_track, "_wrist_steps"), (swivel_track, "_sampled_rows"), (collision, "_torso_rays"), (collision, "_pushed_out"),
    (hands_parting, "gaps"), (hands_parting, "pushes"), (track_kernels, "_segment_rows"),
    (other_arm_clearance, "other_arm_rows"), (other_arm_clearance, "near_frames"), (other_arm_clearance, "other_arm_window"),
    (keyframe_sampling, "_vector_rows"), (keyframe_sampling, "_rotation_rows"), (spline_positions, "_position_rows"),
    (posing, "_head_rows"), (posing, "_neck_rows"), (posing, "_eye_rows"), (shift_sampling, "_turn_rows"), (shift_sampling, "_value_rows"),
    (torso_push, "near_rows"), (torso_push, "hand_rays"), (torso_push, "hand_depths"), (torso_push, "hand_moved"), (torso_push, "hand_pushes"),
]  # fmt: skip


@pytest.mark.parametrize(("module", "name"), LOOPS, ids=[name for _, name in LOOPS])
def test_every_loop_is_compiled_once_with_its_stated_signature(module, name):
    assert warm_up() >= 0.0
    assert len(getattr(module, name).signatures) == 1


def test_read_only_strided_and_integer_inputs_need_no_other_compilation():
    rows = np.broadcast_to(np.array([0.0, 0.0, 0.6, 0.8]), (5, 4))
    assert not rows.flags.writeable
    points = np.arange(30, dtype=np.int64).reshape(10, 3)[::2]
    assert np.allclose(quat.rotate(rows, points), quat.rotate(np.repeat(rows[:1], 5, axis=0), points.astype(float)))
    assert quat.multiply(rows, rows[::-1]).shape == (5, 4)
    assert quat.normalize(points).shape == (5, 3)
    ends = np.broadcast_to(np.ones(3), (5, 3))
    assert distance.segment_distance(ends, points, ends, points).shape == (5,)
    wrists = np.broadcast_to(np.array([-0.2, 1.2, 0.3]), (5, 3))
    assert shape.hand_rotations(load_avatar("max"), "l", np.broadcast_to(np.arange(26), (3, 26))[:, ::1]).shape == (3, 17, 4)
    assert given_swivel.arm_rotations(load_avatar("max"), "r", wrists, rows, np.zeros(5, dtype=np.int64), points, rows[:, ::-1]).shape == (5, 4, 4)
    assert all(len(getattr(module, name).signatures) == 1 for module, name in LOOPS)


def test_warm_up_computes_every_manners_time_profile():
    warm_up()
    assert biocontrol.profile.cache_info().currsize >= len(biocontrol.MANNERS)
