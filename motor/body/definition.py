"""An avatar definition derived from a body: skeleton at rest, and its skin when it has one.

mura's motor core needs more than bones (see :mod:`motor.body.avatar`): named body and
hand locations for HamNoSys and MURML, the signing-space grid, the torso cylinder, rest
postures, joint limits, finger calibration, and collision volumes. A skinned body gives
most of them by measurement — each location is the skin point farthest along its outward
direction in a thin slab of the bone that carries it, each volume encloses the skin of
its joints — and what cannot be measured is taken from the reference avatar ``max``,
scaled by this body's proportions. :func:`derive_definition` returns the definition (the
JSON document :func:`motor.body.avatar.load_avatar` reads) and the list of what it took
without measuring, so a user's avatar says what was guessed.

All positions are in the avatar frame at rest: metres, root joint at the origin, y up,
facing +z, +x the avatar's left.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field

import numpy as np

from motor.body.conventions import AVATAR_DIR, SIDES
from motor.body.volumes import CHEST_FROM, CHEST_JOINT, FOREARM_SHARE, SHOULDER_SHARE

#: The reference avatar whose joint limits, finger calibration, thumb postures and grid
#: proportions are taken (scaled) when a body cannot give them.
REFERENCE = AVATAR_DIR / "max.json"
#: Slab half-thickness for surface queries, metres.
SLAB = 0.006
#: Percentile of skin distances taken as a limb's collision radius.
RADIUS_PERCENTILE = 80.0
#: Finger radius as a fraction of the hand length (wrist to middle fingertip), without skin.
FINGER_RADIUS = 0.045
#: Human proportions: (quantity, low, high) as fractions of stature; outside them the
#: body is warned about as far from human.
PROPORTIONS: tuple[tuple[str, float, float], ...] = (
    ("arm length (shoulder to wrist)", 0.22, 0.45),
    ("shoulder width", 0.12, 0.35),
    ("hand length", 0.07, 0.16),
    ("head height (skull base to crown)", 0.07, 0.2),
)

FINGERS = ("thumb", "index", "middle", "ring", "pinky")


@dataclass(frozen=True, eq=False)
class Skin:
    """A body's skin at rest: vertices ``(V, 3)`` and the joint that carries each most
    (``owner (V,)``, an index into the skeleton's joints)."""

    vertices: np.ndarray
    owner: np.ndarray


@dataclass(frozen=True, eq=False)
class Body:
    """What a definition is derived from.

    Attributes:
        name: the avatar's name.
        joint_names, parents: H-Anim joints, parents first.
        positions: ``(J, 3)`` joint positions at rest, root at the origin.
        floor: height of the soles below the root (positive), metres.
        tips: fingertip positions (``l_index`` ...), when known.
        crown: height of the top of the head above the root, when known.
        skin: the skin, when the body has one.
        description: one line for the file.
    """

    name: str
    joint_names: tuple[str, ...]
    parents: tuple[int, ...]
    positions: np.ndarray
    floor: float
    tips: dict[str, np.ndarray] = field(default_factory=dict)
    crown: float | None = None
    skin: Skin | None = None
    description: str = ""


@dataclass(frozen=True)
class Definition:
    """The avatar document (JSON-ready) and the notes on what was not measured."""

    document: dict
    guessed: tuple[str, ...]
    warnings: tuple[str, ...]


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def _round(value: object) -> object:
    """Floats rounded to 0.1 mm / 1e-4 so the file is short and byte-stable."""
    if isinstance(value, float):
        return round(value, 5) + 0.0
    if isinstance(value, np.ndarray):
        return [_round(float(v)) for v in value]
    if isinstance(value, dict):
        return {k: _round(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_round(v) for v in value]
    return value


class _Measure:
    """Surface and landmark queries on one body."""

    def __init__(self, body: Body) -> None:
        self.body = body
        self.index = {name: i for i, name in enumerate(body.joint_names)}
        self.at = {name: body.positions[i] for i, name in enumerate(body.joint_names)}
        self.guessed: list[str] = []

    def joints(self, *names: str) -> np.ndarray:
        return np.array([self.index[n] for n in names if n in self.index])

    def skin_of(self, *joints: str) -> np.ndarray | None:
        """Skin vertices carried by the named joints, or None without skin."""
        skin = self.body.skin
        if skin is None:
            return None
        points = skin.vertices[np.isin(skin.owner, self.joints(*joints))]
        return points if len(points) else None

    def extreme(self, points: np.ndarray | None, direction: np.ndarray, slab: tuple[int, float] | None = None,
                near: tuple[np.ndarray, float] | None = None) -> np.ndarray | None:
        """The point farthest along ``direction`` among ``points`` within the slab
        ``(axis, value)`` (± :data:`SLAB`) and within ``near = (centre, radius)``."""
        if points is None:
            return None
        around = np.ones(len(points), dtype=bool)
        if near is not None:
            centre, radius = near
            around = np.linalg.norm(points - centre, axis=1) < radius
        for widening in (1.0, 2.0, 4.0):  # sparse meshes (limbs) need a thicker slab
            keep = around if slab is None else around & (np.abs(points[:, slab[0]] - slab[1]) < SLAB * widening)
            if np.any(keep):
                chosen = points[keep]
                return chosen[int(np.argmax(chosen @ direction))]
        return None

    def radius(self, joint: str, a: np.ndarray, b: np.ndarray, fallback: float, percentile: float = RADIUS_PERCENTILE) -> float:
        """Skin distance from segment a–b of the vertices ``joint`` carries (a percentile),
        or ``fallback`` (noted as guessed) without skin."""
        points = self.skin_of(joint)
        if points is None:
            return fallback
        return float(np.percentile(_segment_distance(points, a, b), percentile))


def _segment_distance(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    ab = b - a
    t = np.clip((points - a) @ ab / max(float(ab @ ab), 1e-12), 0.0, 1.0)
    return np.linalg.norm(points - (a + t[:, None] * ab), axis=1)


def derive_definition(body: Body) -> Definition:
    """The avatar definition of ``body`` (see the module docstring)."""
    reference = json.loads(REFERENCE.read_text(encoding="utf-8"))
    measure = _Measure(body)
    scales = _scales(measure, reference)
    face = _face_landmarks(measure, scales)
    locations = {**_central_sites(measure, face), **_side_sites(measure, face)}
    palm = _palm_thickness(locations)
    arms = _arm_volumes(measure, scales, palm)
    torso = _clear_of_arms(_torso(measure, scales), arms)
    document = {
        "name": body.name,
        "description": body.description or f"Avatar {body.name}, derived by mura from its skeleton{' and skin' if body.skin else ''}.",
        "stature": scales["stature"],
        "root_height": body.floor,
        "frame": reference["frame"],
        "rest_pose": reference["rest_pose"],
        "joints": [
            {"name": name, "parent": None if parent < 0 else body.joint_names[parent],
             "offset": body.positions[i] - (body.positions[parent] if parent >= 0 else 0.0)}
            for i, (name, parent) in enumerate(zip(body.joint_names, body.parents))
        ],  # fmt: skip
        "limits": reference["limits"],
        "fingers": reference["fingers"],
        "thumb": reference["thumb"],
        "locations": locations,
        "grid": _grid(measure, reference, scales, face),
        "torso": torso,
        "postures": _postures(measure, reference, scales),
        "collision": {"volumes": _volumes(measure, scales, face, torso, arms), "palm_thickness": palm},
    }
    measure.guessed.append("joint limits, finger calibration and thumb postures: the reference avatar max's")
    if body.skin is None:
        measure.guessed.append("no skin: every location, the torso and the collision volumes are placed by proportions of max")
    return Definition(_round(document), tuple(dict.fromkeys(measure.guessed)), tuple(_proportion_warnings(scales)))


def _scales(m: _Measure, reference: dict) -> dict:
    """The body's size figures and their ratios to the reference avatar's."""
    at = m.at
    shoulder_y = 0.5 * (at["l_shoulder"][1] + at["r_shoulder"][1])
    width = abs(at["l_shoulder"][0] - at["r_shoulder"][0])
    arm = float(np.linalg.norm(at["l_elbow"] - at["l_shoulder"]) + np.linalg.norm(at["l_wrist"] - at["l_elbow"]))
    tip = m.body.tips.get("l_middle")
    if tip is None:
        m.guessed.append("fingertips: the last finger bone continued by 75% of its length")
        tip = at["l_middle3"] + 0.75 * (at["l_middle3"] - at["l_middle2"])
    hand = float(np.linalg.norm(tip - at["l_wrist"]))
    crown = m.body.crown
    if crown is None:
        m.guessed.append("top of the head: skull base plus 0.3 of the head's distance to the shoulders, scaled")
        crown = float(at["skullbase"][1] + 1.6 * (at["skullbase"][1] - shoulder_y))
    stature = crown + m.body.floor
    return {
        "stature": float(stature), "crown": float(crown), "shoulder_y": float(shoulder_y), "width": float(width),
        "arm": arm, "hand": hand,
        "height_ratio": float(shoulder_y / 0.49), "width_ratio": float(width / 0.36), "arm_ratio": arm / 0.58,
        "hand_ratio": hand / 0.19, "reference_stature": reference["stature"],
    }  # fmt: skip


def _proportion_warnings(s: dict) -> list[str]:
    figures = {
        "arm length (shoulder to wrist)": s["arm"], "shoulder width": s["width"], "hand length": s["hand"],
        "head height (skull base to crown)": s["crown"] - (s["shoulder_y"] + 0.38 * (s["crown"] - s["shoulder_y"])),
    }  # fmt: skip
    warnings = []
    for name, low, high in PROPORTIONS:
        ratio = figures[name] / s["stature"]
        if not low <= ratio <= high:
            warnings.append(f"{name} is {ratio:.2f} of the stature, outside the human range {low}–{high}; "
                            "the motion is computed for it but may look odd")  # fmt: skip
    return warnings


def _face_landmarks(m: _Measure, s: dict) -> dict[str, float | np.ndarray]:
    """Heights and points of the face: eyes, nose tip, lips, chin, forehead, crown."""
    head = m.skin_of("skullbase")
    base = m.at["skullbase"]
    crown = s["crown"]
    eyes = [m.at.get(f"{side}_eyeball_joint") for side in SIDES]
    span = crown - base[1]
    if all(e is not None for e in eyes):
        eyes_y = float(0.5 * (eyes[0][1] + eyes[1][1]))
    else:
        m.guessed.append("eye height: 0.28 of the head above the skull base (no eye joints)")
        eyes_y = float(base[1] + 0.28 * span)
    if head is None:
        front = float(base[2] + 0.5 * span * 0.75)
        nose_y = eyes_y - 0.2 * span
        nose = np.array([0.0, nose_y, front + 0.02])
    else:
        central = head[np.abs(head[:, 0]) < 0.008]
        nose = central[int(np.argmax(central[:, 2]))]
        front = float(np.percentile(central[central[:, 1] > eyes_y, 2], 95)) if np.any(central[:, 1] > eyes_y) else float(nose[2])
    lips_y = float(nose[1] - 0.45 * (eyes_y - nose[1]))
    chin_y = float(nose[1] - 1.4 * (eyes_y - nose[1]))
    if head is not None:
        central = head[np.abs(head[:, 0]) < 0.008]
        face = central[central[:, 2] > base[2] + 0.04]
        below = face[face[:, 1] < nose[1] - 0.01]
        if len(below):
            chin_y = float(below[:, 1].min() + 0.012)
            # the lips: the forward-most bulge between nose and chin
            profile = below[(below[:, 1] > chin_y + 0.015)]
            if len(profile):
                lips_y = float(profile[int(np.argmax(profile[:, 2]))][1])
    return {"eyes_y": eyes_y, "nose": nose, "lips_y": lips_y, "chin_y": chin_y, "front": front,
            "forehead_y": eyes_y + 0.4 * (crown - eyes_y), "eyebrows_y": eyes_y + 0.17 * (crown - eyes_y),
            "neck_y": s["shoulder_y"] + 0.52 * (chin_y - s["shoulder_y"])}  # fmt: skip


def _site(bone: str, point: np.ndarray, normal: np.ndarray, m: _Measure) -> dict:
    return {"bone": bone, "offset": point - m.at[bone], "normal": _unit(normal)}


def _surface(m: _Measure, joints: tuple[str, ...], direction: np.ndarray, slab_axis: int, slab_value: float,
             fallback: np.ndarray, near: tuple[np.ndarray, float] | None = None, what: str = "") -> np.ndarray:
    found = m.extreme(m.skin_of(*joints), _unit(direction), (slab_axis, slab_value), near)
    if found is None:
        if m.body.skin is not None and what:
            m.guessed.append(f"location {what}: no skin found there, placed by proportions")
        return fallback
    return found


def _central_sites(m: _Measure, f: dict) -> dict:
    at = m.at
    head_joints = ("skullbase",)
    z = np.array([0.0, 0.0, 1.0])
    front = f["front"]

    def face(name: str, y: float, normal: np.ndarray, depth: float = 0.0) -> dict:
        guess = np.array([0.0, y, front - 0.01])
        point = _surface(m, head_joints, np.array([0.0, 0.0, 1.0]), 1, y, guess, near=(np.array([0.0, y, front]), 0.06), what=name)
        point = np.array([0.0, point[1], point[2] - depth])
        return _site("skullbase", point, normal, m)

    def trunk(name: str, joint: str, joints: tuple[str, ...], y: float) -> dict:
        guess = np.array([0.0, y, at[joint][2] + 0.1 * m.body.floor / 0.98])
        point = _surface(m, joints, z, 1, y, guess, near=(np.array([0.0, y, at[joint][2] + 0.1]), 0.2), what=name)
        return _site(joint, np.array([0.0, point[1], point[2]]), z, m)

    crown_point = np.array([0.0, f["eyes_y"], at["skullbase"][2]])
    head = m.skin_of("skullbase")
    if head is not None:
        crown_point = head[int(np.argmax(head[:, 1]))]
    nose = f["nose"]
    shoulder_y = 0.5 * (at["l_shoulder"][1] + at["r_shoulder"][1])
    sites = {
        "head": _site("skullbase", np.array([0.0, f["eyes_y"] + 0.01, front - 0.07]), z, m),
        "headtop": _site("skullbase", np.array([0.0, crown_point[1], crown_point[2]]), np.array([0.0, 1.0, 0.0]), m),
        "forehead": face("forehead", f["forehead_y"], np.array([0.0, 0.29, 0.96])),
        "eyebrows": face("eyebrows", f["eyebrows_y"], z),
        "eyes": face("eyes", f["eyes_y"], z),
        "nose": _site("skullbase", nose, z, m),
        "nostrils": face("nostrils", nose[1] - 0.015, np.array([0.0, -0.29, 0.96])),
        "lips": face("lips", f["lips_y"], z),
        "tongue": face("tongue", f["lips_y"], z, depth=0.004),
        "teeth": face("teeth", f["lips_y"] + 0.004, z, depth=0.008),
        "chin": face("chin", f["chin_y"] + 0.01, np.array([0.0, -0.2, 0.98])),
        "underchin": _site("skullbase", np.array([0.0, f["chin_y"] - 0.01, front - 0.045]), np.array([0.0, -0.93, 0.37]), m),
        "neck": trunk("neck", "vc4", ("vc4", "vc7"), f["neck_y"]),
        "shoulders": trunk("shoulders", "vt1", ("vt1", "vt6", "vc7", "l_sternoclavicular", "r_sternoclavicular"), float(shoulder_y - 0.03)),
        "chest": trunk("chest", "vt6", ("vt6", "vt10", "vt1"), float(at["vt6"][1] - 0.02)),
        "stomach": trunk("stomach", "vl1", ("vl1", "vl3", "vt10"), float(at["vl1"][1] - 0.03)),
        "belowstomach": trunk("belowstomach", "vl5", ("vl5", "sacroiliac", "humanoid_root", "vl3"), float(at["vl5"][1] - 0.02)),
    }
    return sites


def _side_sites(m: _Measure, f: dict) -> dict:
    sites: dict = {}
    for side in SIDES:
        sign = 1.0 if side == "l" else -1.0
        sites.update(_head_side_sites(m, f, side, sign))
        sites.update(_arm_sites(m, side, sign))
        sites.update(_hand_sites(m, side, sign))
    return sites


def _head_side_sites(m: _Measure, f: dict, side: str, sign: float) -> dict:
    at = m.at
    out = np.array([sign, 0.0, 0.0])
    base = at["skullbase"]
    ear_y = f["eyes_y"] - 0.01
    ear_guess = np.array([sign * 0.075 * m.body.floor / 0.98, ear_y, base[2] - 0.01])
    ear = _surface(m, ("skullbase",), out, 1, ear_y, ear_guess, what=f"{side}_ear")
    lobe = _surface(m, ("skullbase",), out, 1, ear_y - 0.03, ear + np.array([0.0, -0.03, 0.005]), what=f"{side}_earlobe")
    cheek_dir = np.array([sign * 0.6, 0.0, 0.8])
    cheek_y = f["nose"][1] - 0.01
    cheek_guess = np.array([sign * 0.05, cheek_y, f["front"] - 0.03])
    cheek = _surface(m, ("skullbase",), cheek_dir, 1, cheek_y, cheek_guess, near=(np.array([sign * 0.045, cheek_y, f["front"] - 0.02]), 0.035),
                     what=f"{side}_cheek")  # fmt: skip
    shoulder = at[f"{side}_shoulder"]
    top_guess = shoulder + np.array([0.0, 0.045, 0.0])
    top = _surface(m, (f"{side}_sternoclavicular", f"{side}_shoulder"), np.array([0.0, 1.0, 0.0]), 0, float(shoulder[0] - sign * 0.02), top_guess,
                   what=f"{side}_shouldertop")  # fmt: skip
    return {
        f"{side}_ear": _site("skullbase", ear, out, m),
        f"{side}_earlobe": _site("skullbase", lobe, out, m),
        f"{side}_cheek": _site("skullbase", cheek, cheek_dir, m),
        f"{side}_shouldertop": _site(f"{side}_sternoclavicular", top, np.array([0.0, 1.0, 0.0]), m),
    }


def _arm_sites(m: _Measure, side: str, sign: float) -> dict:
    at = m.at
    shoulder, elbow, wrist = (at[f"{side}_{j}"] for j in ("shoulder", "elbow", "wrist"))
    out = np.array([sign, 0.0, 0.0])
    inward = -out
    back = np.array([0.0, 0.0, -1.0])
    front = np.array([0.0, 0.0, 1.0])
    upper_r = m.radius(f"{side}_shoulder", shoulder, elbow, 0.045 * m.body.floor / 0.98, 60.0)
    fore_r = m.radius(f"{side}_elbow", elbow, wrist, 0.035 * m.body.floor / 0.98, 60.0)

    def on(joint: str, point: np.ndarray, direction: np.ndarray, radius: float, name: str) -> dict:
        found = _surface(m, (joint,), direction, 1, float(point[1]), point + radius * direction,
                         near=(point, 2.5 * radius), what=f"{side}_{name}")  # fmt: skip
        return _site(joint, found, direction, m)

    mid_upper = 0.5 * (shoulder + elbow)
    mid_fore = 0.5 * (elbow + wrist)
    near_wrist = wrist + 0.12 * (elbow - wrist)
    return {
        f"{side}_upperarm": on(f"{side}_shoulder", mid_upper, out, upper_r, "upperarm"),
        f"{side}_elbow": on(f"{side}_elbow", elbow, back, fore_r, "elbow"),
        f"{side}_elbowinside": on(f"{side}_elbow", elbow + 0.04 * (wrist - elbow), front, fore_r, "elbowinside"),
        f"{side}_lowerarm": on(f"{side}_elbow", mid_fore, out, fore_r, "lowerarm"),
        f"{side}_wristback": on(f"{side}_elbow", near_wrist, out, 0.7 * fore_r, "wristback"),
        f"{side}_wristpulse": on(f"{side}_elbow", near_wrist, inward, 0.7 * fore_r, "wristpulse"),
    }


def _hand_axes(m: _Measure, side: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Finger axis λ, thumb side and palm normal of one hand at rest (as the loader derives them)."""
    at = m.at
    wrist = at[f"{side}_wrist"]
    finger_axis = _unit(at[f"{side}_middle1"] - wrist)
    across = at[f"{side}_index1"] - at[f"{side}_pinky1"]
    thumb_side = _unit(across - finger_axis * float(across @ finger_axis))
    handedness = 1.0 if side == "l" else -1.0
    return finger_axis, thumb_side, handedness * np.cross(finger_axis, thumb_side)


def _hand_sites(m: _Measure, side: str, sign: float) -> dict:
    at = m.at
    wrist = at[f"{side}_wrist"]
    axis, thumb_side, palm = _hand_axes(m, side)
    back = -palm
    hand_joints = (f"{side}_wrist", f"{side}_ring0", f"{side}_pinky0")
    knuckles = 0.5 * (at[f"{side}_index1"] + at[f"{side}_pinky1"])
    palm_centre = wrist + 0.55 * (knuckles - wrist)
    thickness = 0.5 * _hand_thickness(m, side, palm_centre, palm)

    def hand_site(name: str, centre: np.ndarray, direction: np.ndarray, distance: float) -> dict:
        points = m.skin_of(*hand_joints)
        found = m.extreme(points, direction, None, (centre, 0.012 + 0.3 * distance)) if points is not None else None
        if found is None:
            found = centre + distance * direction
        return _site(f"{side}_wrist", found, direction, m)

    ball = wrist + 0.35 * (at[f"{side}_index1"] - wrist) + 0.3 * (at[f"{side}_thumb2"] - wrist)
    width = float(np.linalg.norm(at[f"{side}_index1"] - at[f"{side}_pinky1"]))
    sites = {
        f"{side}_palm": hand_site("palm", palm_centre, palm, thickness),
        f"{side}_handback": hand_site("handback", palm_centre, back, thickness),
        f"{side}_thumbball": hand_site("thumbball", ball, palm, thickness),
        f"{side}_thumbside": hand_site("thumbside", palm_centre, thumb_side, 0.6 * width),
        f"{side}_pinkyside": hand_site("pinkyside", palm_centre, -thumb_side, 0.6 * width),
    }
    for finger in FINGERS:
        sites.update(_finger_sites(m, side, finger, axis, thumb_side, palm))
    return sites


def _hand_thickness(m: _Measure, side: str, centre: np.ndarray, palm: np.ndarray) -> float:
    points = m.skin_of(f"{side}_wrist", f"{side}_ring0", f"{side}_pinky0")
    if points is None:
        return 0.028 * m.body.floor / 0.98
    near = points[np.linalg.norm(points - centre, axis=1) < 0.02]
    if len(near) < 4:
        return 0.028
    along = (near - centre) @ palm
    return float(along.max() - along.min())


def _finger_sites(m: _Measure, side: str, finger: str, axis: np.ndarray, thumb_side: np.ndarray, palm: np.ndarray) -> dict:
    at = m.at
    first = 1
    chain = [at[f"{side}_{finger}{k}"] for k in (first, first + 1, first + 2)]
    tip = m.body.tips.get(f"{side}_{finger}")
    if tip is None:
        tip = chain[2] + 0.75 * (chain[2] - chain[1])
    distal = f"{side}_{finger}3"
    direction = _unit(tip - chain[2])
    back = -palm
    if finger == "thumb":
        back = _unit(back - thumb_side)
        back = _unit(back - direction * float(back @ direction))
        side_dir = _unit(np.cross(direction, back)) * (1.0 if side == "l" else -1.0)
        side_dir = side_dir if side_dir @ np.array([0.0, 0.0, 1.0]) >= 0 else -side_dir
    else:
        side_dir = _unit(thumb_side - direction * float(thumb_side @ direction))
    hand_length = float(np.linalg.norm(m.body.tips.get(f"{side}_middle", at[f"{side}_middle3"]) - at[f"{side}_wrist"]))
    guess_r = FINGER_RADIUS * hand_length

    def radius(joint: str, point: np.ndarray, along: np.ndarray, toward: np.ndarray) -> float:
        points = m.skin_of(joint)
        if points is None:
            return guess_r
        near = points[np.abs((points - point) @ along) < 0.004]
        near = near[np.linalg.norm(near - point, axis=1) < 2.5 * guess_r]
        if len(near) == 0:
            return guess_r
        return float(np.clip(((near - point) @ toward).max(), 0.3 * guess_r, 2.5 * guess_r))

    nail_point = chain[2] + 0.6 * (tip - chain[2])
    middle_joint = f"{side}_{finger}2"
    base_joint = f"{side}_{finger}1"
    if finger == "thumb":
        middle_joint, base_joint = distal, f"{side}_thumb2"
    mid_point, base_point = at[middle_joint], at[base_joint]
    mid_dir = _unit(chain[2] - chain[1])
    side_point = chain[1] + 0.5 * (chain[2] - chain[1])
    side_joint = f"{side}_{finger}2"
    if finger == "thumb":
        side_point, side_joint = nail_point, distal
    return {
        f"{side}_{finger}_fingertip": _site(distal, tip, direction, m),
        f"{side}_{finger}_fingernail": _site(distal, nail_point + radius(distal, nail_point, direction, back) * back, back, m),
        f"{side}_{finger}_fingerpad": _site(distal, nail_point - radius(distal, nail_point, direction, -back) * back, -back, m),
        f"{side}_{finger}_fingermidjoint": _site(middle_joint, mid_point + radius(middle_joint, mid_point, mid_dir, back) * back, back, m),
        f"{side}_{finger}_fingerbase": _site(base_joint, base_point + radius(base_joint, base_point, mid_dir, back) * back, back, m),
        f"{side}_{finger}_fingerside": _site(side_joint, side_point + radius(side_joint, side_point, mid_dir, side_dir) * side_dir, side_dir, m),
    }


def _grid(m: _Measure, reference: dict, s: dict, f: dict) -> dict:
    grid = reference["grid"]
    trunk = ("LocLowerStomach", "LocStomach", "LocUpperStomach", "LocAbdomen", "LocLowerChest", "LocChest", "LocUpperChest")
    heights = {name: value * s["height_ratio"] for name, value in grid["heights"].items()}
    heights.update({
        "LocHip": 0.0, "LocShoulder": s["shoulder_y"], "LocNeck": f["neck_y"],
        "LocLowerChin": f["chin_y"] - 0.015, "LocChin": f["chin_y"], "LocMouth": f["lips_y"], "LocNose": float(f["nose"][1]),
        "LocEyes": f["eyes_y"], "LocForeHead": f["forehead_y"], "LocHead": s["crown"] - 0.04, "LocAboveHead": s["crown"] + 0.06,
    })  # fmt: skip
    for name in trunk:
        heights[name] = grid["heights"][name] / 0.49 * s["shoulder_y"]
    chest = m.skin_of("vt6", "vt10")
    front = grid["front"] * s["arm_ratio"]
    if chest is not None:
        band = chest[(np.abs(chest[:, 0]) < 0.03) & (np.abs(chest[:, 1] - heights["LocChest"]) < 0.03)]
        if len(band):
            front = float(band[:, 2].max())
    else:
        m.guessed.append("grid front plane: max's, scaled by arm length")
    return {
        "heights": heights,
        "laterals": {name: value * s["width_ratio"] for name, value in grid["laterals"].items()},
        "distances": {name: value * s["arm_ratio"] for name, value in grid["distances"].items()},
        "front": front,
    }


def _trunk_box(m: _Measure, low: float, high: float) -> tuple[np.ndarray, np.ndarray] | None:
    """Bounding box (min, max) of the trunk's skin between two heights, arms excluded."""
    trunk = m.skin_of("humanoid_root", "sacroiliac", "vl5", "vl3", "vl1", "vt10", "vt6", "vt1")
    if trunk is None:
        return None
    band = trunk[(trunk[:, 1] > low) & (trunk[:, 1] < high)]
    if len(band) < 10:
        return None
    return band.min(axis=0), band.max(axis=0)


def _torso(m: _Measure, s: dict) -> dict:
    top = s["shoulder_y"] + 0.02 * s["height_ratio"]
    bottom = -0.05 * s["height_ratio"]
    box = _trunk_box(m, float(m.at["vl5"][1]), s["shoulder_y"] - 0.03)
    if box is None:
        return {"center": [0.0, 0.0, 0.005], "half_width": 0.14 * s["width_ratio"], "half_depth": 0.11 * s["arm_ratio"],
                "bottom": bottom, "top": top}  # fmt: skip
    low, high = box
    return {
        "center": np.array([0.0, 0.0, 0.5 * (low[2] + high[2])]),
        "half_width": float(max(-low[0], high[0])),
        "half_depth": float(0.5 * (high[2] - low[2])),
        "bottom": bottom,
        "top": top,
    }


def _postures(m: _Measure, reference: dict, s: dict) -> dict:
    postures: dict = {"rest": {}, "interim_rest": {}}
    for side in SIDES:
        sign = 1.0 if side == "l" else -1.0
        wrist = m.at[f"{side}_wrist"]
        rest = wrist + np.array([sign * 0.02, 0.01, 0.05]) * s["arm_ratio"]
        postures["rest"][side] = {"wrist": rest, "hand_rotation": [0.0, 0.0, 0.0, 1.0]}
        interim = np.array(reference["postures"]["interim_rest"][side]["wrist"])
        scaled = interim * np.array([s["width_ratio"], s["height_ratio"], s["arm_ratio"]])
        postures["interim_rest"][side] = {"wrist": scaled, "hand_rotation": reference["postures"]["interim_rest"][side]["hand_rotation"]}
    return postures


def _palm_thickness(locations: dict) -> float:
    """How far apart the hands' midlines are when palm touches palm: the right hand's
    thickness from its palm to its back, as measured on the skin (both sites ride on the
    wrist)."""
    palm, back = locations["r_palm"], locations["r_handback"]
    return float(np.linalg.norm(np.asarray(palm["offset"]) - np.asarray(back["offset"])))


def _clear_of_arms(torso: dict, arms: dict[str, list[dict]]) -> dict:
    """The torso narrowed, where the arms hang against it at rest, to the inner surface of
    their upper-arm and forearm capsules: a body's volumes never overlap its own rest pose
    (else every pose of the arm would count as inside the torso, and the swivel search
    would flee a penetration no swivel can end). The trunk's skin is widest where it
    meets the shoulders, and that width is the arms' flesh, not the torso's."""
    width = torso["half_width"]
    share = np.linspace(0.0, 1.0, 33)[:, None]
    for volumes in arms.values():
        for capsule in volumes[:2]:
            a, b = np.asarray(capsule["a"]), np.asarray(capsule["b"])
            points = a + share * (b - a)
            beside = points[(points[:, 1] >= torso["bottom"]) & (points[:, 1] <= torso["top"])]
            if len(beside):
                width = min(width, float(np.min(np.abs(beside[:, 0] - torso["center"][0]))) - capsule["radius"])
    return {**torso, "half_width": width}


def _arm_volumes(m: _Measure, s: dict, palm: float) -> dict[str, list[dict]]:
    """Each side's upper-arm, forearm and hand capsules, as thick as the skin around their
    bones; as the default volumes (:mod:`motor.body.volumes`) the upper arm leaves out the
    shoulder's own flesh next to the joint (:data:`SHOULDER_SHARE`), the forearm stops
    short of the wrist (:data:`FOREARM_SHARE`) and the hand is as thick as the palm — a
    capsule as thick as the hand is wide would make hands placed palm to palm overlap."""
    at = m.at
    arms = {}
    for side in SIDES:
        shoulder, elbow, wrist = (at[f"{side}_{j}"] for j in ("shoulder", "elbow", "wrist"))
        upper = m.radius(f"{side}_shoulder", shoulder, elbow, 0.045 * s["arm_ratio"])
        fore = m.radius(f"{side}_elbow", elbow, wrist, 0.035 * s["arm_ratio"])
        knuckles = 0.5 * (at[f"{side}_index1"] + at[f"{side}_pinky1"])
        arms[side] = [
            {"name": f"{side}_upper_arm", "joint": f"{side}_shoulder", "shape": "capsule",
             "a": shoulder + SHOULDER_SHARE * (elbow - shoulder), "b": elbow, "radius": upper},
            {"name": f"{side}_forearm", "joint": f"{side}_elbow", "shape": "capsule",
             "a": elbow, "b": elbow + FOREARM_SHARE * (wrist - elbow), "radius": fore},
            {"name": f"{side}_hand", "joint": f"{side}_wrist", "shape": "capsule", "a": wrist, "b": knuckles, "radius": 0.5 * palm},
        ]  # fmt: skip
    return arms


def _volumes(m: _Measure, s: dict, f: dict, torso: dict, arms: dict[str, list[dict]]) -> list[dict]:
    at = m.at
    volumes = []
    cylinder = lambda name, joint, bottom, top: {"name": name, "joint": joint, "shape": "elliptic_cylinder", "center": torso["center"],
                                                 "half_width": torso["half_width"], "half_depth": torso["half_depth"], "bottom": bottom, "top": top}  # fmt: skip
    cut = float(at[CHEST_FROM][1])
    volumes.append(cylinder("torso", "vl5", float(at["vl5"][1]), cut))
    volumes.append(cylinder("chest", CHEST_JOINT, cut, torso["top"]))
    pelvis = _trunk_box(m, float(at["l_hip"][1] - 0.08) if "l_hip" in at else -0.1, float(at["vl5"][1]))
    if pelvis is None:
        pelvis = (np.array([-0.16, -0.1, -0.1]) * s["width_ratio"], np.array([0.16, at["vl5"][1], 0.1]) * s["width_ratio"])
    volumes.append({"name": "pelvis", "joint": "humanoid_root", "shape": "ellipsoid", "center": 0.5 * (pelvis[0] + pelvis[1]),
                    "radii": 0.5 * (pelvis[1] - pelvis[0])})  # fmt: skip
    neck_r = m.radius("vc7", at["vc7"], at["skullbase"], 0.055 * s["width_ratio"], 60.0)
    volumes.append({"name": "neck", "joint": "vc7", "shape": "capsule", "a": at["vc7"], "b": at["skullbase"], "radius": neck_r})
    head = m.skin_of("skullbase")
    if head is None:
        centre = np.array([0.0, 0.5 * (at["skullbase"][1] + s["crown"]), f["front"] - 0.1])
        radii = np.array([0.08, 0.5 * (s["crown"] - at["skullbase"][1]) + 0.02, 0.1]) * np.array([s["width_ratio"], 1.0, 1.0])
    else:
        face = head[head[:, 1] > f["chin_y"] - 0.01]
        low, high = face.min(axis=0), face.max(axis=0)
        centre, radii = 0.5 * (low + high), 0.5 * (high - low)
    volumes.append({"name": "head", "joint": "skullbase", "shape": "ellipsoid", "center": centre, "radii": radii})
    for side in SIDES:
        volumes += arms[side]
        if f"{side}_hip" in at and f"{side}_knee" in at:
            thigh = m.radius(f"{side}_hip", at[f"{side}_hip"], at[f"{side}_knee"], 0.07 * s["width_ratio"], 70.0)
            volumes.append({"name": f"{side}_thigh", "joint": f"{side}_hip", "shape": "capsule", "a": at[f"{side}_hip"],
                            "b": at[f"{side}_knee"], "radius": thigh})  # fmt: skip
    return volumes


__all__ = ["Body", "Definition", "Skin", "derive_definition"]
