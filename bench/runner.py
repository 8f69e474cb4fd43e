"""The benchmark harness: run every bench module, record the machine, judge the targets.

Each bench module exposes ``run(quick: bool) -> dict``. :func:`run_bench` imports and runs
them one by one; a module that cannot be imported or fails is recorded as
``{"error": "<Type>: <message>"}`` and the rest go on. The result carries the machine
(:func:`bench.machine.machine_info`), the command and the figures of every module.

:data:`TARGETS` are the rows of the design's "Targets" table, each with where its figure
is found in the results; :func:`judge` says for each whether it is met, missed or not
measured. :func:`format_table` prints them for the terminal and :func:`readme_section`
writes them as markdown between ``<!-- bench:start -->`` and ``<!-- bench:end -->``.
"""

from __future__ import annotations

import time
import traceback
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from importlib import import_module
from pathlib import Path

from bench.machine import machine_info

#: The bench modules, in the order they run.
MODULES: tuple[str, ...] = (
    "bench.tts_speed",
    "bench.trajectory_speed",
    "bench.body_speed",
    "bench.motion_speed",
    "bench.scheduler_speed",
    "bench.signing_speed",
    "bench.corpus_throughput",
    "bench.motion_quality",
    "bench.head_face",
    "bench.motion_audit",
    "bench.memory",
    "bench.verbs",
)

#: Keys of a module's figures too detailed for the terminal table (they stay in --json).
DETAIL_KEYS = frozenset({"utterances", "corpus"})

README_START = "<!-- bench:start -->"
README_END = "<!-- bench:end -->"


@dataclass(frozen=True)
class Target:
    """A row of the targets table: the figure at ``path`` in the results (module name,
    then keys) compared with ``bound`` by ``kind``: ``"min"`` (≥), ``"max"`` (≤),
    ``"below"`` (<) or ``"within"`` (``|figure − bound| ≤ tolerance``)."""

    what: str
    target: str
    path: tuple[str, ...]
    kind: str
    bound: float
    unit: str = ""
    tolerance: float = 0.0

    def met(self, figure: float) -> bool:
        if self.kind == "min":
            return figure >= self.bound
        if self.kind == "max":
            return figure <= self.bound
        if self.kind == "below":
            return figure < self.bound
        if self.kind == "within":
            return abs(figure - self.bound) <= self.tolerance
        raise ValueError(f"target {self.what!r}: unknown kind {self.kind!r}")


