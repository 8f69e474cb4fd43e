"""``mura plot FILE -o DIR``: the seed's Fig. 5 (wrist paths and speed profiles) and Fig. 6
(incremental chunk processing) for an utterance, as PNG."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from agent.commands.options import describe_failure, limits_from, refuse
from agent.commands.render import add_agent_options
from agent.commands.table import SUMMARIES
from agent.export.names import OutputNameError, OutputPlan
from agent.export.staging import OutputFolderError, StagedRun
from agent.plots import plot_timeline, plot_wrist_paths
from agent.sources import read_utterance
from blackboard.clock import VirtualClock
from blackboard.scheduler import Scheduler, SchedulerConfig
from motor.arm.wrist_position import WristPositionLMP
from motor.body.avatar import load_avatar
from motor.body.conventions import AvatarError
from motor.control import MotorControl
from motor.program.gesture import MotorProgram
from mura.errors import SpecError
from mura.limits import LimitError
from tts import SpeechError, make_synthesizer
from tts.interruptible import CheckedSynthesizer


class _RecordingMotorControl(MotorControl):
    """The motor control, keeping every program the scheduler activates, for Fig. 5."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.programs: list[MotorProgram] = []

    def activate(self, program: MotorProgram) -> None:
        self.programs.append(program)
        super().activate(program)


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "plot",
        help=SUMMARIES["plot"],
        description="Perform the utterance offline and write NAME.wrist.png (per gesture and arm: the wrist path "
        "in 3D and its speed with the breakpoints, seed 004 Fig. 5) and NAME.timeline.png (chunks, their states, "
        "speech and gesture phases on one time axis, Fig. 6).",
    )
    parser.add_argument("file", metavar="FILE", help="MURML utterance file")
    parser.add_argument("-o", "--output", required=True, metavar="DIR", help="output folder (created if missing)")
    add_agent_options(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    try:
        limits = limits_from(args)
        fps = limits.check_fps(args.fps)
        config = SchedulerConfig(voice=args.voice, rate=limits.check_rate(args.rate), limits=limits)
        avatar = load_avatar(args.avatar)
        tts = CheckedSynthesizer(make_synthesizer(args.tts))
    except (AvatarError, SpeechError, LimitError) as error:
        return refuse("plot", error)
    try:
        utterance, name = read_utterance(args.file, limits)
        motor = _RecordingMotorControl(avatar, fps)
        scheduler = Scheduler(tts, motor, VirtualClock(), config)
        try:
            result = scheduler.run(utterance, name)
        finally:
            scheduler.close()
    except SpecError as error:
        print(str(error), file=sys.stderr)
        return 1
    except (SpeechError, ValueError) as error:
        print(f"{args.file}: {error}", file=sys.stderr)
        return 1
    except Exception as error:  # noqa: BLE001 - a one-line reason, never a traceback
        print(f"{args.file}: {describe_failure(error)}", file=sys.stderr)
        return 1
    output = Path(args.output)
    try:
        OutputPlan(output, [args.file]).claim(args.file, name, (".timeline.png", ".wrist.png"))
    except OutputNameError as error:
        return refuse("plot", f"{args.file}: {error}", 1)
    try:
        with StagedRun(output) as staged:
            plot_timeline(result.timeline.to_json(), staged.folder / f"{name}.timeline.png")
            wrist = result.motion is not None and any(_moves_a_wrist(p) for p in motor.programs)
            if wrist:
                plot_wrist_paths(avatar, result.motion, motor.programs, staged.folder / f"{name}.wrist.png")
            staged.commit()
    except OutputFolderError as error:
        return refuse("plot", error)
    except (OSError, ValueError) as error:
        return refuse("plot", f"{args.file}: cannot draw the plots: {error}", 1)
    print(f"{args.file}: {output / f'{name}.timeline.png'}")
    if wrist:
        print(f"{args.file}: {output / f'{name}.wrist.png'}")
    else:
        print(f"{args.file}: no gesture moves a wrist; no wrist plot", file=sys.stderr)
    if result.error is not None:
        print(f"{args.file}: chunk {result.failed_chunk + 1} failed: {result.error} (plotted up to it)", file=sys.stderr)
        return 1
    return 0


def _moves_a_wrist(program: MotorProgram) -> bool:
    return any(isinstance(lmp, WristPositionLMP) for lmp in program.lmps)
