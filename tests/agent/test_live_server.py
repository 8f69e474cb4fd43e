"""The live server streams skeleton, timeline and frames, and serves nothing else."""

import json
import urllib.error
import urllib.request

import numpy as np
import pytest

from agent.live_server import LiveServer
from motor.motion import Motion


def _motion(frames: int = 3, start: float = 0.0) -> Motion:
    parents = (-1, 0, 1)
    offsets = np.array([[0.0, 1.0, 0.0], [0.0, 0.3, 0.0], [0.0, 0.2, 0.0]])
    angles = np.linspace(0.0, 0.5, frames)
    rotations = np.zeros((frames, 3, 4))
    rotations[..., 3] = 1.0
    rotations[:, 1, 2] = np.sin(angles / 2)
    rotations[:, 1, 3] = np.cos(angles / 2)
    return Motion(30.0, ("humanoid_root", "vl5", "skullbase"), parents, offsets, rotations, np.zeros((frames, 3)), start)


@pytest.fixture
def server():
    live = LiveServer(_motion(), name="test")
    live.start()
    yield live
    live.close()


def _events(response, count):
    messages = []
    while len(messages) < count:
        line = response.readline().decode()
        if line.startswith("data: "):
            messages.append(json.loads(line[6:]))
    return messages


def test_binds_to_loopback(server):
    assert server.url.startswith("http://127.0.0.1:")


def test_page_and_nothing_else(server):
    base = server.url.split("?")[0]
    page = urllib.request.urlopen(base, timeout=5).read().decode()
    assert "<html" in page.lower()
    for path in ("etc/passwd", "../README.md", "viewer/dist/viewer.js"):
        with pytest.raises(urllib.error.HTTPError) as caught:
            urllib.request.urlopen(base + path, timeout=5)
        assert caught.value.code == 404


def test_stream_sends_skeleton_timeline_then_frames(server):
    base = server.url.split("?")[0]
    server.publish_timeline({"duration": 1.0, "chunks": []})
    response = urllib.request.urlopen(base + "stream", timeout=5)
    skeleton, timeline = _events(response, 2)
    assert [joint["name"] for joint in skeleton["skeleton"]] == ["humanoid_root", "vl5", "skullbase"]
    assert skeleton["skeleton"][2]["parent"] == 1
    assert timeline["timeline"]["duration"] == 1.0
    motion = _motion(frames=4, start=1.0)
    server.publish_motion(motion)
    frames = _events(response, 4)
    assert [frame["frame"] for frame in frames] == [30, 31, 32, 33]
    assert frames[3]["time"] == pytest.approx(1.1)
    assert np.allclose(np.reshape(frames[3]["rotations"], (3, 4)), motion.rotations[3], atol=1e-5)
    response.close()
