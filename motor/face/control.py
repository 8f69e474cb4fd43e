"""The face motor module: every face track activated so far, sampled as ARKit morph weights.

:class:`FaceControl` is what :class:`motor.control.MotorControl` holds beside the arms. It
keeps the activated *face tracks* — anything with ``start``, ``end``, ``columns`` (indices
into :data:`motor.face.arkit.FACE_NAMES`) and a vectorized ``sample(times)`` giving
``(n, len(columns))`` weights: the lip-sync articulation of each chunk of speech
(:mod:`motor.face.lipsync`), expressions (:mod:`motor.face.expressions`) and the brow
raise of pitch accents — and the blinks (:mod:`motor.face.blinks`). A frame's weights are
the sum of the tracks in progress, clipped to 0–1, with the blink closure added to both
``eyeBlink`` weights.

:meth:`FaceControl.speak` turns a chunk's ``SpeechTiming`` into its articulation, a brow
raise on each accented word and a blink at its end; it reports once per performance
what it had to do instead (a backend without phonemes, symbols its table does not know).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

import numpy as np

from motor.face.arkit import FACE_INDEX, FACE_NAMES
from motor.face.blinks import Blinks
from motor.face.expressions import expression
from motor.face.lipsync import Articulation, speech_segments, word_segments
from motor.face.phonemes import ALPHABETS, lookup
from motor.trajectory.envelope import Envelope
from tts.speech import SpeechTiming

#: The brow raise on a pitch-accented word (seed 004's emphasis): weights at its peak.
ACCENT_BROWS: dict[str, float] = {"browInnerUp": 0.55, "browOuterUp*": 0.45}
#: The brow raise rises this long before the accented vowel and fades this long after the word, s.
ACCENT_ATTACK, ACCENT_RELEASE = 0.12, 0.3
_BLINK_COLUMNS = np.array([FACE_INDEX["eyeBlinkLeft"], FACE_INDEX["eyeBlinkRight"]])


class FaceTrack(Protocol):
    """An activated face movement (module docstring)."""

    start: float
    end: float
    columns: np.ndarray

    def sample(self, times: np.ndarray) -> np.ndarray: ...


class FaceControl:
    """The face's activated tracks and blinks; ``seed`` fixes the spontaneous blinks."""

    def __init__(self, seed: int = 0) -> None:
        self.blinks = Blinks(seed)
        self._tracks: list[FaceTrack] = []
        self._said: set[str] = set()

    def activate(self, track: FaceTrack) -> float:
        """Add a track; returns the time (s) from which it shows, its ``start``."""
        self._tracks.append(track)
        return track.start

    def blink_at(self, time: float) -> None:
        """A blink beginning at ``time`` (seconds) besides the spontaneous ones."""
        self.blinks.add(time)

    def speak(self, speech: SpeechTiming, onset: float, accents: Sequence[tuple[float, float]] = ()) -> tuple[tuple[str, ...], tuple[float, ...]]:
        """Lip-sync, accent brows and the boundary blink of one chunk whose speech starts
        at ``onset`` (seconds, utterance clock); ``accents`` are the ``(start, end)``
        utterance-clock spans of the pitch-accented affiliates. Returns the warnings not
        given before and the times of the accented vowels (for a head beat)."""
        notes: list[str] = []
        if speech.phonemes and speech.backend in ALPHABETS:
            parts, unknown = speech_segments([(p.symbol, p.start, p.end) for p in speech.phonemes], speech.backend, onset)
            if unknown:
                notes.append(f"lip-sync: {speech.backend} phoneme(s) {', '.join(map(repr, unknown))} not in mura's table; shown as a neutral mouth shape")
        else:
            parts = word_segments([(w.text, w.start, w.end) for w in speech.words], onset)
            notes.append(f"lip-sync: the {speech.backend} speech backend gives no phonemes mura can read; the mouth opens and closes word by word")
        if parts:
            self.activate(Articulation.of(parts))
        peaks = tuple(self._accent(speech, onset, start, end) for start, end in accents)
        for (start, end), peak in zip(accents, peaks):
            self.activate(expression(ACCENT_BROWS, Envelope.around(peak, max(peak, end), ACCENT_ATTACK, ACCENT_RELEASE), 1.0, "accent"))
        if speech.words:
            self.blinks.add_boundary(onset + speech.words[-1].end)
        return self._once(notes), peaks

    def weights(self, times: np.ndarray) -> np.ndarray:
        """Morph weights ``(n, 52)`` at sorted ``times``."""
        t = np.asarray(times, dtype=float)
        out = np.zeros((t.size, len(FACE_NAMES)))
        if t.size == 0:
            return out
        first, last = float(t[0]), float(t[-1])
        for track in self._tracks:
            if track.end < first or track.start > last:
                continue
            inside = slice(int(np.searchsorted(t, track.start, side="left")), int(np.searchsorted(t, track.end, side="right")))
            if inside.stop > inside.start:
                out[inside, track.columns] += track.sample(t[inside])
        out[:, _BLINK_COLUMNS] += self.blinks.sample(t)[:, None]
        return np.clip(out, 0.0, 1.0)

    def interrupt(self, at: float) -> None:
        """Drop the tracks that would start after ``at`` seconds."""
        self._tracks = [track for track in self._tracks if track.start <= at]

    def forget_before(self, horizon: float) -> None:
        """Drop tracks and blinks over before ``horizon`` seconds."""
        self._tracks = [track for track in self._tracks if track.end >= horizon]
        self.blinks.forget_before(horizon)

    def _once(self, notes: list[str]) -> tuple[str, ...]:
        fresh = tuple(note for note in notes if note not in self._said)
        self._said.update(fresh)
        return fresh

    @staticmethod
    def _accent(speech: SpeechTiming, onset: float, start: float, end: float) -> float:
        """Utterance-clock time of the accented vowel of the first word in ``[start, end)``:
        its stressed vowel when the backend marks stress, else its first vowel, else 30 %
        into the word."""
        words = [w for w in speech.words if onset + w.end > start + 1e-9 and onset + w.start < end - 1e-9]
        if not words:
            return float(start)
        word = words[0]
        inside = [p for p in speech.phonemes if word.start - 1e-9 <= p.start < word.end and not p.symbol.startswith("_")]
        if speech.backend in ALPHABETS:
            vowels = [p for p in inside if lookup(p.symbol, speech.backend)[1] == "vowel"]
            stressed = [p for p in vowels if p.symbol.startswith("'")]
            chosen = (stressed or vowels or [None])[0]
            if chosen is not None:
                return onset + chosen.start
        return onset + word.start + 0.3 * (word.end - word.start)
