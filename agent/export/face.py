"""The face's morph weights as JSON: ``NAME.face.json`` and the avatar page's copy.

``NAME.face.json`` is ``{"fps": …, "names": […], "weights": [[…] per frame]}``: the 52
ARKit blendshape names (:data:`motor.face.arkit.FACE_NAMES`) and, per frame, their weights
(0–1, four significant digits), one frame per line. The avatar page embeds the same
weights for the names that move at all (``script#mura-face``), so that a page stays small.

:class:`FaceWriter` collects the weights window by window in a scratch file (binary
``float32``, the caller's to remove) and writes both texts in blocks; the in-memory path
(:func:`face_json`, :func:`page_face_json`) goes through the same formatting, so the
bytes are equal.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Iterator
from pathlib import Path

import numpy as np

from agent.export.staging import ScratchRows
from motor.face.arkit import FACE_NAMES
from motor.motion import Motion

#: Frames formatted at a time.
FRAMES_PER_BLOCK = 4096


def face_weights(motion: Motion) -> np.ndarray:
    """A motion's weights ``(n, 52)`` in :data:`FACE_NAMES` order (zeros without a face)."""
    out = np.zeros((motion.frame_count, len(FACE_NAMES)), dtype=np.float32)
    if motion.face_weights is None:
        return out
    for column, name in enumerate(motion.face_names):
        if name not in FACE_NAMES:
            raise ValueError(f"face export: {name!r} is not an ARKit blendshape name")
        out[:, FACE_NAMES.index(name)] = motion.face_weights[:, column]
    return out


def json_blocks(fps: float, names: tuple[str, ...], blocks: Iterable[np.ndarray]) -> Iterator[str]:
    """The face JSON text in pieces: ``names`` and the rows of ``blocks`` (``(k, len(names))``)."""
    yield '{"fps": ' + repr(float(fps)) + ', "names": [' + ", ".join(f'"{name}"' for name in names) + '], "weights": [\n'
    pattern = "[" + ",".join(["%.4g"] * len(names)) + "]"
    first = True
    for block in blocks:
        rows = np.asarray(block, dtype=np.float32).astype(np.float64) + 0.0
        if rows.shape[0] == 0:
            continue
        text = ",\n".join(pattern % tuple(row) for row in rows)
        yield text if first else ",\n" + text
        first = False
    yield "\n]}\n"


def face_json(motion: Motion) -> str:
    """``NAME.face.json`` of a whole motion."""
    return "".join(json_blocks(motion.fps, FACE_NAMES, _blocks(face_weights(motion))))


def page_face_json(motion: Motion) -> str:
    """The page's face JSON of a whole motion: the names that move, and their weights."""
    weights = face_weights(motion)
    used = np.flatnonzero(weights.max(axis=0, initial=0.0) > 0.0)
    return "".join(json_blocks(motion.fps, tuple(FACE_NAMES[i] for i in used), _blocks(weights[:, used])))


class FaceWriter:
    """Face weights collected window by window (module docstring)."""

    def __init__(self, scratch: str | os.PathLike[str]) -> None:
        self.scratch = Path(scratch)
        self.fps: float | None = None
        self.frame_count = 0
        self._peak = np.zeros(len(FACE_NAMES), dtype=np.float32)
        self._out = open(self.scratch, "wb")

    def add(self, window: Motion) -> None:
        if self.fps is None:
            self.fps = window.fps
        weights = face_weights(window)
        self._peak = np.maximum(self._peak, weights.max(axis=0, initial=0.0))
        self._out.write(np.ascontiguousarray(weights, dtype="<f4").tobytes())
        self.frame_count += window.frame_count

    def close(self) -> None:
        if not self._out.closed:
            self._out.close()

    def json_blocks(self) -> Iterator[str]:
        """``NAME.face.json`` in pieces."""
        return json_blocks(self._fps(), FACE_NAMES, self._read(np.arange(len(FACE_NAMES))))

    def page_blocks(self) -> Iterator[str]:
        """The page's face JSON in pieces."""
        used = np.flatnonzero(self._peak > 0.0)
        return json_blocks(self._fps(), tuple(FACE_NAMES[i] for i in used), self._read(used))

    def _fps(self) -> float:
        self.close()
        if self.fps is None:
            raise ValueError("face export: no frames were added")
        return self.fps

    def _read(self, columns: np.ndarray) -> Iterator[np.ndarray]:
        """The weights' ``columns``, :data:`FRAMES_PER_BLOCK` frames at a time, read from the
        scratch file a block at a time (:class:`agent.export.staging.ScratchRows`: a map
        of the whole file would keep its pages resident, 45 MB per hour at 60 fps)."""
        frames = ScratchRows(self.scratch, self.frame_count, len(FACE_NAMES), "<f4")
        for start in range(0, self.frame_count, FRAMES_PER_BLOCK):
            yield frames[start : start + FRAMES_PER_BLOCK][:, columns]


def _blocks(weights: np.ndarray) -> Iterator[np.ndarray]:
    for start in range(0, weights.shape[0], FRAMES_PER_BLOCK):
        yield weights[start : start + FRAMES_PER_BLOCK]
