"""Human speed laws measured on the rendered wrist: ``python -m bench.speed_laws [--json FILE]``.

Every example utterance (``specs/utterances``) and every published MURML file
(``../shared/corpora/murml/*.us``) is performed with the scheduler, the ``max`` avatar at
:data:`FPS` frames per second (240: at 60 fps a minimum-jerk start of a short stroke
already reaches 40 % of its peak acceleration one frame after it leaves rest, too coarse
to tell it from a step) and the fake speech. The wrists are then found with a forward kinematics written
here (quaternion products in numpy on the :class:`motor.motion.Motion`'s own offsets and
parents; nothing of the synthesis' kinematics is used) and measured by finite differences:

* **peak speed and acceleration** of each wrist (central differences);
* **starts and stops at rest**: at each departure from a still run of at least
  :data:`MIN_REST` (the wrist moves less than :data:`STILL_SPEED` from one frame to the
  next) and each arrival into one, the
  acceleration at the still frame next to the movement over the movement unit's peak
  acceleration (0 for a start with zero acceleration, about 0.5 for a cubic, 1 for a
  step); units shorter than :data:`MIN_UNIT` are skipped;
* **jerk ratio** of every straight movement unit from rest to rest (chord over path
  length at least :data:`STRAIGHT`): integrated squared jerk over that of the minimum-jerk
  movement between its ends in the same frames, both differentiated alike, the still frames
  on both sides included (so that an acceleration step counts). Units during a sign are
  reported apart: a sign's movement follows its HamNoSys manner (the targetted manner's
  late peak and sharp stop), not the minimum-jerk law;
* **power law** on every curved stroke (the planned stroke phase of a behaviour, total
  turning above :data:`CURVED_TURN` and median radius of curvature below
  :data:`CURVED_RADIUS`): β of ``log v = β log R + c`` on the stroke's inner
  :data:`INNER_FRACTION` of its duration, frames faster than 5 % of the stroke's peak and
  with ``R`` below 1 m; fits whose ``log R`` spreads less than :data:`MIN_LOG_SPREAD`
  (a circle: constant radius, β undefined) are reported by their speed ripple instead,
  ``(max − min) / mean`` of the speed over the same inner part;
* **landmark at the stroke onset**: for each behaviour and arm whose stroke moves the wrist
  more than :data:`DYNAMIC_PATH`, whether the frame of the planned ``stroke_start`` (±1
  frame) is still (a pre-stroke hold or a stop) or a local speed minimum at most
  :data:`DIP_RATIO` of the speed peaks within :data:`PEAK_REACH` on either side;
* **palm gap**: over the behaviours that use both arms, the least distance between the two
  wrists (two palms facing each other touch when it is one palm thickness, 3 cm on ``max``).

Figures, not pass/fail: the tests in ``tests/speed_laws`` assert the properties.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
UTTERANCES = REPO / "specs" / "utterances"
PUBLISHED = REPO.parent / "shared" / "corpora" / "murml"
FPS = 240.0
#: Frame-to-frame wrist speed (m/s) below which the wrist is still.
STILL_SPEED = 1e-3
#: Shortest movement unit measured, frames.
MIN_UNIT = 6
#: Stillness (s) before or after a movement for it to start from or stop at rest.
MIN_REST = 0.02
#: Chord over path length from which a movement unit is straight.
STRAIGHT = 0.999
#: Total turning (radians) and median radius (m) from which a stroke is curved.
CURVED_TURN = np.pi / 3.0
CURVED_RADIUS = 0.3
#: Part of a curved stroke's duration the power law is fitted on (centred).
INNER_FRACTION = 0.8
#: Least standard deviation of log R for a meaningful fit.
MIN_LOG_SPREAD = 0.15
#: Wrist path during the stroke above which a stroke is dynamic, metres.
DYNAMIC_PATH = 0.03
#: A speed minimum is a landmark if at most this fraction of the neighbouring peaks.
DIP_RATIO = 0.7
PEAK_REACH = 0.3


# -- forward kinematics of our own ------------------------------------------------------


def _qmul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    ax, ay, az, aw = np.moveaxis(a, -1, 0)
    bx, by, bz, bw = np.moveaxis(b, -1, 0)
    return np.stack(
        [
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz,
        ],
        axis=-1,
    )


def _qrot(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    u, w = q[..., :3], q[..., 3:]
    t = 2.0 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


def joint_positions(motion, names: tuple[str, ...]) -> dict[str, np.ndarray]:
    """Global positions ``(n, 3)`` of the named joints, by walking the parent chain."""
    index = {name: i for i, name in enumerate(motion.joint_names)}
    out = {}
    for name in names:
        chain = []
        j = index[name]
        while j >= 0:
            chain.append(j)
            j = motion.parents[j]
        chain.reverse()
        rotation = motion.rotations[:, chain[0]]
        position = motion.root_translation + np.asarray(motion.offsets[chain[0]])
        for j in chain[1:]:
            position = position + _qrot(rotation, np.broadcast_to(motion.offsets[j], position.shape))
            rotation = _qmul(rotation, motion.rotations[:, j])
        out[name] = position
    return out


# -- measures ---------------------------------------------------------------------------


def derivatives(x: np.ndarray, fps: float) -> tuple[np.ndarray, np.ndarray]:
    v = np.gradient(x, 1.0 / fps, axis=0)
    a = np.zeros_like(x)
    a[1:-1] = (x[2:] - 2.0 * x[1:-1] + x[:-2]) * fps * fps
    return v, a


def still_pairs(x: np.ndarray, fps: float) -> np.ndarray:
    """``still[k]``: the wrist moves less than STILL_SPEED from frame k to k + 1."""
    return np.linalg.norm(np.diff(x, axis=0), axis=1) * fps < STILL_SPEED


def movement_units(x: np.ndarray, fps: float) -> list[tuple[int, int, bool, bool]]:
    """``(first, last, from_rest, to_rest)`` of each movement: its first and last frames are
    the still frames around it; ``from_rest``/``to_rest`` say that the wrist was still for
    at least :data:`MIN_REST` before/after it (not at the ends of the motion)."""
    moving = ~still_pairs(x, fps)
    edges = np.diff(np.concatenate([[0], moving.astype(int), [0]]))
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    rest = int(round(MIN_REST * fps))
    before = starts - np.concatenate([[0], stops[:-1]])
    after = np.concatenate([starts[1:], [moving.size]]) - stops
    return [
        (int(a), int(b), bool(a > 0 and g >= rest), bool(b < moving.size and h >= rest))
        for a, b, g, h in zip(starts, stops, before, after)
    ]


def squared_jerk(x: np.ndarray, fps: float) -> float:
    j = x
    for _ in range(3):
        j = np.diff(j, axis=0) * fps
    return float(np.sum(j * j) / fps)


def min_jerk_path(a: np.ndarray, b: np.ndarray, frames: int) -> np.ndarray:
    tau = np.linspace(0.0, 1.0, frames)[:, None]
    return a + (tau**3 * (10.0 - 15.0 * tau + 6.0 * tau * tau)) * (b - a)


def radius_of_curvature(x: np.ndarray, fps: float) -> tuple[np.ndarray, np.ndarray]:
    v = np.gradient(x, 1.0 / fps, axis=0)
    a = np.gradient(v, 1.0 / fps, axis=0)
    speed = np.linalg.norm(v, axis=1)
    bend = np.linalg.norm(np.cross(v, a), axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        radius = speed**3 / bend
    return speed, radius


def power_law(x: np.ndarray, fps: float) -> dict:
    """β fitted on a stroke's inner part, or its speed ripple when the radius hardly varies."""
    n = x.shape[0]
    cut = int(round(0.5 * (1.0 - INNER_FRACTION) * n))
    speed, radius = radius_of_curvature(x, fps)
    speed, radius = speed[cut : n - cut], radius[cut : n - cut]
    keep = (speed > 0.05 * speed.max()) & np.isfinite(radius) & (radius > 0.0) & (radius < 1.0)
    if np.count_nonzero(keep) < 5:
        return {"beta": None, "ripple": None}
    log_r, log_v = np.log(radius[keep]), np.log(speed[keep])
    ripple = float((speed.max() - speed.min()) / speed.mean())
    if float(np.std(log_r)) < MIN_LOG_SPREAD:
        return {"beta": None, "ripple": ripple, "log_spread": float(np.std(log_r))}
    slope, _ = np.polyfit(log_r, log_v, 1)
    r = float(np.corrcoef(log_r, log_v)[0, 1])
    return {"beta": float(slope), "r": r, "ripple": ripple, "log_spread": float(np.std(log_r))}


