"""Item 9: the live page server and ``mura play``.

Before: one thread per connection with no timeout (200 half-open connections made 209
threads), a listen backlog of 5, no ``Host`` check (a DNS-rebinding page could read the
stream), a traceback printed per client disconnect, and ``mura play`` exited 0 although
a chunk failed. (The first Ctrl-C is in ``test_signals.py``.)
"""

from __future__ import annotations

import json
import selectors
import socket
import struct
import threading
import urllib.error
import urllib.request

import numpy as np
import pytest
from hostile_helpers import run_mura, utterance

from agent.live_server import LISTEN_BACKLOG, LiveServer
from motor.motion import Motion


def _motion(frames: int, start: float = 0.0) -> Motion:
    rotations = np.zeros((frames, 2, 4))
    rotations[..., 3] = 1.0
    offsets = np.array([[0.0, 1.0, 0.0], [0.0, 0.3, 0.0]])
    return Motion(30.0, ("humanoid_root", "vl5"), (-1, 0), offsets, rotations, np.zeros((frames, 3)), start)


@pytest.fixture
def serve():
    servers = []

    def start(**options) -> tuple[LiveServer, int]:
        server = LiveServer(_motion(1), name="hostile", **options)
        server.start()
        servers.append(server)
        return server, server._httpd.server_address[1]

    yield start
    for server in servers:
        server.close()


def _connect(port: int) -> socket.socket:
    return socket.create_connection(("127.0.0.1", port), timeout=30)


def _request(port: int, path: str = "/", host: str | None = "default") -> bytes:
    """The status line of the response to ``GET path`` with the given Host header (None: no header)."""
    with _connect(port) as connection:
        header = f"Host: 127.0.0.1:{port}\r\n" if host == "default" else ("" if host is None else f"Host: {host}\r\n")
        connection.sendall(f"GET {path} HTTP/1.0\r\n{header}\r\n".encode())
        return connection.makefile("rb").readline()


def _reset(connection: socket.socket) -> None:
    """Close with a TCP reset, as a crashed browser tab does."""
    connection.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
    connection.close()


@pytest.mark.timeout(60)
def test_two_hundred_half_open_connections_hold_a_bounded_number_of_threads(serve):
    baseline = threading.active_count()
    server, port = serve(max_clients=4, request_timeout=60)
    connections = [_connect(port) for _ in range(200)]  # all accepted by the kernel: the backlog is not 5
    refused: set[socket.socket] = set()
    with selectors.DefaultSelector() as selector:
        for connection in connections:
            selector.register(connection, selectors.EVENT_READ)
        while len(refused) < 196:  # every connection beyond the four served is answered at once
            for key, _ in selector.select():
                assert key.fileobj.recv(64).startswith(b"HTTP/1.0 503")
                selector.unregister(key.fileobj)
                refused.add(key.fileobj)
    assert threading.active_count() <= baseline + 1 + 4
    for connection in connections:
        connection.close()
    while True:  # the four served connections end when their clients go; then the page is served again
        response = _request(port)
        if not response.startswith(b"HTTP/1.0 503"):
            break
    assert response.startswith(b"HTTP/1.0 200")
    assert LISTEN_BACKLOG >= 64


@pytest.mark.timeout(30)
def test_a_silent_connection_is_dropped_by_the_server(serve):
    _, port = serve(request_timeout=0.2)
    with _connect(port) as connection:
        assert connection.recv(64) == b""  # closed by the server, not by us


@pytest.mark.parametrize(
    ("host", "status"),
    [("127.0.0.1:{port}", 200), ("localhost:{port}", 200), ("LOCALHOST:{port}", 200), ("evil.example:{port}", 403),
     ("127.0.0.1.evil.example:{port}", 403), ("127.0.0.1:1", 403), ("", 403), (None, 403)],
)  # fmt: skip
@pytest.mark.parametrize("path", ["/", "/stream"])
def test_only_loopback_hosts_are_answered(serve, host, status, path):
    _, port = serve()
    response = _request(port, path, None if host is None else host.format(port=port))
    assert response.split(b" ")[1] == str(status).encode()


@pytest.mark.timeout(30)
def test_clients_that_vanish_leave_no_trace_on_the_console(serve, capfd):
    server, port = serve()
    streaming = _connect(port)
    streaming.sendall(f"GET /stream HTTP/1.0\r\nHost: 127.0.0.1:{port}\r\n\r\n".encode())
    assert streaming.recv(15).startswith(b"HTTP/1.0 200")
    _reset(streaming)
    page = _connect(port)
    page.sendall(f"GET / HTTP/1.0\r\nHost: 127.0.0.1:{port}\r\n\r\n".encode())
    _reset(page)
    while server._clients:  # the stream's handler notices on its next write and unsubscribes
        server.publish_motion(_motion(30))
    server.close()
    assert "Traceback" not in capfd.readouterr().err


@pytest.mark.timeout(30)
def test_a_late_page_gets_the_performance_from_its_start(serve):
    server, port = serve()
    server.publish_timeline({"duration": 1.0, "chunks": []})
    server.publish_motion(_motion(4, start=0.0))
    server.publish_motion(_motion(2, start=4 / 30))
    response = urllib.request.urlopen(f"http://127.0.0.1:{port}/stream", timeout=30)
    messages = []
    while len(messages) < 8:
        line = response.readline().decode()
        if line.startswith("data: "):
            messages.append(json.loads(line[6:]))
    assert "skeleton" in messages[0] and "timeline" in messages[1]
    assert [m["frame"] for m in messages[2:]] == [0, 1, 2, 3, 4, 5]
    response.close()


@pytest.mark.timeout(60)
def test_play_exits_1_when_a_chunk_fails(tmp_path):
    spec = tmp_path / "two.xml"
    spec.write_text(utterance('Hi. <time id="b" chunkborder="true"/> There.'))
    done = run_mura("play", str(spec), "--tts", "fake", "--no-browser", "--linger", "0",
                    hooks=[{"target": "tts.fake:FakeSynthesizer.synthesize", "call": 2, "action": "raise:SpeechError:the voice went away"}])
    assert done.status == 1
    assert "chunk 2 failed: speech of chunk 2 ('There.') failed: the voice went away" in done.err
