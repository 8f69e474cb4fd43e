"""Re-posing the MakeHuman mesh into mura's rest pose, by linear blend skinning.

The base mesh stands in an A-pose with the elbows bent and the hands turned palm down.
:func:`motor.body.rest_pose.normalised_rest` gives the rotation of every joint that
brings the skeleton into mura's rest pose, with the arms tilted outward just enough for
the hands to clear the thighs (:func:`arm_abduction`); the vertices follow by linear
blend skinning with the rig's weights.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from motor.body.makehuman.rig import MappedRig
from motor.body.rest_pose import normalised_rest

#: Clearance between the hanging hand and the thigh surface, metres.
THIGH_CLEARANCE = 0.03
#: Smallest and largest outward tilt of the hanging arm, radians.
ABDUCTION_RANGE = (np.radians(3.0), np.radians(20.0))


@dataclass(frozen=True, eq=False)
class Reposed:
    """Joint positions ``(J, 3)``, fingertips and vertices ``(V, 3)`` in the rest pose,
    the global rotation ``(J,)`` applied to each joint, and the arms' outward tilt (rad)."""

    positions: np.ndarray
    tips: dict[str, np.ndarray]
    vertices: np.ndarray
    rotations: Rotation
    abduction: float


def arm_abduction(rig: MappedRig, vertices: np.ndarray, side: str) -> float:
    """Outward tilt of the hanging arm from the vertical (radians) that keeps the hand
    :data:`THIGH_CLEARANCE` outside the widest trunk or thigh vertex at hand height."""
    at = {name: rig.positions[i] for i, name in enumerate(rig.names)}
    sign = 1.0 if side == "l" else -1.0
    shoulder = at[f"{side}_shoulder"]
    reach = np.linalg.norm(at[f"{side}_elbow"] - shoulder) + np.linalg.norm(at[f"{side}_wrist"] - at[f"{side}_elbow"])
    hand = np.linalg.norm(rig.tips[f"{side}_middle"] - at[f"{side}_wrist"])
    legs = [rig.names.index(n) for n in ("humanoid_root", "sacroiliac", f"{side}_hip", f"{side}_knee")]
    own = rig.weights[:, legs].sum(axis=1) > 0.5
    low, high = shoulder[1] - reach - hand, shoulder[1] - reach + 0.05
    band = own & (vertices[:, 1] > low) & (vertices[:, 1] < high)
    widest = float(np.max(sign * vertices[band, 0]))
    half_hand = 0.025
    lateral = widest + THIGH_CLEARANCE + half_hand - sign * shoulder[0]
    return float(np.clip(np.arcsin(np.clip(lateral / (reach + hand), -1.0, 1.0)), *ABDUCTION_RANGE))


def repose(rig: MappedRig, vertices: np.ndarray) -> Reposed:
    """The rest-pose skeleton and mesh (see the module docstring)."""
    tilts = (arm_abduction(rig, vertices, "l"), arm_abduction(rig, vertices, "r"))
    rest = normalised_rest(rig.names, rig.parents, rig.positions, rig.tips, tilts)
    matrices = rest.rotations.as_matrix()  # (J, 3, 3)
    # v' = sum_j w_j (p'_j + R_j (v - p_j)), all joints at once
    local = vertices[:, None, :] - rig.positions[None, :, :]
    moved = np.einsum("jab,vjb->vja", matrices, local) + rest.positions[None, :, :]
    posed = np.einsum("vj,vja->va", rig.weights, moved)
    return Reposed(rest.positions, rest.tips, posed, rest.rotations, float(np.mean(tilts)))