def total_turning(x: np.ndarray) -> float:
    d = np.diff(x, axis=0)
    norm = np.linalg.norm(d, axis=1)
    d = d[norm > 1e-6] / norm[norm > 1e-6, None]
    if d.shape[0] < 2:
        return 0.0
    return float(np.sum(np.arccos(np.clip(np.einsum("ij,ij->i", d[1:], d[:-1]), -1.0, 1.0))))


def landmark(x: np.ndarray, frame: int, fps: float) -> str | None:
    """``"hold"``, ``"dip"`` or None at ``frame`` (±1)."""
    still = still_pairs(x, fps)
    speed = np.linalg.norm(np.gradient(x, 1.0 / fps, axis=0), axis=1)
    lo, hi = max(frame - 1, 1), min(frame + 1, speed.size - 2)
    for k in range(lo, hi + 1):
        if still[k - 1] or still[min(k, still.size - 1)]:
            return "hold"
    reach = int(PEAK_REACH * fps)
    for k in range(lo, hi + 1):
        if speed[k] <= speed[k - 1] and speed[k] <= speed[k + 1]:
            before = speed[max(k - reach, 0) : k + 1].max()
            after = speed[k : k + reach + 1].max()
            if speed[k] <= DIP_RATIO * min(before, after):
                return "dip"
    return None


