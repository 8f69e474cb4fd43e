"""Biovision Hierarchy (BVH) export of a :class:`~motor.motion.Motion`.

The file follows the layout Blender and three.js ``BVHLoader`` read:

* ``ROOT`` with six channels ``Xposition Yposition Zposition Zrotation Xrotation Yrotation``,
  every ``JOINT`` with three ``Zrotation Xrotation Yrotation``, an ``End Site`` below every
  leaf joint.
* Lengths are in **centimetres** (BVH has no unit field; centimetres is what most tools
  assume). The root's ``OFFSET`` is zero and its position channels carry the absolute root
  position, so loaders that add the offset to the channels (three.js) and loaders that take
  the channels as the position (Blender) agree.
* Rotations are Euler angles in degrees. BVH applies the channels in their listed order as
  intrinsic rotations, so ``Zrotation Xrotation Yrotation`` means ``R = Rz · Rx · Ry``,
  which is scipy's intrinsic ``"ZXY"`` sequence.
* ``Frame Time`` is ``1 / fps``. BVH has no start time: frame 0 is written as if at
  ``motion.start_time``, which the caller keeps track of.

A motion too long to hold goes through :class:`StreamingBvh`: windows of frames are
converted as they come, their lines kept in a scratch file, and the header (whose
``Frames:`` count is known only at the end) is written before them when the file is made.
The bytes are the same as :func:`write_bvh` writes for the whole motion.
"""

from __future__ import annotations

import io
import os
import shutil
from collections.abc import Iterator
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from agent.export.fixed_point import FORMAT, fixed_lines
from agent.export.staging import staged_text
from motor.motion import Motion

CENTIMETRES_PER_METRE = 100.0
ROOT_CHANNELS = "Xposition Yposition Zposition Zrotation Xrotation Yrotation"
JOINT_CHANNELS = "Zrotation Xrotation Yrotation"
EULER_SEQUENCE = "ZXY"
END_SITE_FRACTION = 0.75
"""End-site length as a fraction of the leaf's own bone (a fingertip continues its phalanx)."""
END_SITE_FALLBACK_CM = 2.0
"""End-site length when a leaf has no bone direction to follow (a zero offset), centimetres."""
VALUE_FORMAT = FORMAT
"""How every number of the file is written (the frames by :func:`~agent.export.fixed_point.fixed_lines`)."""
FRAMES_PER_BLOCK = 2048
"""Frames formatted by one compiled pass when writing the MOTION block."""
COPY_BLOCK_CHARS = 1 << 20
"""Characters of frame lines copied or yielded at a time by :class:`StreamingBvh`."""


def bvh_text(motion: Motion) -> str:
    """The whole BVH file for ``motion`` as a string (lengths in centimetres)."""
    buffer = io.StringIO()
    _write(motion, buffer)
    return buffer.getvalue()


def write_bvh(motion: Motion, path: str | os.PathLike[str]) -> None:
    """Write ``motion`` as a BVH file at ``path`` (lengths in centimetres).

    The file is written under a temporary name in the same folder and renamed when
    complete, so a reader never sees a half-written file under ``path``.
    """
    with staged_text(path, encoding="ascii") as stream:
        _write(motion, stream)


