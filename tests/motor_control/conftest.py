"""Shared fixtures for the motor-control tests."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest


def _speed_peak_fraction(trajectory, samples: int = 4001) -> float:
    t = np.linspace(trajectory.start, trajectory.end, samples)
    speed = np.linalg.norm(trajectory.velocity(t), axis=1)
    return float((t[np.argmax(speed)] - trajectory.start) / (trajectory.end - trajectory.start))


@pytest.fixture
def speed_peak_fraction() -> Callable[..., float]:
    """Where (fraction of the breakpoint span) a trajectory's speed peaks."""
    return _speed_peak_fraction
