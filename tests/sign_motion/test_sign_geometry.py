"""Signs of known geometry: the seed's "here", circles, manners, repetitions, symmetry."""

from __future__ import annotations

import numpy as np
import pytest
from sign_helpers import sign_from

from motor.body.kinematics import forward_kinematics
from motor.signing.path_shapes import SIZE_FRACTIONS
from motor.signing.planning import plan_sign
from motor.signing.sign_compiler import INITIAL_HOLD
from motor.signing.sequence import check_motion, realize_signs
from motor.trajectory.biocontrol import movement_duration

HERE = "hamsymmlr hamfinger2 hamthumbacrossmod hamfingerbendmod hamextfingero hampalmd hamstomach hamlrat hammoved hamsmallmod hamrepeatfromstart"
FIGURE_7 = """<sigml><hamgestural_sign gloss="here">
<sign_manual both_hands="true" lr_symm="true">
<handconfig handshape="finger2" thumbpos="across" mainbend="bent"/>
<handconfig extfidir="o" palmor="d"/>
<location_bodyarm location="stomach" side="right_at"/>
<rpt_motion repetition="fromstart"><directedmotion direction="d" size="small"/></rpt_motion>
</sign_manual></hamgestural_sign></sigml>"""


def wrists(avatar, signed):
    """Wrist positions reached (forward kinematics), right and left, (n, 3) each."""
    pose = forward_kinematics(avatar, signed.motion.rotations)
    return tuple(pose.positions[:, avatar.arm_joints(side)[3]] for side in ("r", "l"))


def speeds(signed, arm, start, end, count=400):
    times = np.linspace(start, end, count)
    points = signed.control.timeline((arm, "wrist_position")).sample(times)
    return times[1:], np.linalg.norm(np.diff(points, axis=0), axis=1) / np.diff(times)


@pytest.fixture(scope="module")
def here(avatar):
    return realize_signs(avatar, [sign_from(HERE, "here")])


def test_here_is_mirrored_across_the_sagittal_plane(avatar, here):
    right, left = wrists(avatar, here)
    assert np.max(np.abs(right[:, 0] + left[:, 0])) < 1e-3
    assert np.max(np.abs(right[:, 1] - left[:, 1])) < 1e-3
    assert np.max(np.abs(right[:, 2] - left[:, 2])) < 1e-3
    assert np.all(right[:, 0] < 0.0)  # the right hand stays on the right


def test_here_moves_down_and_back_twice(avatar, here):
    (timing,) = here.timings
    times = np.linspace(timing.ready, timing.end, 300)
    y = here.control.timeline(("right", "wrist_position")).sample(times)[:, 1]
    drop = SIZE_FRACTIONS["small"] * avatar.arm_length("r")
    # two descents of the small size, the first followed by a return to the start height
    lows = [i for i in range(1, len(y) - 1) if y[i] < y[i - 1] and y[i] <= y[i + 1]] + [len(y) - 1]
    assert len(lows) == 2
    for i in lows:
        assert y[0] - y[i] == pytest.approx(drop, abs=0.01)
    highs = [i for i in range(1, len(y) - 1) if y[i] > y[i - 1] and y[i] >= y[i + 1]]
    assert len(highs) == 1 and y[highs[0]] == pytest.approx(y[0], abs=0.005)


def test_gestural_here_realizes_like_the_tag_form(avatar, here):
    from mura.sigml import parse_sigml

    (sign,) = parse_sigml(FIGURE_7).signs
    other = realize_signs(avatar, [sign])
    assert other.motion.frame_count == here.motion.frame_count
    assert np.allclose(other.motion.rotations, here.motion.rotations, atol=1e-9)


def test_circle_has_near_constant_speed(avatar):
    signed = realize_signs(avatar, [sign_from("hamflathand hamextfingeru hampalml hamchest hamcircleo")])
    plan = plan_sign(avatar, sign_from("hamflathand hamextfingeru hampalml hamchest hamcircleo"))
    (move,) = plan.moves[("right", "wrist_position")]
    assert move.manner == "linear"
    (timing,) = signed.timings
    length = move.end - move.start
    # the jerk-bounded start and stop of the linear manner take about a quarter each
    _, v = speeds(signed, "right", timing.ready + move.start + 0.25 * length, timing.ready + move.start + 0.75 * length)
    assert (v.max() - v.min()) / v.mean() < 0.15


