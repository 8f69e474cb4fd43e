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
"""

from __future__ import annotations

import io
import os
import tempfile
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from motor.motion import Motion

CENTIMETRES_PER_METRE = 100.0
ROOT_CHANNELS = "Xposition Yposition Zposition Zrotation Xrotation Yrotation"
JOINT_CHANNELS = "Zrotation Xrotation Yrotation"
EULER_SEQUENCE = "ZXY"
END_SITE_FRACTION = 0.75
"""End-site length as a fraction of the leaf's own bone (a fingertip continues its phalanx)."""
END_SITE_FALLBACK_CM = 2.0
"""End-site length when a leaf has no bone direction to follow (a zero offset), centimetres."""
VALUE_FORMAT = "%.6f"
FRAMES_PER_BLOCK = 2048
"""Frames formatted by one string operation when writing the MOTION block."""


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
    target = Path(path)
    handle, temporary = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".part")
    try:
        with os.fdopen(handle, "w", encoding="ascii", newline="\n") as stream:
            _write(motion, stream)
        os.replace(temporary, target)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


def _write(motion: Motion, stream: io.TextIOBase) -> None:
    _check(motion)
    children = _children(motion.parents)
    order = _depth_first_order(children)
    stream.write("HIERARCHY\n")
    _write_hierarchy(motion, children, stream)
    stream.write("MOTION\n")
    stream.write(f"Frames: {motion.frame_count}\n")
    stream.write(f"Frame Time: {1.0 / motion.fps:.8f}\n")
    _write_frames(_channel_values(motion, order), stream)


def _check(motion: Motion) -> None:
    """Reject what BVH cannot express, naming the joint at fault."""
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
    for label, array in (
        ("offsets", motion.offsets),
        ("rotations", motion.rotations),
        ("root_translation", motion.root_translation),
    ):
        if not np.all(np.isfinite(array)):
            frame_or_joint = np.argwhere(~np.isfinite(array))[0].tolist()
            raise ValueError(f"BVH export: non-finite value in {label} at index {frame_or_joint}")
    norms = np.linalg.norm(motion.rotations, axis=-1)
    if np.any(norms < 1e-9):
        frame, joint = np.argwhere(norms < 1e-9)[0]
        raise ValueError(
            f"BVH export: zero quaternion at frame {frame}, joint {joint} ({motion.joint_names[joint]})"
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
    frames = motion.frame_count
    ordered = motion.rotations[:, order, :].reshape(-1, 4)
    euler = Rotation.from_quat(ordered).as_euler(EULER_SEQUENCE, degrees=True).reshape(frames, 3 * len(order))
    position = motion.root_translation * CENTIMETRES_PER_METRE
    return np.concatenate([position, euler], axis=1)


def _write_frames(values: np.ndarray, stream: io.TextIOBase) -> None:
    """One line per frame, formatted a block of frames per string operation."""
    if values.shape[0] == 0:
        return
    row = " ".join([VALUE_FORMAT] * values.shape[1]) + "\n"
    values = values + 0.0  # turns -0.0 into 0.0 so the text is tidy
    for start in range(0, values.shape[0], FRAMES_PER_BLOCK):
        block = values[start : start + FRAMES_PER_BLOCK]
        stream.write((row * block.shape[0]) % tuple(block.ravel().tolist()))
