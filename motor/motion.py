"""The output of motion synthesis: per-frame local joint rotations of a whole skeleton.

A :class:`Motion` is what every exporter (BVH, the browser viewer, plots) reads. It carries
the skeleton's topology and rest offsets so that it can be written out without the avatar.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, eq=False)
class Motion:
    """Skeletal animation sampled at a fixed frame rate.

    Attributes:
        fps: frames per second.
        joint_names: H-Anim joint names, parents before children.
        parents: index of each joint's parent in ``joint_names``, -1 for the root.
        offsets: ``(J, 3)`` bone offset of each joint from its parent in the parent's frame
            at rest, metres.
        rotations: ``(n, J, 4)`` local rotation of each joint relative to its parent, as
            unit quaternions in scalar-last order ``(x, y, z, w)``; the identity is the rest
            pose.
        root_translation: ``(n, 3)`` position of the root joint, metres.
        start_time: utterance-clock time of frame 0, seconds.
        face_names: names of the face's morph weights, ARKit blendshape names
            (``jawOpen``, ``eyeBlinkLeft`` …); empty when the motion has no face.
        face_weights: ``(n, len(face_names))`` morph weights per frame, 0–1, or None.
    """

    fps: float
    joint_names: tuple[str, ...]
    parents: tuple[int, ...]
    offsets: np.ndarray
    rotations: np.ndarray
    root_translation: np.ndarray
    start_time: float = 0.0
    face_names: tuple[str, ...] = ()
    face_weights: np.ndarray | None = None

    def __post_init__(self) -> None:
        joints = len(self.joint_names)
        if len(self.parents) != joints:
            raise ValueError(f"Motion: {len(self.parents)} parents for {joints} joints")
        if self.offsets.shape != (joints, 3):
            raise ValueError(f"Motion: offsets shape {self.offsets.shape}, expected {(joints, 3)}")
        if self.rotations.ndim != 3 or self.rotations.shape[1:] != (joints, 4):
            raise ValueError(f"Motion: rotations shape {self.rotations.shape}, expected (n, {joints}, 4)")
        if self.root_translation.shape != (self.rotations.shape[0], 3):
            raise ValueError(
                f"Motion: root_translation shape {self.root_translation.shape}, "
                f"expected {(self.rotations.shape[0], 3)}"
            )
        if self.fps <= 0:
            raise ValueError(f"Motion: fps must be positive, got {self.fps}")
        faces = (0, 0) if self.face_weights is None else self.face_weights.shape
        if self.face_names and faces != (self.rotations.shape[0], len(self.face_names)):
            raise ValueError(f"Motion: face_weights shape {faces}, expected {(self.rotations.shape[0], len(self.face_names))}")
        if not self.face_names and self.face_weights is not None:
            raise ValueError("Motion: face_weights given without face_names")

    @property
    def frame_count(self) -> int:
        """Number of frames."""
        return int(self.rotations.shape[0])

    @property
    def duration(self) -> float:
        """Length of the motion in seconds (frame count over fps)."""
        return self.frame_count / self.fps

    @property
    def times(self) -> np.ndarray:
        """Utterance-clock time of every frame, seconds."""
        return self.start_time + np.arange(self.frame_count) / self.fps