TARGETS: tuple[Target, ...] = (
    Target("motion synthesis, full skeleton, 60 fps", "≥ 150,000 frames/s", ("bench.motion_speed", "frames_per_s_60fps"), "min", 150_000, "frames/s"),
    Target("motion synthesis, streamed 0.1 s windows, 60 fps", "≥ 50,000 frames/s", ("bench.motion_speed", "streamed_frames_per_s_60fps"), "min", 50_000, "frames/s"),
    Target("sign synthesis, real SiGML corpora", "≥ 150,000 frames/s", ("bench.signing_speed", "synthesis_frames_per_second"), "min", 150_000, "frames/s"),
    Target("sign planning", "≤ 1 ms per sign", ("bench.signing_speed", "planning_ms_per_sign"), "max", 1.0, "ms"),
    Target("synthesis cost / bare forward kinematics, 60 fps", "≤ 10", ("bench.motion_speed", "synthesis_over_forward_kinematics_60fps"), "max", 10.0),
    Target("synthesis cost / bare compose and write, gestures 60 fps", "≤ 10", ("bench.motion_speed", "synthesis_over_bare_60fps"), "max", 10.0),
    Target("synthesis cost / bare compose and write, signs", "≤ 10", ("bench.signing_speed", "synthesis_over_bare"), "max", 10.0),
    Target("planning latency per chunk (median), fake speech", "≤ 20 ms", ("bench.scheduler_speed", "fake", "planning_ms_median"), "max", 20.0, "ms"),
    Target("planning latency per chunk (median), espeak", "≤ 100 ms", ("bench.scheduler_speed", "espeak", "planning_ms_median"), "max", 100.0, "ms"),
    Target("time to first frame", "≤ 50 ms", ("bench.scheduler_speed", "time_to_first_frame_ms"), "max", 50.0, "ms"),
    Target("stroke onset error (max, from the motion)", "≤ 1 frame at 60 fps", ("bench.motion_quality", "stroke_onset_max_error_frames"), "max", 1.0, "frames"),
    Target("power-law exponent, planned ellipse", "1/3 ± 0.05", ("bench.motion_quality", "power_law_exponent_ellipse"), "within", 1 / 3, tolerance=0.05),
    Target("power-law exponent, rendered curved strokes", "1/3 ± 0.05", ("bench.motion_quality", "power_law_exponent_rendered_median"), "within", 1 / 3, tolerance=0.05),
    Target("joint-limit violations", "0", ("bench.motion_quality", "joint_limit_violations"), "max", 0.0, "frames"),
    Target("torso penetrations", "0", ("bench.motion_quality", "torso_penetrations"), "max", 0.0, "frames"),
    Target("NaN in motions", "0", ("bench.motion_quality", "nan"), "max", 0.0),
    # The independent audit of rendered motion (bench/motion_audit): examples, published MURML, 200 signs.
    Target("motion audit: elbow pops (events)", "0", ("bench.motion_audit", "elbow_pop_events"), "max", 0.0),
    Target("motion audit: wrist speed steps (events)", "0", ("bench.motion_audit", "wrist_step_events"), "max", 0.0),
    Target("motion audit: largest joint rotation per frame", "≤ 25°", ("bench.motion_audit", "largest_joint_turn_deg"), "max", 25.0, "°"),
    Target("motion audit: deepest arm segment in the torso", "≤ 1 cm", ("bench.motion_audit", "torso_penetration_cm"), "max", 1.0, "cm"),
    Target("motion audit: deepest forearm in forearm", "≤ 1 cm", ("bench.motion_audit", "forearm_penetration_cm"), "max", 1.0, "cm"),
    Target("motion audit: deepest hand in hand (palm thickness)", "≤ 1 cm", ("bench.motion_audit", "hand_penetration_cm"), "max", 1.0, "cm"),
    Target("motion audit: peak wrist speed", "≤ 3 m/s", ("bench.motion_audit", "peak_wrist_speed"), "max", 3.0, "m/s"),
    Target("motion audit: power-law β, rendered curved strokes (median)", "1/3 ± 0.05", ("bench.motion_audit", "power_law_beta_median"), "within", 1 / 3, tolerance=0.05),
    Target("motion audit: jerk / minimum jerk, strokes (median)", "≤ 1.5", ("bench.motion_audit", "jerk_ratio_stroke_median"), "max", 1.5),
    Target("motion audit: jerk / minimum jerk, starts from rest (median)", "≤ 1.5", ("bench.motion_audit", "jerk_ratio_start_median"), "max", 1.5),
    Target("motion audit: strokes with a visible onset landmark", "100 %", ("bench.motion_audit", "stroke_landmark_percent"), "min", 100.0, "%"),
    Target("motion audit: stroke onset lead vs acoustic onset (max error, espeak)", "200 ms ± 1 frame", ("bench.motion_audit", "stroke_onset_error_max_frames"), "max", 1.0, "frames"),
    Target("memory for one hour of speech", "< 500 MB", ("bench.memory", "one_hour_peak_rss_mb"), "below", 500.0, "MB"),
    Target("real SiGML signs rendered (of valid signs)", "≥ 99.5%", ("bench.corpus_throughput", "rendered_percent_of_valid"), "min", 99.5, "%"),
    Target("mouth opening vs audio energy, espeak (lowest example)", "r ≥ 0.5", ("bench.head_face", "lipsync_r_min"), "min", 0.5),
    Target("gaze direction error at the stroke (largest)", "< 5°", ("bench.head_face", "gaze_error_max_deg"), "below", 5.0, "°"),
)


def run_module(name: str, quick: bool) -> dict:
    """Import and run one bench module; an error entry instead of raising."""
    started = time.perf_counter()
    try:
        module = import_module(name)
        figures = module.run(quick)
    except Exception as error:  # a broken module is reported, never fatal to the bench
        frame = traceback.extract_tb(error.__traceback__)[-1] if error.__traceback__ else None
        where = f" ({Path(frame.filename).name}:{frame.lineno})" if frame else ""
        return {"error": f"{type(error).__name__}: {error}{where}", "seconds": time.perf_counter() - started}
    if not isinstance(figures, dict):
        return {"error": f"run() returned {type(figures).__name__}, expected dict", "seconds": time.perf_counter() - started}
    return {**figures, "seconds": time.perf_counter() - started}


def run_bench(
    modules: Sequence[str] = MODULES,
    quick: bool = False,
    command: str = "mura bench",
    progress: Callable[[str], None] | None = None,
) -> dict:
    """Run ``modules`` in order; the machine, the command and every module's figures."""
    results: dict[str, dict] = {}
    for name in modules:
        if progress is not None:
            progress(name)
        results[name] = run_module(name, quick)
    return {"command": command, "quick": quick, "machine": machine_info(), "results": results}


