"""A SYNTHETIC recording session of the eight verbs — made by this generator, not captured.

No recording of the seed's verbs is publicly reachable (the CUNY ASL corpus is available
only by request), so the models are trained on performances this module builds from each
verb's description in the seed's Table 1. It stands in for motion capture; every file it
writes says ``"synthetic": true`` and its description says how it was made. Models are
fitted from it by the same code that fits real recordings (:mod:`motor.verbs.fitting`).

**Arrangements.** As in the seed, 42 per verb: the ordered pairs of different positions
among the seven arc positions −1, −⅔, −⅓, 0, ⅓, ⅔, 1 (subject, object). Object-only verbs
are performed for the same 42 pairs; their subject changes nothing.

**The verbs** (signer frame of :mod:`mura.recordings`, shoulder widths; ``u(a)`` the unit
direction toward arc position ``a``, ``C`` the signing centre in front of the chest (:data:`motor.verbs.arc.SIGNING_CENTRE`); each keyframe
places a named *site* of the hand, from which the wrist follows through the orientation;
in the one-handed verbs a point ``C + r u(a)`` lies ``0.56 · max(a, 0)`` further out, as
the right hand reaches its own side with the arm extended):

- ASK: the hooked index fingertip from ``C + 0.45 u(s)`` (raised) to ``C + 0.9 u(o)``,
  pointing at the object at the end.
- GIVE: both flat-O hands side by side (0.2 to either side of the pair's centre),
  fingertips from ``C + 0.6 u(s)`` (pointing outward) to ``C + 0.9 u(o)`` (pointing at the
  object), palms up.
- MEET: both index fingers up, from ``C + 0.7 u(s)`` (right) and ``C + 0.7 u(o)`` (left)
  to 0.08 either side of ``C + 0.7 u((s + o)/2)``, each palm toward the body's midline
  and forward (so facing the other hand's when they meet).
- SCOLD: the index fingertip raised at ``H + 0.6 u(o)`` (``H`` in front of the heart),
  the palm to the left, then wagging toward the object (palm down) and back, twice (four
  keyframes).
- TELL: the index fingertip from the chin (the finger up and back toward it, the palm
  toward the body and the signer's right) to
  ``C + 0.9 u(o)`` near shoulder height.
- COPY: the right palm against the left palm (1 cm apart) at ``C + 0.8 u(o)``; the right
  hand then moves to ``C + 0.45 u(s)``; the left hand stays.
- EMAIL: the left C hand's opening held at ``O = C + 0.7 u((s + o)/2)``; the right
  bent-flat hand's fingertips pass through it, from ``O − 0.3 d`` to ``O + 0.3 d``, ``d``
  the horizontal direction from ``u(s)`` to ``u(o)``; the fingers lead forward and along
  the path, the palm down; the C's palm faces the signer.
- SEND: the right fingertips on the back of the left flat hand at ``C + 0.45 u(s)``, then
  flicking out to ``C + 0.9 u(o)``; the left hand stays.

**Comfortable hands.** Unless a key says otherwise (TELL's finger at the chin, the C
hand; MEET's upright index fingers lean 40 %),
finger directions are turned 75 % of the way toward the line from the hand's shoulder
through it (:func:`motor.verbs.arc.leaning_fingers`), as signers extend the arm rather than
bend the wrist; the hand then stays within the wrist's range on an avatar.

**Human variation.** Four synthetic signers, each with a constant offset of the whole
performance (normal, σ = 0.09 shoulder widths ≈ 3 cm per axis) — signers differ in where
they start while the direction is shared, the reason for the vector model — plus an offset
per performance (σ = 0.025), a location jitter per hand and keyframe (σ = 0.01), an
orientation jitter per hand and keyframe (rotation vector, σ = 4° per axis) and timing
jitter (a movement of 0.4–0.6 s, keyframes ±10 % of a segment). Seeded, so the session is
the same on every machine.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from motor.verbs.arc import ARM_LEAN, SIGNING_CENTRE as CHEST, arc_direction, hand_orientation, leaning_fingers, site_offset
from mura.errors import SourceLocation
from mura.recordings import HandKeyframes, Performance, recordings_json
from mura.verb_lexicon import VerbLexicon, load_verb_lexicon

#: The seven arc positions of the session's targets; their ordered pairs are the 42 arrangements.
ARC_POSITIONS: tuple[float, ...] = (-1.0, -2.0 / 3.0, -1.0 / 3.0, 0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0)
#: Synthetic signers and the spread of their variation (module docstring).
SIGNERS: tuple[str, ...] = ("synthetic-A", "synthetic-B", "synthetic-C", "synthetic-D")
SIGNER_OFFSET = 0.09
PERFORMANCE_OFFSET = 0.025
LOCATION_JITTER = 0.01
ORIENTATION_JITTER = np.radians(4.0)
DURATION_RANGE = (0.4, 0.6)
TIME_JITTER = 0.1
#: The seed of the shipped session.
SEED = 2015
DESCRIPTION = (
    "SYNTHETIC recording session made by motor.verbs.synthetic (not motion capture): 42 subject/object "
    "arrangements per verb built from the verbs' descriptions in seed 001's Table 1, four synthetic signers "
    "with their own start offsets, orientation and timing jitter"
)

_UP = np.array([0.0, 1.0, 0.0])
_DOWN = -_UP
_CHIN = np.array([0.0, 0.3, 0.36])
_HEART = np.array([0.2, -0.35, 0.5])
#: How much further (shoulder widths) the hands reach at arc position +1, the right side.
RIGHT_SIDE_REACH = 0.56
#: MEET's index fingers are held up, leaning less toward the arm's line than other hands.
MEET_LEAN = 0.4


@dataclass(frozen=True)
class _Key:
    """One hand at one keyframe: where its site is, where its fingers point and its palm faces."""

    site: str
    point: np.ndarray
    fingers: np.ndarray
    palm: np.ndarray
    lean: float = ARM_LEAN


_Shape = Callable[[float, float], Mapping[str, list[_Key]]]


def arrangements() -> list[tuple[float, float]]:
    """The 42 (subject, object) arrangements: ordered pairs of different arc positions."""
    return [(s, o) for s in ARC_POSITIONS for o in ARC_POSITIONS if s != o]


def _unit(vector: np.ndarray) -> np.ndarray:
    return vector / np.linalg.norm(vector)


def _horizontal(vector: np.ndarray) -> np.ndarray:
    flat = np.array([vector[0], 0.0, vector[2]])
    return _unit(flat) if np.linalg.norm(flat) > 1e-9 else np.array([0.0, 0.0, 1.0])


def _left_of(direction: np.ndarray) -> np.ndarray:
    """The horizontal unit vector to the left of a direction of travel."""
    return _horizontal(np.cross(_UP, direction))


def _space(position: float, radius: float, reach: float = 0.0) -> np.ndarray:
    """A point of the signing space toward arc ``position``: ``radius`` from the signing
    centre, ``reach · max(position, 0)`` further toward the right side (one-handed verbs:
    :data:`RIGHT_SIDE_REACH`, the right hand reaching its own side with the arm extended
    rather than next to its shoulder; two-handed verbs stay nearer the middle, where the
    left hand can follow)."""
    return CHEST + (radius + reach * max(position, 0.0)) * arc_direction(position)


def _ask(s: float, o: float) -> Mapping[str, list[_Key]]:
    start = _space(s, 0.45, RIGHT_SIDE_REACH) + 0.3 * _UP
    end = _space(o, 0.9, RIGHT_SIDE_REACH) + 0.25 * _UP
    return {"right": [
        _Key("index fingertip", start, arc_direction(o) + 0.8 * _UP, _DOWN),
        _Key("index fingertip", end, arc_direction(o) - 0.2 * _UP, _DOWN),
    ]}  # fmt: skip


def _give(s: float, o: float) -> Mapping[str, list[_Key]]:
    start = _space(s, 0.6) + 0.15 * _UP
    end = _space(o, 0.9) + 0.15 * _UP
    across = np.array([0.2, 0.0, 0.0])  # side by side, the left hand to the signer's left
    first, last = arc_direction(0.5 * s) + 0.3 * _UP, arc_direction(o) + 0.3 * _UP  # outward, then at the object
    return {
        "right": [_Key("fingertips", start - across, first, _UP), _Key("fingertips", end - across, last, _UP)],
        "left": [_Key("fingertips", start + across, first, _UP), _Key("fingertips", end + across, last, _UP)],
    }


def _meet(s: float, o: float) -> Mapping[str, list[_Key]]:
    lift = 0.3 * _UP
    right, left = _space(s, 0.7) + lift, _space(o, 0.7) + lift
    middle = _space(0.5 * (s + o), 0.7) + lift
    toward_subject = _horizontal(right - left)
    palm = np.array([1.0, 0.0, 1.0])  # the right palm toward the midline and forward; the left mirrors it
    mirror = np.array([-1.0, 1.0, 1.0])
    return {
        "right": [
            _Key("index fingertip", right, _UP, palm, MEET_LEAN),
            _Key("index fingertip", middle + 0.08 * toward_subject, _UP, palm, MEET_LEAN),
        ],
        "left": [
            _Key("index fingertip", left, _UP, mirror * palm, MEET_LEAN),
            _Key("index fingertip", middle - 0.08 * toward_subject, _UP, mirror * palm, MEET_LEAN),
        ],
    }


def _scold(s: float, o: float) -> Mapping[str, list[_Key]]:
    base = _HEART - CHEST + _space(o, 0.6, RIGHT_SIDE_REACH)
    raised = _Key("index fingertip", base + 0.2 * _UP, _UP + 0.3 * arc_direction(o), np.array([1.0, 0.0, 0.5]))
    wag = _Key("index fingertip", base + 0.12 * arc_direction(o) - 0.05 * _UP, arc_direction(o) + 0.3 * _UP, _DOWN)
    return {"right": [raised, wag, raised, wag]}


def _tell(s: float, o: float) -> Mapping[str, list[_Key]]:
    end = _space(o, 0.9, RIGHT_SIDE_REACH) + 0.45 * _UP
    return {"right": [
        _Key("index fingertip", _CHIN, _UP - 0.6 * np.array([0.0, 0.0, 1.0]), np.array([-1.0, 0.0, -1.0]), 0.0),
        _Key("index fingertip", end, arc_direction(o) + 0.1 * _UP, _DOWN),
    ]}  # fmt: skip


def _copy(s: float, o: float) -> Mapping[str, list[_Key]]:
    left_palm = _space(o, 0.8) + 0.2 * _UP
    facing = -_left_of(arc_direction(o))  # the left palm faces the signer's right of the object's direction
    fingers = arc_direction(o) + 0.4 * _UP
    start = left_palm + 0.03 * facing
    end = _space(s, 0.45) + 0.2 * _UP
    left_key = _Key("palm centre", left_palm, fingers, facing)
    return {
        "right": [_Key("palm centre", start, fingers, -facing), _Key("palm centre", end, arc_direction(s) + 0.4 * _UP, -facing)],
        "left": [left_key, left_key],
    }


def _email(s: float, o: float) -> Mapping[str, list[_Key]]:
    middle = arc_direction(0.5 * (s + o))
    opening = _space(0.5 * (s + o), 0.7) + 0.2 * _UP
    path = _horizontal(arc_direction(o) - arc_direction(s))
    fingers = middle + 0.6 * (arc_direction(o) - arc_direction(s))  # leading along the path, turning with it
    left_key = _Key("C opening", opening, _UP, -middle, 0.0)
    return {
        "right": [_Key("fingertips", opening - 0.3 * path, fingers, _DOWN), _Key("fingertips", opening + 0.3 * path, fingers, _DOWN)],
        "left": [left_key, left_key],
    }


def _send(s: float, o: float) -> Mapping[str, list[_Key]]:
    back = _space(s, 0.45) + 0.1 * _UP
    left_key = _Key("back of hand", back, np.array([-0.5, 0.0, 1.0]), _DOWN)
    end = _space(o, 0.9) + 0.25 * _UP
    return {
        "right": [_Key("fingertips", back + 0.03 * _UP, arc_direction(o) - 0.5 * _UP, _DOWN), _Key("fingertips", end, arc_direction(o) + 0.2 * _UP, _DOWN)],
        "left": [left_key, left_key],
    }


#: Each verb's performance as keyframes of its hands (module docstring).
VERB_SHAPES: dict[str, _Shape] = {
    "ASK": _ask, "GIVE": _give, "MEET": _meet, "SCOLD": _scold, "TELL": _tell, "COPY": _copy, "EMAIL": _email, "SEND": _send,
}  # fmt: skip


def ideal_keyframes(verb: str, subject: float, obj: float, lexicon: VerbLexicon | None = None) -> dict[str, HandKeyframes]:
    """The generator's noise-free performance: each hand's wrist locations and orientations."""
    lexicon = lexicon or load_verb_lexicon()
    hands = {}
    for hand, keys in VERB_SHAPES[verb](subject, obj).items():
        fingers = np.stack([leaning_fingers(hand, k.point, k.fingers, k.lean) for k in keys])
        orientations = hand_orientation(fingers, np.stack([k.palm for k in keys]), hand)
        offsets = Rotation.from_quat(orientations).apply(np.stack([site_offset(hand, lexicon.sites[k.site]) for k in keys]))
        hands[hand] = HandKeyframes(np.stack([k.point for k in keys]) - offsets, orientations)
    return hands


def synthetic_session(seed: int = SEED, verbs: tuple[str, ...] | None = None, lexicon: VerbLexicon | None = None) -> list[Performance]:
    """The synthetic performances of ``verbs`` (all eight by default), 42 each, seeded."""
    lexicon = lexicon or load_verb_lexicon()
    performances = []
    for verb in verbs or tuple(VERB_SHAPES):
        rng = np.random.default_rng([seed, list(VERB_SHAPES).index(verb)])
        offsets = rng.normal(0.0, SIGNER_OFFSET, (len(SIGNERS), 3))
        pairs = arrangements()
        signers = rng.permutation(np.arange(len(pairs)) % len(SIGNERS))
        for number, ((s, o), signer) in enumerate(zip(pairs, signers)):
            ideal = ideal_keyframes(verb, s, o, lexicon)
            shift = offsets[signer] + rng.normal(0.0, PERFORMANCE_OFFSET, 3)
            count = next(iter(ideal.values())).location.shape[0]
            hands = {}
            for hand, frames in ideal.items():
                location = frames.location + shift + rng.normal(0.0, LOCATION_JITTER, (count, 3))
                turn = Rotation.from_rotvec(rng.normal(0.0, ORIENTATION_JITTER, (count, 3)))
                hands[hand] = HandKeyframes(location, (turn * Rotation.from_quat(frames.orientation)).as_quat())
            duration = rng.uniform(*DURATION_RANGE) * (count - 1) / (1.0 if count == 2 else 2.0)
            times = np.linspace(0.0, duration, count)
            times[1:-1] += rng.uniform(-TIME_JITTER, TIME_JITTER, count - 2) * duration / (count - 1)
            name = f"{verb.lower()}-{number + 1:02d}"
            performances.append(Performance(name, verb, SIGNERS[signer], round(s, 6), round(o, 6), times, hands, SourceLocation("<synthetic>")))
    return performances


def synthetic_session_json(seed: int = SEED) -> str:
    """The shipped session's file content (``specs/verbs/recordings_synthetic.json``)."""
    return recordings_json(synthetic_session(seed), synthetic=True, description=f"{DESCRIPTION} (seed {seed})")
