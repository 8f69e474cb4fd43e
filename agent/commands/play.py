"""``mura play FILE``: perform an utterance live — speech on the audio device, the avatar in a browser page.

The page is served on 127.0.0.1 and follows the frames as the scheduler produces them.
On a machine without an audio device or a browser, the schedule still runs and the
command says what it could not do. The first Ctrl-C (or SIGTERM) interrupts the
utterance (the arms retract), stops the server and ends the command; a chunk that fails
ends the utterance there and the command exits 1.
"""

from __future__ import annotations

import argparse
import sys
import time
import webbrowser

from agent.agent import LiveUtterance
from agent.commands.options import add_lexicon_option, describe_failure, refuse
from agent.commands.render import add_agent_options, make_agent
from agent.commands.table import SUMMARIES
from agent.live_server import LiveServer
from agent.performance import PerformanceError, rest_motion
from agent.signals import signals_deferred
from blackboard.events import Event, FramesReady, SpeechStarted
from motor.body.conventions import AvatarError
from mura.errors import SpecError
from mura.limits import LimitError
from tts import SpeechError


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "play",
        help=SUMMARIES["play"],
        description="Perform the utterance on the wall clock: speech plays on the audio device, and a page "
        "served on 127.0.0.1 shows the avatar following the frames as they are produced. Ctrl-C interrupts it.",
    )
    parser.add_argument("file", metavar="FILE", help="MURML utterance file")
    add_agent_options(parser, default_tts="default")
    add_lexicon_option(parser)
    parser.add_argument("--port", type=int, default=0, help="port of the page on 127.0.0.1 (default: any free port)")
    parser.add_argument("--no-browser", action="store_true", help="print the page's address instead of opening a browser")
    parser.add_argument("--linger", type=float, default=3.0, metavar="SECONDS",
                        help="keep serving the page this long after the utterance ends (default: 3)")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    try:
        agent = make_agent(args)
    except (AvatarError, SpeechError, LimitError, SpecError) as error:
        return refuse("play", error)
    try:
        server = LiveServer(rest_motion(agent.avatar, agent.fps), name=args.file, port=args.port)
    except (OSError, OverflowError) as error:
        return refuse("play", f"cannot serve the page on port {args.port}: {getattr(error, 'strerror', None) or error}")
    live: LiveUtterance | None = None
    try:
        url = server.start()
        print(f"avatar page: {url}")
        if not args.no_browser and not webbrowser.open(url):
            print("mura play: no browser could be opened here; open the address above yourself", file=sys.stderr)
        agent.subscribe(_forward_frames(server))
        with signals_deferred():  # a Ctrl-C while the utterance starts must find it to interrupt
            live = agent.say(args.file)
        status = _perform(live, server, args.file)
        time.sleep(max(0.0, args.linger))
        return status
    except SpecError as error:
        print(str(error), file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        if live is not None:
            live.interrupt()
        raise
    finally:
        agent.close()
        server.close()


def _perform(live: LiveUtterance, server: LiveServer, file: str) -> int:
    """Wait for the utterance; publish its timeline (the part performed when a chunk failed)."""
    try:
        performance = live.wait()
    except PerformanceError as error:
        if error.partial is not None:
            server.publish_timeline(error.partial.timeline)
        print(f"{file}: {error}", file=sys.stderr)
        return 1
    except (SpeechError, ValueError) as error:
        print(f"{file}: {error}", file=sys.stderr)
        return 1
    except Exception as error:  # noqa: BLE001 - one line, never a traceback
        print(f"{file}: {describe_failure(error)}", file=sys.stderr)
        return 1
    server.publish_timeline(performance.timeline)
    print(f"{file}: performed {performance.duration:.2f} s")
    return 0


def _forward_frames(server: LiveServer):
    def observer(event: Event) -> None:
        if isinstance(event, FramesReady):
            server.publish_motion(event.motion)
        elif isinstance(event, SpeechStarted):
            print(f"speaking: {event.text}", file=sys.stderr)

    return observer