def lookup(results: Mapping, path: Sequence[str]) -> float | None:
    """The number at ``path`` in the results, None if absent or not a number."""
    value: object = results
    for key in path:
        if not isinstance(value, Mapping) or key not in value:
            return None
        value = value[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value)


def judge(results: Mapping, targets: Sequence[Target] = TARGETS) -> list[dict]:
    """For each target: its figure (None if not measured) and ``"met"``/``"missed"``/
    ``"not measured"``, with why when not measured."""
    rows = []
    for target in targets:
        figure = lookup(results, target.path)
        module = results.get(target.path[0])
        if figure is not None:
            status, note = ("met" if target.met(figure) else "missed"), ""
        elif module is None:
            status, note = "not measured", f"{target.path[0]} not run"
        elif "error" in module:
            status, note = "not measured", f"{target.path[0]} failed: {module['error']}"
        else:
            status, note = "not measured", _missing(module, target.path[1:])
        rows.append({"what": target.what, "target": target.target, "figure": figure, "unit": target.unit, "status": status, "note": note})
    return rows


def _missing(module: Mapping, keys: Sequence[str]) -> str:
    value: object = module
    for key in keys:
        if not isinstance(value, Mapping) or key not in value:
            return f"no figure '{key}'"
        value = value[key]
    if isinstance(value, Mapping) and "status" in value:
        return str(value.get("reason", value["status"]))
    return f"'{keys[-1]}' is {value!r}"


def format_figure(figure: float | None, unit: str = "") -> str:
    """A figure with a sensible number of digits and its unit."""
    if figure is None:
        return "—"
    if figure != 0 and abs(figure) >= 1000:
        text = f"{figure:,.0f}"
    elif figure == int(figure) and abs(figure) < 1000:
        text = f"{figure:.0f}"
    else:
        text = f"{figure:.3g}"
    return f"{text} {unit}".strip()


def format_table(report: Mapping, targets: Sequence[Target] = TARGETS) -> str:
    """The terminal view: machine, targets with figures, and every module's figures."""
    machine = report["machine"]
    lines = [f"machine: {machine['cpu']}, {machine['cores']} cores, Python {machine['python']}, numpy {machine['numpy']}, "
             f"scipy {machine['scipy']}, lxml {machine['lxml']}, espeak-ng {machine['espeak_ng']}, commit {machine['git_commit']}", ""]  # fmt: skip
    rows = judge(report["results"], targets)
    width = max(len(r["what"]) for r in rows)
    for row in rows:
        status = row["status"] + (f" ({row['note']})" if row["note"] else "")
        lines.append(f"{row['what']:<{width}}  {format_figure(row['figure'], row['unit']):>18}  target {row['target']:<20} {status}")
    lines.append("")
    for name, figures in report["results"].items():
        lines.append(f"{name}:")
        lines.extend(f"  {key}: {_short(value)}" for key, value in figures.items() if key not in DETAIL_KEYS)
    return "\n".join(lines)


def _short(value: object) -> str:
    if isinstance(value, float):
        return format_figure(value)
    if isinstance(value, Mapping):
        return ", ".join(f"{k}={_short(v)}" for k, v in value.items())
    return str(value)


def readme_section(report: Mapping, targets: Sequence[Target] = TARGETS) -> str:
    """Markdown: the targets with the latest figures, the command and the machine."""
    machine = report["machine"]
    lines = [
        "## Benchmarks",
        "",
        f"Measured with `{report['command']}` on {machine['cpu']} ({machine['cores']} cores), Python {machine['python']}, "
        f"numpy {machine['numpy']}, scipy {machine['scipy']}, espeak-ng {machine['espeak_ng']}, commit `{machine['git_commit'][:12]}`."
        + (" Quick run: fewer and shorter cases." if report.get("quick") else ""),
        "",
        "| what | figure | target | met |",
        "|---|---|---|---|",
    ]
    for row in judge(report["results"], targets):
        met = {"met": "yes", "missed": "**no**"}.get(row["status"], f"not measured: {row['note']}")
        lines.append(f"| {row['what']} | {format_figure(row['figure'], row['unit'])} | {row['target']} | {met.replace('|', '/')} |")
    return "\n".join(lines) + "\n"


def update_readme(path: Path, section: str) -> None:
    """Replace what lies between the bench markers in ``path`` with ``section``;
    ValueError naming the file if the markers are missing or out of order."""
    text = path.read_text(encoding="utf-8")
    start, end = text.find(README_START), text.find(README_END)
    if start < 0 or end < 0 or end < start:
        raise ValueError(f"{path}: expected the markers {README_START} and {README_END}, in that order")
    path.write_text(text[: start + len(README_START)] + "\n" + section + text[end:], encoding="utf-8")