@pytest.mark.parametrize(
    ("symbols", "manner", "peak_range"),
    [
        ("hamflathand hamextfingero hampalmd hamchest hammoveo", "targetted", (0.5, 1.0)),
        ("hamflathand hamextfingero hampalmd hamchest hammoveo hamtouch hamchin", "hard_contact", (0.5, 1.0)),
    ],
)
def test_targetted_speed_peaks_late(avatar, symbols, manner, peak_range):
    plan = plan_sign(avatar, sign_from(symbols))
    (move,) = plan.moves[("right", "wrist_position")]
    assert move.manner == manner
    signed = realize_signs(avatar, [plan])
    (timing,) = signed.timings
    times, v = speeds(signed, "right", timing.ready + move.start, timing.ready + move.end)
    peak = (times[np.argmax(v)] - timing.ready - move.start) / (move.end - move.start)
    assert peak_range[0] < peak < peak_range[1]


def test_lax_transition_peaks_near_the_middle(avatar, here):
    (timing,) = here.timings
    times, v = speeds(here, "right", timing.start, timing.ready)
    peak = (times[np.argmax(v)] - timing.start) / (timing.ready - timing.start)
    assert 0.3 < peak < 0.65


def test_static_sign_is_reached_targetted_and_held(avatar):
    plan = plan_sign(avatar, sign_from("hamfist hamextfingeru hampalml hamchin"))
    assert plan.static
    signed = realize_signs(avatar, [plan])
    lmp = signed.control.activated()[("right", "wrist_position")][0]
    assert lmp.transition == "targetted"


@pytest.mark.parametrize(
    ("repeat", "passes", "returns"),
    [("hamrepeatfromstart", 2, ["lax"]), ("hamrepeatfromstartseveral", 3, ["lax", "lax"]), ("hamrepeatreverse", 2, [])],
)
def test_repetitions(avatar, repeat, passes, returns):
    plan = plan_sign(avatar, sign_from(f"hamflathand hamextfingero hampalmd hamchest hammoveu {repeat}"))
    moves = plan.moves[("right", "wrist_position")]
    assert [m.manner for m in moves if m.manner == "lax"] == returns
    strokes = [m for m in moves if m.manner != "lax"]
    assert len(strokes) == passes
    step = movement_duration("straight")
    assert plan.duration == pytest.approx(INITIAL_HOLD + step * (passes + len(returns)))
    if repeat == "hamrepeatreverse":
        assert np.allclose(strokes[1].values, strokes[0].values[::-1])


def test_parallel_symmetry_translates_instead_of_mirroring(avatar):
    plan = plan_sign(avatar, sign_from("hamsymmpar hamflathand hamextfingero hampalmd hammover"))
    right = plan.moves[("right", "wrist_position")][0].values
    left = plan.moves[("left", "wrist_position")][0].values
    assert np.allclose(right - right[0], left - left[0], atol=1e-9)
    assert right[-1, 0] < right[0, 0]  # both move to the right (−x)


def test_hand_constellation_puts_the_named_sites_together(avatar):
    from motor.body.locations import resolve_location
    from mura.values import BodySite

    symbols = "hamflathand hamparbegin hamextfingerol hampalml hamplus hamextfingeror hampalmr hamparend hamparbegin hamfingertip hamplus hampalm hamparend hamtouch"
    sign = sign_from(symbols)
    assert sign.constellation is not None and sign.constellation.contact == "touch"
    signed = realize_signs(avatar, [sign])
    (timing,) = signed.timings
    frame = int(np.searchsorted(signed.motion.times, timing.ready + 0.05))
    pose = forward_kinematics(avatar, signed.motion.rotations[frame : frame + 1])
    right_fingertip = resolve_location(avatar, BodySite("fingertip", proximity="touch"), "l", pose)
    left_palm = resolve_location(avatar, BodySite("palm", proximity="touch"), "r", pose)
    assert np.linalg.norm(right_fingertip - left_palm) < 0.02


def test_sequence_starts_and_ends_at_rest(avatar):
    signs = [sign_from(HERE, "here"), sign_from("hamflathand hamextfingeru hampalml hamchest hamcircleo", "circle")]
    signed = realize_signs(avatar, signs)
    assert [t.gloss for t in signed.timings] == ["here", "circle"]
    assert signed.timings[0].end == pytest.approx(signed.timings[1].start)
    first, last = signed.motion.rotations[0], signed.motion.rotations[-1]
    assert np.allclose(first, last, atol=1e-6)
    check = check_motion(avatar, signed)
    assert check.non_finite == 0 and check.max_shortfall < 1e-3 and check.max_upper_arm_depth < 0.01


def test_alternating_hands_move_in_opposite_directions(avatar):
    sign = sign_from("hamsymmlr hamalternatingmotion hamflathand hamextfingero hampalmd hammoveu")
    assert sign.symmetry is not None and sign.symmetry.alternating
    plan = plan_sign(avatar, sign)
    right = plan.moves[("right", "wrist_position")][0].values
    left = plan.moves[("left", "wrist_position")][0].values
    assert right[-1, 1] - right[0, 1] > 0.05
    assert left[-1, 1] - left[0, 1] == pytest.approx(-(right[-1, 1] - right[0, 1]), abs=1e-6)
