"""A skinned body: the mesh, its skin weights on mura's joints and its face morph targets.

Plain data that exporters write (``agent.export.gltf``) and that avatar definitions are
measured on (``motor.body.definition``). Everything is at rest, in the avatar frame
(metres, root joint at the origin, y up, facing +z, +x the avatar's left).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True, eq=False)
class Part:
    """A group of triangles drawn with one material: ``triangles (T, 3)`` vertex indices,
    base colour RGBA (linear, 0–1) multiplied by the vertex colours, roughness 0–1."""

    name: str
    triangles: np.ndarray
    color: tuple[float, float, float, float]
    roughness: float = 0.6


@dataclass(frozen=True, eq=False)
class MorphTarget:
    """A sparse vertex offset: ``indices (k,)`` ascending, ``offsets (k, 3)`` metres."""

    name: str
    indices: np.ndarray
    offsets: np.ndarray


@dataclass(frozen=True, eq=False)
class SkinnedBody:
    """Mesh and skeleton of an avatar at rest.

    Attributes:
        name: the avatar's name.
        joint_names, parents, offsets: the skeleton (``offsets (J, 3)`` in the parent frame,
            which at rest is the avatar frame).
        root_height: the root's height above the floor, metres.
        positions, normals: ``(V, 3)`` vertices at rest and unit normals.
        colors: ``(V, 4)`` vertex colours (linear RGBA, multiplied by a part's colour).
        joints, weights: ``(V, 4)`` the four most influential joints per vertex and their
            weights (summing to 1).
        parts: triangle groups by material.
        morph_targets: face units named as ARKit blendshapes.
        credits: provenance and licence lines to carry into the file.
    """

    name: str
    joint_names: tuple[str, ...]
    parents: tuple[int, ...]
    offsets: np.ndarray
    root_height: float
    positions: np.ndarray
    normals: np.ndarray
    colors: np.ndarray
    joints: np.ndarray
    weights: np.ndarray
    parts: tuple[Part, ...]
    morph_targets: tuple[MorphTarget, ...] = ()
    credits: tuple[str, ...] = field(default=())

    @property
    def rest_positions(self) -> np.ndarray:
        """``(J, 3)`` joint positions at rest, avatar frame."""
        positions = np.zeros_like(self.offsets)
        for joint, parent in enumerate(self.parents):
            positions[joint] = self.offsets[joint] + (positions[parent] if parent >= 0 else 0.0)
        return positions


def vertex_normals(positions: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Area-weighted vertex normals ``(V, 3)`` (unit; +y where no triangle uses a vertex)."""
    a, b, c = (positions[triangles[:, k]] for k in range(3))
    face = np.cross(b - a, c - a)
    normals = np.zeros_like(positions)
    for k in range(3):
        np.add.at(normals, triangles[:, k], face)
    length = np.linalg.norm(normals, axis=1, keepdims=True)
    fallback = np.tile([0.0, 1.0, 0.0], (len(positions), 1))
    return np.where(length > 1e-12, normals / np.maximum(length, 1e-12), fallback)


def strongest_influences(weights: np.ndarray, count: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` largest weights per row of a ``(V, J)`` matrix and their joints,
    renormalized to sum to 1: ``(joints (V, count) int, weights (V, count))``."""
    order = np.argsort(-weights, axis=1, kind="stable")[:, :count]
    chosen = np.take_along_axis(weights, order, axis=1)
    totals = chosen.sum(axis=1, keepdims=True)
    chosen = np.divide(chosen, totals, out=np.zeros_like(chosen), where=totals > 0)
    chosen[totals[:, 0] <= 0, 0] = 1.0
    return order.astype(np.int64), chosen
