"""Speech–gesture synchrony measured on the rendered motion, not on the plan.

For each gesture of a performed utterance, the stroke's onset and end are detected from the
wrist's speed profile and compared with the timing the seed asks for: the stroke starts
0.2 s (about a syllable) before the affiliate's onset and spans the affiliate to its end.

The detector. A movement unit of the wrist is delimited by *boundaries* of its speed
profile (speed by central differences):

* an **arrival** — the first frame of a still run (the wrist moves slower than
  :data:`STILL_SPEED` from it to the next frame) of two frames or more, entered from
  movement (a single still frame is a momentary stop, which its dip marks); a **departure** —
  the last frame of a still run left into movement;
* a **dip** — a local speed minimum that is not still; a *deep* dip is at most
  :data:`DIP_RATIO` of the lower of the speed peaks within :data:`PEAK_REACH` on either
  side (shallower minima can be the curvature–speed law at work inside one stroke);
* a **kink** — a local maximum of the speed's second time derivative above
  :data:`KINK_JERK`: the wrist suddenly accelerates, as when a preparation that arrives
  with some speed flows into a faster stroke without slowing down first.

The timeline is used only to say where to look and what kind of stroke it is:

* a stroke is *dynamic* if the wrist travels more than :data:`DYNAMIC_PATH` during the
  planned stroke phase, otherwise *static* (a hold, e.g. pointing);
* the preparation's speed peak is the fastest frame between the behaviour's start and the
  expected stroke onset; where the wrist already moves into the behaviour's start (the one
  before skipped its retraction and flows on), the preparation begins at the first
  arrival or deep dip after it, where that movement ends. The preparation is one
  movement unit (one guiding stroke), so its end — the **onset** of the stroke — is the
  first arrival, dip or kink after that peak. When the plan holds the hand before the stroke (``ready`` earlier than
  ``stroke_start``), the onset is instead the first departure, dip or kink after it;
* the **end** of a dynamic stroke is the last arrival or deep dip before the planned
  relax time plus :data:`END_MARGIN`, later than the onset: where the wrist comes to its
  end position before holding or retracting. The end of a static stroke is not visible in
  the wrist's movement and is not measured.

Detected times are frame times, so they carry up to about a frame of quantization.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from motor.body.avatar import Avatar
from motor.body.kinematics import forward_kinematics
from motor.motion import Motion

#: Wrist speed below which the hand counts as still, m/s (1 mm/s: a minimum-jerk reach
#: of 30 cm in 0.9 s drops below it about half a frame at 60 fps before it stops).
STILL_SPEED = 0.001
#: A speed minimum is a boundary if at most this fraction of the neighbouring peaks.
DIP_RATIO = 0.7
#: How far on each side of a minimum its neighbouring peaks are looked for, seconds.
PEAK_REACH = 0.25
#: Second time derivative of speed above which a local maximum is a kink, m/s³ (twice
#: the largest a minimum-jerk reach of 30 cm in 0.5 s ever shows).
KINK_JERK = 300.0
#: Wrist path during the planned stroke above which the stroke is dynamic, metres.
DYNAMIC_PATH = 0.03
#: How far past the planned relax time the stroke's end may be found, seconds.
END_MARGIN = 0.1
#: The stroke onset precedes the affiliate's onset by this much (seed 004), seconds.
STROKE_LEAD = 0.2

ARM_SIDES: Mapping[str, str] = {"right": "r", "left": "l"}


@dataclass(frozen=True)
class Boundary:
    """A boundary between movement units: its frame and kind (arrival, departure, dip,
    kink); ``deep`` for a dip at most :data:`DIP_RATIO` of its neighbouring peaks."""

    frame: int
    kind: str
    deep: bool = False


@dataclass(frozen=True)
class StrokeDetection:
    """One arm's stroke as detected in the motion, seconds on the utterance clock.

    ``end`` is None for a static stroke (not visible in the movement) or when no boundary
    qualifies; ``onset`` is None when no boundary qualifies.
    """

    onset: float | None
    end: float | None
    dynamic: bool


@dataclass(frozen=True)
class StrokeError:
    """Detected minus expected times of one arm of one gesture, seconds (None: not measured)."""

    behavior: str
    arm: str
    dynamic: bool
    expected_onset: float
    detected_onset: float | None
    onset_error: float | None
    expected_end: float
    detected_end: float | None
    end_error: float | None


def boundaries(speed: np.ndarray, fps: float, still: np.ndarray | None = None) -> list[Boundary]:
    """Arrivals, departures, dips and kinks of a speed profile ``(n,)`` in m/s, in frame order.

    ``still`` ``(n,)`` says which frames the hand rests in; by default where ``speed`` is
    below :data:`STILL_SPEED`. :func:`detect_stroke` passes the forward-difference test
    (the hand does not move from this frame to the next), which puts an arrival on the
    first frame at the hold position and a departure on the last one.
    """
    speed = np.asarray(speed, dtype=float)
    if speed.ndim != 1:
        raise ValueError(f"speed must have shape (n,), got {speed.shape}")
    if not fps > 0:
        raise ValueError(f"fps must be positive, got {fps}")
    still = speed < STILL_SPEED if still is None else np.asarray(still, dtype=bool)
    # one still frame between movements is a momentary stop, not a hold: its speed minimum marks it
    lone = still.copy()
    lone[1:] &= ~still[:-1]
    lone[:-1] &= ~still[1:]
    still = still & ~lone
    found = [Boundary(int(i), "arrival") for i in np.flatnonzero(still[1:] & ~still[:-1]) + 1]
    found += [Boundary(int(i), "departure") for i in np.flatnonzero(still[:-1] & ~still[1:])]
    if speed.size >= 3:
        inner = np.arange(1, speed.size - 1)
        minima = inner[(speed[inner] <= speed[inner - 1]) & (speed[inner] < speed[inner + 1]) & ~still[inner]]
        found += [Boundary(int(i), "dip", bool(deep)) for i, deep in zip(minima, _deep(speed, minima, fps))]
        curvature = np.gradient(np.gradient(speed, 1.0 / fps), 1.0 / fps)
        peaks = inner[(curvature[inner] > curvature[inner - 1]) & (curvature[inner] >= curvature[inner + 1])]
        found += [Boundary(int(i), "kink") for i in peaks[curvature[peaks] > KINK_JERK]]
    return sorted(found, key=lambda b: b.frame)


def _deep(speed: np.ndarray, minima: np.ndarray, fps: float) -> np.ndarray:
    """Which speed minima are at most :data:`DIP_RATIO` of the neighbouring peaks."""
    if minima.size == 0:
        return np.empty(0, dtype=bool)
    reach = max(1, int(round(PEAK_REACH * fps)))
    windows = np.lib.stride_tricks.sliding_window_view(np.pad(speed, reach, mode="edge"), reach + 1)
    left = windows[minima].max(axis=1)  # frames minimum - reach .. minimum
    right = windows[minima + reach].max(axis=1)  # frames minimum .. minimum + reach
    return speed[minima] <= DIP_RATIO * np.minimum(left, right)


def detect_stroke(positions: np.ndarray, fps: float, start_time: float, phases: Mapping[str, float], expected_onset: float) -> StrokeDetection:
    """Detect one arm's stroke in wrist positions ``(n, 3)`` (metres, frame 0 at ``start_time``).

    ``phases`` are the behaviour's planned phase times (``start``, ``stroke_start``,
    ``stroke_end``, ``relax``); see the module docstring for how they are used.
    """
    positions = np.asarray(positions, dtype=float)
    if positions.ndim != 2 or positions.shape[1] != 3 or positions.shape[0] < 3:
        raise ValueError(f"wrist positions must have shape (n >= 3, 3), got {positions.shape}")
    missing = [name for name in ("start", "ready", "stroke_start", "stroke_end", "relax") if name not in phases]
    if missing:
        raise ValueError(f"phases lack {', '.join(missing)}")
    speed = np.linalg.norm(np.gradient(positions, 1.0 / fps, axis=0), axis=1)
    frame = lambda t: int(np.clip(round((t - start_time) * fps), 0, speed.size - 1))
    stroke = positions[frame(phases["stroke_start"]) : frame(phases["stroke_end"]) + 1]
    dynamic = stroke.shape[0] > 1 and float(np.linalg.norm(np.diff(stroke, axis=0), axis=1).sum()) > DYNAMIC_PATH
    first, expected = frame(phases["start"]), frame(expected_onset)
    step = np.linalg.norm(np.diff(positions, axis=0), axis=1) * fps
    found = boundaries(speed, fps, np.append(step, step[-1]) < STILL_SPEED)
    if first > 0 and step[min(first, step.size) - 1] >= STILL_SPEED:
        # still moving from the behaviour before (its retraction skipped): the preparation
        # begins where that movement ends
        first = next((b.frame for b in found if first < b.frame < expected and (b.kind == "arrival" or b.deep)), first)
    peak = first + int(np.argmax(speed[first : max(expected, first) + 1]))
    onset = next((b.frame for b in found if b.frame > peak and b.kind in ("arrival", "dip", "kink")), None)
    if onset is not None and phases["stroke_start"] - phases["ready"] > 1.5 / fps:
        onset = next((b.frame for b in found if b.frame > onset and b.kind in ("departure", "dip", "kink")), None)
    end = None
    if dynamic and onset is not None:
        last = frame(phases["relax"] + END_MARGIN)
        ends = [b.frame for b in found if onset < b.frame <= last and (b.kind == "arrival" or b.deep)]
        end = ends[-1] if ends else None
    to_time = lambda f: None if f is None else start_time + f / fps
    return StrokeDetection(onset=to_time(onset), end=to_time(end), dynamic=dynamic)


def stroke_errors(motion: Motion, avatar: Avatar, timeline: Mapping) -> list[StrokeError]:
    """Detected against expected stroke onset and end of every arm of every gesture of a
    timeline (the scheduler's JSON dict) that has an affiliate and arms."""
    if tuple(motion.joint_names) != tuple(avatar.joint_names):
        raise ValueError(f"motion joints do not match avatar {avatar.name!r}")
    pose = forward_kinematics(avatar, motion.rotations, motion.root_translation)
    errors = []
    for behavior in timeline.get("behaviors", ()):
        affiliate = behavior.get("affiliate")
        if not affiliate or not behavior.get("arms"):
            continue
        expected_onset = float(affiliate["onset"]) - STROKE_LEAD
        expected_end = float(affiliate["end"])
        for arm in behavior["arms"]:
            if arm not in ARM_SIDES:
                raise ValueError(f"behavior {behavior.get('id')!r}: unknown arm {arm!r} (expected one of {sorted(ARM_SIDES)})")
            wrist = pose.positions[:, avatar.joint_index(f"{ARM_SIDES[arm]}_wrist")]
            found = detect_stroke(wrist, motion.fps, motion.start_time, behavior["phases"], expected_onset)
            errors.append(
                StrokeError(
                    behavior=str(behavior["id"]),
                    arm=arm,
                    dynamic=found.dynamic,
                    expected_onset=expected_onset,
                    detected_onset=found.onset,
                    onset_error=None if found.onset is None else found.onset - expected_onset,
                    expected_end=expected_end,
                    detected_end=found.end,
                    end_error=None if found.end is None else found.end - expected_end,
                )
            )
    return errors


def summarize(errors: list[StrokeError], fps: float) -> dict[str, float | int | None]:
    """Mean and max absolute onset and end errors in seconds and frames, and how many strokes
    were measured or missed."""
    summary: dict[str, float | int | None] = {"strokes": len(errors)}
    for name in ("onset", "end"):
        values = np.array([abs(getattr(e, f"{name}_error")) for e in errors if getattr(e, f"{name}_error") is not None])
        summary[f"{name}_measured"] = int(values.size)
        summary[f"{name}_mean_error_s"] = float(values.mean()) if values.size else None
        summary[f"{name}_max_error_s"] = float(values.max()) if values.size else None
        summary[f"{name}_mean_error_frames"] = float(values.mean() * fps) if values.size else None
        summary[f"{name}_max_error_frames"] = float(values.max() * fps) if values.size else None
    summary["onsets_missed"] = sum(e.detected_onset is None for e in errors)
    return summary
