"""Figures over many renders: totals, medians and the worst offenders, as JSON and as a table.

:func:`summarize` turns the audits of many files (and the files that could not be
audited) into one JSON-ready dictionary whose top-level numbers are the figures the
targets judge (:data:`FIGURES`); every figure has its worst case with file, time and
what beside it. :func:`format_summary` prints them as a table for the terminal, with the
worst offenders.
"""

from __future__ import annotations

import statistics
from collections.abc import Sequence
from dataclasses import dataclass

from bench.motion_audit.audit import FileAudit
from bench.motion_audit.continuity import TURN_LIMIT
from bench.motion_audit.findings import Failure, Worst, worst_of
from bench.motion_audit.penetration import DEPTH_LIMIT
from bench.motion_audit.stroke_onset import TARGET_LEAD

BETA_TARGET = 1.0 / 3.0
BETA_TOLERANCE = 0.05
JERK_TARGET = 1.5
SPEED_TARGET = 3.0
#: How many offenders the table lists per figure.
OFFENDERS = 3


@dataclass(frozen=True)
class Figure:
    """One row of the table: the key of its figure in the summary, a label, the target as
    text, the unit and the key of its worst case."""

    key: str
    label: str
    target: str
    unit: str
    worst: str


FIGURES: tuple[Figure, ...] = (
    Figure("elbow_pop_events", "elbow pops (events; frames)", "0", "", "elbow_pop_worst"),
    Figure("wrist_step_events", "wrist speed steps > 0.5 m/s (events; frames)", "0", "", "wrist_step_worst"),
    Figure("largest_joint_turn_deg", "largest joint rotation in one frame", f"≤ {TURN_LIMIT:.0f}°", "°", "joint_turn_worst"),
    Figure("torso_penetration_cm", "deepest arm segment in the torso", "≤ 1 cm", "cm", "torso_penetration_worst"),
    Figure("forearm_penetration_cm", "deepest forearm in forearm", "≤ 1 cm", "cm", "forearm_penetration_worst"),
    Figure("hand_penetration_cm", "deepest hand in hand (palm thickness)", "≤ 1 cm", "cm", "hand_penetration_worst"),
    Figure("peak_wrist_speed", "peak wrist speed", "≤ 3 m/s", "m/s", "peak_wrist_speed_worst"),
    Figure("peak_wrist_acceleration", "peak wrist acceleration", "—", "m/s²", "peak_wrist_acceleration_worst"),
    Figure("power_law_beta_median", "power-law β, curved strokes (median)", "1/3 ± 0.05", "", "power_law_worst"),
    Figure("jerk_ratio_stroke_median", "jerk / minimum jerk, strokes (median)", "≤ 1.5", "", "jerk_stroke_worst"),
    Figure("jerk_ratio_start_median", "jerk / minimum jerk, starts from rest (median)", "≤ 1.5", "", "jerk_start_worst"),
    Figure("twist_pinned_percent", "forearm twist pinned at its limit (gesture frames)", "—", "%", "twist_worst"),
    Figure("stroke_landmark_percent", "strokes with a visible onset landmark", "100 %", "%", "landmark_missing_example"),
    Figure("stroke_onset_error_max_frames", "stroke onset lead error (max) vs 200 ms", "≤ 1 frame", "frames", "stroke_onset_worst"),
)


def _json(worst: Worst | None) -> dict | None:
    return worst.as_json() if worst is not None else None


def _offenders(candidates: Sequence[Worst | None], badness=float) -> list[dict]:
    present = sorted((c for c in candidates if c is not None), key=lambda w: badness(w.value), reverse=True)
    return [worst.as_json() for worst in present[:OFFENDERS]]


def _median(values: Sequence[float]) -> float | None:
    return float(statistics.median(values)) if values else None


