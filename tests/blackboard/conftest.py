"""Fixtures of the blackboard tests: the fake motor and fake speech of :mod:`blackboard_fakes`."""

from __future__ import annotations

import pytest

from blackboard_fakes import CORPUS, UTTERANCES, FailingSpeech, FakeMotor, RecordingSpeech, utterance  # noqa: F401


@pytest.fixture
def motor() -> FakeMotor:
    return FakeMotor()


@pytest.fixture
def speech() -> RecordingSpeech:
    return RecordingSpeech()
