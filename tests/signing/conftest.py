"""Fixtures for the signing parsers: the SiGML corpora."""

from __future__ import annotations

from pathlib import Path

import pytest
from signing_helpers import CORPORA


@pytest.fixture(scope="session")
def sigml_corpora(shared: Path) -> dict[str, bytes]:
    folder = shared / "corpora" / "sigml"
    return {name: (folder / name).read_bytes() for name in CORPORA}