def _onsets(audits: Sequence[FileAudit]) -> dict:
    onsets = [onset for audit in audits for onset in audit.onsets]
    with_landmark = [onset for onset in onsets if onset.onset is not None]
    measured = [onset for onset in with_landmark if onset.lead is not None]
    errors = [abs(onset.lead - TARGET_LEAD) for onset in measured]
    worst_onset = max(measured, key=lambda onset: abs(onset.lead - TARGET_LEAD), default=None)
    missing = next((onset for onset in onsets if onset.onset is None), None)
    fps = audits[0].fps if audits else 60.0
    return {
        "strokes": len(onsets),
        "strokes_with_landmark": len(with_landmark),
        "stroke_landmark_percent": 100.0 * len(with_landmark) / len(onsets) if onsets else None,
        "landmarks_by_kind": {kind: sum(o.landmark == kind for o in with_landmark) for kind in ("arrival", "departure", "valley")},
        "strokes_measured_against_speech": len(measured),
        "stroke_lead_median_ms": 1000.0 * statistics.median(o.lead for o in measured) if measured else None,
        "stroke_onset_error_max_frames": fps * max(errors) if errors else None,
        "strokes_within_one_frame": sum(error <= 1.0 / fps + 1e-9 for error in errors),
        "stroke_onset_worst": (
            Worst(worst_onset.lead * 1000.0, worst_onset.onset, f"{worst_onset.behaviour} ({worst_onset.side}), lead in ms; word {worst_onset.acoustic.word!r}", worst_onset.file).as_json()
            if worst_onset
            else None
        ),
        "landmark_missing_example": (
            Worst(0.0, missing.planned, f"{missing.behaviour} ({missing.side}): no hold or valley within 0.2 s of the planned onset", missing.file).as_json()
            if missing
            else None
        ),
        "strokes_detail": [onset.as_json() for onset in onsets],
    }


