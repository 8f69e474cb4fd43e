"""The face's vocabulary: the 52 ARKit blendshape names, in the order every Motion carries them.

Face motion in mura is a set of named morph weights per frame (0–1), named as Apple's
ARKit face-tracking blendshapes, so that any avatar with targets of those names (the
skinned MakeHuman avatar built at set-up has all 52; VRM models map through their
expressions) plays it. :data:`FACE_NAMES` is the fixed order of the columns of
``Motion.face_weights`` and of ``NAME.face.json``.
"""

from __future__ import annotations

import numpy as np

#: The 52 ARKit blendshape names, sorted.
FACE_NAMES: tuple[str, ...] = (
    "browDownLeft", "browDownRight", "browInnerUp", "browOuterUpLeft", "browOuterUpRight",
    "cheekPuff", "cheekSquintLeft", "cheekSquintRight",
    "eyeBlinkLeft", "eyeBlinkRight", "eyeLookDownLeft", "eyeLookDownRight", "eyeLookInLeft", "eyeLookInRight",
    "eyeLookOutLeft", "eyeLookOutRight", "eyeLookUpLeft", "eyeLookUpRight", "eyeSquintLeft", "eyeSquintRight",
    "eyeWideLeft", "eyeWideRight",
    "jawForward", "jawLeft", "jawOpen", "jawRight",
    "mouthClose", "mouthDimpleLeft", "mouthDimpleRight", "mouthFrownLeft", "mouthFrownRight", "mouthFunnel",
    "mouthLeft", "mouthLowerDownLeft", "mouthLowerDownRight", "mouthPressLeft", "mouthPressRight", "mouthPucker",
    "mouthRight", "mouthRollLower", "mouthRollUpper", "mouthShrugLower", "mouthShrugUpper",
    "mouthSmileLeft", "mouthSmileRight", "mouthStretchLeft", "mouthStretchRight", "mouthUpperUpLeft", "mouthUpperUpRight",
    "noseSneerLeft", "noseSneerRight", "tongueOut",
)  # fmt: skip
#: Column of each name in :data:`FACE_NAMES`.
FACE_INDEX: dict[str, int] = {name: index for index, name in enumerate(FACE_NAMES)}


def face_vector(weights: dict[str, float]) -> np.ndarray:
    """A ``(52,)`` weight vector from ``{name: weight}``; ``Left``/``Right`` pairs may be
    given once as ``name*`` (``"mouthSmile*": 0.3`` sets both sides). KeyError on an
    unknown name."""
    vector = np.zeros(len(FACE_NAMES))
    for name, weight in weights.items():
        names = (name[:-1] + "Left", name[:-1] + "Right") if name.endswith("*") else (name,)
        for one in names:
            if one not in FACE_INDEX:
                raise KeyError(f"{one!r} is not an ARKit blendshape name")
            vector[FACE_INDEX[one]] = float(weight)
    return vector
