"""Motion synthesis speed: frames of the full skeleton per second from activated programs.

Not a test: prints figures. ``run(quick)`` plans a multi-gesture utterance — every gesture
of the example utterances, one after another with co-articulated hand-overs — activates
it on a fresh :class:`motor.control.MotorControl` and renders it, at 25 and 60 fps:

* ``frames_per_s_*``: all frames in one ``frames`` call (offline rendering);
* ``streamed_frames_per_s_*``: the same frames in 0.1 s windows, as the scheduler asks;
* ``activation_ms_*``: activating every LMP (building the channel timelines), per LMP
  and not per frame, so timed apart;
* ``bare_*``: the cost of merely composing every joint rotation of every frame with
  numpy — forward kinematics of the rendered rotations (a quaternion product and a
  rotated offset per joint per frame, numpy arithmetic on whole arrays: the floor is
  numpy's, not mura's compiled kernels) and a single quaternion product per joint per
  frame — and the ratio of synthesis time to forward-kinematics time;
* ``bare_compose_and_write_*`` (issue 19's floor): composing the same rotations (forward
  kinematics) and writing them (the local rotations as float32 bytes into a buffer, the
  cheapest honest output), and ``synthesis_over_bare_*`` the synthesis time over it, for
  the whole call and the streamed windows.

Times are this process's CPU time (``time.process_time``: steadier than wall-clock on a
shared machine), medians of several runs. Pin the process to one core for the figures:
``taskset -c 0 .venv/bin/python -m bench.motion_speed``. The design target is ≥ 150,000
frames/s on one core and a ratio ≤ 10 (DESIGN.md).
"""

from __future__ import annotations

import json
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

import io

from bench.timing import median_seconds
from motor.body.avatar import load_avatar
from motor.compiled import warm_up
from motor.control import MotorControl
from motor.program.gesture import MotorProgram
from motor.program.lmp import TimePegs
from mura.model import BehaviorSpec
from mura.murml import load_utterance

UTTERANCES = Path(__file__).resolve().parents[1] / "specs" / "utterances"
#: Seconds from one gesture's start to the next's; the next starts during the retraction.
SPACING = 2.2
#: The clock of every figure: this process's CPU time (module docstring).
CLOCK = time.process_time


def _gestures() -> list[BehaviorSpec]:
    return [b for path in sorted(UTTERANCES.glob("*.xml")) for b in load_utterance(path).behaviors if b.gesture is not None]


def _programs(control: MotorControl, gestures: list[BehaviorSpec]) -> list[MotorProgram]:
    programs = []
    for index, spec in enumerate(gestures):
        t = 0.3 + SPACING * index
        programs.append(control.plan(spec, TimePegs(t, t + 0.6, t + 0.7, t + 1.0, t + 1.4, t + 1.7, t + 2.3)))
    return programs


def _fresh(avatar, fps: float, programs: list[MotorProgram]) -> MotorControl:
    """A control with the programs activated and its channel timelines built, the arms'
    and the gaze's (activation is per LMP, not per frame, and is timed apart)."""
    control = MotorControl(avatar, fps)
    for program in programs:
        control.activate(program)
    for channel in control.activated():
        control.timeline(channel)
    control.neck.timeline()
    return control


