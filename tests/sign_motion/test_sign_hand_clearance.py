"""Hands at the chest, chin and neck stay out of the torso, and no joint snaps.

Signs placed on or near the body, and the transitions from and to rest that bring the
hand there, are rendered at 60 fps and written as BVH; the BVH is read back and measured
with the motion audit's own reader, forward kinematics and volume geometry
(:mod:`bench.motion_audit`, which shares no code with the synthesis): the hand's capsule
(wrist to knuckles, palm-thick) no more than 1 cm inside the torso in any frame, and no
joint — fingers included — turning more than 25° between two frames.

The table holds the signs of the published corpora that did sink the hand into the chest
(their HamNoSys as the corpora write it) and constructed hands whose fingers point into
the body; planning-level properties of :mod:`motor.signing.hand_clearance` are checked on
a table of hand postures with the audit's distance (not the planner's).
"""

from __future__ import annotations

import numpy as np
import pytest
from sign_helpers import sign_from

from agent.export.bvh import bvh_text
from bench.motion_audit.avatar_file import read_avatar, unit_scale
from bench.motion_audit.bvh_reader import parse_bvh
from bench.motion_audit.continuity import joint_turns
from bench.motion_audit.distance import EllipticCylinder as AuditCylinder
from bench.motion_audit.distance import capsule_depth
from bench.motion_audit.kinematics import forward_kinematics
from bench.motion_audit.penetration import group_depths
from bench.motion_audit.volumes import TORSO, audit_volumes
from motor import quaternion as quat
from motor.arm.hand_orientation import hand_rotations_from_vectors
from motor.body.avatar import load_avatar
from motor.hand.shape import FINGER_START, PLAY_BEND, handshape_params, played
from motor.program.lmp import ChannelState, TimePegs
from motor.signing.hand_clearance import (
    HAND_CLEARANCE,
    hand_torso_push,
    hands_clear_of_torso,
    trunk_cylinders,
)
from motor.signing.lmp import SignChannelLMP
from motor.signing.sequence import realize_signs
from motor.trajectory.biocontrol import profile
from mura.values import HandShape

FPS = 60.0
#: Deepest a hand may sink into the torso, metres (the audit's limit).
DEPTH_LIMIT = 0.01
#: Largest turn of any joint between two frames at 60 fps, degrees.
TURN_LIMIT = 25.0
AVATARS = ("makehuman", "max")

#: Signs whose hand entered the chest (corpus gloss: the HamNoSys as written there; the
#: phase where it did on 5198eb2), and constructed hands pointing into the body.
HANDS_AT_THE_BODY = {
    # the hand turning up from rest swept its fingers back through the chest (5.8 cm)
    "WARM2C": "hamceeall hamfingerstraightmod hamextfingerul hampalmul hamchin hamtouch hamparbegin hammover hamreplace hampinchall hamfingerstraightmod hamparend",
    "TO-SMELL2": "hamflathand hamextfingerul hampalmul hamnostrils hamclose hamcircleol hamsmallmod hamrepeatfromstart",
    "leafy-vegetables": "hamflathand hamextfingerul hampalmul hamshoulders hammoveo hamswinging",
    "TROUBLE1": "hamflathand hamfingerstraightmod hamextfingerul hampalmul hamshoulders hamlrat hamtouch hammoved",
    "YELLOW5": "hamfist hamthumboutmod hamextfingeru hampalml hamunderchin hamseqbegin hamtouch hamthumb hamfingerpad hampalm hamseqend hamreplace hamextfingerl hampalmdl hamunderchin hamseqbegin hamtouch hamthumb hamfingerpad hampalm hamseqend",
    # the hand turning back down to rest swept through the chest (4.8 cm)
    "TO-SAY1": "hamfinger2 hamextfingerul hampalml hamchin hamtouch hamparbegin hammovedo hamreplace hamextfingerol hampalmul hamparend",
    "IMAGINATION1B": "hamfinger2345 hamfingerbendmod hamthumboutmod hamextfingeru hampalmul hamforehead hamlrat hamclose hamcircleil hamrepeatfromstart",
    # fingers pointing in at the neck, moving in: the keys themselves sank the palm (4.4 cm)
    "thirsty": "hamfinger2345 hamthumb hamfingerhookmod hamextfingeril hampalml hamneck hamclose hammovei hammoved hammoveu hammoved",
    "fingers into the chest": "hamflathand hamextfingeri hampalmd hamchest hamclose",
    "fist moving into the chest": "hamfist hamextfingeri hampalml hamchest hamtouch hammovei",
    "fingers down the stomach": "hamflathand hamextfingerd hampalml hamstomach hamtouch hammoveu hamlargemod",
}
#: Signs whose hand shape changes quickly: finger play (TUESDAY10A's folded fingers were
#: snapped open and shut, 31.9° in one frame), alternating hooks.
FINGER_MOVEMENT = {
    "TUESDAY10A": "hampinch12 hamextfingeru hampalmdl hamcheek hamlrat hamtouch hamfingerplay",
    "fist finger play": "hamfist hamextfingeru hampalml hamchest hamfingerplay",
    "hooked finger play": "hamfinger2345 hamfingerhookmod hamextfingeru hampalml hamchest hamfingerplay",
    "flat finger play": "hamfinger2345 hamextfingeru hampalml hamchest hamfingerplay",
}


