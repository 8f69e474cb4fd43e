"""Believable arm motion, asserted over tables of real inputs.

Every example utterance, every published MURML file (when ``../shared`` is there) and a
fixed sample of real SiGML signs is rendered at 60 fps, on the light reference avatar
``max`` and on the default skinned avatar ``makehuman`` (built at set-up), and measured with :mod:`checks`
(forward kinematics and plain geometry, no code of the synthesis): no elbow pops, no arm
joint turning more than 25° from one frame to the next, no arm segment more than 1 cm in
the torso or in the other arm, hands that meet keeping a palm thickness, a forearm
twist that never wraps; and frames streamed in short windows equal to frames made at once.

A few published inputs ask for what no body of these proportions can do; they are listed
per avatar in :data:`INFEASIBLE` with the reason and expected to fail (strictly: should
one start to pass, the list must shrink).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from checks import TURN_LIMIT_DEG, figures

from agent.export.bvh import bvh_text
from bench.motion_audit.avatar_file import read_avatar, unit_scale
from bench.motion_audit.bvh_reader import parse_bvh
from bench.motion_audit.kinematics import forward_kinematics
from bench.motion_audit.penetration import group_depths
from bench.motion_audit.volumes import audit_volumes
from motor.body.avatar import load_avatar
from motor.control import MotorControl
from motor.signing.plan import SignPlan
from motor.signing.planning import plan_signs
from motor.signing.sequence import SignProgram, realize_signs
from mura.sigml import parse_sigml

REPO = Path(__file__).resolve().parents[2]
SHARED = REPO.parent / "shared"
FPS = 60.0
#: Signs sampled per corpus, evenly through it.
SIGNS_PER_CORPUS = 12
#: Signs measured besides the sample, by corpus and gloss, each for the case it pins.
NAMED_SIGNS: dict[tuple[str, str], str] = {
    ("Indian_SL.sigml", "ignore"): "the right hand goes from fingers up to rest: turned by a slerp, its fingers swept back into the hip",
}
#: Largest depth (m) of an arm segment in the torso or in the other arm.
DEPTH_LIMIT = 0.01
#: Largest overlap (m) of two hands' palms (the wrists are kept apart as the arms turn the
#: hands, allowing a few millimetres before they are solved again).
PALM_OVERLAP_LIMIT = 0.005
#: The avatars measured: the light reference one and the default (skinned) one.
AVATARS = ("max", "makehuman")
#: Inputs whose spec no body of these proportions can perform clean, with the property
#: it breaks and why.
_INFEASIBLE_MAX: dict[tuple[str, str], str] = {
    ("murml_12_denule_regal", "torso"): "both arms cross the body close to the chest; a trunk turn cannot serve both",
    ("murml_12_denule_regal", "arms"): "both arms cross the body close to the chest: kept out of it, the left forearm passes 1.2 cm into the right upper arm",
}
#: On the default avatar the published inputs' defects still open on its proportions (its
#: arms are 22 % shorter than max's, its shoulders narrower), each named.
_INFEASIBLE_MAKEHUMAN: dict[tuple[str, str], str] = {
    ("example_sign_here", "palms"): "open on makehuman: the hands 1.5 cm into each other where they meet",
}
INFEASIBLE: dict[str, dict[tuple[str, str], str]] = {"max": _INFEASIBLE_MAX, "makehuman": _INFEASIBLE_MAKEHUMAN}
_TIMING = re.compile(r'<timing onset="([0-9.]+)" end="([0-9.]+)"')
_SIGN = re.compile(rb"<(hns_sign|hamgestural_sign)\b.*?</\1>", re.DOTALL)


def _utterance_cases() -> list[tuple[str, Path]]:
    cases = [(f"example_{p.stem}", p) for p in sorted((REPO / "specs" / "utterances").glob("*.xml"))]
    cases += [(f"murml_{p.stem}", p) for p in sorted((SHARED / "corpora" / "murml").glob("*.us"))]
    return cases


def _sign_cases() -> list[tuple[str, bytes, str]]:
    cases = []
    folder = SHARED / "corpora" / "sigml"
    for corpus in ("German_SL_DGS.sigml", "Indian_SL.sigml"):
        if not (folder / corpus).is_file():
            continue
        elements = [m.group(0) for m in _SIGN.finditer((folder / corpus).read_bytes())]
        step = len(elements) // SIGNS_PER_CORPUS
        cases += [(f"sign_{corpus[:3]}_{i}", element, corpus) for i, element in enumerate(elements[::step][:SIGNS_PER_CORPUS])]
        for named_corpus, gloss in NAMED_SIGNS:
            if named_corpus == corpus:
                cases += [(f"sign_{corpus[:3]}_{gloss}", e, corpus) for e in elements if f'gloss="{gloss}"'.encode() in e[:200]]
    return cases


UTTERANCES = _utterance_cases()
SIGNS = _sign_cases()
CASES = [name for name, _ in UTTERANCES] + [name for name, _, _ in SIGNS]
_RENDERED: dict[str, tuple] = {}


def _render_utterance(avatar: str, path: Path):
    from agent.agent import Agent

    agent = Agent(avatar=avatar, tts="fake", fps=FPS)
    try:
        return agent.render(path).motion
    except Exception:  # noqa: BLE001 - published timings may be too early: retried 1 s later
        shifted = _TIMING.sub(lambda m: f'<timing onset="{float(m[1]) + 1.0:g}" end="{float(m[2]) + 1.0:g}"', path.read_text())
        return agent.render(shifted.encode(), name=path.stem).motion


def _render_sign(avatar_name: str, element: bytes, corpus: str):
    avatar = load_avatar(avatar_name)
    result = parse_sigml(b"<sigml>" + element + b"</sigml>", file=corpus)
    if not result.signs:
        pytest.skip(f"{corpus}: sign does not parse: {result.failures[0].error}")
    (plan,) = plan_signs(avatar, result.signs)
    if not isinstance(plan, SignPlan):
        pytest.skip(f"{corpus}: sign does not plan: {plan}")
    return realize_signs(avatar, [plan], FPS).motion


def rendered(avatar_name: str, name: str):
    """The case's avatar, motion and figures on the named avatar, rendered once per session."""
    if (avatar_name, name) not in _RENDERED:
        avatar = load_avatar(avatar_name)
        utterances = dict(UTTERANCES)
        if name in utterances:
            motion = _render_utterance(avatar_name, utterances[name])
        else:
            _, element, corpus = next(case for case in SIGNS if case[0] == name)
            motion = _render_sign(avatar_name, element, corpus)
        _RENDERED[avatar_name, name] = (avatar, motion, figures(avatar, motion))
    return _RENDERED[avatar_name, name]


