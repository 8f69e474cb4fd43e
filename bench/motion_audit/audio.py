"""The affiliate's acoustic onset: the speech backend's word event, refined on the WAV.

The affiliate's first word is the first word of the timeline whose middle lies at or
after the affiliate's onset mark and which starts before the affiliate's end (espeak
places its SSML mark before the emphasis pause it inserts, so the mark itself can lie
inside the preceding word's events). Its event time is then refined on the render's
audio:

* the energy envelope is the RMS of the samples in the :data:`ENVELOPE_WINDOW` *ending* at
  each point, every :data:`ENVELOPE_HOP` (a trailing window, so that the envelope rises
  where the sound starts, not half a window before);
* the threshold is :data:`ONSET_FRACTION` (−30 dB) of the envelope's peak over the word,
  and never below :data:`SILENCE` of full scale;
* the onset is the first upward crossing of the threshold within
  [:data:`SEARCH_BEFORE` before the event, :data:`SEARCH_AFTER` after it], linearly
  interpolated between envelope points. When there is none (the word starts without a
  gap in the sound, as in running speech), the event time stands.

The WAV's first sample is time 0 on the render's clock. 16-bit PCM, any channel count
(channels are averaged); other formats are an :class:`AudioError`.
"""

from __future__ import annotations

import wave
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bench.motion_audit.timeline import Word

ENVELOPE_WINDOW = 0.010
ENVELOPE_HOP = 0.001
ONSET_FRACTION = 10 ** (-30 / 20)
SILENCE = 1e-4
SEARCH_BEFORE = 0.05
SEARCH_AFTER = 0.08
#: Longest WAV read, seconds.
MAX_SECONDS = 3 * 3600


class AudioError(ValueError):
    """A WAV file that cannot be used; the message names the file."""


@dataclass(frozen=True)
class Audio:
    """Samples as floats in [−1, 1] and their rate."""

    samples: np.ndarray
    rate: int


@dataclass(frozen=True)
class AcousticOnset:
    """The affiliate's first word, its event time and its onset on the audio (seconds)."""

    word: str
    event: float
    onset: float
    refined: bool


def read_wav(path: Path) -> Audio:
    """A 16-bit PCM WAV file; AudioError naming the file otherwise."""
    try:
        with wave.open(str(path), "rb") as source:
            width, channels, rate, count = source.getsampwidth(), source.getnchannels(), source.getframerate(), source.getnframes()
            if width != 2:
                raise AudioError(f"{path}: {8 * width}-bit samples; the audit reads 16-bit PCM")
            if count > MAX_SECONDS * rate:
                raise AudioError(f"{path}: longer than {MAX_SECONDS} s")
            data = np.frombuffer(source.readframes(count), dtype="<i2")
    except (wave.Error, EOFError, OSError) as error:
        raise AudioError(f"{path}: not a readable WAV file: {error}") from None
    samples = data.reshape(-1, channels).mean(axis=1) / 32768.0
    return Audio(samples, rate)


def envelope(audio: Audio, first: float, last: float) -> tuple[np.ndarray, np.ndarray]:
    """Times and RMS envelope (trailing window) from ``first`` to ``last`` seconds, every
    :data:`ENVELOPE_HOP`."""
    times = np.arange(max(first, 0.0), max(last, first) + ENVELOPE_HOP / 2, ENVELOPE_HOP)
    width = max(1, int(round(ENVELOPE_WINDOW * audio.rate)))
    energy = np.concatenate(([0.0], np.cumsum(audio.samples * audio.samples)))
    high = np.clip(np.round(times * audio.rate).astype(int), 0, audio.samples.size)
    low = np.clip(high - width, 0, audio.samples.size)
    rms = np.sqrt(np.maximum(energy[high] - energy[low], 0.0) / np.maximum(high - low, 1))
    return times, rms


def affiliate_word(words: tuple[Word, ...], onset: float, end: float | None) -> Word | None:
    """The affiliate's first word (see the module's rule); None when no word qualifies."""
    for word in words:
        if 0.5 * (word.start + word.end) >= onset and (end is None or word.start < end):
            return word
    return None


def acoustic_onset(audio: Audio | None, word: Word) -> AcousticOnset:
    """The word's onset refined on the envelope (the event time without audio or a crossing)."""
    if audio is None:
        return AcousticOnset(word.text, word.start, word.start, refined=False)
    _, over_word = envelope(audio, word.start, word.end)
    threshold = max(ONSET_FRACTION * float(over_word.max(initial=0.0)), SILENCE)
    times, rms = envelope(audio, word.start - SEARCH_BEFORE, word.start + SEARCH_AFTER)
    crossings = np.flatnonzero((rms[:-1] < threshold) & (rms[1:] >= threshold))
    if crossings.size == 0:
        return AcousticOnset(word.text, word.start, word.start, refined=False)
    k = int(crossings[0])
    fraction = (threshold - rms[k]) / (rms[k + 1] - rms[k])
    return AcousticOnset(word.text, word.start, float(times[k] + fraction * ENVELOPE_HOP), refined=True)