class StreamingBvh:
    """A BVH file made from windows of frames whose total is known only at the end.

    ``add(window)`` converts the window's frames (a block at a time) into lines appended to
    ``scratch``, a text file the caller owns; ``write(stream)`` then writes the header and
    copies the lines after it, and ``text_blocks()`` yields the same text in pieces (for a
    page that embeds it). Memory holds at most :data:`FRAMES_PER_BLOCK` frames.
    """

    def __init__(self, scratch: str | os.PathLike[str]) -> None:
        self.scratch = Path(scratch)
        self.frame_count = 0
        self._skeleton: Motion | None = None
        self._pending: list[Motion] = []
        self._pending_frames = 0
        self._lines = open(self.scratch, "w", encoding="ascii", newline="\n")

    @property
    def skeleton(self) -> Motion | None:
        """The first window added: its joints, offsets and fps head the file."""
        return self._skeleton

    def add(self, window: Motion) -> None:
        """Append ``window``'s frames (same skeleton and fps as the first window)."""
        if self._skeleton is None:
            _check_skeleton(window)
            self._skeleton = window
        else:
            _check_same_skeleton(self._skeleton, window, self.frame_count + self._pending_frames)
        _check_values(window, self.frame_count + self._pending_frames)
        self._pending.append(window)
        self._pending_frames += window.frame_count
        if self._pending_frames >= FRAMES_PER_BLOCK:
            self._flush()

    def close(self) -> None:
        """Write the frames still buffered and close the scratch file (no more windows)."""
        if self._lines.closed:
            return
        self._flush()
        self._lines.close()

    def header(self) -> str:
        """Everything before the frame lines, ``Frames:`` being the count added so far."""
        if self._skeleton is None:
            raise ValueError("BVH export: no frames were added, so there is no skeleton to write")
        return bvh_header(self._skeleton, self.frame_count)

    def write(self, stream: io.TextIOBase) -> None:
        """The whole file: header, then the frame lines copied from the scratch file in blocks."""
        self.close()
        stream.write(self.header())
        with open(self.scratch, encoding="ascii", newline="\n") as lines:
            shutil.copyfileobj(lines, stream, COPY_BLOCK_CHARS)

    def text_blocks(self) -> Iterator[str]:
        """The whole file as pieces of text: the header first, then blocks of frame lines."""
        self.close()
        yield self.header()
        with open(self.scratch, encoding="ascii", newline="\n") as lines:
            while block := lines.read(COPY_BLOCK_CHARS):
                yield block

    def _flush(self) -> None:
        if not self._pending:
            return
        rotations = np.concatenate([m.rotations for m in self._pending])
        translation = np.concatenate([m.root_translation for m in self._pending])
        order = _depth_first_order(_children(self._skeleton.parents))
        _write_frames(_channel_values_of(rotations, translation, order), self._lines)
        self.frame_count += self._pending_frames
        self._pending, self._pending_frames = [], 0


def bvh_header(motion: Motion, frame_count: int) -> str:
    """The BVH text before the frame lines for ``motion``'s skeleton and ``frame_count`` frames."""
    _check_skeleton(motion)
    buffer = io.StringIO()
    buffer.write("HIERARCHY\n")
    _write_hierarchy(motion, _children(motion.parents), buffer)
    buffer.write("MOTION\n")
    buffer.write(f"Frames: {frame_count}\n")
    buffer.write(f"Frame Time: {1.0 / motion.fps:.8f}\n")
    return buffer.getvalue()


def _write(motion: Motion, stream: io.TextIOBase) -> None:
    _check(motion)
    stream.write(bvh_header(motion, motion.frame_count))
    _write_frames(_channel_values(motion, _depth_first_order(_children(motion.parents))), stream)


def _check(motion: Motion) -> None:
    """Reject what BVH cannot express, naming the joint at fault."""
    _check_skeleton(motion)
    _check_values(motion, 0)


def _check_skeleton(motion: Motion) -> None:
    """One root first, parents before children, joint names that are single tokens."""
    roots = [index for index, parent in enumerate(motion.parents) if parent < 0]
    if roots != [0]:
        raise ValueError(f"BVH export: needs exactly one root joint at index 0, found roots at {roots}")
    for index, (name, parent) in enumerate(zip(motion.joint_names, motion.parents)):
        if not name or any(character.isspace() for character in name) or name in ("{", "}"):
            raise ValueError(f"BVH export: joint {index} has name {name!r}, which is not a single BVH token")
        if index > 0 and not 0 <= parent < index:
            raise ValueError(
                f"BVH export: joint {index} ({name}) has parent {parent}; parents must come before children"
            )


def _check_same_skeleton(first: Motion, window: Motion, frame: int) -> None:
    same = (
        window.joint_names == first.joint_names
        and window.parents == first.parents
        and window.fps == first.fps
        and np.array_equal(window.offsets, first.offsets)
    )
    if not same:
        raise ValueError(f"BVH export: the frames from frame {frame} on have another skeleton or frame rate than frame 0")


def _check_values(motion: Motion, first_frame: int) -> None:
    """Finite offsets, rotations and root positions and no zero quaternion; frames are
    reported counted from ``first_frame`` (where this window starts in the whole motion)."""
    for label, array, frames in (
        ("offsets", motion.offsets, False),
        ("rotations", motion.rotations, True),
        ("root_translation", motion.root_translation, True),
    ):
        if not np.all(np.isfinite(array)):
            frame_or_joint = np.argwhere(~np.isfinite(array))[0].tolist()
            if frames:
                frame_or_joint[0] += first_frame
            raise ValueError(f"BVH export: non-finite value in {label} at index {frame_or_joint}")
    norms = np.linalg.norm(motion.rotations, axis=-1)
    if np.any(norms < 1e-9):
        frame, joint = np.argwhere(norms < 1e-9)[0]
        raise ValueError(
            f"BVH export: zero quaternion at frame {first_frame + frame}, joint {joint} ({motion.joint_names[joint]})"
        )


