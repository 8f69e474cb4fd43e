"""Fixtures for the signing parsers: the SiGML corpora."""

from __future__ import annotations

from pathlib import Path

import pytest

CORPORA = ("German_SL_DGS.sigml", "Indian_SL.sigml")


@pytest.fixture(scope="session")
def sigml_corpora(shared: Path) -> dict[str, bytes]:
    folder = shared / "corpora" / "sigml"
    return {name: (folder / name).read_bytes() for name in CORPORA}
