"""The hand orientations a collection of signs writes, for computing their rotations at once.

Compiling a collection of signs asks for the global rotation of every hand orientation it
meets (:meth:`motor.signing.hand_geometry.HandGeometry.rotation`), one at a time as the signs
are compiled: some 360 for both corpora, each a dozen numpy operations on one row. Nearly
all of them pair an extended-finger direction and a palm direction that some sign writes
(in a posture or in its movement), each as written or mirrored across the sagittal plane
(the other hand of a symmetric sign). :func:`written_orientations` lists every such pair,
so that their rotations are computed in one vectorized pass per side before the signs are
compiled (:meth:`~motor.signing.hand_geometry.HandGeometry.prefetch_rotations`); any other
orientation (a relative palm turned with its fingers) is computed when asked, as before.
"""

from __future__ import annotations

import struct
from collections.abc import Iterable, Iterator

import numpy as np

from mura.constraints import Static, iter_leaves
from mura.signs import Sign
from mura.values import Direction, PalmOrientation


def written_orientations(
    signs: Iterable[Sign], fingers: Iterable[tuple[float, float, float]], palms: Iterable[tuple[float, float, float]]
) -> tuple[np.ndarray, np.ndarray]:
    """Every pair of an extended-finger direction and a palm direction ``(n, 3)`` each:
    the directions ``signs`` write and the ``fingers`` and ``palms`` given besides (a
    planner's defaults), each as written and mirrored across the sagittal plane (x negated,
    as :func:`motor.trajectory.symmetry.mirror_directions` gives it: a zero becomes −0)."""
    written_fingers, written_palms = list(fingers), list(palms)
    for sign in signs:
        for value in _written_values(sign):
            if isinstance(value, Direction):
                written_fingers.append(value.vector)
            elif isinstance(value, PalmOrientation):
                written_palms.append(value.direction)
    finger_rows, palm_rows = _mirrored_rows(written_fingers), _mirrored_rows(written_palms)
    return np.repeat(finger_rows, len(palm_rows), axis=0), np.tile(palm_rows, (len(finger_rows), 1))


def _written_values(sign: Sign) -> Iterator[object]:
    """The values of the sign's postures and of its movement's leaves and segments."""
    for posture in (sign.posture, sign.nondominant):
        if posture is not None:
            yield posture.ext_finger
            yield posture.palm
    if sign.movement is None:
        return
    for leaf in iter_leaves(sign.movement):
        if isinstance(leaf, Static):
            yield leaf.value
        else:
            for segment in leaf.segments:
                yield segment.start
                yield segment.end


def _mirrored_rows(vectors: list[tuple[float, float, float]]) -> np.ndarray:
    """The distinct rows ``(k, 3)`` of ``vectors`` and of their mirror images, distinct by
    their bytes (so that 0 and −0, which rotation memo keys tell apart, both stay)."""
    rows = np.asarray(_first_of_each(vectors), dtype=float).reshape(-1, 3)
    rows = np.concatenate([rows, rows * np.array([-1.0, 1.0, 1.0])])
    distinct = {row.tobytes(): row for row in rows}
    return np.array(list(distinct.values())).reshape(-1, 3)


def _first_of_each(vectors: list[tuple[float, float, float]]) -> list[tuple[float, float, float]]:
    """``vectors`` in the order written, each set of the very same three float64 numbers
    once (their packed bytes, which tell 0 from −0 as the rows' do): the corpora write
    ~9,000 vectors, ~60 of them distinct, and numpy converts tuples one by one. Anything
    but triples of numbers is left as it is, for numpy to refuse."""
    try:
        return list({struct.pack("3d", *vector): vector for vector in vectors}.values())
    except (struct.error, TypeError):
        return vectors