def _expect(avatar: str, name: str, prop: str, request: pytest.FixtureRequest) -> None:
    reason = INFEASIBLE[avatar].get((name, prop))
    if reason is not None:
        request.applymarker(pytest.mark.xfail(reason=reason, strict=True))


@pytest.mark.parametrize("avatar", AVATARS)
@pytest.mark.parametrize("name", CASES)
def test_the_elbow_never_pops(avatar, name):
    _, _, found = rendered(avatar, name)
    assert found.pop_frames == 0, f"{name}: {found.pop_frames} frames with the elbow at up to {found.max_elbow_speed:.2f} m/s"


@pytest.mark.parametrize("avatar", AVATARS)
@pytest.mark.parametrize("name", CASES)
def test_no_arm_joint_turns_more_than_25_degrees_a_frame(avatar, name, request):
    _expect(avatar, name, "turns", request)
    _, _, found = rendered(avatar, name)
    assert found.max_turn_deg <= TURN_LIMIT_DEG, f"{name}: {found.max_turn_deg:.1f}° in one frame"


@pytest.mark.parametrize("avatar", AVATARS)
@pytest.mark.parametrize("name", CASES)
def test_the_arms_stay_out_of_the_torso(avatar, name, request):
    _expect(avatar, name, "torso", request)
    _, _, found = rendered(avatar, name)
    assert found.torso_depth <= DEPTH_LIMIT, f"{name}: an arm {100 * found.torso_depth:.1f} cm into the torso"


