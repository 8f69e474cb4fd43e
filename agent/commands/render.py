"""``mura render FILE... -o DIR``: perform utterances offline and save WAV, BVH, timeline and page.

Every file is rendered on its own: one that fails is reported with its reason and the
others go on; the exit status is 1 when any failed. Outputs are staged and moved into the
output folder when the run ends, so an interrupted run leaves the folder as it was. Two
inputs with the same name, or an output that would replace an input, are refused.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

from tqdm import tqdm

from agent.agent import Agent, PerformanceError
from agent.batch.report import summarize_warnings
from agent.commands.options import add_lexicon_option, add_limit_option, describe_failure, lexicon_of, limits_from, refuse
from agent.commands.table import SUMMARIES
from agent.export.names import OutputPlan
from agent.export.staging import OutputFolderError, StagedRun
from motor.body.conventions import DEFAULT_AVATAR, AvatarError
from mura.errors import SpecError
from mura.limits import LimitError
from tts import SpeechError


def add_agent_options(parser: argparse.ArgumentParser, default_tts: str = "fake") -> None:
    """The options every command that builds an :class:`Agent` shares (``--limit`` included)."""
    parser.add_argument("--tts", default=default_tts, choices=("fake", "espeak", "pyttsx3", "default"),
                        help=f"speech backend (default: {default_tts}; 'default' is espeak when available, else fake)")
    parser.add_argument("--avatar", default=DEFAULT_AVATAR,
                        help=f"avatar name (max, kim, {DEFAULT_AVATAR}), an avatar file, or your own .vrm/.glb/.gltf humanoid "
                        f"(default: {DEFAULT_AVATAR}, the skinned avatar built at set-up)")  # fmt: skip
    parser.add_argument("--fps", type=float, default=60.0, help="frames per second of the motion (default: 60)")
    parser.add_argument("--voice", default=None, help="voice of the speech backend")
    parser.add_argument("--rate", type=float, default=1.0, help="relative speaking rate (default: 1.0)")
    add_limit_option(parser)


def make_agent(args: argparse.Namespace) -> Agent:
    """The agent the options ask for (with the ``--lexicon`` files, when the command has
    them); raises AvatarError, SpeechError, LimitError or SpecError (a bad lexicon). A
    fallback (``--tts default`` without espeak-ng) is said in one line on stderr."""
    lexicon = lexicon_of(args)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        agent = Agent(avatar=args.avatar, tts=args.tts, fps=args.fps, voice=args.voice, rate=args.rate, limits=limits_from(args),
                      lexicon=lexicon)
    for warning in caught:
        print(f"mura {args.command}: {warning.message}", file=sys.stderr)
    return agent


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "render",
        help=SUMMARIES["render"],
        description="Perform each utterance offline and write NAME.wav, NAME.bvh, NAME.timeline.json, "
        "NAME.html and NAME.glb (the avatar with its animation) into the output folder. Files appear only when "
        "the run ends; an interrupted run leaves the folder as it was. A file that fails is reported and the others go on.",
    )
    parser.add_argument("files", nargs="+", metavar="FILE", help="MURML utterance files or BML 1.0 blocks (.bml)")
    parser.add_argument("-o", "--output", required=True, metavar="DIR", help="output folder (created if missing)")
    parser.add_argument("--no-glb", dest="glb", action="store_false", help="do not write NAME.glb")
    add_agent_options(parser)
    add_lexicon_option(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    try:
        agent = make_agent(args)
    except (AvatarError, SpeechError, LimitError, SpecError) as error:
        return refuse("render", error)
    output = Path(args.output)
    plan = OutputPlan(output, args.files)
    try:
        with StagedRun(output) as staged, tqdm(args.files, desc="rendering", unit="utterance",
                                                 disable=len(args.files) < 2, file=sys.stderr) as progress:
            failed = 0
            for path in progress:
                failed += render_one(agent, Path(path), staged.folder, output, plan, glb=args.glb) != 0
            staged.commit()
    except OutputFolderError as error:
        return refuse("render", error)
    if len(args.files) > 1:
        print(f"rendered {len(args.files) - failed} of {len(args.files)} utterances"
              + (f"; {failed} failed" if failed else ""), file=sys.stderr)
    return 1 if failed else 0


def render_one(agent: Agent, path: Path, folder: Path, output: Path, plan: OutputPlan | None = None, glb: bool = True) -> int:
    """Render one file straight to disk into ``folder`` (memory bounded for any length;
    ``output`` is where its files end up), with NAME.glb unless ``glb`` is false; prints
    what was written or the one-line reason, returns the exit status. Nothing but a
    ``KeyboardInterrupt`` escapes."""
    try:
        if plan is not None:
            plan.claim(str(path), path.stem)
        files = agent.render_files(path, folder, glb=glb)
    except SpecError as error:
        print(str(error), file=sys.stderr)
        return 1
    except (PerformanceError, SpeechError, ValueError, OSError) as error:
        print(f"{path}: {error}", file=sys.stderr)
        return 1
    except Exception as error:  # noqa: BLE001 - one failing item never stops the batch
        print(f"{path}: {describe_failure(error)}", file=sys.stderr)
        return 1
    print(f"{path}: {files.duration:.2f} s -> {output / files.html.name}")
    for warning in summarize_warnings(files.warnings):  # each said once, with its subjects and count
        located = warning.startswith(f"{path}:")  # a reader's warning names its own place
        print(warning if located else f"{path}: warning: {warning}", file=sys.stderr)
    return 0
