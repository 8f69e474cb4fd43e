"""Signs written as HamNoSys symbol names, for the sign-realization tests."""

from __future__ import annotations

from mura.hamnosys import hamnosys_string, parse_hamnosys
from mura.signs import Sign


def sign_from(symbols: str, gloss: str = "test") -> Sign:
    """A sign from space-separated HamNoSys symbol names."""
    return parse_hamnosys(hamnosys_string(symbols.split()), gloss=gloss)