#: Hands the planner places clear that the arm does not keep there, per avatar, with why
#: (strict: should one start to pass, the list must shrink).
OPEN: dict[tuple[str, str], str] = {}


@pytest.fixture(scope="module", params=AVATARS)
def avatar_name(request) -> str:
    return request.param


def rendered(avatar_name: str, symbols: str, gloss: str):
    """The sign rendered at 60 fps, read back from its BVH by the audit's own code: its
    kinematics and the audit's collision volumes."""
    motion = realize_signs(load_avatar(avatar_name), [sign_from(symbols, gloss)], FPS).motion
    bvh = parse_bvh(bvh_text(motion), f"{gloss}.bvh")
    avatar_file = read_avatar(avatar_name)
    kinematics = forward_kinematics(bvh, unit_scale(bvh, avatar_file))
    return kinematics, audit_volumes(avatar_file, kinematics)


@pytest.mark.parametrize("gloss", sorted(HANDS_AT_THE_BODY))
def test_hands_stay_out_of_the_torso(request, avatar_name, gloss):
    if (avatar_name, gloss) in OPEN:
        request.applymarker(pytest.mark.xfail(strict=True, reason=OPEN[(avatar_name, gloss)]))
    kinematics, volumes = rendered(avatar_name, HANDS_AT_THE_BODY[gloss], gloss)
    depths = group_depths(kinematics, volumes[TORSO], [volumes["l_hand"], volumes["r_hand"]])
    frame = int(np.argmax(depths.max(axis=1)))
    assert depths.max() <= DEPTH_LIMIT, f"{gloss}: a hand {100 * depths.max():.1f} cm in the torso at {frame / FPS:.2f} s"


@pytest.mark.parametrize("gloss", sorted(HANDS_AT_THE_BODY | FINGER_MOVEMENT))
def test_no_joint_turns_faster_than_the_limit(avatar_name, gloss):
    kinematics, _ = rendered(avatar_name, (HANDS_AT_THE_BODY | FINGER_MOVEMENT)[gloss], gloss)
    largest = joint_turns(kinematics).largest
    assert largest is None or largest.value <= TURN_LIMIT, f"{gloss}: {largest.what} turns {largest.value:.1f}° in one frame at {largest.time:.2f} s"


# -- the planner's push, checked with the audit's geometry ------------------------------

