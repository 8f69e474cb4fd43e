"""Hands brought together touch and do not overlap: the wrists of a symmetric gesture keep
at least a palm thickness apart where the spec brings them together (join_hands and a
synthetic table of symmetries, centres and heights)."""

from __future__ import annotations

import numpy as np
import pytest

from bench.speed_laws import joint_positions
from motor.body.avatar import load_avatar
from motor.control import MotorControl
from motor.program.lmp import TimePegs
from mura.constraints import Arm, Dynamic, Parallel, Segment, SegmentKind, Static, Symmetrical, Symmetry
from mura.values import Direction, GridLocation, PalmOrientation
from tests.motor_program.conftest import behavior
from tests.speed_laws.conftest import EXAMPLES, rendered

#: How far (m) the gap may fall short of the palm thickness: contact is kept at the
#: locations the spec names; between them the two paths, each kept in reach and out of the
#: torso on its own, may approach a fraction of a millimetre closer.
ROUNDING = 5e-4
FPS = 60.0


def _gap(wrists: dict[str, np.ndarray]) -> np.ndarray:
    return np.linalg.norm(wrists["right"] - wrists["left"], axis=1)


def test_join_hands_palms_touch_without_overlapping(avatar) -> None:
    performance = rendered(next(p for p in EXAMPLES if p.stem == "assembly_two_bars"), FPS)
    (join,) = [b for b in performance.behaviors() if b["id"] == "join_hands"]
    first, last = performance.frame(join["phases"]["stroke_start"]), performance.frame(join["phases"]["relax"])
    gap = _gap(performance.wrists)[first : last + 1]
    assert gap.min() >= avatar.collision.palm_thickness - ROUNDING
    assert gap[-1] == pytest.approx(avatar.collision.palm_thickness, abs=1e-3), "the hands meet"


@pytest.mark.parametrize(
    ("start", "end", "symmetry", "centered"),
    [
        (GridLocation("LocChest", "LocPeripheryRight", "LocNorm"), GridLocation("LocChest", "LocCCenter", "LocNorm"), "S", False),
        (GridLocation("LocChest", "LocPeripheryRight", "LocNorm"), GridLocation("LocShoulder", "LocCCenter", "LocFar"), "S", False),
        (GridLocation("LocChest", "LocPeripheryRight", "LocNorm"), GridLocation("LocStomach", "LocCCenter", "LocNorm"), "S", True),
        (GridLocation("LocShoulder", "LocCenterRight", "LocNorm"), GridLocation("LocChest", "LocCenterRight", "LocNorm"), "T", True),
    ],
    ids=["chest, sagittal", "shoulder far, sagittal", "stomach, sagittal through a centre", "transversal through the end"],
)
def test_synthetic_symmetric_gestures_keep_a_palm_thickness_apart(avatar, start, end, symmetry: str, centered: bool) -> None:
    """Synthetic gestures: the right hand moves to ``end``, the left hand mirrors it, so
    that the two meet there; the mirror planes pass through the end point when
    ``centered`` (the spec's centre in millimetres, height from the floor)."""
    height = avatar.root_height + avatar.grid.heights[end.height]
    center = (0.0, 1000.0 * height, 1000.0 * (avatar.grid.front + avatar.grid.distances[end.distance])) if centered else None
    child = Parallel((
        Static("PalmOrientation", PalmOrientation((1.0, 0.0, 0.0)), scope=Arm.RIGHT),
        Static("ExtFingerOrientation", Direction((0.0, 0.0, 1.0), "DirA"), scope=Arm.RIGHT),
        Dynamic("HandLocation", (Segment(SegmentKind.LINEAR, start=start, end=end),), scope=Arm.RIGHT),
    ))  # fmt: skip
    gesture = Symmetrical(child, Arm.RIGHT, Symmetry(frozenset(symmetry), f"SymM{symmetry}"), center)
    control = MotorControl(avatar, FPS)
    program = control.plan(behavior(gesture, "together"), TimePegs(0.0, 1.0, 1.0, 1.2, 1.6, 2.0, 2.8))
    control.activate(program)
    motion = control.frames(0.0, program.pegs.end + 0.1)
    joints = joint_positions(motion, ("r_wrist", "l_wrist"))
    gap = _gap({"right": joints["r_wrist"], "left": joints["l_wrist"]})
    assert gap.min() >= avatar.collision.palm_thickness - ROUNDING
    assert gap.min() == pytest.approx(avatar.collision.palm_thickness, abs=1e-3), "the hands meet"


@pytest.mark.parametrize("name", ["max", "kim", "makehuman"])
def test_palm_thickness_is_the_hands_own(name: str) -> None:
    """One palm thickness per avatar, in its collision entry: the distance between the
    palm and the back of the hand, where the avatar's locations put them."""
    avatar = load_avatar(name)
    palm, back = (avatar.rest_positions[avatar.sites[site].bone] + np.asarray(avatar.sites[site].offset) for site in ("r_palm", "r_handback"))
    assert avatar.collision.palm_thickness == pytest.approx(float(np.linalg.norm(palm - back)), abs=5e-4)
    assert 0.01 < avatar.collision.palm_thickness < 0.06
