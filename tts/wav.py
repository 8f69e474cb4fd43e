"""WAV files of int16 mono speech, through the standard library's ``wave`` module."""

from __future__ import annotations

import wave
from pathlib import Path

import numpy as np

from tts.speech import SpeechError


def write_wav(path: str | Path, samples: np.ndarray, sample_rate: int) -> None:
    """Write int16 mono ``samples`` at ``sample_rate`` Hz to ``path``."""
    data = np.asarray(samples)
    if data.ndim != 1 or data.dtype != np.int16:
        raise SpeechError(f"WAV samples must be a 1-D int16 array, got {data.dtype} with shape {data.shape}")
    if sample_rate <= 0:
        raise SpeechError(f"WAV sample rate must be positive, got {sample_rate}")
    with wave.open(str(path), "wb") as out:
        out.setnchannels(1)
        out.setsampwidth(2)
        out.setframerate(int(sample_rate))
        out.writeframes(data.astype("<i2").tobytes())


def read_wav(path: str | Path) -> tuple[np.ndarray, int]:
    """Read a 16-bit PCM WAV as int16 mono samples (channels averaged) and its sample rate."""
    try:
        with wave.open(str(path), "rb") as source:
            channels, width, rate = source.getnchannels(), source.getsampwidth(), source.getframerate()
            raw = source.readframes(source.getnframes())
    except (wave.Error, EOFError) as error:
        raise SpeechError(f"{path}: not a readable WAV file ({error})") from error
    if width != 2:
        raise SpeechError(f"{path}: {8 * width}-bit samples, only 16-bit PCM is read")
    frames = np.frombuffer(raw, dtype="<i2").reshape(-1, channels)
    mono = frames[:, 0] if channels == 1 else np.round(frames.mean(axis=1))
    return mono.astype(np.int16), rate
