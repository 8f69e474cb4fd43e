"""``mura render FILE... -o DIR``: perform utterances offline and save WAV, BVH, timeline and page."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from tqdm import tqdm

from agent.agent import Agent, PerformanceError
from agent.batch.report import summarize_warnings
from motor.body.avatar import DEFAULT_AVATAR, AvatarError
from mura.errors import SpecError
from mura.lexicon import GestureLexicon, load_lexicons
from tts import SpeechError


def add_agent_options(parser: argparse.ArgumentParser, default_tts: str = "fake") -> None:
    """The options every command that builds an :class:`Agent` shares."""
    parser.add_argument("--tts", default=default_tts, choices=("fake", "espeak", "pyttsx3", "default"),
                        help=f"speech backend (default: {default_tts}; 'default' is espeak when available, else fake)")
    parser.add_argument("--avatar", default=DEFAULT_AVATAR,
                        help=f"avatar name (max, kim, {DEFAULT_AVATAR}), an avatar file, or your own .vrm/.glb/.gltf humanoid "
                        f"(default: {DEFAULT_AVATAR}, the skinned avatar built at set-up)")  # fmt: skip
    parser.add_argument("--fps", type=float, default=60.0, help="frames per second of the motion (default: 60)")
    parser.add_argument("--voice", default=None, help="voice of the speech backend")
    parser.add_argument("--rate", type=float, default=1.0, help="relative speaking rate (default: 1.0)")
    add_lexicon_option(parser)


def add_lexicon_option(parser: argparse.ArgumentParser) -> None:
    """``--lexicon FILE`` (repeatable): gesture lexicons or symbol tables layered over the bundled lexicon."""
    parser.add_argument("--lexicon", action="append", default=[], metavar="FILE",
                        help="a gesture lexicon (<lexicon> or the published <gestures>) or symbol table (<hns>) whose "
                        "functions and names utterances may use; repeatable, later files win")  # fmt: skip


def lexicon_of(args: argparse.Namespace) -> GestureLexicon | None:
    """The lexicon the command's ``--lexicon`` files make (None: the bundled one); raises SpecError."""
    return load_lexicons(args.lexicon) if args.lexicon else None


def make_agent(args: argparse.Namespace) -> Agent:
    return Agent(avatar=args.avatar, tts=args.tts, fps=args.fps, voice=args.voice, rate=args.rate, lexicon=lexicon_of(args))


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "render",
        help="perform utterances offline and save WAV, BVH, timeline JSON and the avatar page",
        description="Perform each utterance offline and write NAME.wav, NAME.bvh, NAME.timeline.json, "
        "NAME.html and NAME.glb (the avatar with its animation) into the output folder. Files appear only when complete.",
    )
    parser.add_argument("files", nargs="+", metavar="FILE", help="MURML utterance files")
    parser.add_argument("-o", "--output", required=True, metavar="DIR", help="output folder (created if missing)")
    parser.add_argument("--no-glb", dest="glb", action="store_false", help="do not write NAME.glb")
    add_agent_options(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    try:
        agent = make_agent(args)
    except (AvatarError, SpeechError, SpecError) as error:
        print(f"mura render: {error}", file=sys.stderr)
        return 2
    status = 0
    for path in tqdm(args.files, desc="rendering", unit="utterance", disable=len(args.files) < 2, file=sys.stderr):
        status |= render_one(agent, Path(path), Path(args.output), glb=args.glb)
    return status


def render_one(agent: Agent, path: Path, output: Path, glb: bool = True) -> int:
    """Render one file straight to disk (memory bounded for any length), with NAME.glb
    unless ``glb`` is false; prints what was written or the one-line reason, returns the
    exit status."""
    try:
        files = agent.render_files(path, output, glb=glb)
    except SpecError as error:
        print(str(error), file=sys.stderr)
        return 1
    except (PerformanceError, SpeechError, ValueError, OSError) as error:
        print(f"{path}: {error}", file=sys.stderr)
        return 1
    print(f"{path}: {files.duration:.2f} s -> {files.html}")
    for warning in summarize_warnings(files.warnings):  # each said once, with its subjects and count
        print(f"{path}: warning: {warning}", file=sys.stderr)
    return 0
