"""Fixtures of the blackboard tests: the fake motor and fake speech of :mod:`blackboard_fakes`."""

from __future__ import annotations

import pytest
from blackboard_fakes import (  # noqa: F401
    CORPUS,
    UTTERANCES,
    FailingSpeech,
    FakeMotor,
    RecordingSpeech,
    utterance,
)


@pytest.fixture
def motor() -> FakeMotor:
    return FakeMotor()


@pytest.fixture
def speech() -> RecordingSpeech:
    return RecordingSpeech()
