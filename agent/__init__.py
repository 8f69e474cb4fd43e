"""What users touch: the Agent API, the ``mura`` command line, exporters and the live page."""

from agent.agent import Agent, LiveUtterance, PerformanceError
from agent.performance import Performance

__all__ = ["Agent", "LiveUtterance", "Performance", "PerformanceError"]
