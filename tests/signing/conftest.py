"""Fixtures for the signing parsers: the SiGML corpora, and the avatar signs are planned on."""

from __future__ import annotations

from pathlib import Path

import pytest
from signing_helpers import CORPORA

from motor.body.avatar import Avatar, load_avatar


@pytest.fixture(scope="session")
def sigml_corpora(shared: Path) -> dict[str, bytes]:
    folder = shared / "corpora" / "sigml"
    return {name: (folder / name).read_bytes() for name in CORPORA}


@pytest.fixture(scope="session")
def avatar() -> Avatar:
    """The reference avatar the sign planner is checked on."""
    return load_avatar("max")
