"""Phoneme → viseme tables, one per phoneme alphabet: espeak-ng's, the fake's, SAMPA.

tts must not know about faces: a speech backend only hands over ``SpeechTiming``
(phonemes in its own alphabet, words); this module reads each alphabet into
:class:`Segment` s — a viseme of :mod:`motor.face.visemes` over a time span, with its
dominance and an amplitude — that :mod:`motor.face.lipsync` blends.

* ``espeak``: espeak-ng's ASCII phoneme mnemonics (``a``, ``aI``, ``@``, ``3:``, ``tS``,
  ``dZ``, ``T``, ``D``, ``N`` …), primary and secondary stress written before the vowel
  (``'aU``, ``,eI``) and pauses ``_``, ``_:``, ``_!``. Stressed vowels open fully,
  unstressed ones to :data:`UNSTRESSED`. Mnemonics of other voices are read by the same
  table where they coincide (``y``, ``2``, ``9``, ``x``, ``C`` …).
* ``fake``: the deterministic fake backend's grapheme units (letters and digraphs such as
  ``th``, ``sh``, ``ee``, ``ou``); a digit or a letter of another script is a vowel, as
  the fake counts it.
* ``sampa``: SAMPA, the alphabet of HamNoSys/SiGML mouth pictures (``hVlU`` is "hello"):
  one ASCII symbol per segment, ``tS``/``dZ`` and the length mark ``:`` kept together,
  stress ``"`` ``%`` ``'`` and syllable ``.`` marks skipped.

Diphthongs (``aI``, ``aU``, ``eI``, ``oU``, ``OI``, ``i@`` …) become two segments, the
first 60 % of the time. A symbol the table does not know is read by its first letter
(a vowel letter: a mid vowel; otherwise a tongue consonant) and reported once.
"""

from __future__ import annotations

from dataclasses import dataclass

from motor.face.visemes import DOMINANCE, VOWEL_VISEMES

#: Amplitude of an unstressed vowel's mouth shape relative to a stressed one (espeak).
UNSTRESSED = 0.8
#: Share of a diphthong's time taken by its first part.
DIPHTHONG_SPLIT = 0.6
#: A pause closes the mouth fully once it lasts this long, seconds; shorter ones less
#: (a 30 ms word gap barely shows).
SILENCE_FULL = 0.2
#: Dominance of the shortest pause.
SILENCE_FLOOR = 0.05
#: Stress marks that may precede a symbol.
STRESS_MARKS = "'\",%"


@dataclass(frozen=True)
class Segment:
    """One viseme over ``[start, end)`` seconds, with its dominance and amplitude."""

    viseme: str
    start: float
    end: float
    dominance: float
    amplitude: float = 1.0


def _entry(visemes: str, kind: str) -> tuple[tuple[str, ...], str]:
    return tuple(visemes.split("+")), kind


