"""What users touch: the Agent API, the ``mura`` command line, exporters and the live page.

``Agent``, ``LiveUtterance``, ``Performance`` and ``PerformanceError`` load on first use
(PEP 562): importing the command line or an exporter does not load the motor and its
compiled kernels, which take seconds."""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from agent.agent import Agent, LiveUtterance, PerformanceError
    from agent.performance import Performance

__all__ = ["Agent", "LiveUtterance", "Performance", "PerformanceError"]

#: Where each public name lives.
_HOMES = {"Agent": "agent.agent", "LiveUtterance": "agent.agent", "PerformanceError": "agent.agent", "Performance": "agent.performance"}


def __getattr__(name: str) -> object:
    if name not in _HOMES:
        raise AttributeError(f"module 'agent' has no attribute {name!r}")
    return getattr(importlib.import_module(_HOMES[name]), name)
