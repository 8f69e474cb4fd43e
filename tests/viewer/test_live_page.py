"""Live mode (``?live=1``): the page builds the body from a stream's skeleton and poses it
from frame messages, served here by a throwaway event-stream server."""

from __future__ import annotations

import io
import json
import queue
import threading
from collections.abc import Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import numpy as np
import pytest
from bvh import Bvh
from headless_chromium import Browser
from matplotlib.image import imread

from agent.export.bvh import bvh_text
from agent.export.html import render_html, write_html
from motor.motion import Motion


class _Stream:
    """A page at /live.html and an event stream at /stream fed from a queue of messages."""

    def __init__(self, page: str) -> None:
        self.messages: queue.Queue[dict | None] = queue.Queue()
        stream = self

        class Handler(BaseHTTPRequestHandler):
            def log_message(self, *args: object) -> None:
                pass

            def do_GET(self) -> None:  # noqa: N802 (http.server's naming)
                if self.path.startswith("/live.html"):
                    body = page.encode()
                    self.send_response(200)
                    self.send_header("Content-Type", "text/html; charset=utf-8")
                    self.send_header("Content-Length", str(len(body)))
                    self.end_headers()
                    self.wfile.write(body)
                    return
                if self.path != "/stream":
                    self.send_error(404)
                    return
                self.send_response(200)
                self.send_header("Content-Type", "text/event-stream")
                self.send_header("Cache-Control", "no-cache")
                self.end_headers()
                while (message := stream.messages.get()) is not None:
                    self.wfile.write(f"data: {json.dumps(message)}\n\n".encode())
                    self.wfile.flush()

        self.server = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.server.daemon_threads = True
        self.thread = threading.Thread(target=self.server.serve_forever, daemon=True)
        self.thread.start()

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.server.server_address[1]}/live.html?live=1"

    def close(self) -> None:
        self.messages.put(None)
        self.server.shutdown()
        self.server.server_close()


def _joint_list(motion: Motion) -> list[dict]:
    return [
        {"name": name, "parent": parent, "offset": offset.tolist()}
        for name, parent, offset in zip(motion.joint_names, motion.parents, motion.offsets)
    ]


@pytest.fixture(params=["bvh-hierarchy", "joint-list"])
def skeleton_kind(request: pytest.FixtureRequest) -> str:
    return request.param


@pytest.fixture
def stream(motion: Motion, timeline: dict, skeleton_kind: str) -> Iterator[_Stream]:
    bvh = bvh_text(motion)
    served = _Stream(render_html(name="live", bvh_text=bvh, timeline={}, wav_filename=None))
    skeleton = bvh[: bvh.index("MOTION")] if skeleton_kind == "bvh-hierarchy" else _joint_list(motion)
    served.messages.put({"skeleton": skeleton, "timeline": timeline})
    yield served
    served.close()


def _frame(motion: Motion, order: list[int], index: int) -> dict:
    return {
        "frame": index,
        "time": index / motion.fps,
        "rotations": motion.rotations[index, order].ravel().tolist(),
        "root": motion.root_translation[index].tolist(),
    }


def test_live_stream_poses_the_body(
    browser: Browser, stream: _Stream, motion: Motion, skeleton_kind: str, tmp_path: Path
) -> None:
    """Rotations come in the skeleton's joint order: BVH hierarchy order, or the list's."""
    joint_order = Bvh(bvh_text(motion)).get_joints_names() if skeleton_kind == "bvh-hierarchy" else motion.joint_names
    order = [motion.joint_names.index(name) for name in joint_order]
    wait_for = (
        "new Promise((resolve) => { const check = () => (window.__mura && window.__mura.time() === {t})"
        " ? resolve(true) : setTimeout(check, 10); check(); })"
    )
    shots = {}
    browser.open(stream.url)
    for index in (6, 66):
        frame = _frame(motion, order, index)
        stream.messages.put(frame)
        assert browser.evaluate(wait_for.replace("{t}", repr(frame["time"])))
        browser.evaluate("new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve)))")
        shots[index] = imread(io.BytesIO(browser.screenshot("#mura-stage")), format="png")[..., :3]
    assert browser.evaluate("window.__mura.joints()") == len(motion.joint_names)
    listed = browser.evaluate("document.getElementById('mura-timeline-list').innerText")
    assert browser.exceptions() == []
    live_meshes = browser.evaluate("window.__mura.meshes()")
    assert "gesture_1" in listed and "And now take this bar" in listed
    changed = np.abs(shots[6] - shots[66]).max(axis=-1) > 0.1
    assert changed.sum() > 2000, f"only {changed.sum()} pixels differ between the two streamed frames"
    file_page = tmp_path / "file.html"
    write_html(file_page, name="file", bvh_text=bvh_text(motion), timeline={}, wav_filename=None)
    browser.open(file_page.as_uri())
    assert live_meshes == browser.evaluate("window.__mura.meshes"), "live body differs from the file-mode body"
