"""SiGML/HamNoSys non-manuals: head, eye gaze, torso, shoulders, face and mouth pictures of signs."""

from __future__ import annotations

import numpy as np
import pytest
from face_helpers import weight

from bench.head_face import joint_frames
from motor.body.avatar import load_avatar
from motor.face.expressions import EYEBROWS, EYELIDS, NOSE
from motor.signing.sequence import realize_signs
from mura.sigml import parse_sigml

MANUAL = "<hamnosys_manual><hamfist/><hamextfingeru/><hampalml/><hamchest/><hammoveo/><hamrepeatfromstart/></hamnosys_manual>"


@pytest.fixture(scope="module")
def avatar():
    return load_avatar("max")


def sign(nonmanual: str, gloss: str = "s"):
    (parsed,) = parse_sigml(f'<sigml><hns_sign gloss="{gloss}"><hamnosys_nonmanual>{nonmanual}</hamnosys_nonmanual>{MANUAL}</hns_sign></sigml>', "nm.sigml").signs
    return parsed


def gestural(nonmanual: str):
    document = (
        f'<sigml><hamgestural_sign gloss="g"><sign_nonmanual>{nonmanual}</sign_nonmanual><sign_manual>'
        '<handconfig handshape="fist"/><handconfig extfidir="u" palmor="l"/><location_bodyarm location="chest"/>'
        '<directedmotion direction="o"/></sign_manual></hamgestural_sign></sigml>'
    )
    (parsed,) = parse_sigml(document, "g.sigml").signs
    return parsed


def head_angles(motion) -> np.ndarray:
    """Per frame, the head's pitch (+ down), yaw (+ left) and roll (+ crown to the right),
    degrees, from the face's forward and up directions (independent kinematics)."""
    _, orientations = joint_frames(motion, np.arange(motion.frame_count))
    head = orientations[motion.joint_names.index("skullbase")]
    forward, up = head.apply([0.0, 0.0, 1.0]), head.apply([0.0, 1.0, 0.0])
    return np.degrees(np.stack([-np.arcsin(forward[:, 1]), np.arctan2(forward[:, 0], forward[:, 2]), np.arctan2(-up[:, 0], up[:, 1])], axis=1))


@pytest.mark.parametrize("form", ["hns", "gestural"])
def test_a_nod_and_a_mouth_picture_move_the_head_and_the_mouth(avatar, form):
    made = sign('<hnm_head tag="NO"/><hnm_mouthpicture picture="hVlU"/>') if form == "hns" else gestural(
        '<head_tier><head_movement movement="NO"/></head_tier><mouthing_tier><mouth_picture picture="hVlU"/></mouthing_tier>'
    )
    signed = realize_signs(avatar, [made])
    motion, (timing,) = signed.motion, signed.timings
    pitch = head_angles(motion)[:, 0]
    jaw = weight(motion, "jawOpen")
    during = (motion.times >= timing.ready) & (motion.times <= timing.end)
    dips = np.flatnonzero((pitch[1:-1] > pitch[:-2]) & (pitch[1:-1] >= pitch[2:]) & (pitch[1:-1] > 5.0))
    assert len(dips) == 2, pitch.round(1)
    assert jaw[during].max() > 0.3 and abs(pitch[0]) < 1e-6 and abs(pitch[-1]) < 1e-6
    assert jaw[0] == 0.0 and jaw[-1] == 0.0
    assert signed.warnings == ()


@pytest.mark.parametrize(
    ("code", "axis", "sign_of"),
    [("NO", 0, 1), ("NF", 0, 1), ("NB", 0, -1), ("SL", 1, 1), ("SR", 1, -1), ("TL", 2, -1), ("TR", 2, 1), ("SH", 1, 0)],
)
def test_head_codes_turn_the_head_about_their_axis(avatar, code, axis, sign_of):
    angles = head_angles(realize_signs(avatar, [sign(f'<hnm_head tag="{code}"/>')]).motion)
    biggest = np.abs(angles).max(axis=0)
    assert biggest[axis] > 5.0 and all(biggest[k] < 0.5 * biggest[axis] for k in range(3) if k != axis), biggest
    extreme = angles[np.argmax(np.abs(angles[:, axis])), axis]
    if sign_of:
        assert np.sign(extreme) == sign_of
    else:
        assert angles[:, axis].max() > 5.0 and angles[:, axis].min() < -5.0


