"""The scheduler's settings."""

from __future__ import annotations

from dataclasses import dataclass

from blackboard.chunk_timing import TimingConfig
from mura.limits import DEFAULT_LIMITS, Limits


@dataclass(frozen=True)
class SchedulerConfig:
    """Scheduler settings.

    ``frame_window``: seconds of frames sampled at a time in a live run;
    ``offline_frame_window`` the same on a virtual clock, where nobody waits for a window
    and longer ones spare the motor control's per-call cost. ``live_margin``: in a live
    run, how far ahead of the moment planning starts the planned chunk may begin, s (the
    time planning may take). ``voice``/``rate``/``with_audio`` go to the speech requests.
    ``keep_output``: collect the frames and audio into the result; when False they reach
    observers only (``FramesReady``, ``SpeechStarted``), each chunk's audio is dropped once
    published, and memory stays flat however long the utterance. ``limits``: a chunk that
    would make the utterance last past ``max_duration`` (or ``max_frames``) fails.
    """

    timing: TimingConfig = TimingConfig()
    frame_window: float = 0.1
    live_margin: float = 0.1
    voice: str | None = None
    rate: float = 1.0
    with_audio: bool = True
    keep_output: bool = True
    offline_frame_window: float = 1.0
    limits: Limits = DEFAULT_LIMITS

    def __post_init__(self) -> None:
        for name in ("frame_window", "offline_frame_window"):
            value = getattr(self, name)
            if not value > 0.0:
                raise ValueError(f"SchedulerConfig.{name} must be a positive number of seconds, got {value}")
