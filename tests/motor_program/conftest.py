"""Shared fixtures for the motor-program tests: an avatar, gestures built in code, and
rendering planned gestures into frames and wrist paths."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pytest

from motor.body.avatar import Avatar, load_avatar
from motor.body.kinematics import Pose, forward_kinematics
from motor.control import MotorControl
from motor.motion import Motion
from motor.program.lmp import TimePegs
from mura.constraints import Constraint
from mura.model import AbsoluteTiming, BehaviorSpec, Gesture


@pytest.fixture(scope="session")
def avatar() -> Avatar:
    return load_avatar("max")


def behavior(constraints: Constraint, name: str = "g") -> BehaviorSpec:
    """A gesture behaviour around a constraint tree (its timing is not used by motor)."""
    return BehaviorSpec(name, "gesture", AbsoluteTiming(0.0, 1.0), Gesture(name, constraints))


def pegs(start: float, ready: float, stroke_start: float, stroke_end: float, relax: float | None = None) -> TimePegs:
    """Pegs with the stroke peak mid-stroke and the retraction estimate 0.5 s after relax."""
    relax = stroke_end if relax is None else relax
    return TimePegs(start, ready, stroke_start, 0.5 * (stroke_start + stroke_end), stroke_end, relax, relax + 0.5)


def render(
    avatar: Avatar, planned: Sequence[tuple[BehaviorSpec, TimePegs]], fps: float = 60.0, end: float | None = None, **plan_options
) -> tuple[MotorControl, Motion]:
    """Plan and activate every behaviour, then render everything in one call."""
    control = MotorControl(avatar, fps)
    for spec, timing in planned:
        control.activate(control.plan(spec, timing, **plan_options))
    last = max(control.busy_until(arm) for arm in ("right", "left"))
    return control, control.frames(0.0, (last + 0.2) if end is None else end)


def pose(avatar: Avatar, motion: Motion) -> Pose:
    """Global joint poses of a motion in the avatar frame (root at the origin)."""
    return forward_kinematics(avatar, motion.rotations)


def joint_path(avatar: Avatar, motion: Motion, joint: str) -> np.ndarray:
    return pose(avatar, motion).positions[:, avatar.joint_index(joint)]