#: Hand postures near the chest: the extended fingers' direction and the palm's (avatar
#: frame: +x left, +y up, +z forward), for the right hand.
POSTURES = {
    "fingers in": ((0.0, 0.0, -1.0), (0.0, -1.0, 0.0)),
    "fingers in and down": ((0.0, -0.7, -0.7), (1.0, 0.0, 0.0)),
    "fingers across to the left, palm in": ((1.0, 0.0, 0.0), (0.0, 0.0, -1.0)),
    "fingers up, palm in": ((0.0, 1.0, 0.0), (0.0, 0.0, -1.0)),
    "fingers forward": ((0.0, 0.0, 1.0), (1.0, 0.0, 0.0)),
    "fingers down, palm left": ((0.0, -1.0, 0.0), (1.0, 0.0, 0.0)),
}
#: Wrist positions relative to the front of the torso's top half: on it, 3 cm in front,
#: 8 cm to the right, inside it, 12 cm in front.
WRIST_PLACES = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.03], [-0.08, -0.05, 0.0], [0.0, 0.05, -0.05], [0.02, 0.0, 0.12]])


def posture_table(avatar):
    """Wrist positions ``(n, 3)`` and right-hand rotations ``(n, 4)`` of every posture at
    every place."""
    trunk = trunk_cylinders(avatar)
    torso, bottom, top = trunk[0], min(c.bottom for c in trunk), max(c.top for c in trunk)
    front = np.array([torso.center[0], 0.5 * (bottom + top) + 0.1, torso.center[2] + torso.half_depth])
    wrists, rotations = [], []
    for fingers, palm in POSTURES.values():
        turn = hand_rotations_from_vectors(avatar, "r", np.array([fingers], float), np.array([palm], float))[0]
        for place in WRIST_PLACES:
            wrists.append(front + place)
            rotations.append(turn)
    return np.array(wrists), np.array(rotations)


def audit_depth(avatar, wrists: np.ndarray, rotations: np.ndarray) -> np.ndarray:
    """Depth (m) of the right hand's capsule in the torso, by the audit's distance."""
    capsule = avatar.collision.arm("r", "hand")
    rest = avatar.rest_positions[avatar.joint_index("r_wrist")]
    start = wrists + quat.rotate(rotations, capsule.a - rest)
    end = wrists + quat.rotate(rotations, capsule.b - rest)
    shapes = [AuditCylinder(c.center, c.half_width, c.half_depth, c.bottom, c.top) for c in trunk_cylinders(avatar)]
    return np.max([capsule_depth(start, end, capsule.radius, shape)[0] for shape in shapes], axis=0)


@pytest.fixture(scope="module")
def planning_avatar():
    return load_avatar("makehuman")


def test_pushed_hands_lie_clear_of_the_torso(planning_avatar):
    wrists, rotations = posture_table(planning_avatar)
    pushed = hands_clear_of_torso(planning_avatar, "r", wrists, rotations)
    assert np.allclose(pushed[:, :2], wrists[:, :2]), "the wrist moves forward only"
    assert np.all(pushed[:, 2] >= wrists[:, 2])
    depth = audit_depth(planning_avatar, pushed, rotations)
    assert np.all(depth <= -0.5 * HAND_CLEARANCE), f"deepest {100 * depth.max():.2f} cm"
    assert np.any(audit_depth(planning_avatar, wrists, rotations) > DEPTH_LIMIT), "the table has hands in the torso"


def test_clear_hands_stay_where_they_are(planning_avatar):
    wrists, rotations = posture_table(planning_avatar)
    clear = audit_depth(planning_avatar, wrists, rotations) < -0.05
    assert clear.any()
    assert np.all(hand_torso_push(planning_avatar, "r", wrists[clear], rotations[clear]) == 0.0)
    pushed = hands_clear_of_torso(planning_avatar, "r", wrists, rotations)
    assert np.array_equal(hands_clear_of_torso(planning_avatar, "r", pushed, rotations), pushed), "idempotent"


def test_push_is_the_least_that_clears(planning_avatar):
    wrists, rotations = posture_table(planning_avatar)
    push = hand_torso_push(planning_avatar, "r", wrists, rotations)
    moved = push > 0.005
    assert moved.any()
    short = wrists[moved] + np.array([0.0, 0.0, 1.0]) * (push[moved] - 0.005)[:, None]
    assert np.all(hand_torso_push(planning_avatar, "r", short, rotations[moved]) > 0.0)


