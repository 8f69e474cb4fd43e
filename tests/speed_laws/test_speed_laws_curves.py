"""Curved strokes follow the one-third power law on the rendered path, and circles are
traced at an even speed: the example and published curves, and a synthetic table of
MURML curve segments (shape × extent × roundness × skewedness) rendered the same way."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from bench.speed_laws import CURVED_RADIUS, CURVED_TURN, joint_positions, power_law, radius_of_curvature, total_turning
from motor.control import MotorControl
from motor.program.lmp import TimePegs
from mura.constraints import Arm, Dynamic, Segment, SegmentKind
from mura.values import Direction, GridLocation
from tests.motor_program.conftest import behavior
from tests.speed_laws.conftest import Rendered

BETA = 1.0 / 3.0
TOLERANCE = 0.05
#: Speed ripple allowed on a circle, (max − min) / mean over its inner 80 %.
RIPPLE = 0.05
FPS = 240.0
START = GridLocation("LocChest", "LocCenterRight", "LocNorm")
END = GridLocation("LocShoulder", "LocPeripheryRight", "LocNorm")
FORWARD = Direction((0.0, 0.0, 1.0), "DirA")
#: Synthetic curves: every shape, extent, roundness and skewedness combination below.
CURVES = list(itertools.product(("LeftC", "RightS"), (0.3, 0.5, 0.8), (-1.0, 0.0, 1.0), (0.0, 0.5)))


def _curved(stroke: np.ndarray, fps: float) -> bool:
    _, radius = radius_of_curvature(stroke, fps)
    return total_turning(stroke) > CURVED_TURN and float(np.nanmedian(radius)) < CURVED_RADIUS


def _check(stroke: np.ndarray, fps: float, what: str) -> None:
    fit = power_law(stroke, fps)
    if fit["beta"] is None:  # a circle: constant radius, nothing to fit
        assert fit["ripple"] < RIPPLE, f"{what}: speed ripples {fit['ripple']:.0%} on a circle"
    else:
        assert fit["beta"] == pytest.approx(BETA, abs=TOLERANCE), what


def test_curved_strokes_of_the_examples_and_published_files(fine: Rendered) -> None:
    checked = 0
    for behavior_entry in fine.behaviors("gesture"):
        phases = behavior_entry["phases"]
        first, last = fine.frame(phases["stroke_start"]), fine.frame(phases["stroke_end"])
        for arm in behavior_entry["arms"]:
            stroke = fine.wrists[arm][first : last + 1]
            if stroke.shape[0] > 8 and _curved(stroke, fine.fps):
                _check(stroke, fine.fps, f"{behavior_entry['id']} ({arm})")
                checked += 1
    if not checked:
        pytest.skip("no curved stroke")


@pytest.mark.parametrize(("shape", "extent", "roundness", "skewedness"), CURVES, ids=lambda v: str(v))
def test_synthetic_curve_segments(avatar, shape: str, extent: float, roundness: float, skewedness: float) -> None:
    segment = Segment(SegmentKind.CURVE, start=START, end=END, normal=FORWARD, shape=shape, extent=extent, roundness=roundness, skewedness=skewedness)
    control = MotorControl(avatar, FPS)
    program = control.plan(behavior(Dynamic("HandLocation", (segment,), scope=Arm.RIGHT)), TimePegs(0.0, 1.0, 1.0, 1.2, 2.2, 2.4, 3.2))
    control.activate(program)
    motion = control.frames(0.0, program.pegs.end + 0.2)
    wrist = joint_positions(motion, ("r_wrist",))["r_wrist"]
    stroke = wrist[int(round(program.pegs.stroke_start * FPS)) : int(round(program.pegs.stroke_end * FPS)) + 1]
    assert _curved(stroke, FPS)
    _check(stroke, FPS, f"synthetic {shape} extent {extent} roundness {roundness} skewedness {skewedness}")