def numpy_product(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Hamilton product of quaternions ``(..., 4)`` (scalar last) in numpy arithmetic."""
    px, py, pz, pw = p[..., 0], p[..., 1], p[..., 2], p[..., 3]
    qx, qy, qz, qw = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    out = np.empty(np.broadcast_shapes(p.shape, q.shape))
    out[..., 0] = pw * qx + px * qw + py * qz - pz * qy
    out[..., 1] = pw * qy - px * qz + py * qw + pz * qx
    out[..., 2] = pw * qz + px * qy - py * qx + pz * qw
    out[..., 3] = pw * qw - px * qx - py * qy - pz * qz
    return out


def numpy_rotated(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Vectors ``(..., 3)`` rotated by unit quaternions ``(..., 4)`` in numpy arithmetic
    (``v + 2w (u × v) + u × (2 u × v)``)."""
    x, y, z, w = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    vx, vy, vz = v[..., 0], v[..., 1], v[..., 2]
    tx, ty, tz = 2.0 * (y * vz - z * vy), 2.0 * (z * vx - x * vz), 2.0 * (x * vy - y * vx)
    out = np.empty(np.broadcast_shapes(q.shape[:-1], v.shape[:-1]) + (3,))
    out[..., 0] = vx + w * tx + y * tz - z * ty
    out[..., 1] = vy + w * ty + z * tx - x * tz
    out[..., 2] = vz + w * tz + x * ty - y * tx
    return out


def numpy_forward_kinematics(avatar, rotations: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Global joint positions and orientations of local rotations ``(n, J, 4)``, level by
    level of the skeleton (all joints of a level in one numpy call): the bare floor's
    composition, sharing no code with mura's."""
    local = np.ascontiguousarray(rotations.transpose(1, 0, 2))
    positions = np.empty(local.shape[:2] + (3,))
    orientations = np.empty_like(local)
    root = avatar.levels[0]
    orientations[root] = local[root]
    positions[root] = avatar.offsets[root][:, None, :]
    for level in avatar.levels[1:]:
        parent = avatar.parents[level]
        orientations[level] = numpy_product(orientations[parent], local[level])
        positions[level] = positions[parent] + numpy_rotated(orientations[parent], avatar.offsets[level][:, None, :])
    return positions, orientations


def compose_and_write(avatar, rotations: np.ndarray) -> int:
    """The bare floor of synthesis: compose the joint rotations (forward kinematics, numpy)
    and write them (float32 bytes into a buffer); returns the bytes written."""
    numpy_forward_kinematics(avatar, rotations)
    buffer = io.BytesIO()
    buffer.write(rotations.astype(np.float32).tobytes())
    return buffer.tell()


def _timed_frames(avatar, fps: float, programs: list[MotorProgram], render: Callable[[MotorControl], object], repeats: int) -> float:
    """Median process seconds of ``render`` on freshly activated controls (activation not timed)."""
    durations = []
    for _ in range(repeats):
        control = _fresh(avatar, fps, programs)
        started = time.process_time()
        render(control)
        durations.append(time.process_time() - started)
    return statistics.median(durations)


def _streamed(control: MotorControl, end: float, window: float = 0.1) -> int:
    edges = np.arange(0.0, end + window, window)
    return sum(control.frames(a, b).frame_count for a, b in zip(edges, edges[1:]))


def run(quick: bool) -> dict:
    """Frames per second of motion synthesis and of the bare rotation composition."""
    avatar = load_avatar("max")
    warm_up()
    repeats = 3 if quick else 7
    gestures = _gestures()
    if quick:
        gestures = gestures[:4]
    planning_control = MotorControl(avatar)
    planning = median_seconds(lambda: _programs(planning_control, gestures), repeats, CLOCK)
    programs = _programs(planning_control, gestures)
    end = max(program.pegs.end for program in programs) + 0.3
    result: dict[str, object] = {
        "timing": "process time (time.process_time), medians",
        "joints": avatar.joint_count,
        "gestures": len(gestures),
        "utterance_seconds": round(end, 3),
        "planning_ms_per_gesture": 1000.0 * planning / len(gestures),
    }
    for fps in (25.0, 60.0):
        label = f"{int(fps)}fps"
        frames = _fresh(avatar, fps, programs).frames(0.0, end)
        count = frames.frame_count
        whole = _timed_frames(avatar, fps, programs, lambda control: control.frames(0.0, end), repeats)
        streamed = _timed_frames(avatar, fps, programs, lambda control: _streamed(control, end), repeats)
        activation = median_seconds(lambda: _fresh(avatar, fps, programs), repeats, CLOCK)
        rotations = frames.rotations
        fk = median_seconds(lambda: numpy_forward_kinematics(avatar, rotations), repeats, CLOCK)
        product = median_seconds(lambda: numpy_product(rotations, rotations), repeats, CLOCK)
        bare = median_seconds(lambda: compose_and_write(avatar, rotations), repeats, CLOCK)
        result.update({
            f"frames_{label}": count,
            f"frames_per_s_{label}": count / whole,
            f"streamed_frames_per_s_{label}": count / streamed,
            f"bare_forward_kinematics_frames_per_s_{label}": count / fk,
            f"bare_quaternion_product_frames_per_s_{label}": count / product,
            f"synthesis_over_forward_kinematics_{label}": whole / fk,
            f"bare_compose_and_write_frames_per_s_{label}": count / bare,
            f"synthesis_over_bare_{label}": whole / bare,
            f"streamed_synthesis_over_bare_{label}": streamed / bare,
            f"activation_ms_{label}": 1000.0 * activation,
        })  # fmt: skip
    return result


if __name__ == "__main__":
    print(json.dumps(run(quick="--quick" in sys.argv), indent=2))