# -- finger play ------------------------------------------------------------------------

PLAYED_SHAPES = {
    "flat": HandShape("flathand"),
    "fist": HandShape("fist"),
    "pinch": HandShape("pinch12"),
    "hooked": HandShape("finger2345", bending="hooked"),
    "bent": HandShape("finger2345", bending="bent"),
}


@pytest.mark.parametrize("name", sorted(PLAYED_SHAPES))
def test_finger_play_moves_each_finger_by_half_a_bend_at_its_base(name):
    params = handshape_params(PLAYED_SHAPES[name])
    moved = played(params, ("index", "middle", "ring", "pinky"))
    for k in range(4):
        base = FINGER_START + 4 * k
        folded = params[base] >= 0.9 and params[base + 2] >= 0.9
        assert np.isclose(abs(moved[base] - params[base]), 0.0 if folded else PLAY_BEND)
        assert 0.0 <= moved[base] <= 1.0
        assert np.array_equal(moved[base + 1 : base + 4], params[base + 1 : base + 4]), "splay, middle and end joints stay"
    assert np.array_equal(moved[:FINGER_START], params[:FINGER_START]), "the thumb stays"


# -- the hand turns along the wrist's transition ------------------------------------------


@pytest.mark.parametrize("gloss", sorted(HANDS_AT_THE_BODY))
def test_planned_hands_stay_clear_in_every_frame(avatar_name, gloss):
    """The wrist targets and hand rotations the arm is given, frame by frame (transitions
    from and to rest included), keep the hand clear: the hand turns as the wrist travels
    its way (its rotation keys reached when the wrist reaches its way points), not ahead
    of or behind it."""
    avatar = load_avatar(avatar_name)
    signed = realize_signs(avatar, [sign_from(HANDS_AT_THE_BODY[gloss], gloss)], FPS)
    times = signed.motion.times
    wrists = signed.control.wrist_targets(times)["right"]
    turns = signed.control.timeline(("right", "hand_rotation")).sample(times)
    depth = audit_depth(avatar, wrists, turns)
    assert depth.max() <= 0.002, f"{gloss}: the planned hand {100 * depth.max():.1f} cm in the torso at {times[int(np.argmax(depth))]:.2f} s"


def rotation_lmp(via_fractions):
    turns = quat.from_axis_angle(np.array([[1.0, 0.0, 0.0]] * 2), np.array([0.6, 1.2]))
    pegs = TimePegs(0.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0)
    first = quat.from_axis_angle(np.array([1.0, 0.0, 0.0]), 1.8)
    return SignChannelLMP(("right", "hand_rotation"), pegs, first, (), "lax", turns, None, via_fractions), turns


@pytest.mark.parametrize("fractions", [(0.2, 0.5), (0.5, 0.9), (0.1, 0.15)])
def test_rotation_passes_its_way_turns_at_their_fractions(fractions):
    lmp, turns = rotation_lmp(np.array(fractions))
    track = lmp.activate(ChannelState(quat.IDENTITY.copy(), np.zeros(3), 0.0))
    times = np.linspace(0.0, 1.0, 2001)
    samples = track.sample(times)
    angle = np.degrees(quat.to_rotation_vector(samples)[:, 0])  # about x only
    lax = profile("lax").fractions
    for turn, fraction in zip(turns, fractions):
        at = np.interp(fraction, lax, np.linspace(0.0, 1.0, lax.size))  # the time the profile reaches it
        passed = np.interp(at, times, angle)
        assert passed == pytest.approx(np.degrees(quat.to_rotation_vector(turn)[0]), abs=0.2)


@pytest.mark.parametrize("fractions", [(0.5,), (0.6, 0.4), (0.0, 0.5), (0.5, 1.0)])
def test_bad_way_fractions_are_refused_naming_the_channel(fractions):
    with pytest.raises(ValueError, match="hand_rotation.*via_fractions"):
        rotation_lmp(np.array(fractions))
