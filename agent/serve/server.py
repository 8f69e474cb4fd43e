"""The realizer server: agents in other processes send BML blocks over a WebSocket and hear
BML feedback back (protocol: :mod:`agent.serve.protocol`).

One :class:`~agent.agent.Agent` performs every block live, in the order composition gives
(``APPEND``/``MERGE`` queue, ``REPLACE`` interrupts). Feedback about a block goes to the
connection that sent it and to every observer. The same port answers plain HTTP ``GET /``
with the avatar page, which connects back as an observer and follows the frames.

The server binds to 127.0.0.1 by default; it accepts WebSocket connections from programs
(no ``Origin``) and from its own page only, so that a web page elsewhere cannot drive the
avatar. A bad message is answered with a located error and the connection stays open;
messages above :data:`~agent.serve.protocol.MAX_MESSAGE_BYTES` close it (WebSocket code
1009). A client too slow to take its frames loses frames, never feedback.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
from collections.abc import Callable
from dataclasses import dataclass, field
from http import HTTPStatus

from websockets.asyncio.server import Server, ServerConnection, serve
from websockets.datastructures import Headers
from websockets.exceptions import ConnectionClosed
from websockets.http11 import Request as HttpRequest
from websockets.http11 import Response

from agent.agent import Agent
from agent.export.bvh import bvh_text
from agent.export.html import render_html
from agent.live_server import frame_messages, skeleton_message
from agent.performance import rest_motion
from agent.serve.protocol import MAX_MESSAGE_BYTES, PROTOCOL_VERSION, Request, error_message, feedback_message, read_request
from agent.sources import read_spec
from blackboard.events import FramesReady
from blackboard.feedback import BlockProgress, BmlFeedback, PredictionFeedback, SyncPointProgress, WarningFeedback
from mura.bml import parse_bml

#: Frame messages a client may have waiting before new frames are dropped for it.
FRAME_BACKLOG = 600
_FEEDBACK = (BlockProgress, SyncPointProgress, PredictionFeedback, WarningFeedback)


@dataclass(eq=False)
class _Client:
    """One connection: its outgoing queue and what it asked to hear."""

    connection: ServerConnection
    outbox: asyncio.Queue = field(default_factory=asyncio.Queue)
    observer: bool = False
    frames: bool = False
    waiting_frames: int = 0


class RealizerServer:
    """Serves ``agent`` on ``ws://host:port`` (``port`` 0: any free port); see the module docstring."""

    def __init__(self, agent: Agent, host: str = "127.0.0.1", port: int = 0, audio: bool = True) -> None:
        self.agent = agent
        self.host = host
        self.port = port
        self.audio = audio
        self._clients: set[_Client] = set()
        self._owners: dict[str, _Client] = {}
        self._loop: asyncio.AbstractEventLoop | None = None
        self._server: Server | None = None
        self._count = 0
        rest = rest_motion(agent.avatar, agent.fps)
        self._skeleton = json.dumps(skeleton_message(rest), separators=(",", ":"))
        self._page = render_html(name="mura serve", bvh_text=bvh_text(rest), timeline={}, wav_filename=None)
        agent.subscribe(self._hear)

    @property
    def address(self) -> str:
        return f"ws://{self.host}:{self.port}"

    @property
    def page(self) -> str:
        return f"http://{self.host}:{self.port}/?live=ws"

    async def run(self, ready: Callable[[RealizerServer], None] | None = None, stop: asyncio.Event | None = None) -> None:
        """Serve until ``stop`` is set (forever without one); ``ready`` is called once listening."""
        self._loop = asyncio.get_running_loop()
        async with serve(self._connection, self.host, self.port, process_request=self._http, max_size=MAX_MESSAGE_BYTES,
                         compression=None) as server:
            self._server = server
            self.port = server.sockets[0].getsockname()[1]
            if ready is not None:
                ready(self)
            await (stop.wait() if stop is not None else asyncio.get_running_loop().create_future())
        self.agent.interrupt()

    # -- HTTP: the page, and who may open a WebSocket -----------------------------------

    def _http(self, connection: ServerConnection, request: HttpRequest) -> Response | None:
        origin = request.headers.get("Origin")
        if origin is not None and origin not in (f"http://{self.host}:{self.port}", f"http://localhost:{self.port}"):
            return connection.respond(HTTPStatus.FORBIDDEN, "origin not allowed\n")
        if request.headers.get("Upgrade", "").lower() == "websocket":
            return None
        if request.path.split("?", 1)[0] != "/":
            return connection.respond(HTTPStatus.NOT_FOUND, "not found\n")
        body = self._page.encode("utf-8")
        headers = Headers([("Content-Type", "text/html; charset=utf-8"), ("Content-Length", str(len(body))), ("Cache-Control", "no-store")])
        return Response(HTTPStatus.OK, "OK", headers, body)

    # -- connections --------------------------------------------------------------------

    async def _connection(self, connection: ServerConnection) -> None:
        client = _Client(connection)
        self._clients.add(client)
        sender = asyncio.create_task(self._send_all(client))
        client.outbox.put_nowait(json.dumps({"type": "hello", "protocol": PROTOCOL_VERSION, "server": "mura", "page": self.page}))
        try:
            async for text in connection:
                self._answer(client, text)
        except ConnectionClosed:
            pass
        finally:
            self._clients.discard(client)
            self._owners = {block: owner for block, owner in self._owners.items() if owner is not client}
            sender.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await sender

    async def _send_all(self, client: _Client) -> None:
        while True:
            message = await client.outbox.get()
            if message.startswith('{"frame"'):
                client.waiting_frames -= 1
            try:
                await client.connection.send(message)
            except ConnectionClosed:
                return

    def _answer(self, client: _Client, text: str | bytes) -> None:
        """Perform one client message; every failure becomes an ``error`` answer."""
        self._count += 1
        tag = None
        try:
            request = read_request(text)
            tag = request.tag
            reply = self._perform(client, request)
        except Exception as error:  # noqa: BLE001 (one bad message never ends the connection)
            reply = error_message(error, tag)
        if reply is not None:
            if tag is not None:
                reply["request"] = tag
            self._send(client, reply)

    def _perform(self, client: _Client, request: Request) -> dict | None:
        kind, fields = request.type, request.fields
        if kind == "ping":
            return {"type": "pong"}
        if kind == "observe":
            client.observer = True
            client.frames = bool(fields.get("frames", False))
            if client.frames:
                client.outbox.put_nowait(self._skeleton)
            return {"type": "observing", "frames": client.frames}
        if kind == "interrupt":
            return {"type": "interrupted", "blocks": self.agent.interrupt(fields.get("block"))}
        label = f"<message {self._count}>"
        if kind == "bml":
            source = parse_bml(fields["xml"], file=label)
            name = source.id
        else:
            source, _, _ = read_spec(fields["xml"].encode("utf-8"))
            name = fields.get("id") or f"utterance-{self._count}"
        previous = self._owners.get(name)
        self._owners[name] = client
        try:
            self.agent.say(source, name=name, audio=self.audio)
        except BaseException:
            if previous is not None:
                self._owners[name] = previous
            else:
                self._owners.pop(name, None)
            raise
        return {"type": "accepted", "block": name}

    # -- events from the scheduler's thread ---------------------------------------------

    def _hear(self, event: object) -> None:
        loop = self._loop
        if loop is None or loop.is_closed():
            return
        if isinstance(event, _FEEDBACK):
            message = json.dumps(feedback_message(event), separators=(",", ":"))
            loop.call_soon_threadsafe(self._route, event, message)
        elif isinstance(event, FramesReady):
            loop.call_soon_threadsafe(self._frames, frame_messages(event.motion))

    def _route(self, feedback: BmlFeedback, message: str) -> None:
        owner = self._owners.get(feedback.block)
        for client in self._clients:
            if client is owner or client.observer:
                client.outbox.put_nowait(message)
        if isinstance(feedback, BlockProgress) and feedback.point == "end":
            self._owners.pop(feedback.block, None)

    def _frames(self, messages: list[str]) -> None:
        for client in self._clients:
            if not client.frames or client.waiting_frames + len(messages) > FRAME_BACKLOG:
                continue
            client.waiting_frames += len(messages)
            for message in messages:
                client.outbox.put_nowait(message)

    def _send(self, client: _Client, reply: dict) -> None:
        client.outbox.put_nowait(json.dumps(reply, separators=(",", ":")))
