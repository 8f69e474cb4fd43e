"""Inflected verbs and pointing signs as sign plans for the motor core.

A :class:`motor.verbs.model.VerbForm` is in the signer frame in shoulder widths; an
avatar has its own size. A form is put on an avatar by scaling it by the avatar's
shoulder width (the distance between its shoulder joints at rest) from the midpoint of
its shoulders, and its orientations are carried from the canonical rest hand onto the
avatar's own rest hand frame. The result is a :class:`motor.signing.plan.SignPlan` — each
hand's first posture, then one straight, targetted move per keyframe segment (positions
linear by distance, orientations by slerp), the hand shape held — so that the same motor
core realizes it as any sign: in a row of signs (:mod:`motor.signing.sequence`) or timed
against speech in an utterance (:mod:`motor.verbs.behavior`). Keyframe wrists inside the
torso are pushed out of it and wrists beyond the arm's reach pulled in
(:func:`motor.signing.reach.within_reach`, judged by position: the recorded hand
orientation is left to the IK's swivel, which keeps the upper arm out of the torso as well
as it can), the two hands of a verb by the same amount so that their relation holds, with
a warning when one moves more than :data:`REACH_NOTE`.

**Pointing** to an arc position (placing or referring to an entity) is the index hand's
fingertip thrust from :data:`POINT_NEAR` to :data:`POINT_FAR` shoulder widths from the
signing centre (:data:`motor.verbs.arc.SIGNING_CENTRE`) — moved toward the right shoulder
for positions on the right (:data:`POINT_SHIFT`) — toward the arc position, the finger along the direction (turned toward the line of the arm,
:func:`motor.verbs.arc.leaning_fingers`), palm down, in
:data:`POINT_DURATION` seconds.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from scipy.spatial.transform import Rotation

from motor.body.avatar import Avatar
from motor.body.conventions import AVATAR_SIDE
from motor.hand.shape import handshape_params
from motor.signing.lmp import Move
from motor.signing.plan import HandPose, SignPlan, SignPlanningError
from motor.body.collision import outside_torso
from motor.signing.reach import within_reach
from motor.verbs.arc import RIGHT_SHOULDER, SIGNING_CENTRE, arc_direction, hand_orientation, leaning_fingers, palm_normal, site_offset
from motor.verbs.model import VerbForm
from mura.values import HandShape
from mura.verb_lexicon import VerbEntry, VerbLexicon

#: Pointing: the fingertip's distance from the body's axis at the start and the end of the
#: thrust (shoulder widths), its height above the arc, and the thrust's duration (s).
POINT_NEAR = 0.75
POINT_FAR = 0.95
POINT_LIFT = 0.3
POINT_DURATION = 0.3
#: Toward the pointing hand's own side the thrust starts nearer its shoulder (this share of
#: the way from the signing centre at arc position +1): the arm extends to point there.
POINT_SHIFT = 0.7
#: … and reaches further (shoulder widths per unit of that share), the arm extended.
POINT_EXTEND = 0.8
#: The pointing hand shape (HamNoSys ``hamfinger2``: the index extended).
POINTING_SHAPE = HandShape("finger2", name="hamfinger2")
#: A keyframe moved further than this (m) to be reachable is reported.
REACH_NOTE = 0.005
_MANNER = "targetted"


def avatar_scale(avatar: Avatar) -> tuple[np.ndarray, float]:
    """The avatar's shoulder midpoint ``(3,)`` and shoulder width (m), at rest."""
    right = avatar.rest_positions[avatar.joint_index("r_shoulder")]
    left = avatar.rest_positions[avatar.joint_index("l_shoulder")]
    return 0.5 * (right + left), float(np.linalg.norm(left - right))


def on_avatar(avatar: Avatar, points: np.ndarray) -> np.ndarray:
    """Signer-frame points (shoulder widths) as avatar-frame positions (metres)."""
    centre, width = avatar_scale(avatar)
    return centre + width * np.asarray(points, dtype=float)


def avatar_rotations(avatar: Avatar, hand: str, orientations: np.ndarray) -> np.ndarray:
    """Canonical-frame hand orientations ``(n, 4)`` as the avatar's global hand rotations."""
    frame = avatar.hand_frames[AVATAR_SIDE[hand]]
    finger = np.array([0.0, -1.0, 0.0])
    canonical = np.stack([finger, palm_normal(hand), np.cross(finger, palm_normal(hand))], axis=-1)
    own = np.stack([frame.finger_axis, frame.palm_normal, np.cross(frame.finger_axis, frame.palm_normal)], axis=-1)
    canonical_to_own = Rotation.from_matrix(own @ canonical.T)
    return (Rotation.from_quat(orientations) * canonical_to_own.inv()).as_quat()


