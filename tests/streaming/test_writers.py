"""The streaming writers on their own: WAV mixing and padding, BVH windows, the page in pieces."""

from __future__ import annotations

import io

import numpy as np
import pytest

from agent.export.bvh import StreamingBvh, bvh_text
from agent.export.html import render_html, write_html_stream
from agent.performance import SILENT_RATE, rest_motion
from agent.streaming import StreamingWav
from motor.body.avatar import load_avatar
from motor.motion import Motion
from tts.wav import read_wav, write_wav

RATE = 22050


def reference_track(pieces: list[tuple[float, np.ndarray]], duration: float, rate: int = RATE) -> np.ndarray:
    """What the scheduler and Performance.soundtrack make: a clipped int32 mix padded or cut."""
    starts = [int(round(t * rate)) for t, _ in pieces]
    mix = np.zeros(max([s + len(a) for s, (_, a) in zip(starts, pieces)] + [0]), dtype=np.int32)
    for start, (_, audio) in zip(starts, pieces):
        mix[start : start + len(audio)] += audio
    audio = np.clip(mix, -32768, 32767).astype(np.int16)
    track = np.zeros(int(round(duration * rate)), dtype=np.int16)
    track[: min(len(track), len(audio))] = audio[: len(track)]
    return track


def tone(samples: int, level: int) -> np.ndarray:
    return np.full(samples, level, dtype=np.int16)


