"""Items 3, 4 and 12: unbounded times, counts, text and rates, and the messages about them.

3. ``onset="100000"`` wrote a 24 GB BVH, ``1e9`` filled the disk, ``1e300`` was an
   OverflowError traceback, and ``mura check`` said OK to all.
4. 1 MB of text in one chunk made the fake speech allocate 11 GiB; ``--rate 1e-6`` asked
   for 298 GiB, ``--fps 100000`` grew to 1.5 GB for 5 s.
12. ``onset="nan"`` said "unknown time tag", a distance of 1e30 "ready 2e+27 must follow
   start", ``1e400`` became infinity without a location, ``--fps inf`` "cannot convert
   float NaN", and chunk numbers mixed 0- and 1-based.

Every refusal is checked with ``mura check`` (FILE:LINE:COL) and ``mura render`` (no file
written); the memory-hungry ones run in a subprocess under an address-space limit.
"""

from __future__ import annotations

import pytest
from hostile_helpers import LIGHT, absolute_gesture, all_files, run_mura, utterance

from agent.agent import Agent, PerformanceError
from agent.cli import main
from blackboard.clock import VirtualClock
from blackboard.scheduler import Scheduler
from motor.body.avatar import load_avatar
from motor.control import MotorControl
from mura.errors import SpecError
from mura.limits import LimitError, Limits
from mura.model import AbsoluteTiming, BehaviorSpec, Gesture, Utterance
from mura.constraints import Static
from mura.values import HandShape
from tts import FakeSynthesizer, SpeechError

SEGMENT = '<dynamic slot="HandLocation"><segment type="linear"><value type="direction" name="DirU"/><value type="distance" {}/></segment></dynamic>'


def _spec_at(spec_text: str, attribute: str, after: str = "<behaviorspec") -> tuple[int, int]:
    """Line and column (1-based) of the first ``attribute=`` in ``spec_text`` after ``after``."""
    offset = spec_text.index(f" {attribute}=", spec_text.index(after)) + 1
    return spec_text.count("\n", 0, offset) + 1, offset - (spec_text.rfind("\n", 0, offset) + 1) + 1


TIMINGS = [
    ("100000", "100001", "onset", "timing onset of 'g1': 100000 s is beyond the limit of 600 s (raise with --limit max_duration=N)"),
    ("1", "1e9", "end", "timing end of 'g1': 1e+09 s is beyond the limit of 600 s (raise with --limit max_duration=N)"),
    ("1e300", "2e300", "onset", "timing onset of 'g1': 1e+300 s is beyond the limit of 600 s"),
    ("nan", "2", "onset", "timing onset of 'g1': nan is not a finite number of seconds"),
    ("0", "inf", "end", "timing end of 'g1': inf is not a finite number of seconds"),
    ("0", "1e400", "end", "timing end of 'g1': inf is not a finite number of seconds"),
]


@pytest.mark.parametrize(("onset", "end", "attribute", "message"), TIMINGS, ids=[t[0] + "-" + t[1] for t in TIMINGS])
def test_absolute_times_are_refused_where_they_are_written(write, tmp_path, capsys, onset, end, attribute, message):
    text = utterance(behaviors="\n" + absolute_gesture(onset, end))
    spec = write("timing.xml", text)
    line, column = _spec_at(text, attribute, after="<timing")
    assert main(["check", str(spec)]) == 1
    checked = capsys.readouterr().out.strip()
    assert checked.startswith(f"{spec}:{line}:{column}: {message}")
    assert main(["render", str(spec), "-o", str(tmp_path / "out")]) == 1
    assert capsys.readouterr().err.strip().startswith(f"{spec}:{line}:{column}: {message}")
    assert all_files(tmp_path / "out") == []


def test_a_longer_utterance_passes_with_a_raised_limit(write, capsys):
    spec = write("long.xml", utterance(behaviors=absolute_gesture("700", "701")))
    assert main(["check", str(spec)]) == 1
    assert main(["check", str(spec), "--limit", "max_duration=800"]) == 0


@pytest.mark.timeout(60)
def test_speech_longer_than_the_limit_fails_when_rendered(tmp_path, capsys):
    """How long speech lasts is known only once spoken: the chunk that passes the limit fails."""
    example = "specs/utterances/fig2_take_this_bar.xml"
    assert main(["render", example, "-o", str(tmp_path / "out"), "--limit", "max_duration=3"]) == 1
    message = capsys.readouterr().err
    assert "chunk 2 failed: the utterance, up to chunk 2, would end at" in message and "beyond the limit of 3 s" in message
    assert all_files(tmp_path / "out") == []


