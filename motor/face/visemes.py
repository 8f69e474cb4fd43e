"""Visemes: the visible mouth shapes of speech, as ARKit morph weights, and how strongly each
one holds its shape against its neighbours.

The set is the 15 visemes of the Oculus/Meta OVRLipSync convention (``sil`` and 14 mouth
shapes, each named by a phoneme that shows it; MPEG-4 face animation groups phonemes
into 14 visemes and a neutral face alike): ``PP`` lips closed (p, b, m), ``FF``
lower lip to the upper teeth (f, v), ``TH`` tongue between the teeth, ``DD`` tongue tip
behind the upper teeth (t, d), ``kk`` back of the tongue (k, g), ``CH`` protruded,
rounded lips over close teeth (tʃ, dʒ, ʃ, ʒ), ``SS`` spread lips over close teeth (s, z),
``nn`` (n, l), ``RR`` (r, lightly rounded), and the vowels ``aa`` (open), ``E`` (mid),
``ih`` (close, spread), ``oh`` (mid, rounded) and ``ou`` (close, rounded). The phoneme
tables of :mod:`motor.face.phonemes` map every speech backend's alphabet onto them.

The weights are mura's own: a jaw opening that grows with vowel openness (open vowels
about 0.65, close ones 0.18, consonants 0.15 or less, bilabials 0 — and ``mouthClose``,
which in ARKit closes the lips over an open jaw, so that a bilabial between open vowels
still seals the lips while its neighbours keep the jaw partly open), lip rounding
(``mouthPucker``, ``mouthFunnel``) for rounded vowels and postalveolars, lip spreading
(``mouthStretch``, ``mouthSmile``) for close front vowels and sibilants, lips pressed for
bilabials, the lower lip rolled in for labiodentals and the tongue shown for dentals.

**Dominance** (how much a segment imposes its shape on its neighbours, the idea of
Cohen and Massaro's coarticulation model): segments whose lips must reach a target to be
heard as such — the lip closure of p/b/m, the lip–teeth contact of f/v, the rounding of
w and the postalveolars — dominate; tongue consonants (t, d, n, k, g, l) barely show and
take the lip shape of the vowels around them; h has no shape of its own.
"""

from __future__ import annotations

import numpy as np

from motor.face.arkit import FACE_INDEX, face_vector

#: Viseme names, ``sil`` (the mouth at rest) first.
VISEMES: tuple[str, ...] = ("sil", "PP", "FF", "TH", "DD", "kk", "CH", "SS", "nn", "RR", "aa", "E", "ih", "oh", "ou")
VISEME_INDEX: dict[str, int] = {name: index for index, name in enumerate(VISEMES)}

#: Morph weights of each viseme (names not given are 0).
VISEME_WEIGHTS: dict[str, dict[str, float]] = {
    "sil": {},
    "PP": {"mouthPress*": 0.45, "mouthRollLower": 0.2, "mouthRollUpper": 0.12, "mouthClose": 0.3},
    "FF": {"jawOpen": 0.06, "mouthRollLower": 0.55, "mouthUpperUp*": 0.22, "mouthPress*": 0.1},
    "TH": {"jawOpen": 0.16, "tongueOut": 0.35, "mouthStretch*": 0.1},
    "DD": {"jawOpen": 0.14, "mouthStretch*": 0.12, "mouthLowerDown*": 0.08},
    "kk": {"jawOpen": 0.18, "mouthStretch*": 0.1},
    "CH": {"jawOpen": 0.1, "mouthFunnel": 0.5, "mouthPucker": 0.25, "mouthUpperUp*": 0.15, "mouthLowerDown*": 0.1},
    "SS": {"jawOpen": 0.05, "mouthStretch*": 0.28, "mouthSmile*": 0.15},
    "nn": {"jawOpen": 0.14, "mouthStretch*": 0.08},
    "RR": {"jawOpen": 0.14, "mouthFunnel": 0.35, "mouthPucker": 0.2},
    "aa": {"jawOpen": 0.65, "mouthLowerDown*": 0.3, "mouthStretch*": 0.08},
    "E": {"jawOpen": 0.4, "mouthStretch*": 0.22, "mouthLowerDown*": 0.15},
    "ih": {"jawOpen": 0.18, "mouthSmile*": 0.32, "mouthStretch*": 0.28},
    "oh": {"jawOpen": 0.45, "mouthFunnel": 0.55, "mouthPucker": 0.22},
    "ou": {"jawOpen": 0.18, "mouthPucker": 0.75, "mouthFunnel": 0.35},
}

#: Dominance classes and their strengths (module docstring).
DOMINANCE: dict[str, float] = {
    "bilabial": 1.0,   # p b m: the lips must close
    "labiodental": 0.9,
    "rounded": 0.8,    # w, and the rounding of ʃ ʒ tʃ dʒ
    "sibilant": 0.45,
    "dental": 0.4,
    "liquid": 0.4,     # r
    "vowel": 0.5,
    "lingual": 0.25,   # t d n k g l: the lips follow the vowels around them
    "glottal": 0.08,   # h
}
#: Dominance class of each viseme when the segment is a consonant.
CONSONANT_CLASS: dict[str, str] = {
    "PP": "bilabial", "FF": "labiodental", "TH": "dental", "DD": "lingual", "kk": "lingual", "CH": "rounded",
    "SS": "sibilant", "nn": "lingual", "RR": "liquid", "ou": "rounded", "ih": "lingual", "E": "glottal",
}  # fmt: skip
#: Visemes that are vowels (a segment showing one of them is a syllable nucleus).
VOWEL_VISEMES: frozenset[str] = frozenset({"aa", "E", "ih", "oh", "ou"})
#: Viseme morph weights as a ``(len(VISEMES), 52)`` table.
VISEME_TABLE: np.ndarray = np.stack([face_vector(VISEME_WEIGHTS[name]) for name in VISEMES])
#: The columns any viseme moves, and the jaw's.
MOUTH_COLUMNS: np.ndarray = np.flatnonzero(np.any(VISEME_TABLE != 0.0, axis=0))
JAW_OPEN = FACE_INDEX["jawOpen"]
