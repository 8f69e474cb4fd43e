"""Inflected verbs as the avatar performs them, measured on the rendered frames with the BVH
kinematics of motor.verbs.capture (which share no code with the avatar's); and motion
capture read back from a BVH clip with its sidecar."""

import json

import numpy as np
import pytest

from agent.export.bvh import bvh_text
from motor import quaternion as quat
from motor.body.kinematics import forward_kinematics
from motor.body.locations import resolve_location
from motor.signing.sequence import realize_signs
from motor.verbs.capture import global_transforms, read_capture
from motor.verbs.plan import avatar_scale, pointing_form, pointing_plan, verb_plan
from mura.bvh import parse_bvh
from mura.errors import SpecError
from mura.values import BodySite

FPS = 25.0


def _render(avatar, plan):
    signed = realize_signs(avatar, [plan], FPS)
    return signed, parse_bvh(bvh_text(signed.motion))


def _joint_at(signed, clip, avatar, joint, times):
    frames = np.round((np.asarray(times) - signed.motion.start_time) * FPS).astype(int)
    _, positions = global_transforms(clip, frames, root_fixed=False)
    return positions[:, clip.names.index(joint)] / 100.0 - np.array([0.0, avatar.root_height, 0.0])


@pytest.mark.parametrize("kind", ["point", "vector"])
@pytest.mark.parametrize(("subject", "obj", "lateral"), [(-0.6, 0.9, -1.0), (0.9, -0.6, 1.0)])
def test_give_moves_the_dominant_hand_across_the_signing_space(max_avatar, models, lexicon, kind, subject, obj, lateral):
    plan = verb_plan(max_avatar, lexicon.entry("GIVE"), models["GIVE"].predict(kind, subject, obj))
    signed, clip = _render(max_avatar, plan)
    timing = signed.timings[0]
    start, end = _joint_at(signed, clip, max_avatar, "r_wrist", [timing.ready, timing.end])
    centre, width = avatar_scale(max_avatar)
    # +x is the avatar's left: from the left side (−0.6) to the right side (+0.9) is x falling
    assert np.sign(end[0] - start[0]) == lateral
    assert abs(end[0] - start[0]) > 0.5 * width
    if kind == "point":
        assert np.sign(start[0] - centre[0]) == -lateral and np.sign(end[0] - centre[0]) == lateral


@pytest.mark.parametrize("avatar_name", ["max", "kim"])
@pytest.mark.parametrize("obj", [-0.8, 0.0, 0.8])
def test_tell_starts_at_the_chin(models, lexicon, avatar_name, obj):
    from motor.body.avatar import load_avatar

    avatar = load_avatar(avatar_name)
    signed, clip = _render(avatar, verb_plan(avatar, lexicon.entry("TELL"), models["TELL"].predict("point", 0.0, obj)))
    timing = signed.timings[0]
    start, end = _joint_at(signed, clip, avatar, "r_index3", [timing.ready, timing.end])
    chin = resolve_location(avatar, BodySite("chin", proximity="touch"), "r")
    assert np.linalg.norm(start - chin) < 0.06  # the last finger joint; the tip is about 2 cm on
    assert np.linalg.norm(end - chin) > 0.25


@pytest.mark.parametrize("arc", [-1.0, -0.3, 0.5, 1.0])
def test_pointing_ends_toward_its_arc_position(max_avatar, lexicon, arc):
    signed, clip = _render(max_avatar, pointing_plan(max_avatar, arc, lexicon))
    timing = signed.timings[0]
    wrist, tip = _joint_at(signed, clip, max_avatar, "r_wrist", [timing.end]), _joint_at(signed, clip, max_avatar, "r_index3", [timing.end])
    finger = (tip - wrist)[0]
    wanted = np.array([-np.sin(arc * np.pi / 2), 0.0, np.cos(arc * np.pi / 2)])
    horizontal = finger * np.array([1.0, 0.0, 1.0])
    assert np.degrees(np.arccos(horizontal @ wanted / np.linalg.norm(horizontal))) < 30.0


