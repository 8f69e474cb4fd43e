"""Fixtures of the body tests: the shipped avatars, loaded once."""

from __future__ import annotations

import pytest

from motor.body.avatar import Avatar, load_avatar

AVATARS = ("max", "kim")


@pytest.fixture(scope="session", params=AVATARS)
def avatar(request: pytest.FixtureRequest) -> Avatar:
    return load_avatar(request.param)


@pytest.fixture(scope="session")
def avatars() -> dict[str, Avatar]:
    return {name: load_avatar(name) for name in AVATARS}
