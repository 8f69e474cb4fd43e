"""Fixtures for sign realization: the avatar, signs written as HamNoSys symbol names."""

from __future__ import annotations

import pytest

from motor.avatar import Avatar, load_avatar
from mura.hamnosys import hamnosys_string, parse_hamnosys
from mura.signs import Sign


@pytest.fixture(scope="session")
def avatar() -> Avatar:
    return load_avatar("max")


def sign_from(symbols: str, gloss: str = "test") -> Sign:
    """A sign from space-separated HamNoSys symbol names."""
    return parse_hamnosys(hamnosys_string(symbols.split()), gloss=gloss)