def summarize(audits: Sequence[FileAudit], failures: Sequence[Failure] = ()) -> dict:
    """Totals, medians and worst cases over ``audits``; ``failures`` listed by name."""
    pops = [count for audit in audits for count in audit.elbow_pops.values()]
    steps = [count for audit in audits for count in audit.wrist_steps.values()]
    turns = [audit.joint_turns for audit in audits]
    groups = {group: [audit.penetrations[group] for audit in audits] for group in ("torso", "forearms", "hands")}
    fits = [fit for audit in audits for fit in audit.power_laws]
    betas = [fit.beta for fit in fits if fit.beta is not None]
    jerk_strokes = [w for audit in audits for w in audit.jerk_strokes]
    jerk_starts = [w for audit in audits for w in audit.jerk_starts]
    gesture = sum(t.gesture_frames for audit in audits for t in audit.twist.values())
    pinned = sum(t.pinned_frames for audit in audits for t in audit.twist.values())
    worst_fit = max((f for f in fits if f.beta is not None), key=lambda f: abs(f.beta - BETA_TARGET), default=None)

    def depth(group: str) -> float:
        worst = worst_of(p.worst for p in groups[group])
        return worst.value if worst else 0.0

    summary = {
        "files": len(audits),
        "frames": sum(audit.frames for audit in audits),
        "failed": [failure.as_json() for failure in failures],
        "elbow_pop_events": sum(c.events for c in pops),
        "elbow_pop_frames": sum(c.frames for c in pops),
        "files_with_elbow_pops": sum(any(c.events for c in audit.elbow_pops.values()) for audit in audits),
        "elbow_pop_worst": _json(worst_of(c.worst for c in pops)),
        "elbow_pop_offenders": _offenders([c.worst for c in pops]),
        "wrist_step_events": sum(c.events for c in steps),
        "wrist_step_frames": sum(c.frames for c in steps),
        "files_with_wrist_steps": sum(any(c.events for c in audit.wrist_steps.values()) for audit in audits),
        "wrist_step_worst": _json(worst_of(c.worst for c in steps)),
        "wrist_step_offenders": _offenders([c.worst for c in steps]),
        "largest_joint_turn_deg": max((t.largest.value for t in turns if t.largest), default=0.0),
        "frames_with_joint_turn_over_limit": sum(t.frames_over for t in turns),
        "files_with_joint_turn_over_limit": sum(t.frames_over > 0 for t in turns),
        "joint_turn_worst": _json(worst_of(t.largest for t in turns)),
        "joint_turn_offenders": _offenders([t.largest for t in turns]),
        "torso_penetration_cm": depth("torso"),
        "forearm_penetration_cm": depth("forearms"),
        "hand_penetration_cm": depth("hands"),
        "torso_penetration_worst": _json(worst_of(p.worst for p in groups["torso"])),
        "forearm_penetration_worst": _json(worst_of(p.worst for p in groups["forearms"])),
        "hand_penetration_worst": _json(worst_of(p.worst for p in groups["hands"])),
        "penetration_offenders": {group: _offenders([p.worst for p in found]) for group, found in groups.items()},
        "frames_penetrating_over_1cm": {group: sum(p.frames_over for p in found) for group, found in groups.items()},
        "files_penetrating_over_1cm": {group: sum(p.frames_over > 0 for p in found) for group, found in groups.items()},
        "peak_wrist_speed": max((a.peak_speed.value for a in audits), default=0.0),
        "peak_wrist_speed_worst": _json(worst_of(a.peak_speed for a in audits)),
        "files_over_speed_target": sum(a.peak_speed.value > SPEED_TARGET for a in audits),
        "peak_wrist_acceleration": max((a.peak_acceleration.value for a in audits), default=0.0),
        "peak_wrist_acceleration_worst": _json(worst_of(a.peak_acceleration for a in audits)),
        "curved_strokes": len(fits),
        "curved_strokes_fitted": len(betas),
        "power_law_beta_median": _median(betas),
        "power_law_beta_range": [min(betas), max(betas)] if betas else None,
        "curved_strokes_within_target": sum(abs(b - BETA_TARGET) <= BETA_TOLERANCE for b in betas),
        "power_law_worst": (
            {**Worst(worst_fit.beta, worst_fit.time, worst_fit.what, worst_fit.file).as_json(), "r_squared": worst_fit.r_squared} if worst_fit else None
        ),
        "power_law_strokes": [fit.as_json() for fit in fits],
        "jerk_strokes": len(jerk_strokes),
        "jerk_ratio_stroke_median": _median([w.value for w in jerk_strokes]),
        "jerk_ratio_stroke_max": max((w.value for w in jerk_strokes), default=None),
        "jerk_strokes_within_target": sum(w.value <= JERK_TARGET for w in jerk_strokes),
        "jerk_stroke_worst": _json(worst_of(jerk_strokes)),
        "jerk_starts_from_rest": len(jerk_starts),
        "jerk_ratio_start_median": _median([w.value for w in jerk_starts]),
        "jerk_ratio_start_max": max((w.value for w in jerk_starts), default=None),
        "jerk_starts_within_target": sum(w.value <= JERK_TARGET for w in jerk_starts),
        "jerk_start_worst": _json(worst_of(jerk_starts)),
        "twist_gesture_frames": gesture,
        "twist_pinned_frames": pinned,
        "twist_pinned_percent": 100.0 * pinned / gesture if gesture else 0.0,
        "twist_worst": _json(worst_of(t.worst for audit in audits for t in audit.twist.values())),
    }
    summary.update(_onsets(audits))
    return summary


def _figure_text(summary: dict, figure: Figure) -> str:
    value = summary.get(figure.key)
    if value is None:
        return "—"
    if figure.key == "elbow_pop_events":
        return f"{value}; {summary['elbow_pop_frames']}"
    if figure.key == "wrist_step_events":
        return f"{value}; {summary['wrist_step_frames']}"
    if figure.key == "stroke_landmark_percent":
        return f"{value:.0f} % ({summary['strokes_with_landmark']} of {summary['strokes']})"
    if figure.key == "power_law_beta_median":
        return f"{value:.3f} ({summary['curved_strokes_fitted']} strokes)"
    text = f"{value:.3g}" if isinstance(value, float) else str(value)
    return f"{text} {figure.unit}".strip()


def _where(worst: dict | None) -> str:
    if not worst:
        return ""
    return f"{worst['file']} @ {worst['time']:.2f} s: {worst['what']} ({worst['value']:.3g})"


