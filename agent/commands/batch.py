"""``mura batch INPUT… -o DIR [--workers N] [--scheduler ADDRESS]``: render a corpus on Dask.

Inputs are SiGML collections (every sign an item) and MURML utterance files or folders of
them (every file an item). Items are rendered in parallel on a local cluster of processes
(all cores by default) or on a running Dask scheduler, each failing alone with its reason;
``DIR/manifest.json`` records every item and makes the run resumable (a rerun skips what is
done), ``DIR/report.json`` groups failures and warnings by kind, and ``DIR/index.html``
plays every rendered item (see :mod:`agent.batch.run`).
"""

from __future__ import annotations

import argparse
import sys

from agent.batch.items import read_corpus
from agent.batch.render import DEFAULT_TIME_LIMIT, RenderOptions
from agent.commands.options import add_lexicon_option, add_limit_option, limits_from
from agent.commands.table import SUMMARIES
from motor.body.avatar import load_avatar
from motor.body.conventions import DEFAULT_AVATAR, AvatarError
from mura.lexicon import load_lexicons
from mura.limits import LimitError


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "batch",
        help=SUMMARIES["batch"],
        description="Render every sign of SiGML collections and every MURML utterance of the files and folders given, "
        "in parallel on Dask, into DIR: per item BVH and a motion file for DIR/index.html (the corpus viewer), "
        "DIR/manifest.json (resumable: a rerun skips completed items) and DIR/report.json (failures and warnings by kind).",
    )
    parser.add_argument("inputs", nargs="+", metavar="INPUT", help="SiGML files, MURML files, or folders of them")
    parser.add_argument("-o", "--output", required=True, metavar="DIR", help="output folder (created if missing; reused to resume)")
    parser.add_argument("--workers", type=int, default=None, metavar="N", help="local worker processes (default: one per core)")
    parser.add_argument("--scheduler", default=None, metavar="ADDRESS",
                        help="a running Dask scheduler (tcp://host:8786) whose workers see DIR, instead of a local cluster")  # fmt: skip
    parser.add_argument("--gloss", action="append", default=[], metavar="NAME", help="only items with this gloss (wildcards * ? allowed); repeatable")
    parser.add_argument("--avatar", default=DEFAULT_AVATAR, help=f"avatar name or file (default: {DEFAULT_AVATAR})")
    parser.add_argument("--fps", type=float, default=None, help="frames per second (default: 25 for signs, 60 for utterances)")
    parser.add_argument("--tts", default="fake", choices=("fake", "espeak", "pyttsx3", "default"), help="speech backend of utterances (default: fake)")
    parser.add_argument("--pages", action="store_true", help="also write a stand-alone page NAME.html per item")
    parser.add_argument("--glb", action="store_true", help="also write NAME.glb (the avatar with its animation) per item")
    parser.add_argument("--time-limit", type=float, default=DEFAULT_TIME_LIMIT, metavar="SECONDS",
                        help=f"longest time one item may take (default: {DEFAULT_TIME_LIMIT:g})")  # fmt: skip
    parser.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar")
    add_lexicon_option(parser)
    add_limit_option(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    problem = _check_arguments(args)
    if problem is not None:
        print(f"mura batch: {problem}", file=sys.stderr)
        return 2
    options = RenderOptions(args.avatar, args.fps, args.glb, args.pages, args.tts, tuple(args.lexicon), args.time_limit, tuple(args.limit))
    corpus = read_corpus(args.inputs, args.gloss, options.input_limits())
    for source, reason in corpus.unreadable:
        print(f"{source}: cannot read: {reason}", file=sys.stderr)
    if not corpus.items:
        print("mura batch: no items to render" + (f" with gloss {', '.join(args.gloss)}" if args.gloss else ""), file=sys.stderr)
        return 1
    from agent.batch.run import run_batch  # Dask loads when a batch runs, not with every command (0.7 s)

    summary = run_batch(corpus, args.output, options, args.workers, args.scheduler, args.progress)
    print(
        f"{summary.items} item(s): {summary.skipped} already done, {summary.rendered} rendered, {summary.failed} failed "
        f"in {summary.seconds:.1f} s ({summary.items_per_second:.2f} items/s on {summary.workers} worker(s)) -> {args.output}"
    )
    if summary.failed:
        print(f"failures by kind: {args.output}/report.json", file=sys.stderr)
    return 0 if summary.failed == 0 and not corpus.unreadable else 1


def _check_arguments(args: argparse.Namespace) -> str | None:
    if args.workers is not None and args.workers < 1:
        return f"--workers must be at least 1, got {args.workers}"
    try:
        limits = limits_from(args)
        if args.fps is not None:
            limits.check_fps(args.fps)
    except LimitError as error:
        return str(error)
    if not args.time_limit > 0:
        return f"--time-limit must be positive, got {args.time_limit}"
    try:
        load_avatar(args.avatar)
        load_lexicons(args.lexicon)
    except (AvatarError, OSError, ValueError) as error:
        return str(error)
    return None
