"""Rendering every example utterance writes four consistent files; bad input writes none."""

import json
from pathlib import Path

import numpy as np
import pytest
from bvh import Bvh

from agent.agent import Agent
from agent.cli import main
from tts.wav import read_wav

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((REPO / "specs" / "utterances").glob("*.xml"))


@pytest.fixture(scope="module")
def agent():
    return Agent(avatar="max", tts="fake", fps=30)


@pytest.fixture(scope="module")
def rendered(agent, tmp_path_factory):
    folder = tmp_path_factory.mktemp("render")
    return {path.stem: (agent.render(path), agent.render(path).save(folder)) for path in EXAMPLES}


@pytest.mark.parametrize("name", [path.stem for path in EXAMPLES])
def test_four_files_agree(rendered, name):
    performance, files = rendered[name]
    for path in (files.wav, files.bvh, files.timeline, files.html):
        assert path.is_file() and path.stat().st_size > 0
    timeline = json.loads(files.timeline.read_text())
    samples, rate = read_wav(files.wav)
    assert len(samples) / rate == pytest.approx(timeline["duration"], abs=1.0 / rate)
    assert timeline["duration"] >= performance.motion.duration - 1.0 / performance.motion.fps
    mocap = Bvh(files.bvh.read_text())
    assert len(mocap.get_joints_names()) == len(performance.motion.joint_names)
    assert mocap.nframes == performance.motion.frame_count
    assert mocap.frame_time == pytest.approx(1.0 / 30)
    assert not np.isnan(performance.motion.rotations).any()
    assert not list(files.wav.parent.glob(".*.part"))


def test_bvh_channel_data_round_trips(rendered):
    performance, files = rendered["fig2_take_this_bar"]
    mocap = Bvh(files.bvh.read_text())
    wrist = mocap.frames_joint_channels("r_wrist", ["Zrotation", "Xrotation", "Yrotation"])
    from scipy.spatial.transform import Rotation

    angles = np.asarray(wrist, dtype=float)
    rebuilt = Rotation.from_euler("ZXY", angles, degrees=True).as_quat()
    original = performance.motion.rotations[:, performance.motion.joint_names.index("r_wrist")]
    same = np.abs(np.sum(rebuilt * original, axis=1))
    assert np.all(same > 1 - 1e-6)


def test_render_is_deterministic(agent):
    first = agent.render(EXAMPLES[0])
    second = agent.render(EXAMPLES[0])
    assert first.timeline == second.timeline
    assert np.array_equal(first.motion.rotations, second.motion.rotations)
    assert np.array_equal(first.audio, second.audio)


def test_bad_spec_is_one_line_and_no_files(tmp_path, capsys):
    bad = REPO / "tests" / "mura" / "malformed" / "unknown_time_tag.xml"
    out = tmp_path / "out"
    assert main(["render", str(bad), "-o", str(out)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"{bad}:5:29: behaviour 'g1': end names unknown time tag 't9' (known: t1, t2)"]
    assert not out.exists() or not any(out.iterdir())


def test_failure_while_saving_leaves_nothing_that_looks_complete(agent, tmp_path, monkeypatch):
    performance = agent.render(EXAMPLES[0])
    import agent.performance as saving

    def broken(*args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(saving, "write_html", broken)
    with pytest.raises(OSError, match="disk full"):
        performance.save(tmp_path)
    assert list(tmp_path.iterdir()) == []


def test_render_command_writes_files(tmp_path, capsys):
    assert main(["render", str(EXAMPLES[0]), "-o", str(tmp_path), "--fps", "25"]) == 0
    stem = EXAMPLES[0].stem
    names = {p.name for p in tmp_path.iterdir()}
    sidecars = {name for name in names if name.startswith("mura-avatar-makehuman-") and name.endswith(".js")}
    assert len(sidecars) == 1  # the default skinned avatar's model, shared by the folder's pages
    assert names - sidecars == {f"{stem}.wav", f"{stem}.bvh", f"{stem}.timeline.json", f"{stem}.face.json", f"{stem}.html", f"{stem}.glb"}
    assert f"-> {tmp_path / (stem + '.html')}" in capsys.readouterr().out


def test_unknown_avatar_is_one_line(tmp_path, capsys):
    assert main(["render", str(EXAMPLES[0]), "-o", str(tmp_path), "--avatar", "nobody"]) == 2
    assert "nobody" in capsys.readouterr().err