def _children(parents: tuple[int, ...]) -> list[list[int]]:
    children: list[list[int]] = [[] for _ in parents]
    for index, parent in enumerate(parents):
        if parent >= 0:
            children[parent].append(index)
    return children


def _depth_first_order(children: list[list[int]]) -> list[int]:
    """Joint indices in the order BVH lists them (and their channels): depth first from the root."""
    order: list[int] = []
    stack = [0]
    while stack:
        joint = stack.pop()
        order.append(joint)
        stack.extend(reversed(children[joint]))
    return order


def _write_hierarchy(motion: Motion, children: list[list[int]], stream: io.TextIOBase) -> None:
    offsets_cm = motion.offsets * CENTIMETRES_PER_METRE
    # (joint, depth, closing) items; closing items emit the brace that ends a joint.
    stack: list[tuple[int, int, bool]] = [(0, 0, False)]
    while stack:
        joint, depth, closing = stack.pop()
        indent = "\t" * depth
        if closing:
            stream.write(f"{indent}}}\n")
            continue
        if joint == 0:
            stream.write(f"ROOT {motion.joint_names[0]}\n{{\n\tOFFSET 0.000000 0.000000 0.000000\n")
            stream.write(f"\tCHANNELS 6 {ROOT_CHANNELS}\n")
        else:
            stream.write(f"{indent}JOINT {motion.joint_names[joint]}\n{indent}{{\n")
            stream.write(f"{indent}\tOFFSET {_format_vector(offsets_cm[joint])}\n")
            stream.write(f"{indent}\tCHANNELS 3 {JOINT_CHANNELS}\n")
        if not children[joint]:
            end = _end_site_offset(offsets_cm, motion.parents, joint)
            stream.write(f"{indent}\tEnd Site\n{indent}\t{{\n{indent}\t\tOFFSET {_format_vector(end)}\n{indent}\t}}\n")
        stack.append((joint, depth, True))
        stack.extend((child, depth + 1, False) for child in reversed(children[joint]))


def _end_site_offset(offsets_cm: np.ndarray, parents: tuple[int, ...], leaf: int) -> np.ndarray:
    """A short continuation of the leaf's bone (or of its parent's, if the leaf has none)."""
    for joint in (leaf, parents[leaf]):
        if joint <= 0:
            break
        length = float(np.linalg.norm(offsets_cm[joint]))
        if length > 1e-6:
            return offsets_cm[joint] * END_SITE_FRACTION
    return np.array([0.0, END_SITE_FALLBACK_CM, 0.0])


def _format_vector(vector: np.ndarray) -> str:
    return " ".join(VALUE_FORMAT % (value + 0.0) for value in vector)


def _channel_values(motion: Motion, order: list[int]) -> np.ndarray:
    """``(n, 6 + 3 (J-1))`` channel values in file order: root position (cm), then ZXY degrees."""
    return _channel_values_of(motion.rotations, motion.root_translation, order)


def _channel_values_of(rotations: np.ndarray, root_translation: np.ndarray, order: list[int]) -> np.ndarray:
    frames = rotations.shape[0]
    if frames == 0:
        return np.zeros((0, 3 + 3 * len(order)))
    ordered = rotations[:, order, :].reshape(-1, 4)
    euler = Rotation.from_quat(ordered).as_euler(EULER_SEQUENCE, degrees=True).reshape(frames, 3 * len(order))
    position = root_translation * CENTIMETRES_PER_METRE
    return np.concatenate([position, euler], axis=1)


def _write_frames(values: np.ndarray, stream: io.TextIOBase) -> None:
    """One line per frame, each number as :data:`VALUE_FORMAT` writes it, a block of
    frames per compiled pass (:func:`agent.export.fixed_point.fixed_lines`)."""
    if values.shape[0] == 0:
        return
    values = values + 0.0  # turns -0.0 into 0.0 so the text is tidy
    for start in range(0, values.shape[0], FRAMES_PER_BLOCK):
        stream.write(fixed_lines(values[start : start + FRAMES_PER_BLOCK]))
