"""``mura say TEXT``: speak a sentence and show its phoneme, word and mark timings."""

from __future__ import annotations

import argparse
import re
import sys
import warnings
from pathlib import Path

from agent.commands.options import add_limit_option, limits_from, refuse
from agent.commands.table import SUMMARIES
from agent.export.staging import staged_file
from mura.limits import LimitError
from tts import (
    BACKENDS,
    PlaybackUnavailable,
    SpeechError,
    SpeechRequest,
    SpeechTiming,
    TextMark,
    make_synthesizer,
    play,
    write_wav,
)

_NOTATION = re.compile(r"\[([^\[\]]*)\]|\*([^*]+)\*")

_EPILOG = """text notation:
  [name]    a time tag at that point, between words (an XML name: t1, stroke, ...)
  *words*   emphasis on the words inside the stars (the gesture's affiliate)
example:
  mura say "I saw [t1]*this* big [t2]fish." --timings"""


def parse_marked_text(text: str) -> tuple[str, tuple[TextMark, ...], tuple[tuple[int, int], ...]]:
    """Plain text, time tags and emphasis spans from the CLI notation ``[t1]`` and ``*word*``."""
    plain: list[str] = []
    marks: list[TextMark] = []
    emphasis: list[tuple[int, int]] = []
    length = 0
    cursor = 0
    for match in _NOTATION.finditer(text):
        plain.append(text[cursor : match.start()])
        length += match.start() - cursor
        cursor = match.end()
        if match.group(2) is None:
            marks.append(TextMark(match.group(1), length))
            continue
        emphasis.append((length, length + len(match.group(2))))
        plain.append(match.group(2))
        length += len(match.group(2))
    plain.append(text[cursor:])
    return "".join(plain), tuple(marks), tuple(emphasis)


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "say",
        help=SUMMARIES["say"],
        description="Synthesize TEXT, print its phoneme/word/mark timings, and write or play the audio.",
        epilog=_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("text", metavar="TEXT", help="what to say; [t1] places a time tag, *word* emphasizes")
    parser.add_argument("--tts", choices=[*sorted(BACKENDS), "default"], default="default",
                        help="speech backend (default: espeak when it can speak here, else fake)")
    parser.add_argument("-o", "--output", metavar="OUT.wav", help="write the audio to this WAV file")
    parser.add_argument("--timings", action="store_true", help="print the phoneme, word and mark table")
    parser.add_argument("--play", action="store_true", help="play the audio on the default sound device")
    parser.add_argument("--voice", metavar="V", help="voice name of the backend (espeak: en, en-us, de, ...)")
    parser.add_argument("--rate", metavar="R", type=float, default=1.0, help="relative speaking rate (default 1.0)")
    parser.add_argument("--not-final", dest="final", action="store_false", help="another chunk follows: no final fall")
    add_limit_option(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    text, marks, emphasis = parse_marked_text(args.text)
    try:
        limits = limits_from(args)
        limits.check_chunk_text(text, "the text")
        rate = limits.check_rate(args.rate)
    except LimitError as error:
        return refuse("say", error)
    if args.output and Path(args.output).is_dir():
        return refuse("say", f"-o {args.output}: is a folder; give the WAV file's name")
    want_audio = bool(args.output or args.play)
    request = SpeechRequest(text, marks, emphasis, args.final, args.voice, rate, want_audio)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            synthesizer = make_synthesizer(args.tts)
        for warning in caught:
            print(f"mura say: {warning.message}", file=sys.stderr)
        timing = synthesizer.synthesize(request)
    except SpeechError as error:
        print(f"mura say: {error}", file=sys.stderr)
        return 2
    print(f"{timing.backend}: {len(timing.words)} words, {timing.duration:.3f} s"
          + (" (approximate timings)" if timing.approximate else ""))
    if args.timings:
        print(format_timings(timing))
    if args.output:
        try:
            with staged_file(args.output) as temporary:
                write_wav(temporary, timing.audio, timing.sample_rate)
        except OSError as error:
            return refuse("say", f"cannot write {args.output}: {error.strerror or error}", 1)
        print(f"wrote {args.output}")
    if args.play:
        try:
            play(timing.audio, timing.sample_rate)
        except PlaybackUnavailable as error:
            print(f"mura say: {error}", file=sys.stderr)
            return 1
    return 0


def format_timings(timing: SpeechTiming) -> str:
    """The phoneme, word and mark table, times in seconds."""
    lines = ["kind     start    end      what"]
    lines += [f"phoneme  {p.start:7.3f}  {p.end:7.3f}  {p.symbol}" for p in timing.phonemes]
    lines += [f"word     {w.start:7.3f}  {w.end:7.3f}  {w.text} [{w.char_start}:{w.char_end}]" for w in timing.words]
    lines += [f"mark     {t:7.3f}           {name}" for name, t in sorted(timing.marks.items(), key=lambda kv: kv[1])]
    return "\n".join(lines)
