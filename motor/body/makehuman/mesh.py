"""The MakeHuman base mesh (hm08) and its targets, read into numpy arrays.

The OBJ is in decimetres with y up and the body facing +z, +x its left — mura's axes —
so reading it only scales by :data:`METRES_PER_UNIT`. Quads are split into two
triangles along their first diagonal. Targets (``.target`` files: ``vertex dx dy dz``
lines, the same units) are sparse vertex offsets.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Base-mesh unit (decimetre) in metres.
METRES_PER_UNIT = 0.1


@dataclass(frozen=True, eq=False)
class BaseMesh:
    """The whole base mesh, body and helper geometry.

    Attributes:
        positions: ``(V, 3)`` vertex positions, metres, mura's axes.
        uvs: ``(V, 2)`` one texture coordinate per vertex (the first the faces give it).
        triangles: ``(T, 3)`` vertex indices, counter-clockwise seen from outside.
        triangle_groups: ``(T,)`` index into ``groups`` of each triangle's face group.
        groups: face-group names in file order (``body``, ``helper-l-eye``, ``joint-…``).
    """

    positions: np.ndarray
    uvs: np.ndarray
    triangles: np.ndarray
    triangle_groups: np.ndarray
    groups: tuple[str, ...]

    def group_triangles(self, *names: str) -> np.ndarray:
        """Triangles ``(k, 3)`` of the named face groups (names are matched exactly or as prefixes ending in ``-``)."""
        wanted = [i for i, group in enumerate(self.groups) if any(group == n or group.startswith(n + "-") for n in names)]
        return self.triangles[np.isin(self.triangle_groups, wanted)]


def read_obj(text: str) -> BaseMesh:
    """Parse the base mesh OBJ text (``v``, ``vt``, ``g`` and ``f`` records)."""
    positions: list[list[float]] = []
    uvs: list[list[float]] = []
    triangles: list[tuple[int, int, int]] = []
    corners_uv: list[tuple[int, int]] = []
    triangle_groups: list[int] = []
    groups: list[str] = []
    group = -1
    for line in text.splitlines():
        if line.startswith("v "):
            positions.append([float(v) for v in line.split()[1:4]])
        elif line.startswith("vt "):
            uvs.append([float(v) for v in line.split()[1:3]])
        elif line.startswith("g "):
            name = line[2:].strip()
            if name not in groups:
                groups.append(name)
            group = groups.index(name)
        elif line.startswith("f "):
            corners = [corner.split("/") for corner in line.split()[1:]]
            vertex = [int(c[0]) - 1 for c in corners]
            for c in corners:
                if len(c) > 1 and c[1]:
                    corners_uv.append((int(c[0]) - 1, int(c[1]) - 1))
            for k in range(1, len(vertex) - 1):
                triangles.append((vertex[0], vertex[k], vertex[k + 1]))
                triangle_groups.append(group)
    points = np.array(positions) * METRES_PER_UNIT
    per_vertex = np.zeros((len(points), 2))
    if corners_uv and uvs:
        pairs = np.array(corners_uv)
        # the first texture coordinate each vertex is given (reversed so the first wins)
        per_vertex[pairs[::-1, 0]] = np.array(uvs)[pairs[::-1, 1]]
    return BaseMesh(
        positions=points,
        uvs=per_vertex,
        triangles=np.array(triangles, dtype=np.int64),
        triangle_groups=np.array(triangle_groups, dtype=np.int64),
        groups=tuple(groups),
    )


def read_target(text: str, vertex_count: int, where: str) -> tuple[np.ndarray, np.ndarray]:
    """A sparse target: vertex indices ``(k,)`` ascending and offsets ``(k, 3)`` in metres.

    Raises ValueError naming ``where`` and the line of a malformed record.
    """
    indices: list[int] = []
    offsets: list[list[float]] = []
    for number, line in enumerate(text.splitlines(), start=1):
        fields = line.split()
        if not fields or fields[0].startswith("#"):
            continue
        if len(fields) != 4:
            raise ValueError(f"{where}:{number}: expected 'vertex dx dy dz', got {line!r}")
        vertex = int(fields[0])
        if not 0 <= vertex < vertex_count:
            raise ValueError(f"{where}:{number}: vertex {vertex} outside the mesh's {vertex_count}")
        indices.append(vertex)
        offsets.append([float(v) for v in fields[1:]])
    order = np.argsort(indices, kind="stable")
    return np.array(indices, dtype=np.int64)[order], np.array(offsets)[order] * METRES_PER_UNIT


def vertex_group_ranges(groups: dict[str, list[list[int]]], name: str) -> np.ndarray:
    """Vertex indices of a named vertex group given as inclusive ``[first, last]`` ranges."""
    if name not in groups:
        raise KeyError(f"the base mesh has no vertex group {name!r}")
    return np.concatenate([np.arange(first, last + 1) for first, last in groups[name]])
