"""Speech synthesis behind one protocol: ``synthesize(request) -> SpeechTiming``.

Backends: a deterministic fake (tests), espeak-ng through its C library (measured
phoneme, word and mark times, SSML emphasis) and pyttsx3 (portable, estimated times).
Plus WAV files and audio playback. tts knows nothing about gestures.
"""

from tts.espeak import EspeakSynthesizer
from tts.factory import BACKENDS, make_synthesizer
from tts.fake import FakeSynthesizer
from tts.playback import PlaybackUnavailable, Player, make_player, play
from tts.pyttsx3_backend import Pyttsx3Synthesizer
from tts.speech import (
    BackendUnavailable,
    Phoneme,
    SpeechError,
    SpeechRequest,
    SpeechSynthesizer,
    SpeechTiming,
    TextMark,
    UnknownVoice,
    Word,
)
from tts.wav import read_wav, write_wav

__all__ = [
    "BACKENDS",
    "BackendUnavailable",
    "EspeakSynthesizer",
    "FakeSynthesizer",
    "Phoneme",
    "PlaybackUnavailable",
    "Player",
    "Pyttsx3Synthesizer",
    "SpeechError",
    "SpeechRequest",
    "SpeechSynthesizer",
    "SpeechTiming",
    "TextMark",
    "UnknownVoice",
    "Word",
    "make_player",
    "make_synthesizer",
    "play",
    "read_wav",
    "write_wav",
]
