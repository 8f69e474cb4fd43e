"""``mura demo``: render the seed's Fig. 2 utterance with real speech and print the page's address."""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

from agent.agent import Agent
from agent.commands.options import add_limit_option, limits_from, refuse
from agent.commands.render import render_one
from agent.commands.table import SUMMARIES
from agent.export.staging import OutputFolderError, StagedRun
from motor.body.conventions import DEFAULT_AVATAR, AvatarError
from mura.limits import LimitError
from mura.resources import SPECS_DIR
from tts import SpeechError

DEMO_UTTERANCE = SPECS_DIR / "utterances" / "fig2_take_this_bar.xml"


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "demo",
        help=SUMMARIES["demo"],
        description="Render 'And now take this bar and make it this big.' with espeak-ng speech (the fake "
        "speech if espeak-ng cannot load) into the output folder, and print the address of the avatar page.",
    )
    parser.add_argument("-o", "--output", default="out/demo", metavar="DIR", help="output folder (default: out/demo)")
    parser.add_argument("--avatar", default=DEFAULT_AVATAR, help=f"avatar name or file (default: {DEFAULT_AVATAR})")
    add_limit_option(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            agent = Agent(avatar=args.avatar, tts="default", limits=limits_from(args))
    except (AvatarError, SpeechError, LimitError) as error:
        return refuse("demo", error)
    for warning in caught:
        print(f"mura demo: {warning.message}", file=sys.stderr)
    try:
        with StagedRun(args.output) as staged:
            status = render_one(agent, DEMO_UTTERANCE, staged.folder, Path(args.output))
            staged.commit()
    except OutputFolderError as error:
        return refuse("demo", error)
    if status == 0:
        page = (Path(args.output) / f"{DEMO_UTTERANCE.stem}.html").resolve()
        print(f"speech: {agent.tts.name}; open the avatar page: {page.as_uri()}")
    return status
