"""Lip-sync: visemes blended by dominance from the phonemes of ``SpeechTiming`` (seed 004).

Seed 004 asserts the speech timing to the chunk blackboard "to compose lip-synchronous
speech animations": the same phoneme times that place the gesture strokes drive the
mouth here, so lip-sync is exact with every backend, the fake included.

**Coarticulation.** Each segment (a phoneme's viseme, :mod:`motor.face.phonemes`) has a
dominance ``α`` that is full over its own span and decays exponentially outside it —
with time constant :data:`REACH_BEFORE` ahead of the segment (anticipation: the lips
start forming a sound before it is heard) and :data:`REACH_AFTER` behind it (carry-over).
The mouth at time ``t`` is the dominance-weighted mean of the segments' viseme weights,

    w(t) = Σ α_i d_i(t) a_i V_i / (Σ α_i d_i(t) + α_rest),

``d_i`` the decay, ``a_i`` the segment's amplitude (stress), ``V_i`` its viseme's morph
weights, and ``α_rest`` (:data:`REST_DOMINANCE`) a constant pull toward the closed mouth,
so that the face comes to rest away from speech; a chunk's speech is framed by full
pauses, so the mouth is closed before it begins and after it ends. Bilabials (dominance 1) close the lips
whatever surrounds them; tongue consonants (0.25) take the lip shape of their vowels;
a long pause (dominance up to 1) closes the mouth, a 30 ms word gap barely does. The
whole articulation runs :data:`ANTICIPATION` seconds ahead of the audio: visible
articulation leads the sound it makes. The sum runs over the :data:`NEIGHBOURS` segments
on each side of the one in progress, a bounded gather per frame (vectorized).

**Word-level fallback.** A backend without phonemes (pyttsx3 gives word times only) is
read word by word: each word becomes its syllables (groups of vowel letters, at least
one), each a lingual closing followed by a mid vowel opening, and the gaps between words
pauses — the same blending then opens and closes the mouth with the words.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from motor.face.phonemes import ALPHABETS, SILENCE_FULL, Segment, lookup, sampa_symbols, segments
from motor.face.visemes import DOMINANCE, MOUTH_COLUMNS, VISEME_INDEX, VISEME_TABLE

#: Decay time of a segment's dominance before it starts and after it ends, seconds.
REACH_BEFORE = 0.04
REACH_AFTER = 0.035
#: How far the mouth leads the audio, seconds.
ANTICIPATION = 0.05
#: Pull toward the closed mouth everywhere.
REST_DOMINANCE = 0.02
#: Segments on each side of the current one that take part in the blend.
NEIGHBOURS = 3
#: Beyond this many decay times a segment no longer shows (support of an articulation).
_SUPPORT = 12.0
#: Relative times of a mouth picture's segments: consonant, vowel, long vowel.
MOUTHING_UNITS = (1.0, 2.0, 3.0)
#: The mouth is closed this long before and after a mouth picture, seconds.
MOUTHING_REST = 0.2
_VOWEL_GROUPS = re.compile(r"[aeiouyäöüàáâèéêìíîòóôùúû]+", re.IGNORECASE)


@dataclass(frozen=True, eq=False)
class Articulation:
    """Segments of visible speech on the utterance clock, sampled as mouth weights.

    ``columns`` are the indices into :data:`motor.face.arkit.FACE_NAMES` that
    :meth:`sample` fills (the mouth's).
    """

    starts: np.ndarray
    ends: np.ndarray
    visemes: np.ndarray
    dominance: np.ndarray
    amplitude: np.ndarray
    channel: tuple[str, str] = ("face", "mouth")

    @property
    def columns(self) -> np.ndarray:
        return MOUTH_COLUMNS

    @classmethod
    def of(cls, parts: Sequence[Segment], lead: float = ANTICIPATION) -> Articulation:
        """The articulation of ``parts`` (sorted by start), shifted ``lead`` seconds earlier."""
        if not parts:
            raise ValueError("an articulation needs at least one segment")
        return cls(
            np.array([s.start for s in parts]) - lead,
            np.array([s.end for s in parts]) - lead,
            np.array([VISEME_INDEX[s.viseme] for s in parts]),
            np.array([s.dominance for s in parts]),
            np.array([s.amplitude for s in parts]),
        )

    @property
    def start(self) -> float:
        return float(self.starts[0] - _SUPPORT * REACH_BEFORE)

    @property
    def end(self) -> float:
        return float(self.ends[-1] + _SUPPORT * REACH_AFTER)

    def sample(self, times: np.ndarray) -> np.ndarray:
        """Mouth weights ``(n, len(columns))`` at ``times`` (module docstring)."""
        t = np.asarray(times, dtype=float)
        current = np.searchsorted(self.starts, t, side="right") - 1
        around = current[:, None] + np.arange(-NEIGHBOURS, NEIGHBOURS + 1)[None, :]
        valid = (around >= 0) & (around < self.starts.size)
        index = np.clip(around, 0, self.starts.size - 1)
        before = np.maximum(self.starts[index] - t[:, None], 0.0) / REACH_BEFORE
        after = np.maximum(t[:, None] - self.ends[index], 0.0) / REACH_AFTER
        weight = np.where(valid, self.dominance[index] * np.exp(-(before + after)), 0.0)
        shapes = VISEME_TABLE[:, self.columns][self.visemes[index]]
        mouth = np.einsum("nk,nkf->nf", weight * self.amplitude[index], shapes)
        return mouth / (weight.sum(axis=1) + REST_DOMINANCE)[:, None]


def speech_segments(
    phonemes: Sequence[tuple[str, float, float]], alphabet: str, onset: float = 0.0
) -> tuple[list[Segment], tuple[str, ...]]:
    """Segments of ``(symbol, start, end)`` phonemes (seconds from ``onset``) in
    ``alphabet``, on the utterance clock, and the symbols no table knew (each once)."""
    if alphabet not in ALPHABETS:
        raise ValueError(f"no phoneme table for {alphabet!r} (known: {', '.join(ALPHABETS)})")
    parts: list[Segment] = []
    unknown: list[str] = []
    for symbol, start, end in _pauses_merged(phonemes):
        if end <= start:
            continue
        shown, known = segments(symbol, onset + start, onset + end, alphabet)
        parts.extend(shown)
        if not known and symbol not in unknown:
            unknown.append(symbol)
    return _at_rest_around(parts), tuple(unknown)


def _at_rest_around(parts: list[Segment]) -> list[Segment]:
    """``parts`` with a full pause before and after: the mouth is closed before the
    speech begins and after it ends, not merely pulled toward rest."""
    if not parts:
        return parts
    strength = DOMINANCE["bilabial"]
    first = 1 if parts[0].viseme == "sil" else 0
    last = len(parts) - 1 if parts[-1].viseme == "sil" else len(parts)
    if first >= last:
        return parts
    begin, finish = parts[first].start, parts[last - 1].end
    before = Segment("sil", min(begin - SILENCE_FULL, parts[0].start), begin, strength)
    after = Segment("sil", finish, max(finish + SILENCE_FULL, parts[-1].end), strength)
    return [before, *parts[first:last], after]


def _pauses_merged(phonemes: Sequence[tuple[str, float, float]]) -> list[tuple[str, float, float]]:
    """Consecutive pause symbols (``_``, ``_:`` …) joined into one pause: a pause's
    dominance grows with its whole length."""
    merged: list[tuple[str, float, float]] = []
    for symbol, start, end in phonemes:
        if merged and symbol.startswith("_") and merged[-1][0].startswith("_"):
            merged[-1] = ("_", merged[-1][1], end)
        else:
            merged.append((symbol, start, end))
    return merged


def word_segments(words: Sequence[tuple[str, float, float]], onset: float = 0.0) -> list[Segment]:
    """Segments of words alone (module docstring: word-level fallback)."""
    parts: list[Segment] = []
    previous_end: float | None = None
    for text, start, end in words:
        if end <= start:
            continue
        start, end = onset + start, onset + end
        if previous_end is not None and start > previous_end:
            parts.append(Segment("sil", previous_end, start, DOMINANCE["bilabial"] * min(1.0, (start - previous_end) / 0.2)))
        syllables = max(1, len(_VOWEL_GROUPS.findall(text)))
        bounds = np.linspace(start, end, syllables + 1)
        for a, b in zip(bounds[:-1], bounds[1:]):
            middle = a + 0.35 * (b - a)
            parts.append(Segment("DD", float(a), float(middle), DOMINANCE["lingual"]))
            parts.append(Segment("E", float(middle), float(b), DOMINANCE["vowel"]))
        previous_end = end
    return _at_rest_around(parts)


def mouth_picture(picture: str, start: float, end: float) -> tuple[Articulation | None, list[tuple[int, str]]]:
    """A SAMPA mouth picture spoken over ``[start, end]`` seconds (its segments timed in
    proportion to :data:`MOUTHING_UNITS`), with the characters left out because no table
    knows them (position, character); None when nothing is left to show."""
    symbols, skipped = sampa_symbols(picture)
    if not symbols or end <= start:
        return None, skipped
    units = []
    for symbol in symbols:
        visemes, kind, _ = lookup(symbol, "sampa")
        units.append(MOUTHING_UNITS[0] if kind != "vowel" else MOUTHING_UNITS[2 if symbol.endswith(":") else 1])
    bounds = start + (end - start) * np.concatenate([[0.0], np.cumsum(units)]) / sum(units)
    parts = [Segment("sil", start - MOUTHING_REST, start, DOMINANCE["bilabial"])]
    for symbol, a, b in zip(symbols, bounds[:-1], bounds[1:]):
        parts.extend(segments(symbol, float(a), float(b), "sampa")[0])
    parts.append(Segment("sil", end, end + MOUTHING_REST, DOMINANCE["bilabial"]))
    return Articulation.of(parts, lead=0.0), skipped
