"""``mura serve [--port N]``: the realizer server — BML blocks in over a WebSocket, feedback out.

Prints its ``ws://HOST:PORT`` address on the first line and the avatar page's address on
the second, then performs what clients send until Ctrl-C or SIGTERM (see
:mod:`agent.serve.protocol` for the messages).
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import signal
import sys

from agent.commands.render import add_agent_options
from agent.agent import Agent
from agent.commands.table import SUMMARIES
from agent.serve.server import RealizerServer
from motor.body.conventions import AvatarError
from tts import SpeechError


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "serve",
        help=SUMMARIES["serve"],
        description="Listen on ws://HOST:PORT (printed on the first line) for JSON messages carrying BML 1.0 blocks or "
        "MURML utterances, perform them live (speech on the audio device, the avatar page at http://HOST:PORT/), and "
        "send predictions, block and sync-point progress and warnings back.",
    )
    add_agent_options(parser, default_tts="default")
    parser.add_argument("--host", default="127.0.0.1", help="interface to listen on (default: 127.0.0.1, this machine only)")
    parser.add_argument("--port", type=int, default=0, help="port (default: any free port)")
    parser.add_argument("--no-audio", action="store_true", help="do not play the speech on the audio device")
    parser.add_argument("--speedup", type=float, default=1.0,
                        help="run the performance clock this many times faster than real time (previews, tests; default 1)")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if not (0 <= args.port <= 65535):
        print(f"mura serve: port must be 0..65535, got {args.port}", file=sys.stderr)
        return 2
    if not args.speedup > 0:
        print(f"mura serve: --speedup must be positive, got {args.speedup}", file=sys.stderr)
        return 2
    try:
        agent = Agent(avatar=args.avatar, tts=args.tts, fps=args.fps, voice=args.voice, rate=args.rate, speedup=args.speedup)
    except (AvatarError, SpeechError, ValueError) as error:
        print(f"mura serve: {error}", file=sys.stderr)
        return 2
    if args.host not in ("127.0.0.1", "localhost", "::1"):
        print(f"mura serve: listening on {args.host}: other machines can drive this avatar", file=sys.stderr)
    server = RealizerServer(agent, host=args.host, port=args.port, audio=not args.no_audio)
    try:
        asyncio.run(_serve(server))
    except OSError as error:
        print(f"mura serve: cannot listen on {args.host}:{args.port}: {error.strerror or error}", file=sys.stderr)
        return 2
    finally:
        agent.close()
    return 0


async def _serve(server: RealizerServer) -> None:
    stop = asyncio.Event()
    loop = asyncio.get_running_loop()
    for signum in (signal.SIGINT, signal.SIGTERM):
        with contextlib.suppress(NotImplementedError, RuntimeError):
            loop.add_signal_handler(signum, stop.set)
    await server.run(_announce, stop)


def _announce(server: RealizerServer) -> None:
    print(server.address, flush=True)
    print(f"avatar page: {server.page}", flush=True)
