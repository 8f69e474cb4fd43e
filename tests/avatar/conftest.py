"""The built default avatar, and user avatars the tests make from it."""

from __future__ import annotations

from pathlib import Path

import pytest
from avatar_fixtures import BUILT_GLB, make_vrm

from agent.export.gltf import read_glb


@pytest.fixture(scope="session")
def built() -> tuple[dict, bytes]:
    if not BUILT_GLB.is_file():
        pytest.fail(f"{BUILT_GLB} is missing: run `make setup` (it builds the default avatar)")
    return read_glb(BUILT_GLB.read_bytes(), BUILT_GLB.name)


@pytest.fixture(scope="session")
def vrm_fixture(built, tmp_path_factory) -> Path:
    return make_vrm(built, tmp_path_factory.mktemp("vrm") / "fixture.vrm")
