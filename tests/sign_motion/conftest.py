"""Fixtures for sign realization: the avatar."""

from __future__ import annotations

import pytest

from motor.body.avatar import Avatar, load_avatar


@pytest.fixture(scope="session")
def avatar() -> Avatar:
    return load_avatar("max")