@pytest.mark.parametrize("avatar", AVATARS)
@pytest.mark.parametrize("name", CASES)
def test_the_hands_stay_out_of_the_torso(avatar, name):
    """Read back from the BVH with the motion audit's reader, kinematics and volumes (the
    hand a capsule from the wrist to the middle finger's knuckle, as thick as the palm):
    ``41_tanedila_welle``'s left hand, turning on its way down to rest, went 2.9 cm into
    the hip while its wrist was clear."""
    _, motion, _ = rendered(avatar, name)
    bvh = parse_bvh(bvh_text(motion), f"{name}.bvh")
    avatar_file = read_avatar(avatar)
    kinematics = forward_kinematics(bvh, unit_scale(bvh, avatar_file))
    volumes = audit_volumes(avatar_file, kinematics)
    depth = group_depths(kinematics, volumes["torso"], [volumes["l_hand"], volumes["r_hand"]])
    frame = int(np.argmax(depth.max(axis=1)))
    assert depth.max() <= DEPTH_LIMIT, f"{name}: a hand {100 * depth.max():.1f} cm in the torso at {frame / FPS:.2f} s"


@pytest.mark.parametrize("avatar", AVATARS)
@pytest.mark.parametrize("name", CASES)
def test_the_arms_stay_out_of_each_other(avatar, name, request):
    _expect(avatar, name, "arms", request)
    _, _, found = rendered(avatar, name)
    assert found.arm_depth <= DEPTH_LIMIT, f"{name}: the arms {100 * found.arm_depth:.1f} cm into each other"


@pytest.mark.parametrize("avatar", AVATARS)
@pytest.mark.parametrize("name", CASES)
def test_hands_that_meet_keep_a_palm_thickness(avatar, name, request):
    _expect(avatar, name, "palms", request)
    _, _, found = rendered(avatar, name)
    assert found.palm_gap >= -PALM_OVERLAP_LIMIT, f"{name}: the palms {100 * -found.palm_gap:.1f} cm into each other"


@pytest.mark.parametrize("avatar", AVATARS)
@pytest.mark.parametrize("name", CASES)
def test_the_forearm_twist_never_wraps(avatar, name):
    _, _, found = rendered(avatar, name)
    assert found.twist_wraps == 0, f"{name}: {found.twist_wraps} frames where the forearm turns over in one frame"


@pytest.mark.parametrize("avatar", AVATARS)
def test_joined_hands_touch_palm_to_palm(avatar):
    """The ``join_hands`` gesture brings both fists to the centre: they touch (within the
    ease of a few millimetres), they do not overlap."""
    body, motion, found = rendered(avatar, "example_assembly_two_bars")
    from motor.body.kinematics import forward_kinematics

    from checks import PALM_THICKNESS, segment_distance

    positions = forward_kinematics(body, motion.rotations).positions
    at = lambda joint: positions[:, body.joint_index(joint)]
    gap = segment_distance(at("l_wrist"), at("l_middle1"), at("r_wrist"), at("r_middle1")) - PALM_THICKNESS
    assert -PALM_OVERLAP_LIMIT <= found.palm_gap and float(np.min(gap)) < 0.01


@pytest.mark.parametrize("avatar", AVATARS)
@pytest.mark.parametrize("name", [n for n, _, _ in SIGNS[:: max(1, len(SIGNS) // 4)]])
def test_signs_streamed_in_short_windows_are_the_frames_made_at_once(avatar, name):
    """The sign's LMPs activated on a fresh control and sampled in 0.1 s windows, as the
    live path does, give the arms' frames of one call over the whole sign."""
    _, element, corpus = next(case for case in SIGNS if case[0] == name)
    avatar = load_avatar(avatar)
    plan = plan_signs(avatar, parse_sigml(b"<sigml>" + element + b"</sigml>", file=corpus).signs)[0]
    if not isinstance(plan, SignPlan):
        pytest.skip("sign does not plan")
    whole = realize_signs(avatar, [plan], FPS)
    control = MotorControl(avatar, FPS)
    for lmp in sorted((lmp for lmps in whole.control.activated().values() for lmp in lmps), key=lambda lmp: lmp.pegs.start):
        control.activate(SignProgram(name, (lmp,)))
    edges = np.arange(0.0, whole.motion.duration + 0.1, 0.1)
    streamed = np.concatenate([control.frames(a, b).rotations for a, b in zip(edges, edges[1:])])[: whole.motion.frame_count]
    # the sign sequence turns the head afterwards for non-manual tiers: the arms and trunk
    joints = np.concatenate([avatar.arm_joints(side) for side in "lr"] + [[avatar.joint_index(j) for j in ("vt10", "vt6", "vt1")]])
    np.testing.assert_allclose(streamed[:, joints], whole.motion.rotations[:, joints], rtol=0.0, atol=1e-12)