def form_plan(avatar: Avatar, gloss: str, form: VerbForm, shapes: Mapping[str, HandShape]) -> SignPlan:
    """A sign plan performing ``form`` on ``avatar`` with the given hand shapes (module docstring)."""
    times = np.asarray(form.times, dtype=float) - float(form.times[0])
    if times.shape[0] < 2 or np.any(np.diff(times) <= 0):
        raise SignPlanningError(f"{gloss}: keyframe times {times.tolist()} do not increase")
    wanted = {hand: on_avatar(avatar, locations) for hand, locations in form.locations.items()}
    rotations = {hand: avatar_rotations(avatar, hand, form.orientations[hand]) for hand in form.locations}
    for hand in wanted:
        if not (np.all(np.isfinite(wanted[hand])) and np.all(np.isfinite(rotations[hand]))):
            raise SignPlanningError(f"{gloss}: the {hand} hand's predicted posture is not finite")
    wrists = _reachable(avatar, wanted)
    first, moves, notes = {}, {}, []
    for hand in wanted:
        shift = float(np.max(np.linalg.norm(wrists[hand] - wanted[hand], axis=1)))
        if shift > REACH_NOTE:
            notes.append(f"{gloss}: the {hand} hand moved up to {100 * shift:.1f} cm to be within reach and out of the body")
        first[hand] = HandPose(wrists[hand][0], rotations[hand][0], handshape_params(shapes[hand]))
        segments = range(times.shape[0] - 1)
        moves[(hand, "wrist_position")] = tuple(Move(times[k], times[k + 1], _MANNER, wrists[hand][k : k + 2]) for k in segments)
        moves[(hand, "hand_rotation")] = tuple(Move(times[k], times[k + 1], _MANNER, rotations[hand][k : k + 2]) for k in segments)
    return SignPlan(gloss, float(times[-1]), first, moves, static=False, warnings=tuple(notes))


def _reachable(avatar: Avatar, wanted: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Keyframe wrists within reach and out of the torso. Two hands move together: at each
    keyframe both take the larger of their own shifts (so that EMAIL's hand still passes
    through the C, COPY's palms still meet), then each is checked once more on its own."""
    own = {hand: within_reach(avatar, hand, outside_torso(avatar, points))[0] - points for hand, points in wanted.items()}
    if len(wanted) == 1:
        return {hand: wanted[hand] + own[hand] for hand in wanted}
    right, left = own["right"], own["left"]
    larger = np.where((np.linalg.norm(right, axis=1) >= np.linalg.norm(left, axis=1))[:, None], right, left)
    return {hand: within_reach(avatar, hand, outside_torso(avatar, points + larger))[0] for hand, points in wanted.items()}


def verb_plan(avatar: Avatar, entry: VerbEntry, form: VerbForm) -> SignPlan:
    """An inflected verb as a sign plan with its lexicon hand shapes."""
    return form_plan(avatar, entry.gloss, form, entry.handshapes)


def pointing_form(position: float, lexicon: VerbLexicon) -> VerbForm:
    """The pointing thrust toward arc ``position`` as keyframes (module docstring)."""
    direction = arc_direction(position)
    own_side = POINT_SHIFT * max(float(position), 0.0)
    origin = SIGNING_CENTRE + own_side * (RIGHT_SHOULDER - SIGNING_CENTRE)
    reach = own_side * POINT_EXTEND
    tips = np.stack([origin + (radius + reach) * direction + np.array([0.0, POINT_LIFT, 0.0]) for radius in (POINT_NEAR, POINT_FAR)])
    fingers = np.stack([leaning_fingers("right", tip, direction - np.array([0.0, 0.15, 0.0])) for tip in tips])
    orientation = hand_orientation(fingers, np.array([[0.0, -1.0, 0.0]] * 2), "right")
    offsets = Rotation.from_quat(orientation).apply(site_offset("right", lexicon.sites["index fingertip"]))
    return VerbForm("POINT", {"right": tips - offsets}, {"right": orientation}, np.array([0.0, POINT_DURATION]))


def pointing_plan(avatar: Avatar, position: float, lexicon: VerbLexicon, gloss: str = "POINT") -> SignPlan:
    """Pointing to arc ``position`` as a sign plan."""
    return form_plan(avatar, gloss, pointing_form(position, lexicon), {"right": POINTING_SHAPE})
