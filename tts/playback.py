"""Audio playback behind one small interface, for the live demo and ``mura say --play``.

Backends, tried in this order when none is named: ``simpleaudio``, ``sounddevice`` (both
in the ``audio`` extra) and ``aplay`` (ALSA's command-line player, through a subprocess).
``null`` consumes the samples in real time without a sound device; headless tests use it,
or ``aplay`` with the device ``null``. No backend is needed to install mura: when none can
play, :class:`PlaybackUnavailable` says what was tried and why each failed.
"""

from __future__ import annotations

import io
import shutil
import subprocess
import time
from typing import Protocol

import numpy as np

from tts.wav import write_wav


class PlaybackUnavailable(RuntimeError):
    """No audio backend can play on this machine (or the named one cannot)."""


class Player(Protocol):
    """Plays int16 mono samples and returns when they have been played."""

    name: str

    def play(self, samples: np.ndarray, sample_rate: int) -> None: ...


class SimpleaudioPlayer:
    name = "simpleaudio"

    def __init__(self, device: str | None = None) -> None:
        if device is not None:
            raise PlaybackUnavailable("simpleaudio plays only to the default device")
        try:
            import simpleaudio
        except ImportError as error:
            raise PlaybackUnavailable(f"simpleaudio is not installed ({error})") from error
        self._module = simpleaudio

    def play(self, samples: np.ndarray, sample_rate: int) -> None:
        data = np.ascontiguousarray(samples, dtype=np.int16)
        self._module.play_buffer(data, 1, 2, int(sample_rate)).wait_done()


class SounddevicePlayer:
    name = "sounddevice"

    def __init__(self, device: str | None = None) -> None:
        try:
            import sounddevice
        except (ImportError, OSError) as error:
            raise PlaybackUnavailable(f"sounddevice is not usable ({error})") from error
        self._module = sounddevice
        self._device = device

    def play(self, samples: np.ndarray, sample_rate: int) -> None:
        self._module.play(np.asarray(samples, dtype=np.int16), int(sample_rate), device=self._device, blocking=True)


class AplayPlayer:
    """ALSA's ``aplay`` reading a WAV from its standard input; ``device`` is its ``-D``."""

    name = "aplay"

    def __init__(self, device: str | None = None) -> None:
        self._executable = shutil.which("aplay")
        if self._executable is None:
            raise PlaybackUnavailable("aplay is not on the PATH (Debian package alsa-utils)")
        self._device = device

    def play(self, samples: np.ndarray, sample_rate: int) -> None:
        buffer = io.BytesIO()
        write_wav(buffer, np.asarray(samples, dtype=np.int16), sample_rate)
        command = [self._executable, "-q"] + (["-D", self._device] if self._device else [])
        result = subprocess.run(command, input=buffer.getvalue(), capture_output=True, check=False)
        if result.returncode != 0:
            raise PlaybackUnavailable(f"aplay failed: {result.stderr.decode(errors='replace').strip()}")


class NullPlayer:
    """Consumes samples at the pace of real playback (``realtime=False``: at once), no sound."""

    name = "null"

    def __init__(self, device: str | None = None, realtime: bool = True) -> None:
        self._realtime = realtime
        self.played = 0  # samples consumed so far

    def play(self, samples: np.ndarray, sample_rate: int) -> None:
        count = len(samples)
        if self._realtime and count:
            time.sleep(count / sample_rate)
        self.played += count


PLAYERS = {p.name: p for p in (SimpleaudioPlayer, SounddevicePlayer, AplayPlayer, NullPlayer)}
_AUTOMATIC = ("simpleaudio", "sounddevice", "aplay")


def make_player(backend: str | None = None, device: str | None = None) -> Player:
    """The named playback backend, or the first that works; raises :class:`PlaybackUnavailable`."""
    if backend is not None and backend not in PLAYERS:
        raise PlaybackUnavailable(f"unknown playback backend {backend!r}; choose from {', '.join(PLAYERS)}")
    reasons = []
    for name in (backend,) if backend else _AUTOMATIC:
        try:
            return PLAYERS[name](device)
        except PlaybackUnavailable as error:
            reasons.append(f"{name}: {error}")
    raise PlaybackUnavailable("no audio backend can play here — " + "; ".join(reasons) + " (install mura[audio])")


def play(samples: np.ndarray, sample_rate: int, device: str | None = None, backend: str | None = None) -> None:
    """Play int16 mono ``samples`` at ``sample_rate`` Hz and return when done."""
    data = np.asarray(samples)
    if data.ndim != 1 or data.dtype != np.int16:
        raise ValueError(f"playback needs a 1-D int16 array, got {data.dtype} with shape {data.shape}")
    make_player(backend, device).play(data, sample_rate)