@dataclass
class Figures:
    peak_speed: list[float] = field(default_factory=list)
    peak_acceleration: list[float] = field(default_factory=list)
    start_ratios: list[float] = field(default_factory=list)
    stop_ratios: list[float] = field(default_factory=list)
    jerk_ratios: list[float] = field(default_factory=list)
    sign_jerk_ratios: list[float] = field(default_factory=list)
    wrist_gaps: list[float] = field(default_factory=list)
    betas: list[float] = field(default_factory=list)
    ripples: list[float] = field(default_factory=list)
    strokes: int = 0
    landmarks: int = 0
    details: list[dict] = field(default_factory=list)


def render(path: Path, fps: float = FPS):
    from blackboard.clock import VirtualClock
    from blackboard.scheduler import Scheduler
    from motor.body.avatar import load_avatar
    from motor.control import MotorControl
    from mura.murml import load_utterance
    from tts import FakeSynthesizer

    avatar = load_avatar("max")
    performed = Scheduler(FakeSynthesizer(), MotorControl(avatar, fps), VirtualClock()).run(load_utterance(path), name=path.stem)
    if performed.error is not None:
        raise RuntimeError(f"{path.name}: {performed.error}")
    return performed


def measure(path: Path, figures: Figures, fps: float = FPS) -> dict:
    performed = render(path, fps)
    motion = performed.motion
    timeline = performed.timeline.to_json()
    wrists = joint_positions(motion, ("r_wrist", "l_wrist"))
    signs = [(b["phases"]["start"], b["phases"]["end"]) for b in timeline["behaviors"] if b["kind"] == "sign"]
    entry: dict = {"file": path.name, "warnings": [w for w in performed.warnings if "GazeDirection" not in w and "not realized" not in w]}
    for side, x in wrists.items():
        v, a = derivatives(x, fps)
        speed, accel = np.linalg.norm(v, axis=1), np.linalg.norm(a, axis=1)
        figures.peak_speed.append(float(speed.max()))
        figures.peak_acceleration.append(float(accel.max()))
        entry[f"{side}_peak_speed"] = float(speed.max())
        entry[f"{side}_peak_acceleration"] = float(accel.max())
        for first, last, from_rest, to_rest in movement_units(x, fps):
            if last - first < MIN_UNIT:
                continue
            peak = float(accel[first + 1 : last].max())
            if peak <= 0.0:
                continue
            if from_rest:
                figures.start_ratios.append(float(accel[first] / peak))
            if to_rest:
                figures.stop_ratios.append(float(accel[last] / peak))
            path_length = float(np.sum(np.linalg.norm(np.diff(x[first : last + 1], axis=0), axis=1)))
            chord = float(np.linalg.norm(x[last] - x[first]))
            if from_rest and to_rest and path_length > 0.02 and chord / path_length >= STRAIGHT:
                lo, hi = first - 1, last + 2
                reference = np.concatenate([x[lo : first + 1], min_jerk_path(x[first], x[last], last - first + 1)[1:-1], x[last:hi]])
                ratio = squared_jerk(x[lo:hi], fps) / squared_jerk(reference, fps)
                t0, t1 = motion.start_time + first / fps, motion.start_time + last / fps
                during_sign = any(t0 < end and t1 > start for start, end in signs)
                (figures.sign_jerk_ratios if during_sign else figures.jerk_ratios).append(ratio)
    start = motion.start_time
    for behavior in timeline["behaviors"]:
        phases = behavior["phases"]
        if len(behavior["arms"]) == 2:
            f0, f1 = (int(round((phases[name] - start) * fps)) for name in ("start", "end"))
            gap = np.linalg.norm(wrists["r_wrist"][f0 : f1 + 1] - wrists["l_wrist"][f0 : f1 + 1], axis=1)
            figures.wrist_gaps.append(float(gap.min()))
        for arm in behavior["arms"]:
            x = wrists["r_wrist" if arm == "right" else "l_wrist"]
            f0 = int(round((phases["stroke_start"] - start) * fps))
            f1 = int(round((phases["stroke_end"] - start) * fps))
            if f1 - f0 < 3:
                continue
            stroke = x[f0 : f1 + 1]
            length = float(np.sum(np.linalg.norm(np.diff(stroke, axis=0), axis=1)))
            if length < DYNAMIC_PATH:
                continue
            figures.strokes += 1
            mark = landmark(x, f0, fps)
            figures.landmarks += mark is not None
            detail = {"file": path.name, "behavior": behavior["id"], "arm": arm, "landmark": mark}
            _, radius = radius_of_curvature(stroke, fps)
            if total_turning(stroke) > CURVED_TURN and np.nanmedian(radius) < CURVED_RADIUS:
                fit = power_law(stroke, fps)
                detail.update(fit)
                if fit["beta"] is not None:
                    figures.betas.append(fit["beta"])
                elif fit["ripple"] is not None:
                    figures.ripples.append(fit["ripple"])
            figures.details.append(detail)
    return entry