def _write_clip(tmp_path, avatar, models, lexicon, verb, arrangement, sidecar_extra=None):
    form = models[verb].predict("point", *arrangement)
    plan = verb_plan(avatar, lexicon.entry(verb), form)
    signed = realize_signs(avatar, [plan], FPS)
    timing = signed.timings[0]
    (tmp_path / "clip.bvh").write_text(bvh_text(signed.motion))
    keyframes = [timing.ready - signed.motion.start_time + t for t in (form.times - form.times[0]) * (timing.end - timing.ready) / (form.times[-1] - form.times[0])]
    sidecar = {
        "format": "mura verb capture", "version": 1, "signer": "max (rendered)", "synthetic": True,
        "performances": [{"id": "p1", "verb": verb, "subject": arrangement[0], "object": arrangement[1], "keyframes": keyframes}],
    }  # fmt: skip
    sidecar.update(sidecar_extra or {})
    (tmp_path / "clip.json").write_text(json.dumps(sidecar, indent=1))
    return form, plan, signed, keyframes


@pytest.mark.parametrize(("verb", "arrangement"), [("GIVE", (-0.6, 0.9)), ("ASK", (0.3, -0.3)), ("TELL", (0.0, 0.6))])
def test_capture_reads_back_the_rendered_keyframes(tmp_path, max_avatar, models, lexicon, verb, arrangement):
    """The capture reader recovers the rendered clip at the keyframes: the wrists where the
    plan put them (the IK reaches positions exactly), the hands turned as the rendered arm
    turned them (the motor core's forward kinematics, slerped between the two nearest
    frames as the reader does; BVH text keeps rotations to 1e-4 degrees)."""
    form, plan, signed, keyframes = _write_clip(tmp_path, max_avatar, models, lexicon, verb, arrangement)
    session = read_capture(tmp_path / "clip.bvh")
    assert session.refused == () and len(session.performances) == 1
    performance = session.performances[0]
    centre, width = avatar_scale(max_avatar)
    orientations = forward_kinematics(max_avatar, signed.motion.rotations).orientations
    position = np.asarray(keyframes) * FPS
    low = np.floor(position).astype(int)
    for hand in form.locations:
        planned = np.stack([plan.first[hand].wrist] + [m.values[-1] for m in plan.moves[(hand, "wrist_position")]])
        recovered = centre + width * performance.hands[hand].location
        assert np.max(np.linalg.norm(recovered - planned, axis=1)) < 0.01  # within a frame's travel
        wrist = max_avatar.joint_index(f"{'r' if hand == 'right' else 'l'}_wrist")
        rendered = quat.slerp(orientations[low, wrist], orientations[low + 1, wrist], position - low)
        assert np.degrees(quat.angle_between(performance.hands[hand].orientation, rendered)).max() < 1.0


@pytest.mark.parametrize(
    ("performance", "message"),
    [
        ({"subject": 1.5}, "outside [-1, 1]"),
        ({"keyframes": [0.2, 99.0]}, "fall outside the clip"),
        ({"keyframes": [0.5, 0.2]}, "increasing"),
    ],
)
def test_bad_capture_performance_is_refused_by_sidecar_line(tmp_path, max_avatar, models, lexicon, performance, message):
    _write_clip(tmp_path, max_avatar, models, lexicon, "ASK", (0.3, -0.3))
    sidecar = json.loads((tmp_path / "clip.json").read_text())
    good = dict(sidecar["performances"][0])
    sidecar["performances"] = [good, {**good, "id": "p2", **performance}]
    text = json.dumps({k: v for k, v in sidecar.items() if k != "performances"})[:-1] + ', "performances": [\n'
    text += ",\n".join(json.dumps(p) for p in sidecar["performances"]) + "\n]}"
    (tmp_path / "clip.json").write_text(text)
    session = read_capture(tmp_path / "clip.bvh")
    assert len(session.performances) == 1 and len(session.refused) == 1
    assert message in session.refused[0].message
    assert session.refused[0].file.endswith("clip.json") and session.refused[0].line == 3


