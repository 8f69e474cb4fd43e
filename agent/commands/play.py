"""``mura play FILE``: perform an utterance live — speech on the audio device, the avatar in a browser page.

The page is served on 127.0.0.1 and follows the frames as the scheduler produces them.
On a machine without an audio device or a browser, the schedule still runs and the
command says what it could not do.
"""

from __future__ import annotations

import argparse
import sys
import time
import webbrowser

from agent.commands.render import add_agent_options, make_agent
from agent.live_server import LiveServer
from agent.performance import PerformanceError, rest_motion
from blackboard.events import Event, FramesReady, SpeechStarted
from motor.body.avatar import AvatarError
from mura.errors import SpecError
from tts import SpeechError


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "play",
        help="perform an utterance live with audio and the avatar in a browser page",
        description="Perform the utterance on the wall clock: speech plays on the audio device, and a page "
        "served on 127.0.0.1 shows the avatar following the frames as they are produced.",
    )
    parser.add_argument("file", metavar="FILE", help="MURML utterance file")
    add_agent_options(parser, default_tts="default")
    parser.add_argument("--port", type=int, default=0, help="port of the page on 127.0.0.1 (default: any free port)")
    parser.add_argument("--no-browser", action="store_true", help="print the page's address instead of opening a browser")
    parser.add_argument("--linger", type=float, default=3.0, metavar="SECONDS",
                        help="keep serving the page this long after the utterance ends (default: 3)")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    try:
        agent = make_agent(args)
    except (AvatarError, SpeechError, SpecError) as error:
        print(f"mura play: {error}", file=sys.stderr)
        return 2
    server = LiveServer(rest_motion(agent.avatar, agent.fps), name=args.file, port=args.port)
    url = server.start()
    print(f"avatar page: {url}")
    if not args.no_browser and not webbrowser.open(url):
        print("mura play: no browser could be opened here; open the address above yourself", file=sys.stderr)
    agent.subscribe(_forward_frames(server))
    try:
        performance = agent.say(args.file).wait()
    except SpecError as error:
        print(str(error), file=sys.stderr)
        return 1
    except (PerformanceError, SpeechError, ValueError) as error:
        print(f"{args.file}: {error}", file=sys.stderr)
        return 1
    finally:
        agent.close()
    server.publish_timeline(performance.timeline)
    print(f"{args.file}: performed {performance.duration:.2f} s")
    time.sleep(max(0.0, args.linger))
    server.close()
    return 0


def _forward_frames(server: LiveServer):
    def observer(event: Event) -> None:
        if isinstance(event, FramesReady):
            server.publish_motion(event.motion)
        elif isinstance(event, SpeechStarted):
            print(f"speaking: {event.text}", file=sys.stderr)

    return observer
