"""File names from glosses: Unicode letters kept, safe on common file systems, unique.

A gloss is any text a corpus gives (``HOUSE1A^``, ``नमस्ते``, ``a b/c``). Its file-name
stem keeps letters, marks and digits of every script (normalized to NFC) and ``-`` and
``.``; every other run of characters becomes one ``_``. Stems are cut to
:data:`MAX_STEM_BYTES` bytes of UTF-8 (on a character boundary, well under the 255-byte
limit of common file systems with room for suffixes), never end in a dot or space, and
never are a name Windows reserves (``CON``, ``NUL``, ``COM1`` … get a ``_`` appended). A
gloss with nothing left becomes ``sign``.

Names are unique without regard to case (case-insensitive file systems): a stem already
taken gets ``_2``, ``_3`` … in the order the items come, so the same corpus always gets
the same names, however it is later split among workers.
"""

from __future__ import annotations

import re
import unicodedata
from collections.abc import Iterable

#: Longest stem, bytes of UTF-8.
MAX_STEM_BYTES = 120

_RUNS = re.compile(r"_+")
#: Unicode categories kept: letters, marks (vowel signs, accents) and digits.
_KEPT = ("L", "M", "N")
_RESERVED = frozenset({"con", "prn", "aux", "nul", *(f"com{i}" for i in range(1, 10)), *(f"lpt{i}" for i in range(1, 10))})


def safe_stem(gloss: str, fallback: str = "sign") -> str:
    """A file-name stem for ``gloss`` (module docstring), not yet made unique."""
    text = unicodedata.normalize("NFC", gloss)
    kept = "".join(c if unicodedata.category(c)[0] in _KEPT or c in "-." else "_" for c in text)
    stem = _RUNS.sub("_", kept).strip("_. ")
    stem = _cut(stem, MAX_STEM_BYTES).rstrip("_. ")
    if not stem or set(stem) <= {"."}:
        return fallback
    if stem.split(".")[0].lower() in _RESERVED:
        stem += "_"
    return stem


def unique_stems(glosses: Iterable[str], fallback: str = "sign") -> list[str]:
    """Stems for ``glosses`` in order, unique regardless of case (module docstring)."""
    taken: set[str] = set()
    stems = []
    for gloss in glosses:
        stems.append(unique_stem(gloss, taken, fallback))
    return stems


def unique_stem(gloss: str, taken: set[str], fallback: str = "sign") -> str:
    """The stem of ``gloss``, made unique in ``taken`` (case-insensitively), which it joins."""
    stem = safe_stem(gloss, fallback)
    candidate, number = stem, 2
    while candidate.casefold() in taken:
        suffix = f"_{number}"
        candidate = _cut(stem, MAX_STEM_BYTES - len(suffix)) + suffix
        number += 1
    taken.add(candidate.casefold())
    return candidate


def _cut(text: str, limit: int) -> str:
    data = text.encode("utf-8")[:limit]
    return data.decode("utf-8", "ignore")