#: espeak-ng mnemonics → (visemes, dominance class).
ESPEAK: dict[str, tuple[tuple[str, ...], str]] = {
    **{s: _entry("PP", "bilabial") for s in ("p", "b", "m")},
    **{s: _entry("FF", "labiodental") for s in ("f", "v")},
    **{s: _entry("TH", "dental") for s in ("T", "D")},
    **{s: _entry("DD", "lingual") for s in ("t", "d", "t#", "d#", "n", "n-", "l", "l-", "L")},
    **{s: _entry("kk", "lingual") for s in ("k", "g", "N", "x", "C", "c", "J")},
    **{s: _entry("CH", "rounded") for s in ("tS", "dZ", "S", "Z")},
    **{s: _entry("SS", "sibilant") for s in ("s", "z", "ts", "dz")},
    **{s: _entry("RR", "liquid") for s in ("r", "r-", "R", "*", "3:r")},
    **{s: _entry("ou", "rounded") for s in ("w", "W")},
    "j": _entry("ih", "lingual"),
    **{s: _entry("E", "glottal") for s in ("h", "?")},
    **{s: _entry("aa", "vowel") for s in ("a", "a#", "aa", "a:", "A", "A:", "A@", "V", "&")},
    **{s: _entry("E", "vowel") for s in ("@", "@2", "@5", "@L", "3", "3:", "e", "e:", "E", "E:", "E2", "e@", "6")},
    **{s: _entry("ih", "vowel") for s in ("i", "i:", "I", "I#", "I2", "i@3")},
    **{s: _entry("oh", "vowel") for s in ("0", "O", "O:", "O@", "o", "o:", "2", "2:", "9")},
    **{s: _entry("ou", "vowel") for s in ("u", "u:", "U", "y", "y:", "Y")},
    "aI": _entry("aa+ih", "vowel"), "aI@": _entry("aa+ih", "vowel"), "aI3": _entry("aa+ih", "vowel"),
    "aU": _entry("aa+ou", "vowel"), "aU@": _entry("aa+ou", "vowel"),
    "eI": _entry("E+ih", "vowel"), "oU": _entry("oh+ou", "vowel"), "OI": _entry("oh+ih", "vowel"),
    "i@": _entry("ih+E", "vowel"), "U@": _entry("ou+E", "vowel"), "@U": _entry("E+ou", "vowel"),
}  # fmt: skip

#: The fake backend's grapheme units → (visemes, dominance class).
FAKE: dict[str, tuple[tuple[str, ...], str]] = {
    **{s: _entry("PP", "bilabial") for s in ("p", "b", "m")},
    **{s: _entry("FF", "labiodental") for s in ("f", "v", "ph")},
    "th": _entry("TH", "dental"),
    **{s: _entry("DD", "lingual") for s in ("t", "d", "n", "l")},
    **{s: _entry("kk", "lingual") for s in ("k", "c", "ck", "g", "q", "gh", "ng", "x")},
    **{s: _entry("CH", "rounded") for s in ("ch", "tch", "sh", "j")},
    **{s: _entry("SS", "sibilant") for s in ("s", "z")},
    "r": _entry("RR", "liquid"),
    **{s: _entry("ou", "rounded") for s in ("w", "wh", "qu")},
    "h": _entry("E", "glottal"),
    "a": _entry("aa", "vowel"), "e": _entry("E", "vowel"), "i": _entry("ih", "vowel"), "y": _entry("ih", "vowel"),
    "o": _entry("oh", "vowel"), "u": _entry("ou", "vowel"),
    **{s: _entry("ih", "vowel") for s in ("ee", "ea", "ie", "ei", "ey")},
    **{s: _entry("ou", "vowel") for s in ("oo", "ue", "ew")},
    **{s: _entry("aa+ou", "vowel") for s in ("ou", "ow")},
    **{s: _entry("E+ih", "vowel") for s in ("ai", "ay")},
    "oa": _entry("oh+ou", "vowel"), "oi": _entry("oh+ih", "vowel"), "oy": _entry("oh+ih", "vowel"),
    **{s: _entry("oh", "vowel") for s in ("au", "aw")},
}  # fmt: skip

#: SAMPA symbols → (visemes, dominance class).
SAMPA: dict[str, tuple[tuple[str, ...], str]] = {
    **{s: _entry("PP", "bilabial") for s in ("p", "b", "m")},
    **{s: _entry("FF", "labiodental") for s in ("f", "v")},
    **{s: _entry("TH", "dental") for s in ("T", "D")},
    **{s: _entry("DD", "lingual") for s in ("t", "d", "n", "l")},
    **{s: _entry("kk", "lingual") for s in ("k", "g", "N", "x", "c", "J")},
    **{s: _entry("CH", "rounded") for s in ("tS", "dZ", "S", "Z")},
    **{s: _entry("SS", "sibilant") for s in ("s", "z", "C")},
    **{s: _entry("RR", "liquid") for s in ("r", "R")},
    "w": _entry("ou", "rounded"), "j": _entry("ih", "lingual"),
    **{s: _entry("E", "glottal") for s in ("h", "?")},
    **{s: _entry("ih", "vowel") for s in ("i", "I")},
    **{s: _entry("E", "vowel") for s in ("e", "E", "@", "3", "6")},
    **{s: _entry("aa", "vowel") for s in ("{", "a", "A", "V", "&")},
    **{s: _entry("oh", "vowel") for s in ("Q", "O", "o", "2", "9")},
    **{s: _entry("ou", "vowel") for s in ("U", "u", "y", "Y")},
}  # fmt: skip

