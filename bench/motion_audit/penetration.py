"""How deep body segments sink into each other in every frame.

Pairs checked (:data:`PAIRS`), in three groups: each arm's upper arm, forearm and hand
against the **torso**; forearm against forearm (**forearms**); hand against hand
(**hands**, whose capsules are as thick as the palm, so hands that touch are apart by
the palm's thickness and hands on one point are reported).

Each volume moves rigidly with its joint: a point ``x`` of it at rest is at
``p_j(t) + R_j(t)·(x − p_j(rest))`` in frame ``t``. The moving capsule of a pair is taken
into the rest frame of the other volume (``p_k(rest) + R_k(t)⁻¹·(y − p_k(t))``), where
:func:`bench.motion_audit.distance.capsule_depth` measures its depth. Depths are in
metres (positive: overlapping); the report gives centimetres.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from bench.motion_audit.distance import Capsule, capsule_depth
from bench.motion_audit.findings import Worst
from bench.motion_audit.kinematics import Kinematics
from bench.motion_audit.volumes import CHEST, TORSO, Volume

#: Each group's pairs (fixed volume, moving capsule); pairs whose fixed volume the avatar
#: lacks (a chest) are left out.
PAIRS: dict[str, tuple[tuple[str, str], ...]] = {
    "torso": tuple((trunk, f"{side}_{segment}") for trunk in (TORSO, CHEST) for side in ("l", "r") for segment in ("upper_arm", "forearm", "hand")),
    "forearms": (("l_forearm", "r_forearm"),),
    "hands": (("l_hand", "r_hand"),),
}
#: Depth above which a frame counts as penetrating, metres.
DEPTH_LIMIT = 0.01


@dataclass(frozen=True)
class Penetration:
    """One group: the deepest overlap (``worst.value`` in cm) and the frames deeper than
    :data:`DEPTH_LIMIT`."""

    frames_over: int
    worst: Worst | None

    def as_json(self) -> dict:
        return {"frames_over": self.frames_over, "worst": self.worst.as_json() if self.worst else None}


def _to_world(kinematics: Kinematics, joint: int, points: np.ndarray) -> np.ndarray:
    """Rest-frame points ``(3,)`` of a volume on ``joint`` in every frame ``(frames, 3)``."""
    rotation = Rotation.from_quat(kinematics.orientations[:, joint])
    return kinematics.positions[:, joint] + rotation.apply(points - kinematics.rest_positions[joint])


def _to_rest(kinematics: Kinematics, joint: int, points: np.ndarray) -> np.ndarray:
    """World points ``(frames, 3)`` into the rest frame of a volume on ``joint``."""
    rotation = Rotation.from_quat(kinematics.orientations[:, joint])
    return kinematics.rest_positions[joint] + rotation.apply(points - kinematics.positions[:, joint], inverse=True)


def _capsule_in(kinematics: Kinematics, fixed: Volume, moving: Volume) -> tuple[np.ndarray, np.ndarray, float]:
    """The axis ends ``(frames, 3)`` of capsule ``moving`` in the rest frame of ``fixed``, and its radius."""
    capsule = moving.shape
    if not isinstance(capsule, Capsule):
        raise TypeError(f"volume {moving.name!r} must be a capsule to be measured against {fixed.name!r}")
    carrier, holder = kinematics.index(moving.joint), kinematics.index(fixed.joint)
    start = _to_rest(kinematics, holder, _to_world(kinematics, carrier, capsule.a))
    end = _to_rest(kinematics, holder, _to_world(kinematics, carrier, capsule.b))
    return start, end, capsule.radius


def group_depths(kinematics: Kinematics, fixed: Volume, moving: list[Volume]) -> np.ndarray:
    """Depth ``(frames, len(moving))`` in metres of each capsule of ``moving`` in ``fixed``,
    all measured in one vectorized search."""
    ends = [_capsule_in(kinematics, fixed, volume) for volume in moving]
    frames = kinematics.frame_count
    start = np.concatenate([e[0] for e in ends])
    end = np.concatenate([e[1] for e in ends])
    radius = np.repeat([e[2] for e in ends], frames)
    depth, _ = capsule_depth(start, end, radius, fixed.shape)
    return depth.reshape(len(moving), frames).T


def penetrations(kinematics: Kinematics, volumes: dict[str, Volume], start: float = 0.0) -> dict[str, Penetration]:
    """Every group of :data:`PAIRS`: frames deeper than the limit and the deepest overlap."""
    results = {}
    for group, listed in PAIRS.items():
        pairs = [(a, b) for a, b in listed if a in volumes]
        fixed = dict.fromkeys(a for a, _ in pairs)
        depths = np.concatenate([group_depths(kinematics, volumes[a], [volumes[b] for f, b in pairs if f == a]) for a in fixed], axis=1)
        deepest = depths.max(axis=1)
        frame, pair = np.unravel_index(int(np.argmax(depths)), depths.shape)
        worst = None
        if depths[frame, pair] > 0:
            a, b = pairs[pair]
            worst = Worst(100.0 * float(depths[frame, pair]), start + frame / kinematics.fps, f"{b} in {a}")
        results[group] = Penetration(int(np.count_nonzero(deepest > DEPTH_LIMIT)), worst)
    return results