def test_frames_past_the_limit_fail_when_rendered(tmp_path, capsys):
    example = "specs/utterances/fig2_take_this_bar.xml"
    assert main(["render", example, "-o", str(tmp_path / "out"), "--fps", "240", "--limit", "max_frames=300"]) == 1
    assert "frames" in capsys.readouterr().err and all_files(tmp_path / "out") == []


@pytest.mark.parametrize(
    ("onset", "end", "below_the_agent"),
    [(1e300, 2e300, "would end at 10000.3 s, beyond the limit of 600 s"), (float("inf"), float("inf"), "beyond the limit of 600 s"),
     (float("nan"), 1.0, "nan s is not a time the schedule can hold"), (-1e300, 1.0, "-1e+300 s is not a time the schedule can hold")],
)  # fmt: skip
def test_a_model_built_in_python_is_held_to_the_same_limits(onset, end, below_the_agent):
    gesture = Gesture("g1", Static("HandShape", HandShape("fist")))
    model = Utterance((), (BehaviorSpec("g1", "gesture", AbsoluteTiming(onset, end), gesture),), "model.xml")
    with pytest.raises(SpecError, match="timing onset of 'g1'"):
        Agent(avatar="max").render(model)
    scheduler = Scheduler(FakeSynthesizer(), MotorControl(load_avatar("max"), 30.0), VirtualClock())
    result = scheduler.run(model)  # below the agent: the chunk fails with a reason instead of overflowing
    assert isinstance(result.error, ValueError) and below_the_agent in str(result.error)


# -- item 4: text, rate, fps ----------------------------------------------------------------

TEXTS = {
    "1 MB of text": "Hello there. " * 80_000,
    "one 1 MB word": "a" * 1_000_000,
    "10,000 words": "word " * 10_000,
}


@pytest.mark.timeout(90)
def test_huge_chunks_are_refused_under_a_memory_limit(write, tmp_path):
    """Each oversized chunk is refused where its chunk begins; the one good file of the
    batch renders; the process stays within its address-space limit."""
    specs = [write(f"text{k}.xml", utterance(text)) for k, text in enumerate(TEXTS.values())]
    good = write("good.xml", utterance("Hello there."))
    checked = run_mura("check", *map(str, specs))
    assert checked.status == 1
    for spec, text in zip(specs, TEXTS.values()):
        assert f"{spec}:1:12: chunk 1 has {len(text.strip())} characters, more than the limit of 2000" in checked.out
    rendered = run_mura("render", *map(str, specs), str(good), "-o", str(tmp_path / "out"), *LIGHT)
    assert rendered.status == 1
    assert all_files(tmp_path / "out") == ["good.bvh", "good.face.json", "good.html", "good.timeline.json", "good.wav"]
    assert "rendered 1 of 4 utterances; 3 failed" in rendered.err


