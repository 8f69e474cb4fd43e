"""Item 5: SIGTERM (``timeout``, a process manager) during ``render`` left hidden ``.part``
files behind, and ``mura play`` ignored the first Ctrl-C. Now SIGTERM and SIGINT both leave
the output folder exactly as before the run in ``render``, ``sign``, ``say`` and ``plot``,
and ``play`` stops at the first one.

Each run signals itself at a chosen call in the middle of its work (``mura_runner.py``
hooks): a deterministic point, no timer.
"""

from __future__ import annotations

import pytest
from hostile_helpers import all_files, run_mura, utterance

from mura.hamnosys import hamnosys_string

FIG2 = "specs/utterances/fig2_take_this_bar.xml"
STATUS = {"SIGINT": 130, "SIGTERM": 143}
#: Both signals where the command's own handling differs; SIGTERM alone where both take
#: the same path (SIGTERM raises the KeyboardInterrupt that Ctrl-C raises).
SIGNALS = pytest.mark.parametrize("signal_name", ["SIGTERM", "SIGINT"])
SIGTERM = pytest.mark.parametrize("signal_name", ["SIGTERM"])


def _hook(target: str, call: int, signal_name: str) -> list[dict]:
    return [{"target": target, "call": call, "action": signal_name}]


@pytest.fixture
def previous_output(tmp_path):
    """An output folder from an earlier run: one file that the new run would replace."""
    folder = tmp_path / "out"
    folder.mkdir()
    (folder / "fig2_take_this_bar.bvh").write_text("from an earlier run\n")
    return folder


@SIGNALS
@pytest.mark.timeout(60)
def test_render_interrupted_in_the_second_file_leaves_the_folder_as_it_was(write, previous_output, signal_name):
    first = write("first.xml", utterance("Hello there."))
    done = run_mura("render", str(first), FIG2, "-o", str(previous_output),
                    hooks=_hook("tts.fake:FakeSynthesizer.synthesize", 3, signal_name))  # chunk 2 of the second file
    assert done.status == STATUS[signal_name]
    assert "interrupted" in done.err
    assert all_files(previous_output) == ["fig2_take_this_bar.bvh"]
    assert (previous_output / "fig2_take_this_bar.bvh").read_text() == "from an earlier run\n"


@SIGTERM
@pytest.mark.timeout(60)
def test_render_interrupted_creates_no_folder(tmp_path, signal_name):
    out = tmp_path / "new" / "out"
    done = run_mura("render", FIG2, "-o", str(out), hooks=_hook("tts.fake:FakeSynthesizer.synthesize", 2, signal_name))
    assert done.status == STATUS[signal_name]
    assert not (tmp_path / "new").exists()


@SIGTERM
@pytest.mark.timeout(60)
def test_sign_interrupted_at_the_second_sign_leaves_nothing(write, tmp_path, signal_name):
    names = ["hamflathand", "hamextfingeru", "hampalml", "hamshoulders", "hammoveo"]
    sign = "".join(f"<{name}/>" for name in names)
    document = write("two.sigml", f'<sigml><hns_sign gloss="A"><hamnosys_manual>{sign}</hamnosys_manual></hns_sign>'
                                  f'<hns_sign gloss="B"><hamnosys_manual>{sign}</hamnosys_manual></hns_sign></sigml>')
    out, report = tmp_path / "out", tmp_path / "reports" / "report.json"
    done = run_mura("sign", str(document), "-o", str(out), "--report", str(report),
                    hooks=_hook("agent.batch.render:realize_prepared", 2, signal_name))  # the second sign
    assert done.status == STATUS[signal_name]
    assert not out.exists() and not report.parent.exists()
    assert hamnosys_string(names)  # the symbols exist (the document is a valid two-sign corpus)


@SIGTERM
@pytest.mark.timeout(60)
def test_say_interrupted_while_writing_leaves_no_file(tmp_path, signal_name):
    done = run_mura("say", "Hello there.", "--tts", "fake", "-o", str(tmp_path / "hello.wav"),
                    hooks=_hook("agent.commands.say:write_wav", 1, signal_name))
    assert done.status == STATUS[signal_name]
    assert all_files(tmp_path) == []


@SIGTERM
@pytest.mark.timeout(60)
def test_plot_interrupted_after_the_first_picture_leaves_nothing(tmp_path, signal_name):
    done = run_mura("plot", FIG2, "-o", str(tmp_path / "plots"), "--fps", "30",
                    hooks=_hook("agent.commands.plot:plot_wrist_paths", 1, signal_name))
    assert done.status == STATUS[signal_name]
    assert not (tmp_path / "plots").exists()


@SIGNALS
@pytest.mark.timeout(60)
@pytest.mark.parametrize(
    "moment",
    ["agent.live_server:LiveServer.publish_motion", "agent.agent:LiveUtterance.__init__"],
    ids=["at-the-first-frames", "while-the-utterance-starts"],
)
def test_play_stops_at_the_first_interrupt(write, signal_name, moment):
    """A two-minute utterance, interrupted at its first frames or while it is being
    started: the command ends (the subprocess timeout is the bound) with the signal's
    status, the arms retracted."""
    text = " ".join(f'Here is part {k} of a long story <time id="b{k}" chunkborder="true"/>' for k in range(40))
    spec = write("long.xml", utterance(text))
    done = run_mura("play", str(spec), "--tts", "fake", "--no-browser", "--linger", "0", hooks=_hook(moment, 1, signal_name))
    assert done.status == STATUS[signal_name]
    assert "interrupted" in done.err
    assert "performed" not in done.out