WAV_CASES = {
    "apart": ([(0.1, tone(500, 1000)), (0.5, tone(800, -2000))], 1.0),
    "touching": ([(0.0, tone(RATE // 10, 7)), (0.1, tone(100, 9))], 0.3),
    "overlap summed": ([(0.0, tone(4000, 1000)), (0.1, tone(4000, 2000))], 0.5),
    "overlap clipped": ([(0.0, tone(4000, 30000)), (0.1, tone(4000, 30000)), (0.15, tone(100, -30000))], 0.4),
    "inside the previous": ([(0.0, tone(10000, 5)), (0.1, tone(100, 6))], 0.5),
    "cut at the duration": ([(0.0, tone(RATE, 3))], 0.5),
    "long pause": ([(0.0, tone(10, 3)), (8.0, tone(10, 4))], 9.0),
}


@pytest.mark.parametrize("pieces, duration", WAV_CASES.values(), ids=WAV_CASES.keys())
def test_streaming_wav_equals_mixed_track(tmp_path, pieces, duration):
    wav = StreamingWav(tmp_path / "streamed.wav")
    for time, audio in pieces:
        wav.add(time, audio, RATE)
    wav.finish(duration)
    write_wav(tmp_path / "whole.wav", reference_track(pieces, duration), RATE)
    assert (tmp_path / "streamed.wav").read_bytes() == (tmp_path / "whole.wav").read_bytes()


def test_streaming_wav_without_speech_is_silent_at_the_silent_rate(tmp_path):
    wav = StreamingWav(tmp_path / "silent.wav")
    wav.finish(1.5)
    samples, rate = read_wav(tmp_path / "silent.wav")
    assert rate == SILENT_RATE and len(samples) == int(round(1.5 * SILENT_RATE)) and not samples.any()


@pytest.mark.parametrize(
    "second, message",
    [
        ((0.5, tone(10, 1), 16000), "16000 Hz after speech at 22050 Hz"),
        ((0.05, tone(10, 1), RATE), "arrived after speech that starts later"),
    ],
)
def test_streaming_wav_refuses_inconsistent_speech(tmp_path, second, message):
    wav = StreamingWav(tmp_path / "bad.wav")
    wav.add(0.1, tone(10, 1), RATE)
    with pytest.raises(ValueError, match=message):
        wav.add(*second)
    wav.close()


@pytest.fixture(scope="module")
def motion() -> Motion:
    avatar = load_avatar("max")
    rng = np.random.default_rng(7)
    frames = 5000
    rotations = rng.normal(size=(frames, avatar.joint_count, 4))
    rotations /= np.linalg.norm(rotations, axis=-1, keepdims=True)
    translation = rng.normal(size=(frames, 3))
    return Motion(60.0, avatar.joint_names, tuple(int(p) for p in avatar.parents), np.asarray(avatar.offsets), rotations, translation, 1.5)


def windows(motion: Motion, sizes: list[int]) -> list[Motion]:
    out, start = [], 0
    for size in sizes:
        out.append(Motion(motion.fps, motion.joint_names, motion.parents, motion.offsets,
                          motion.rotations[start : start + size], motion.root_translation[start : start + size],
                          motion.start_time + start / motion.fps))  # fmt: skip
        start += size
    return out


WINDOW_SIZES = {
    "one window": [5000],
    "scheduler windows": [6] * 833 + [2],
    "ragged": [1, 2047, 1, 2048, 3, 900],
}


@pytest.mark.parametrize("sizes", WINDOW_SIZES.values(), ids=WINDOW_SIZES.keys())
def test_streaming_bvh_equals_whole_text(tmp_path, motion, sizes):
    bvh = StreamingBvh(tmp_path / "frames.part")
    for window in windows(motion, sizes):
        bvh.add(window)
    out = io.StringIO()
    bvh.write(out)
    assert out.getvalue() == bvh_text(motion)
    assert "".join(bvh.text_blocks()) == bvh_text(motion)
    assert bvh.frame_count == motion.frame_count


def test_streaming_bvh_names_the_bad_frame_in_the_whole_motion(tmp_path, motion):
    parts = windows(motion, [10, 10])
    broken = parts[1].rotations.copy()
    broken[3, 5] = np.nan
    bad = Motion(60.0, motion.joint_names, motion.parents, motion.offsets, broken, parts[1].root_translation)
    bvh = StreamingBvh(tmp_path / "frames.part")
    bvh.add(parts[0])
    with pytest.raises(ValueError, match=r"non-finite value in rotations at index \[13, 5, "):
        bvh.add(bad)
    bvh.close()


def test_streaming_bvh_refuses_another_skeleton(tmp_path, motion):
    rest = rest_motion(load_avatar("max"), 30.0)
    bvh = StreamingBvh(tmp_path / "frames.part")
    bvh.add(windows(motion, [4])[0])
    with pytest.raises(ValueError, match="from frame 4 on have another skeleton or frame rate"):
        bvh.add(rest)
    bvh.close()


def test_streaming_bvh_without_frames_has_no_header(tmp_path):
    bvh = StreamingBvh(tmp_path / "frames.part")
    with pytest.raises(ValueError, match="no frames were added"):
        bvh.header()
    bvh.close()


TIMELINE = {"name": "x", "duration": 2.0, "words": [{"text": "<b>&\u2028", "start": 0.1, "end": 0.4}]}


@pytest.mark.parametrize("cut", [[], [17], [200, 201, 5000], list(range(1000, 60000, 777))])
def test_page_in_pieces_equals_whole_page(motion, cut):
    text = bvh_text(windows(motion, [300])[0]) + "</script><!-- é \u2028"
    header_end = text.index("Frame Time")
    bounds = [0, header_end] + [c for c in cut if c > header_end and c < len(text)] + [len(text)]
    blocks = [text[a:b] for a, b in zip(bounds, bounds[1:])]
    whole = render_html(name="a <b>", bvh_text=text, timeline=TIMELINE, wav_filename="a b.wav")
    out = io.StringIO()
    write_html_stream(out, name="a <b>", bvh_blocks=blocks, timeline=TIMELINE, wav_filename="a b.wav")
    assert out.getvalue() == whole


@pytest.mark.parametrize(
    "blocks, timeline, wav, message",
    [
        (["MOTION\n"], TIMELINE, None, "not a BVH file"),
        ([], TIMELINE, None, "not a BVH file"),
        (["HIERARCHY\nROOT x\nMOTION\n"], {"duration": float("nan")}, None, "finite numbers"),
        (["HIERARCHY\nROOT x\nMOTION\n"], TIMELINE, "/abs/a.wav", "relative to the page"),
    ],
)
def test_page_in_pieces_refuses_bad_input_before_writing(blocks, timeline, wav, message):
    out = io.StringIO()
    with pytest.raises(ValueError, match=message):
        write_html_stream(out, name="n", bvh_blocks=blocks, timeline=timeline, wav_filename=wav)
    assert out.getvalue() == ""


def test_published_files_get_the_usual_permissions(tmp_path):
    from agent.export.staging import UMASK, staged_text

    target = tmp_path / "out.txt"
    with staged_text(target) as stream:
        stream.write("done\n")
    assert target.read_text() == "done\n"
    assert target.stat().st_mode & 0o777 == 0o666 & ~UMASK
    assert [p.name for p in tmp_path.iterdir()] == ["out.txt"]


def test_a_failed_staged_write_leaves_nothing(tmp_path):
    import pytest

    from agent.export.staging import staged_text

    with pytest.raises(RuntimeError):
        with staged_text(tmp_path / "out.txt") as stream:
            stream.write("half")
            raise RuntimeError("disk full")
    assert list(tmp_path.iterdir()) == []