@pytest.mark.timeout(60)
def test_longest_chunk_at_the_slowest_rate_fits_in_memory(tmp_path):
    """2,000 characters spoken at a quarter of the normal rate (about eleven minutes of
    audio) are synthesized within the address-space limit."""
    text = ("Take this bar and make it this big. " * 56)[:2000].strip()
    said = run_mura("say", text, "--tts", "fake", "--rate", "0.25", "-o", str(tmp_path / "long.wav"))
    assert said.status == 0, said.err
    assert (tmp_path / "long.wav").stat().st_size > 20_000_000


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["say", "x" * 3000], "mura say: the text has 3000 characters, more than the limit of 2000"),
        (["say", "hello", "--rate", "1e-6"], "mura say: speaking rate (--rate) 1e-06 is outside 0.25..4"),
        (["render", "{spec}", "-o", "{out}", "--rate", "1e-6"], "mura render: speaking rate (--rate) 1e-06 is outside 0.25..4"),
        (["render", "{spec}", "-o", "{out}", "--fps", "100000"], "mura render: frame rate (--fps) 100000 is outside 1..240"),
        (["render", "{spec}", "-o", "{out}", "--fps", "inf"], "mura render: frame rate (--fps) must be a finite number, got inf"),
        (["render", "{spec}", "-o", "{out}", "--fps", "nan"], "mura render: frame rate (--fps) must be a finite number, got nan"),
        (["sign", "--hamnosys", "\ue000", "-o", "{out}", "--fps", "0"], "mura sign: frame rate (--fps) 0 is outside 1..240"),
        (["plot", "{spec}", "-o", "{out}", "--fps", "-5"], "mura plot: frame rate (--fps) -5 is outside 1..240"),
        (["render", "{spec}", "-o", "{out}", "--limit", "max_duration=-1"], "mura render: limit max_duration must be a positive finite number, got -1"),
        (["render", "{spec}", "-o", "{out}", "--limit", "frames=9"], "mura render: --limit 'frames=9': expected NAME=VALUE with NAME one of"),
        (["check", "{spec}", "--limit", "max_fps=0.5"], "mura check: limit min_fps (1.0) is above max_fps (0.5)"),
    ],
    ids=["say-text", "say-rate", "render-rate", "render-fps", "fps-inf", "fps-nan", "sign-fps", "plot-fps",
         "negative-limit", "unknown-limit", "crossed-range"],
)  # fmt: skip
def test_out_of_range_options_are_one_line(write, tmp_path, capsys, arguments, message):
    spec = write("u.xml", utterance())
    argv = [a.format(spec=spec, out=tmp_path / "out") for a in arguments]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith(message) and err.count("\n") == 1
    assert all_files(tmp_path / "out") == []


def test_the_ranges_can_be_widened(write, tmp_path):
    spec = write("u.xml", utterance("Hi."))
    assert main(["render", str(spec), "-o", str(tmp_path / "out"), "--fps", "300", "--limit", "max_fps=300"]) == 0


@pytest.mark.parametrize("name", ["max_chunk_chars", "max_duration", "max_frames", "max_fps", "max_rate", "stream_timeout"])
@pytest.mark.parametrize("value", [0, -3, float("nan"), float("inf"), "7", True])
def test_limits_are_validated_numbers(name, value):
    with pytest.raises(LimitError, match=f"limit {name} must be"):
        Limits(**{name: value})


# -- item 12: messages ----------------------------------------------------------------------

MESSAGES = [
    (SEGMENT.format('value="1e30"'), "value", "length '1e30' = 1e+28 m is more than the limit of 10 m (raise with --limit max_length=N)"),
    (SEGMENT.format('value="1e400"'), "value", "'1e400' is too large to be a number"),
    (SEGMENT.format('value="-20m"'), "value", "length '-20m' = -20 m is more than the limit of 10 m"),
    ('<static slot="HandLocation" value="0 1e30 0"/>', "value", "HandLocation: length '1e30' = 1e+28 m is more than the limit of 10 m"),
    ('<static slot="ExtFingerOrientation" value="1e400 0 0"/>', "value", "'1e400' is too large to be a number"),
]


@pytest.mark.parametrize(("constraint", "attribute", "message"), MESSAGES, ids=["distance-1e30", "distance-1e400", "distance-20m", "position-1e30", "direction-1e400"])
def test_numbers_are_refused_where_they_are_written(write, capsys, constraint, attribute, message):
    text = utterance(behaviors="\n" + absolute_gesture("0.5", "1.5", constraint=constraint))
    spec = write("n.xml", text)
    assert main(["check", str(spec)]) == 1
    line, column = _spec_at(text, attribute, after="<constraints>")
    assert capsys.readouterr().out.strip().startswith(f"{spec}:{line}:{column}: {message}")


def test_chunk_numbers_are_one_based_everywhere(tmp_path):
    class FailsOnChunkTwo(FakeSynthesizer):
        def __init__(self) -> None:
            self.calls = 0

        def synthesize(self, request):
            self.calls += 1
            if self.calls == 2:
                raise SpeechError("the voice went away")
            return super().synthesize(request)

    with pytest.raises(PerformanceError) as caught:
        Agent(tts=FailsOnChunkTwo()).render("specs/utterances/fig2_take_this_bar.xml")
    assert str(caught.value).startswith("chunk 2 failed: speech of chunk 2 ('and make it this big.') failed: the voice went away")
    assert caught.value.partial is not None and caught.value.partial.timeline["chunks"][0]["index"] == 0
