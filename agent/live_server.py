"""The live avatar: a small HTTP server on 127.0.0.1 streaming frames to the browser page.

``mura play`` schedules an utterance on the wall clock; as the scheduler produces frames
they are pushed to every connected page as server-sent events (the protocol of
``viewer/src/live.js``): first the skeleton and the timeline, then one message per frame
with the local joint rotations. The server binds to the loopback interface by default and
serves exactly two paths of its own — the page (``/``) and the stream (``/stream``) — and
nothing from the file system.

Hostile or unlucky clients cannot take it down: at most :data:`MAX_CLIENTS` connections
are served at once (more get ``503`` at once), a connection that sends no request within
:data:`REQUEST_TIMEOUT` seconds, or stops reading the stream for as long, is dropped; a
request whose ``Host`` is not the loopback address it serves on is refused with ``403``
(a web page on another site that a DNS-rebinding trick points at 127.0.0.1 cannot read the
stream); a client that goes away ends its stream without a word on the console. A page
that connects late gets the performance from its start (up to the last
:data:`HISTORY_FRAMES` frames), then the frames as they come.
"""

from __future__ import annotations

import collections
import json
import queue
import sys
import threading
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

import numpy as np

from agent.export.bvh import bvh_text
from agent.export.html import render_html
from motor.motion import Motion

#: Seconds between keep-alive comments on an idle stream.
KEEPALIVE_SECONDS = 10.0
#: Frame messages kept for pages that connect late (100 s at 60 frames/s).
HISTORY_FRAMES = 6000
#: Messages a slow client may lag behind before it is dropped (the history, then as much again).
CLIENT_BACKLOG = 2 * HISTORY_FRAMES
#: Connections served at once; more are refused with 503.
MAX_CLIENTS = 16
#: Seconds a connection may take to send its request, or block a write, before it is dropped.
REQUEST_TIMEOUT = 5.0
#: Connections the operating system queues before the server accepts them.
LISTEN_BACKLOG = 64
#: Errors that only mean a client went away or stalled.
_DISCONNECTS = (ConnectionError, TimeoutError)


class _BoundedServer(ThreadingHTTPServer):
    """A threading HTTP server with at most ``max_clients`` handler threads, quiet about
    clients that disconnect or stall."""

    daemon_threads = True
    request_queue_size = LISTEN_BACKLOG

    def __init__(self, address: tuple[str, int], handler: type[BaseHTTPRequestHandler], max_clients: int) -> None:
        self._slots = threading.BoundedSemaphore(max_clients)
        super().__init__(address, handler)

    def process_request(self, request, client_address) -> None:  # noqa: ANN001 (socketserver's signature)
        if not self._slots.acquire(blocking=False):
            self._refuse_busy(request)
            return
        try:
            super().process_request(request, client_address)
        except BaseException:
            self._slots.release()
            raise

    def process_request_thread(self, request, client_address) -> None:  # noqa: ANN001
        try:
            super().process_request_thread(request, client_address)
        finally:
            self._slots.release()

    def _refuse_busy(self, request) -> None:  # noqa: ANN001
        try:
            request.settimeout(1.0)
            request.sendall(b"HTTP/1.0 503 Service Unavailable\r\nContent-Length: 0\r\nConnection: close\r\n\r\n")
        except OSError:
            pass
        self.shutdown_request(request)

    def handle_error(self, request, client_address) -> None:  # noqa: ANN001
        error = sys.exc_info()[1]
        if isinstance(error, _DISCONNECTS):
            return
        print(f"mura live: a request from {client_address[0]} failed: {type(error).__name__}: {error}", file=sys.stderr)


def skeleton_message(motion: Motion) -> dict:
    """The stream's first message: the joint list (name, parent index, offset in metres)."""
    joints = [
        {"name": name, "parent": int(parent), "offset": [float(v) for v in offset]}
        for name, parent, offset in zip(motion.joint_names, motion.parents, motion.offsets)
    ]
    return {"skeleton": joints}


def frame_messages(motion: Motion) -> list[str]:
    """One JSON message per frame of ``motion``: frame index, time, rotations, root and,
    when the motion has a face, ``face``: ``{name: weight}`` of the weights not zero."""
    first = int(round(motion.start_time * motion.fps))
    rotations = np.round(motion.rotations.reshape(motion.frame_count, -1), 5).tolist()
    roots = np.round(motion.root_translation, 5).tolist()
    times = np.round(motion.times, 5).tolist()
    faces = _face_frames(motion)
    return [
        json.dumps({"frame": first + i, "time": t, "rotations": r, "root": root, **face}, separators=(",", ":"))
        for i, (t, r, root, face) in enumerate(zip(times, rotations, roots, faces))
    ]


def _face_frames(motion: Motion) -> list[dict]:
    if motion.face_weights is None:
        return [{} for _ in range(motion.frame_count)]
    weights = np.round(motion.face_weights, 3)
    return [{"face": {motion.face_names[j]: float(row[j]) for j in np.flatnonzero(row)}} for row in weights]


