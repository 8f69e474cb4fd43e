"""Peak memory of rendering: a callable run in a fresh interpreter, its peak RSS reported.

Memory is measured in a subprocess so that nothing the benchmark itself holds counts, and
so that the peak belongs to one job only. The peak is the child's ``VmHWM`` from
``/proc/self/status`` (its own address space's high-water mark); ``ru_maxrss`` is the
fallback elsewhere, though on Linux it also remembers the resident size of the parent
that forked the child, before ``exec``. The callable is named ``"module:function"`` and takes string arguments;
the child prints one JSON line with its peak RSS, the run time and the callable's result.

The one-hour case: :func:`long_utterance` builds an utterance of about an hour of speech
by repeating the seed's Fig. 2 utterance (two chunks, a deictic and an iconic gesture)
with fresh time tags and ids, each repetition its own pair of chunks.

What is measured is the streaming render (``Agent.render_files`` with ``NAME.glb``, what
``mura render`` runs) at a short and a long length (60 s and 600 s; ``--quick``: 30 s and 120 s) and, in
the full run, at one hour. Memory is *flat* when the peak grows by less than
:data:`FLAT_MB_PER_HOUR` per hour of speech between the two lengths: what remains is the
timeline (words, phonemes, chunk states), while accumulating the frames and the audio
would add about 530 MB per hour at 60 fps and 22,050 Hz. The full run also renders the
long length through ``Agent.render`` (everything in memory) for comparison.
"""

from __future__ import annotations

import copy
import json
import math
import resource
import subprocess
import sys
import time
from importlib import import_module
from pathlib import Path

from lxml import etree

from bench.machine import REPO_ROOT

FIG2 = REPO_ROOT / "specs" / "utterances" / "fig2_take_this_bar.xml"
#: Seconds of performance one repetition of Fig. 2 adds with the fake speech when
#: repetitions follow each other (measured: 12 repetitions performed in 46.6 s).
FIG2_SECONDS = 3.9
#: The utterance length the memory target is stated for, and the one ``--quick`` uses.
HOUR_SECONDS = 3600.0
QUICK_SECONDS = 30.0
#: The (short, long) lengths whose peaks tell whether memory is flat, seconds.
FLAT_SECONDS = (60.0, 600.0)
QUICK_FLAT_SECONDS = (30.0, 120.0)
#: Largest growth of the peak per hour of speech still called flat, MB.
FLAT_MB_PER_HOUR = 100.0
_MARKER = "bench-memory-result:"


def _long_job_limits():
    """Limits raised for the hour-long renders (the defaults stop at 10 minutes)."""
    from mura.limits import Limits

    return Limits(max_duration=2 * HOUR_SECONDS, max_frames=int(2 * HOUR_SECONDS * 60))


class MeasurementError(RuntimeError):
    """The measured callable failed; the message carries the child's last error line."""


def peak_rss(target: str, *args: str, timeout: float = 3600.0) -> dict[str, object]:
    """Run ``target`` (``"module:function"``) with ``args`` in a fresh Python and return
    ``{"peak_rss_mb", "seconds", "result"}``; MeasurementError if it fails or times out."""
    module, _, function = target.partition(":")
    if not module or not function:
        raise ValueError(f"target must be 'module:function', got {target!r}")
    try:
        done = subprocess.run(
            [sys.executable, "-m", "bench.memory", target, *args],
            cwd=REPO_ROOT, capture_output=True, text=True, timeout=timeout, check=False,
        )  # fmt: skip
    except subprocess.TimeoutExpired:
        raise MeasurementError(f"{target}: still running after {timeout:.0f} s") from None
    lines = [line for line in done.stdout.splitlines() if line.startswith(_MARKER)]
    if done.returncode != 0 or not lines:
        last = (done.stderr.strip().splitlines() or [f"exit status {done.returncode}, no output"])[-1]
        raise MeasurementError(f"{target}: {last}")
    return json.loads(lines[-1][len(_MARKER) :])


def _run_in_this_process(target: str, args: list[str]) -> None:
    module, _, function = target.partition(":")
    callable_ = getattr(import_module(module), function)
    started = time.perf_counter()
    result = callable_(*args)
    seconds = time.perf_counter() - started
    print(_MARKER + json.dumps({"peak_rss_mb": _peak_kb() / 1024.0, "seconds": seconds, "result": result}))


def _peak_kb() -> float:
    """This process's peak resident set size, kilobytes."""
    try:
        for line in Path("/proc/self/status").read_text(encoding="ascii").splitlines():
            if line.startswith("VmHWM:"):
                return float(line.split()[1])
    except OSError:
        pass
    return float(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)