ALPHABETS: dict[str, dict[str, tuple[tuple[str, ...], str]]] = {"espeak": ESPEAK, "fake": FAKE, "sampa": SAMPA}
_VOWEL_LETTERS = frozenset("aeiouyAEIOUVY@0369{&")


def lookup(symbol: str, alphabet: str) -> tuple[tuple[str, ...], str, bool]:
    """Visemes, dominance class and whether ``symbol`` was known, for one symbol of
    ``alphabet`` (stress marks and a length mark allowed). Unknown symbols are read by
    their first letter (module docstring)."""
    table = ALPHABETS[alphabet]
    bare = symbol.lstrip(STRESS_MARKS)
    for candidate in (bare, bare.rstrip(":"), bare.rstrip("#:0123456789"), bare.lower() if alphabet == "fake" else bare):
        if candidate in table:
            return (*table[candidate], True)
    if alphabet == "fake" and bare and (not bare.isascii() or bare.isdigit()):
        return ("E",), "vowel", True
    first = bare[:1]
    return (("E",), "vowel", False) if first in _VOWEL_LETTERS else (("DD",), "lingual", False)


def segments(symbol: str, start: float, end: float, alphabet: str) -> tuple[list[Segment], bool]:
    """The segments one phoneme shows over ``[start, end)`` and whether its symbol was known.

    A symbol starting with ``_`` is a pause (``sil``) whose dominance grows with its length.
    """
    if symbol.startswith("_") or not symbol.strip():
        strength = DOMINANCE["bilabial"] * min(1.0, max(SILENCE_FLOOR, (end - start) / SILENCE_FULL))
        return [Segment("sil", start, end, strength)], True
    visemes, kind, known = lookup(symbol, alphabet)
    amplitude = 1.0
    if alphabet == "espeak" and kind == "vowel" and not symbol.startswith(("'", ",")):
        amplitude = UNSTRESSED
    dominance = DOMINANCE[kind]
    if len(visemes) == 1:
        return [Segment(visemes[0], start, end, dominance, amplitude)], known
    middle = start + DIPHTHONG_SPLIT * (end - start)
    return [Segment(visemes[0], start, middle, dominance, amplitude), Segment(visemes[1], middle, end, dominance, amplitude)], known


def sampa_symbols(picture: str) -> tuple[list[str], list[tuple[int, str]]]:
    """A SAMPA mouth picture split into its symbols (module docstring), and the characters
    no table knows with their positions (1-based), which are left out."""
    symbols: list[str] = []
    skipped: list[tuple[int, str]] = []
    index = 0
    while index < len(picture):
        char = picture[index]
        pair = picture[index : index + 2]
        if char in STRESS_MARKS + ".-_ ":
            index += 1
        elif pair in ("tS", "dZ"):
            symbols.append(pair)
            index += 2
        elif char in SAMPA:
            symbols.append(char)
            index += 1
        elif char in ":~" and symbols:
            symbols[-1] += char
            index += 1
        else:
            skipped.append((index + 1, char))
            index += 1
    return symbols, skipped


def is_vowel(visemes: tuple[str, ...], kind: str) -> bool:
    """Whether a looked-up symbol is a syllable nucleus."""
    return kind == "vowel" and visemes[0] in VOWEL_VISEMES