class LiveServer:
    """Serves the live page and pushes skeleton, timeline and frames to every client."""

    def __init__(self, motion_template: Motion, *, name: str = "mura live", host: str = "127.0.0.1", port: int = 0,
                 max_clients: int = MAX_CLIENTS, request_timeout: float = REQUEST_TIMEOUT) -> None:
        rest = Motion(
            motion_template.fps,
            motion_template.joint_names,
            motion_template.parents,
            motion_template.offsets,
            motion_template.rotations[:1],
            motion_template.root_translation[:1],
        )
        self._page = render_html(name=name, bvh_text=bvh_text(rest), timeline={}, wav_filename=None).encode("utf-8")
        self._header: list[str] = [json.dumps(skeleton_message(rest), separators=(",", ":"))]
        self._history: collections.deque[str] = collections.deque(maxlen=HISTORY_FRAMES)
        self._clients: set[queue.Queue[str | None]] = set()
        self._lock = threading.Lock()
        self._httpd = _BoundedServer((host, port), self._handler_class(request_timeout), max_clients)
        bound_host, bound_port = self._httpd.server_address[:2]
        self._hosts = frozenset(f"{name}:{bound_port}" for name in ("127.0.0.1", "localhost", "[::1]", str(bound_host)))
        self._thread = threading.Thread(target=self._httpd.serve_forever, name="mura-live-server", daemon=True)

    @property
    def url(self) -> str:
        """The page's address, live mode on."""
        host, port = self._httpd.server_address[:2]
        return f"http://{host}:{port}/?live=1"

    def start(self) -> str:
        """Start serving in a background thread; returns the page's address."""
        self._thread.start()
        return self.url

    def close(self) -> None:
        """Stop serving and end every stream."""
        with self._lock:
            for client in self._clients:
                client.put(None)
        if self._thread.is_alive():
            self._httpd.shutdown()
        self._httpd.server_close()

    def publish_timeline(self, timeline: dict) -> None:
        """Send (and remember for later clients) the current timeline."""
        message = json.dumps({"timeline": timeline}, separators=(",", ":"))
        with self._lock:
            self._header = self._header[:1] + [message]
            self._broadcast([message])

    def publish_motion(self, motion: Motion) -> None:
        """Send every frame of ``motion`` to every connected client."""
        messages = frame_messages(motion)
        with self._lock:
            self._history.extend(messages)
            self._broadcast(messages)

    def _broadcast(self, messages: list[str]) -> None:
        for client in list(self._clients):
            if client.qsize() + len(messages) > CLIENT_BACKLOG:
                client.put(None)
                self._clients.discard(client)
                continue
            for message in messages:
                client.put(message)

    def _subscribe(self) -> queue.Queue[str | None]:
        client: queue.Queue[str | None] = queue.Queue()
        with self._lock:
            for message in (*self._header, *self._history):
                client.put(message)
            self._clients.add(client)
        return client

    def _unsubscribe(self, client: queue.Queue[str | None]) -> None:
        with self._lock:
            self._clients.discard(client)

    def _handler_class(self, request_timeout: float) -> type[BaseHTTPRequestHandler]:
        server = self

        class Handler(BaseHTTPRequestHandler):
            timeout = request_timeout

            def do_GET(self) -> None:  # noqa: N802 (the http.server name)
                path = self.path.split("?", 1)[0]
                if self.headers.get("Host", "").strip().lower() not in server._hosts:
                    self._send(403, "text/plain; charset=utf-8", b"forbidden: this server answers only to 127.0.0.1 and localhost\n")
                elif path == "/":
                    self._send(200, "text/html; charset=utf-8", server._page)
                elif path == "/stream":
                    self._stream()
                else:
                    self._send(404, "text/plain; charset=utf-8", b"not found\n")

            def _send(self, status: int, kind: str, body: bytes) -> None:
                try:
                    self.send_response(status)
                    self.send_header("Content-Type", kind)
                    self.send_header("Content-Length", str(len(body)))
                    self.send_header("Cache-Control", "no-store")
                    self.end_headers()
                    self.wfile.write(body)
                except _DISCONNECTS:
                    self.close_connection = True

            def _stream(self) -> None:
                self.send_response(200)
                self.send_header("Content-Type", "text/event-stream")
                self.send_header("Cache-Control", "no-store")
                self.end_headers()
                client = server._subscribe()
                try:
                    self.wfile.flush()
                    while True:
                        try:
                            message = client.get(timeout=KEEPALIVE_SECONDS)
                        except queue.Empty:
                            self.wfile.write(b": keep-alive\n\n")
                            self.wfile.flush()
                            continue
                        if message is None:
                            return
                        self.wfile.write(b"data: " + message.encode("utf-8") + b"\n\n")
                        self.wfile.flush()
                except _DISCONNECTS:
                    return
                finally:
                    server._unsubscribe(client)

            def log_message(self, format: str, *args: object) -> None:  # noqa: A002 (the http.server name)
                return

        return Handler
