"""Items 8 and 11: where outputs go.

8. ``mura sign --hamnosys … -o EXISTING_FILE`` (or a read-only place), ``mura plot F -o
   FILE``, ``mura say hi -o DIR`` and ``--report DIR`` ended in tracebacks.
11. ``mura render a/x.xml b/x.xml -o out`` silently replaced a's files with b's, an input
   inside the output folder could be overwritten by its own output, and
   ``render_files(…, name="../../x")`` wrote outside the folder.
"""

from __future__ import annotations

import pytest
from hostile_helpers import LIGHT, all_files, utterance

from agent.agent import Agent
from agent.cli import main
from agent.export.names import OutputNameError
from mura.hamnosys import hamnosys_string

FIG2 = "specs/utterances/fig2_take_this_bar.xml"
SIGN = hamnosys_string(["hamflathand", "hamextfingeru", "hampalml", "hamshoulders", "hammoveo"])


@pytest.fixture
def a_file(tmp_path):
    path = tmp_path / "a_file"
    path.write_text("not a folder\n")
    return path


CASES = {
    "sign -o FILE": (["sign", "--hamnosys", SIGN, "-o", "{file}"], "mura sign: output folder {file}: a file of that name is in the way"),
    "sign -o FILE/sub": (["sign", "--hamnosys", SIGN, "-o", "{file}/sub"], "mura sign: output folder {file}/sub: a part of the path is a file"),
    "sign -o unwritable": (["sign", "--hamnosys", SIGN, "-o", "/proc/mura-out"], "mura sign: output folder /proc/mura-out: cannot create it"),
    "sign --report DIR": (["sign", "--hamnosys", SIGN, "-o", "{tmp}/out", "--report", "{tmp}"], "mura sign: --report {tmp}: is a folder"),
    "sign --report FILE/x": (["sign", "--hamnosys", SIGN, "-o", "{tmp}/out", "--report", "{file}/r.json"], "mura sign: output folder {file}: a file of that name is in the way"),
    "plot -o FILE": (["plot", FIG2, "-o", "{file}", "--fps", "30"], "mura plot: output folder {file}: a file of that name is in the way"),
    "say -o DIR": (["say", "hi", "--tts", "fake", "-o", "{tmp}"], "mura say: -o {tmp}: is a folder; give the WAV file's name"),
    "say -o FILE/x.wav": (["say", "hi", "--tts", "fake", "-o", "{file}/x.wav"], "mura say: cannot write {file}/x.wav: Not a directory"),
    "render -o FILE": (["render", FIG2, "-o", "{file}"], "mura render: output folder {file}: a file of that name is in the way"),
    "demo -o FILE": (["demo", "-o", "{file}"], "mura demo: output folder {file}: a file of that name is in the way"),
}  # fmt: skip


@pytest.mark.parametrize(("arguments", "message"), CASES.values(), ids=CASES.keys())
def test_unusable_outputs_are_one_line(tmp_path, a_file, capsys, arguments, message):
    before = all_files(tmp_path)
    argv = [a.format(file=a_file, tmp=tmp_path) for a in arguments]
    assert main(argv) in (1, 2)
    err = [line for line in capsys.readouterr().err.splitlines() if not line.startswith("mura demo: espeak")]
    assert err and err[-1].startswith(message.format(file=a_file, tmp=tmp_path))
    assert all_files(tmp_path) == before
    assert a_file.read_text() == "not a folder\n"


def test_two_inputs_with_one_name_are_not_silently_merged(write, tmp_path, capsys):
    first = write("a/x.xml", utterance("First of all."))
    second = write("b/x.xml", utterance("Second thoughts."))
    out = tmp_path / "out"
    assert main(["render", str(first), str(second), "-o", str(out), *LIGHT]) == 1
    err = capsys.readouterr().err
    assert f"{second}: its output name 'x' is already used by {first} in this run" in err
    assert "rendered 1 of 2 utterances; 1 failed" in err
    assert all_files(out) == ["x.bvh", "x.face.json", "x.html", "x.timeline.json", "x.wav"]
    assert "First of all." in (out / "x.timeline.json").read_text()


@pytest.mark.parametrize("suffix", [".html", ".bvh", ".wav"])
def test_an_input_is_never_overwritten_by_an_output(write, tmp_path, capsys, suffix):
    out = tmp_path / "out"
    inside = write(f"out/x{suffix}", utterance("I live in the output folder."))
    content = inside.read_bytes()
    assert main(["render", str(inside), "-o", str(out)]) == 1
    assert f"{inside}: its output {out / f'x{suffix}'} would overwrite the input {inside}" in capsys.readouterr().err
    assert inside.read_bytes() == content and all_files(out) == [f"x{suffix}"]


def test_an_input_of_another_item_is_never_overwritten(write, tmp_path, capsys):
    out = tmp_path / "out"
    victim = write("out/y.wav", utterance("I am an input too."))
    content = victim.read_bytes()
    producer = write("y.xml", utterance("I would write y.wav."))
    assert main(["render", str(victim), str(producer), "-o", str(out)]) == 1
    assert victim.read_bytes() == content


@pytest.mark.parametrize("name", ["../../x", "../x", "a/b", "/tmp/x", "", ".", "..", "x\n", "x\x00"])
def test_output_names_cannot_leave_the_folder(tmp_path, name):
    agent = Agent()
    (tmp_path / "deep" / "out").mkdir(parents=True)
    with pytest.raises(OutputNameError):
        agent.render_files(FIG2, tmp_path / "deep" / "out", name=name)
    with pytest.raises(OutputNameError):
        agent.render(FIG2, name=name)
    assert all_files(tmp_path) == ["deep", "deep/out"]


def test_sign_glosses_become_safe_unique_names(write, tmp_path, capsys):
    manual = "".join(f"<{n}/>" for n in ["hamflathand", "hamextfingeru", "hampalml", "hamshoulders", "hammoveo"])
    signs = "".join(f'<hns_sign gloss="{gloss}"><hamnosys_manual>{manual}</hamnosys_manual></hns_sign>'
                    for gloss in ("../../evil", "../../evil", "CON"))
    document = write("s.sigml", f"<sigml>{signs}</sigml>")
    assert main(["sign", str(document), "-o", str(tmp_path / "out"), *LIGHT]) == 0
    # CON is a name Windows reserves: CON_ (agent.batch.naming); every sign plays in index.html
    expected = [f"{stem}{suffix}" for stem in ("CON_", "evil", "evil_2") for suffix in (".bvh", ".face.json", ".motion.js")]
    assert all_files(tmp_path / "out") == sorted([*expected, "index.html"])
