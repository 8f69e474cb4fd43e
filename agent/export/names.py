"""Output file names that cannot escape their folder, collide, or overwrite an input.

A performance named ``x`` is saved as ``x.wav``, ``x.bvh``, ``x.timeline.json`` and
``x.html`` in the output folder. The name comes from the input file's stem or from the
caller, so it is checked: a plain file name (no folder part, not ``.`` or ``..``, no
control characters), so nothing is written outside the folder. In a batch, two inputs
with the same stem (``a/x.xml`` and ``b/x.xml``) would write the same files; the second
is refused by name, as is an input that its own or another item's output would replace.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

#: The files one performance named ``NAME`` is saved as.
PERFORMANCE_SUFFIXES: tuple[str, ...] = (".wav", ".bvh", ".timeline.json", ".face.json", ".html", ".glb")
#: Longest name accepted, characters (file systems allow 255 bytes, suffixes included).
MAX_STEM = 200


class OutputNameError(ValueError):
    """An output name that would leave its folder, collide with another, or overwrite an input."""


def check_stem(name: str) -> str:
    """``name`` when it is a plain file name stem, else :class:`OutputNameError`."""
    if not isinstance(name, str) or not name or name in (".", "..") or len(name) > MAX_STEM:
        raise OutputNameError(f"output name {name!r} is not a file name (1 to {MAX_STEM} characters, not '.' or '..')")
    if "/" in name or "\\" in name or os.sep in name or (os.altsep and os.altsep in name):
        raise OutputNameError(f"output name {name!r} has a folder part; give a plain file name")
    if any(ord(ch) < 32 or ch == "\x7f" for ch in name):
        raise OutputNameError(f"output name {name!r} holds control characters")
    return name


class OutputPlan:
    """The output names of one run: refuses a second item with the same name and any
    output path that is one of the run's inputs."""

    def __init__(self, folder: Path, inputs: Iterable[str | os.PathLike[str]]) -> None:
        self.folder = folder
        self._inputs = {_identity(Path(path)): str(path) for path in inputs}
        self._taken: dict[str, str] = {}

    def claim(self, item: str, stem: str, suffixes: tuple[str, ...] = PERFORMANCE_SUFFIXES) -> None:
        """Reserve ``stem`` (its files with ``suffixes``) for ``item``; :class:`OutputNameError` when taken or an input."""
        check_stem(stem)
        key = stem.casefold()  # two names that differ in case are one file on some file systems
        owner = self._taken.get(key)
        if owner is not None:
            raise OutputNameError(f"its output name {stem!r} is already used by {owner} in this run; "
                                  "rename one of them or render them into different folders")
        for suffix in suffixes:
            target = self.folder / f"{stem}{suffix}"
            source = self._inputs.get(_identity(target))
            if source is not None:
                raise OutputNameError(f"its output {target} would overwrite the input {source}")
        self._taken[key] = item


def _identity(path: Path) -> tuple[int, int] | str:
    """What makes two paths the same file: device and inode when it exists, else the resolved path."""
    try:
        info = path.stat()
    except OSError:
        return str(path.resolve())
    return (info.st_dev, info.st_ino)