@pytest.mark.parametrize(
    ("tier", "code", "names"),
    [("eyebrows", "RB", {"browInnerUp"}), ("eyebrows", "FU", {"browDownLeft", "browDownRight"}), ("eyelids", "CB", {"eyeBlinkLeft", "eyeBlinkRight"}),
     ("eyelids", "WB", {"eyeWideLeft"}), ("eyelids", "SR", {"eyeSquintRight"}), ("nose", "WR", {"noseSneerLeft"}), ("mouthgesture", "C01", {"cheekPuff"}),
     ("mouthgesture", "T03", {"tongueOut"}), ("eyelids", "BB", {"eyeBlinkLeft"})],
)  # fmt: skip
def test_facial_codes_move_their_morphs(avatar, tier, code, names):
    signed = realize_signs(avatar, [sign(f'<hnm_{tier} tag="{code}"/>')])
    for name in names:
        assert weight(signed.motion, name).max() > 0.5, name
    assert weight(signed.motion, "jawOpen").max() <= (0.2 if code == "T03" else 0.0)


def test_every_facial_code_of_the_tables_is_read(avatar):
    items = "".join(f'<hnm_{tier} tag="{code}"/>' for tier, table in (("eyebrows", EYEBROWS), ("eyelids", EYELIDS), ("nose", NOSE)) for code in table)
    assert realize_signs(avatar, [sign(items)]).warnings == ()


@pytest.mark.parametrize(
    ("code", "joint", "moves"),
    [("UB", "l_shoulder", (0.0, 1.0, 0.0)), ("UB", "r_shoulder", (0.0, 1.0, 0.0)), ("UL", "l_shoulder", (0.0, 1.0, 0.0)),
     ("HR", "r_shoulder", (0.0, 0.0, 1.0)), ("TF", "vc7", (0.0, 0.0, 1.0)), ("TB", "vc7", (0.0, 0.0, -1.0)), ("TL", "vc7", (1.0, 0.0, 0.0)),
     ("RL", "r_shoulder", (0.0, 0.0, 1.0))],  # turning left brings the right shoulder forward
)  # fmt: skip
def test_body_and_shoulder_codes_move_the_trunk(avatar, code, joint, moves):
    tier = "shoulder" if code[0] in "UHS" else "body"
    motion = realize_signs(avatar, [sign(f'<hnm_{tier} tag="{code}"/>')]).motion
    positions, _ = joint_frames(motion, np.arange(motion.frame_count))
    shift = positions[:, motion.joint_names.index(joint)] - positions[0, motion.joint_names.index(joint)]
    along = shift @ np.asarray(moves)
    assert along.max() > 0.015, along.max()


@pytest.mark.parametrize(("code", "target"), [("AD", "listener"), ("HD", "right_palm")])
def test_eye_gaze_codes_aim_the_eyes(avatar, code, target):
    from bench.head_face import gaze_errors

    signed = realize_signs(avatar, [sign(f'<hnm_eyegaze tag="{code}"/>')])
    timing = signed.timings[0]
    errors = gaze_errors(signed.motion, 0.5 * (timing.ready + timing.end), target, {})
    assert max(errors.values()) < 5.0, errors


@pytest.mark.parametrize(
    ("nonmanual", "expected"),
    [('<hnm_head tag="XX"/>', "unknown head lexeme 'XX'"), ('<hnm_eyebrows tag="ZZ"/>', "unknown eyebrows code 'ZZ'"),
     ('<hnm_mouthpicture picture="pa!"/>', "unknown SAMPA symbol '!' at position 3"), ('<hnm_eyegaze tag="QQ"/>', "unknown eye gaze code 'QQ'"),
     ('<hnm_body tag="XY"/>', "unknown body or shoulder movement 'XY'"), ('<hnm_mouthgesture tag="L12"/>', "realized by its family: lips pursed")],
)  # fmt: skip
def test_unknown_codes_are_reported_where_they_stand_and_the_sign_goes_on(avatar, nonmanual, expected):
    signed = realize_signs(avatar, [sign(nonmanual, "odd")])
    (warning,) = [w for w in signed.warnings if expected in w]
    assert warning.startswith("sign 'odd' (nm.sigml:1:")
    assert signed.motion.frame_count > 0 and np.all(np.isfinite(signed.motion.rotations))


def test_the_corpus_mouth_picture_is_performed(avatar, shared):
    result = parse_sigml((shared / "corpora" / "sigml" / "Indian_SL.sigml").read_bytes(), "Indian_SL.sigml")
    hello = next(s for s in result.signs if s.gloss == "hello")
    signed = realize_signs(avatar, [hello])
    jaw = weight(signed.motion, "jawOpen")
    rounded = weight(signed.motion, "mouthPucker")
    assert jaw.max() > 0.4 and rounded.max() > 0.3  # hVlU: the open V, then the rounded U
    assert np.argmax(jaw) < np.argmax(rounded)