def _summary(values: list[float]) -> dict | None:
    if not values:
        return None
    return {"count": len(values), "min": min(values), "median": statistics.median(values), "max": max(values)}


def run(fps: float = FPS) -> dict:
    figures = Figures()
    files = sorted(UTTERANCES.glob("*.xml")) + sorted(PUBLISHED.glob("*.us"))
    per_file = [measure(path, figures, fps) for path in files]
    return {
        "fps": fps,
        "files": len(files),
        "peak_speed_max": max(figures.peak_speed),
        "peak_acceleration_max": max(figures.peak_acceleration),
        "start_acceleration_ratio": _summary(figures.start_ratios),
        "stop_acceleration_ratio": _summary(figures.stop_ratios),
        "jerk_ratio_straight": _summary(figures.jerk_ratios),
        "jerk_ratio_straight_signs": _summary(figures.sign_jerk_ratios),
        "least_wrist_gap_bimanual": min(figures.wrist_gaps) if figures.wrist_gaps else None,
        "power_law_beta": _summary(figures.betas),
        "circle_speed_ripple": _summary(figures.ripples),
        "strokes": figures.strokes,
        "strokes_with_landmark": figures.landmarks,
        "per_file": per_file,
        "strokes_detail": figures.details,
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.speed_laws", description=__doc__.splitlines()[0])
    parser.add_argument("--json", type=Path, help="write every figure to this file")
    parser.add_argument("--fps", type=float, default=FPS, help=f"frames per second of the renders (default {FPS:g})")
    args = parser.parse_args(argv)

    report = run(args.fps)
    if args.json:
        args.json.write_text(json.dumps(report, indent=1))
    short = {k: v for k, v in report.items() if k not in ("per_file", "strokes_detail")}
    print(json.dumps(short, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
