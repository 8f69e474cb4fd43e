"""The arc of spatial reference points and the geometry of the signer frame (seed 001).

Entities are placed on a semicircular arc at chest height around the signer: arc position
``a`` in [−1, 1] is the angle ``a · 90°`` from straight ahead, negative to the signer's
left, positive to the right (``−1`` far left, ``+1`` far right). The signer frame is that of
:mod:`mura.recordings`: origin midway between the shoulder joints, y up, +z forward, +x the
signer's left, lengths in shoulder widths.

Hand sites: a named point of a hand (:attr:`mura.verb_lexicon.VerbLexicon.sites`) is given
along the hand's finger axis, palm normal and thumb side in its canonical rest frame
(fingers down, palm to the thigh, thumb forward); :func:`site_points` places it for a wrist
location and a hand orientation.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

#: Height of the arc below the shoulder joints, shoulder widths (0.36 m for the
#: reference signer, so 18 cm: chest height).
ARC_HEIGHT = -0.5
#: The centre of the arc: the body's vertical axis at chest height (signer frame).
CHEST = np.array([0.0, ARC_HEIGHT, 0.0])
#: Where the hands sign, in front of the chest: the centre the verbs' paths are laid
#: out around (about 12 cm in front of the chest of the reference signer).
SIGNING_CENTRE = np.array([0.0, ARC_HEIGHT, 0.7])
#: Radius of the arc drawn in plots, shoulder widths (the front of the chest is at 0.36).
ARC_RADIUS = 1.5

#: The right shoulder joint in the signer frame (the left one mirrors it).
RIGHT_SHOULDER = np.array([-0.5, 0.0, 0.0])
#: How far a hand's finger direction turns toward the line from its shoulder through the
#: hand (0 keeps the direction asked for, 1 puts the hand in line with the arm).
ARM_LEAN = 0.75

_FINGER = np.array([0.0, -1.0, 0.0])
_THUMB = np.array([0.0, 0.0, 1.0])


def arc_direction(position: np.ndarray | float) -> np.ndarray:
    """Unit horizontal directions ``(…, 3)`` from the chest toward arc positions."""
    angle = np.asarray(position, dtype=float) * (np.pi / 2.0)
    return np.stack([-np.sin(angle), np.zeros_like(angle), np.cos(angle)], axis=-1)


def arc_point(position: np.ndarray | float, radius: float = ARC_RADIUS) -> np.ndarray:
    """Points ``(…, 3)`` of the arc at ``radius`` from the chest centre (signer frame)."""
    return CHEST + radius * arc_direction(position)


def leaning_fingers(hand: str, point: np.ndarray, fingers: np.ndarray, lean: float = ARM_LEAN) -> np.ndarray:
    """A finger direction turned by ``lean`` toward the line from the hand's shoulder to
    ``point``: the hand nearly in line with the forearm, as a comfortable wrist keeps it (a
    hand pointing far to its own side is reached with the arm extended, not by bending the
    wrist)."""
    shoulder = RIGHT_SHOULDER if hand == "right" else -RIGHT_SHOULDER
    along_arm = np.asarray(point, dtype=float) - shoulder
    wanted = np.asarray(fingers, dtype=float)
    return (1.0 - lean) * wanted / np.linalg.norm(wanted) + lean * along_arm / np.linalg.norm(along_arm)


def palm_normal(hand: str) -> np.ndarray:
    """The canonical palm normal of a hand at rest: toward the body's midline."""
    return np.array([1.0 if hand == "right" else -1.0, 0.0, 0.0])


def site_offset(hand: str, site: tuple[float, float, float]) -> np.ndarray:
    """A site's offset from the wrist ``(3,)`` with the hand at rest (canonical frame)."""
    along, normal, thumb = site
    return along * _FINGER + normal * palm_normal(hand) + thumb * _THUMB


def site_points(hand: str, site: tuple[float, float, float], wrists: np.ndarray, orientations: np.ndarray) -> np.ndarray:
    """Where a site of the hand is ``(n, 3)`` for wrist locations ``(n, 3)`` and hand
    orientations ``(n, 4)`` (quaternions ``x, y, z, w``)."""
    return np.asarray(wrists, dtype=float) + Rotation.from_quat(orientations).apply(site_offset(hand, site))


def hand_orientation(fingers: np.ndarray, palms: np.ndarray, hand: str) -> np.ndarray:
    """Quaternions ``(n, 4)`` taking the canonical rest hand to one whose fingers point along
    ``fingers`` and whose palm faces ``palms`` (made perpendicular to the fingers)."""
    fingers = np.atleast_2d(np.asarray(fingers, dtype=float))
    fingers = fingers / np.linalg.norm(fingers, axis=1, keepdims=True)
    palms = np.atleast_2d(np.asarray(palms, dtype=float))
    palms = palms - np.sum(palms * fingers, axis=1, keepdims=True) * fingers
    palms = palms / np.linalg.norm(palms, axis=1, keepdims=True)
    target = np.stack([fingers, palms, np.cross(fingers, palms)], axis=-1)
    rest = np.stack([_FINGER, palm_normal(hand), np.cross(_FINGER, palm_normal(hand))], axis=-1)
    return Rotation.from_matrix(target @ rest.T).as_quat()
