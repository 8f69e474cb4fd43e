"""Fixtures of the indicating-verb tests: the lexicon, the shipped SYNTHETIC session and models."""

import pytest

from motor.body.avatar import load_avatar
from motor.verbs.shipped import MODELS_PATH, RECORDINGS_PATH, shipped_models
from mura.recordings import read_recordings
from mura.verb_lexicon import load_verb_lexicon


@pytest.fixture(scope="session")
def lexicon():
    return load_verb_lexicon()


@pytest.fixture(scope="session")
def session():
    return read_recordings(RECORDINGS_PATH)


@pytest.fixture(scope="session")
def models():
    return shipped_models(MODELS_PATH)


@pytest.fixture(scope="session")
def max_avatar():
    return load_avatar("max")
