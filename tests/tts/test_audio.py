"""WAV files and playback."""

from __future__ import annotations

import shutil
import wave

import numpy as np
import pytest

from tts import (
    FakeSynthesizer,
    PlaybackUnavailable,
    SpeechError,
    SpeechRequest,
    make_player,
    play,
    read_wav,
    write_wav,
)


@pytest.mark.parametrize("sample_rate", [16000, 22050, 44100])
def test_wav_round_trip_keeps_length_and_rate(tmp_path, sample_rate):
    samples = (np.arange(1234, dtype=np.int64) * 37 % 65536 - 32768).astype(np.int16)
    path = tmp_path / "a.wav"
    write_wav(path, samples, sample_rate)
    with wave.open(str(path)) as source:
        assert (source.getnchannels(), source.getsampwidth(), source.getframerate(), source.getnframes()) == (1, 2, sample_rate, 1234)
    back, rate = read_wav(path)
    assert rate == sample_rate and back.dtype == np.int16 and np.array_equal(back, samples)


def test_speech_wav_has_the_speech_duration(tmp_path):
    timing = FakeSynthesizer().synthesize(SpeechRequest("Write me down.", with_audio=True))
    write_wav(tmp_path / "s.wav", timing.audio, timing.sample_rate)
    samples, rate = read_wav(tmp_path / "s.wav")
    assert rate == 22050 and len(samples) / rate == pytest.approx(timing.duration, abs=1 / rate)


def test_stereo_is_mixed_down(tmp_path):
    path = tmp_path / "stereo.wav"
    with wave.open(str(path), "wb") as out:
        out.setnchannels(2)
        out.setsampwidth(2)
        out.setframerate(8000)
        out.writeframes(np.array([100, 300, -50, -150], dtype="<i2").tobytes())
    samples, rate = read_wav(path)
    assert rate == 8000 and samples.tolist() == [200, -100]


@pytest.mark.parametrize(
    ("samples", "rate", "message"),
    [
        (np.zeros(4, np.float32), 22050, "int16"),
        (np.zeros((2, 2), np.int16), 22050, "1-D"),
        (np.zeros(4, np.int16), 0, "sample rate"),
    ],
)
def test_bad_wav_input_is_refused(tmp_path, samples, rate, message):
    with pytest.raises(SpeechError, match=message):
        write_wav(tmp_path / "x.wav", samples, rate)


def test_unreadable_wav_names_the_file(tmp_path):
    path = tmp_path / "junk.wav"
    path.write_bytes(b"not a wav at all")
    with pytest.raises(SpeechError, match="junk.wav"):
        read_wav(path)


def test_eight_bit_wav_is_refused(tmp_path):
    path = tmp_path / "u8.wav"
    with wave.open(str(path), "wb") as out:
        out.setnchannels(1)
        out.setsampwidth(1)
        out.setframerate(8000)
        out.writeframes(bytes(10))
    with pytest.raises(SpeechError, match="8-bit"):
        read_wav(path)


def test_null_player_consumes_every_sample():
    player = make_player("null")
    player.play(np.zeros(441, np.int16), 22050)  # 20 ms in real time
    assert player.played == 441


def test_play_through_null_backend():
    play(np.zeros(220, np.int16), 22050, backend="null")


def test_play_refuses_float_samples():
    with pytest.raises(ValueError, match="int16"):
        play(np.zeros(10), 22050, backend="null")


@pytest.mark.skipif(shutil.which("aplay") is None, reason="aplay (alsa-utils) is not installed")
def test_aplay_to_the_null_device():
    make_player("aplay", device="null").play(np.zeros(2205, np.int16), 22050)


def test_unknown_backend_is_named():
    with pytest.raises(PlaybackUnavailable, match="unknown playback backend 'speaker'"):
        make_player("speaker")


def test_no_backend_explains_every_attempt(monkeypatch):
    import tts.playback as playback

    def refuse(name):
        class Refusing:
            def __init__(self, device=None):
                raise PlaybackUnavailable(f"{name} missing")

        return Refusing

    for name in ("simpleaudio", "sounddevice", "aplay"):
        monkeypatch.setitem(playback.PLAYERS, name, refuse(name))
    with pytest.raises(PlaybackUnavailable) as caught:
        make_player()
    assert all(f"{name}: {name} missing" in str(caught.value) for name in ("simpleaudio", "sounddevice", "aplay"))