def format_leads(summary: dict, limit: int = 60) -> str:
    """One line per stroke measured against speech: where its landmark is and its lead."""
    measured = [stroke for stroke in summary.get("strokes_detail", []) if stroke["lead"] is not None]
    lines = [
        f"    {s['file']} {s['behaviour']} ({s['side']}): {s['landmark']} at {s['onset']:.3f} s, "
        f"{s['affiliate_word']!r} at {s['acoustic_onset']:.3f} s, lead {1000 * s['lead']:.0f} ms"
        for s in measured[:limit]
    ]
    missing = [s for s in summary.get("strokes_detail", []) if s["onset"] is None]
    lines += [f"    {s['file']} {s['behaviour']} ({s['side']}): no landmark near {s['planned_onset']:.3f} s" for s in missing[:limit]]
    return "\n".join(["  strokes:", *lines]) if lines else ""


def format_summary(summary: dict, title: str = "motion audit") -> str:
    """The figures with their targets and where each is worst, then the worst offenders."""
    lines = [f"{title}: {summary['files']} renders, {summary['frames']} frames" + (f", {len(summary['failed'])} failed" if summary["failed"] else "")]
    rows = [(figure.label, _figure_text(summary, figure), figure.target, _where(summary.get(figure.worst))) for figure in FIGURES]
    widths = [max(len(row[k]) for row in rows) for k in range(3)]
    lines += [f"  {a:<{widths[0]}}  {b:>{widths[1]}}  target {c:<{widths[2]}}  {d}" for a, b, c, d in rows]
    for name, key in (("elbow pops", "elbow_pop_offenders"), ("wrist steps", "wrist_step_offenders"), ("joint turns", "joint_turn_offenders")):
        if summary.get(key):
            lines.append(f"  worst {name}:")
            lines += [f"    {_where(worst)}" for worst in summary[key]]
    for group, offenders in summary.get("penetration_offenders", {}).items():
        offenders = [worst for worst in offenders if worst["value"] > 100 * DEPTH_LIMIT]
        if offenders:
            lines.append(f"  worst penetrations ({group}, cm):")
            lines += [f"    {_where(worst)}" for worst in offenders]
    for failure in summary["failed"]:
        lines.append(f"  failed: {failure['file']}: {failure['reason']}")
    return "\n".join(lines)



#: The columns of the per-group table: summary key, heading, format.
GROUP_COLUMNS: tuple[tuple[str, str, str], ...] = (
    ("files", "files", "{:d}"),
    ("elbow_pop_events", "pops", "{:d}"),
    ("files_with_elbow_pops", "files w/ pops", "{:d}"),
    ("wrist_step_events", "steps", "{:d}"),
    ("largest_joint_turn_deg", "max °/frame", "{:.0f}"),
    ("files_with_joint_turn_over_limit", "files >25°", "{:d}"),
    ("torso_penetration_cm", "torso cm", "{:.1f}"),
    ("forearm_penetration_cm", "forearms cm", "{:.1f}"),
    ("hand_penetration_cm", "hands cm", "{:.1f}"),
    ("peak_wrist_speed", "peak m/s", "{:.2f}"),
    ("peak_wrist_acceleration", "peak m/s²", "{:.0f}"),
    ("power_law_beta_median", "β median", "{:.3f}"),
    ("jerk_ratio_stroke_median", "jerk strokes", "{:.2f}"),
    ("jerk_ratio_start_median", "jerk starts", "{:.2f}"),
    ("twist_pinned_percent", "twist pinned %", "{:.0f}"),
    ("stroke_landmark_percent", "landmark %", "{:.0f}"),
    ("stroke_lead_median_ms", "lead ms", "{:.0f}"),
    ("stroke_onset_error_max_frames", "lead err fr", "{:.1f}"),
)


def format_groups(groups: dict[str, dict]) -> str:
    """One line per group (subfolder) with its key figures; — where not measured."""
    header = ["group", *(heading for _, heading, _ in GROUP_COLUMNS)]
    rows = [[name, *("—" if summary.get(key) is None else form.format(summary[key]) for key, _, form in GROUP_COLUMNS)] for name, summary in groups.items()]
    widths = [max(len(row[k]) for row in [header, *rows]) for k in range(len(header))]
    return "\n".join("  " + "  ".join(cell.rjust(width) if k else cell.ljust(width) for k, (cell, width) in enumerate(zip(row, widths))) for row in [header, *rows])