def long_utterance(seconds: float, source: Path = FIG2) -> str:
    """An utterance XML of about ``seconds`` of speech and gesture: the ``source``
    utterance repeated with renamed time tags and behaviour ids, a chunk border between
    repetitions."""
    if not seconds > 0:
        raise ValueError(f"seconds must be positive, got {seconds}")
    tree = etree.parse(str(source), etree.XMLParser(resolve_entities=False, no_network=True))
    utterance = tree.getroot().find("utterance")
    specification = utterance.find("specification")
    behaviors = utterance.findall("behaviorspec")
    repeats = max(1, math.ceil(seconds / FIG2_SECONDS))
    new_specification = etree.Element("specification")
    new_specification.text = specification.text
    new_behaviors = []
    for k in range(repeats):
        part = copy.deepcopy(specification)
        for tag in part.iter("time"):
            tag.set("id", f"{tag.get('id')}_{k}")
        times = part.findall("time")
        if k < repeats - 1 and times:
            times[-1].set("chunkborder", "true")
        if k > 0 and part.text:
            previous = new_specification[-1] if len(new_specification) else None
            if previous is not None:
                previous.tail = (previous.tail or "") + " " + part.text.strip() + " "
        new_specification.extend(list(part))
        for behavior in behaviors:
            clone = copy.deepcopy(behavior)
            clone.set("id", f"{behavior.get('id')}_{k}")
            for affiliate in clone.iter("affiliate"):
                for end in ("onset", "end"):
                    affiliate.set(end, f"{affiliate.get(end)}_{k}")
            new_behaviors.append(clone)
    utterance.replace(specification, new_specification)
    for behavior in behaviors:
        utterance.remove(behavior)
    utterance.extend(new_behaviors)
    return etree.tostring(tree.getroot(), encoding="unicode")


def render_with_agent(seconds: str) -> dict[str, float]:
    """Render a :func:`long_utterance` of ``seconds`` with ``agent.Agent().render`` (the
    ``max`` avatar, fake speech, 60 fps); returns the performed duration and frame count."""
    from agent.agent import Agent

    performance = Agent(limits=_long_job_limits()).render(long_utterance(float(seconds)), name="long")
    return {"duration_s": performance.duration, "frames": performance.motion.frame_count}


def render_streaming(seconds: str) -> dict[str, float]:
    """Render a :func:`long_utterance` of ``seconds`` with ``Agent().render_files`` (the
    streaming path ``mura render`` takes, ``NAME.glb`` included as it writes it unless
    ``--no-glb``) into a temporary folder; returns the performed duration and the size of
    the files written, MB."""
    import tempfile

    from agent.agent import Agent

    with tempfile.TemporaryDirectory(prefix="mura-bench-memory-") as folder:
        files = Agent(limits=_long_job_limits()).render_files(long_utterance(float(seconds)), folder, name="long", glb=True)
        size = sum(path.stat().st_size for path in (files.wav, files.bvh, files.timeline, files.html, files.glb) if path is not None)
    return {"duration_s": files.duration, "files_mb": size / 2**20}


def run(quick: bool) -> dict:
    """Peak RSS of the interpreter alone and of the streaming render at a short and a long
    length (and one hour unless ``quick``), each in its own process, with the verdict on
    flatness; the full run adds the in-memory render of the long length."""
    figures: dict[str, object] = {"baseline_peak_rss_mb": peak_rss("bench.memory:idle")["peak_rss_mb"]}
    short, long = QUICK_FLAT_SECONDS if quick else FLAT_SECONDS
    lengths = (short, long) if quick else (short, long, HOUR_SECONDS)
    streaming = {f"{seconds:.0f}s": _measure("bench.memory:render_streaming", seconds) for seconds in lengths}
    figures["streaming"] = streaming
    figures["flat"] = flatness(streaming[f"{short:.0f}s"], streaming[f"{long:.0f}s"])
    if quick:
        figures["one_hour_peak_rss_mb"] = {"status": "not measured", "reason": f"--quick renders {long:.0f} s at most"}
        return figures
    figures["one_hour_peak_rss_mb"] = streaming[f"{HOUR_SECONDS:.0f}s"]["peak_rss_mb"]
    figures["in_memory_render"] = {f"{long:.0f}s": _measure("bench.memory:render_with_agent", long)}
    return figures


def flatness(short: dict, long: dict) -> dict[str, object]:
    """Growth of the peak between two measured renders, per hour of performed speech."""
    growth = long["peak_rss_mb"] - short["peak_rss_mb"]
    hours = (long["duration_s"] - short["duration_s"]) / HOUR_SECONDS
    per_hour = growth / hours
    return {
        "growth_mb": growth,
        "ratio": long["peak_rss_mb"] / short["peak_rss_mb"],
        "growth_mb_per_hour": per_hour,
        "flat": per_hour < FLAT_MB_PER_HOUR,
    }


def _measure(target: str, seconds: float) -> dict[str, object]:
    measured = peak_rss(target, str(seconds))
    return {"requested_s": seconds, **measured["result"], "peak_rss_mb": measured["peak_rss_mb"], "seconds": measured["seconds"]}


def idle() -> None:
    """Nothing: the interpreter's own peak, the baseline of every measurement."""


if __name__ == "__main__":
    _run_in_this_process(sys.argv[1], sys.argv[2:])