@pytest.mark.parametrize(
    ("text", "line", "message"),
    [
        ("HIERARCHY\nROOT hips\n{\n OFFSET 0 0\n", 4, "OFFSET and three numbers"),
        ("HIERARCHY\nROOT hips\n{\n OFFSET 0 0 0\n CHANNELS 1 Wrotation\n}\n", 5, "unknown channel"),
        ("HIERARCHY\nROOT hips\n{\n OFFSET 0 0 0\n CHANNELS 1 Xrotation\n}\nMOTION\nFrames: 2\nFrame Time: 0.04\n1\nx\n", 11, "not a number"),
        ("HIERARCHY\nROOT hips\n{\n OFFSET 0 0 0\n CHANNELS 1 Xrotation\n}\nMOTION\nFrames: 2\nFrame Time: 0.04\n1\n1 2\n", 11, "2 values"),
    ],
)
def test_bad_bvh_names_its_line(text, line, message):
    with pytest.raises(SpecError, match=message) as caught:
        parse_bvh(text, "bad.bvh")
    assert caught.value.file == "bad.bvh" and caught.value.line == line


def test_pointing_form_reaches_further_toward_the_target(lexicon):
    form = pointing_form(0.4, lexicon)
    step = form.locations["right"][1] - form.locations["right"][0]
    assert step @ np.array([-np.sin(0.2 * np.pi), 0.0, np.cos(0.2 * np.pi)]) > 0.9 * np.linalg.norm(step)


def _site_track(clip, frames, joint, hand, site, width):
    """A lexicon hand site through the rendered frames (metres), from the BVH's own kinematics."""
    from motor.verbs.arc import site_offset

    rotations, positions = global_transforms(clip, frames)
    index = clip.names.index(joint)
    return positions[:, index] / 100.0 + rotations[index].apply(width * site_offset(hand, site))


def _closest_approach(gap: np.ndarray) -> float:
    """Smallest length (m) of the gap between two sites over frames, the motion between two
    frames taken as straight (as a viewer interpolates it): the frames alone can miss the
    closest point of a hand passing at speed."""
    if len(gap) == 1:
        return float(np.linalg.norm(gap[0]))
    start, step = gap[:-1], np.diff(gap, axis=0)
    along = np.clip(-np.einsum("ij,ij->i", start, step) / np.maximum(np.einsum("ij,ij->i", step, step), 1e-18), 0.0, 1.0)
    return float(np.min(np.linalg.norm(start + along[:, None] * step, axis=1)))


@pytest.mark.parametrize(
    "arrangement",
    [
        pytest.param(
            (-0.6, 0.9),
            marks=pytest.mark.xfail(
                strict=True,
                reason="on max the swivel track's half-way clearance (68c692f) changes the right arm's posture "
                "there, and the hand's site passes 3.7 cm from the C (3 cm allowed)",
            ),
        ),
        (0.9, -0.6),
        (-1.0, 0.0),
        (0.3, -0.3),
    ],
)
def test_rendered_email_passes_through_the_c_and_copy_starts_together(max_avatar, models, lexicon, arrangement):
    _, width = avatar_scale(max_avatar)
    for verb in ("EMAIL", "COPY"):
        entry = lexicon.entry(verb)
        signed, clip = _render(max_avatar, verb_plan(max_avatar, entry, models[verb].predict("point", *arrangement)))
        timing = signed.timings[0]
        times = np.arange(timing.ready, timing.end + 1e-9, 1.0 / FPS) if entry.relation.kind == "passes_through" else np.array([timing.ready])
        frames = np.round((times - signed.motion.start_time) * FPS).astype(int)
        right = _site_track(clip, frames, "r_wrist", "right", lexicon.sites[entry.relation.right_site], width)
        left = _site_track(clip, frames, "l_wrist", "left", lexicon.sites[entry.relation.left_site], width)
        assert _closest_approach(right - left) <= entry.relation.within, (verb, _closest_approach(right - left), entry.relation.within)
