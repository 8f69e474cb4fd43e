"""Files that appear only when complete, and runs that leave the output folder as it was.

Every output is written under a hidden temporary name beside its target (``.NAME.xxx.part``)
and renamed into place when it is whole — a rename within one folder is atomic — so a
reader never finds a half-written file under the real name, and a failure leaves nothing
that looks finished. Temporary files are created private (mode 0600); a published file
gets the usual permissions (0666 less the process's umask), like any file the user writes.

A command that writes many files (``mura render a.xml b.xml``, ``mura sign corpus.sigml``)
writes them into a hidden folder of its own inside the output folder (:class:`StagedRun`)
and moves them into place when the run ends; interrupted (Ctrl-C, SIGTERM) or failed as a
whole, the run removes that folder, and the output folder is exactly as before the run —
no temporary file, no half of a batch. Renames and removals run with the interrupt
signals held back (:func:`~agent.signals.signals_deferred`), so that a signal cannot cut
a publication in half.

Writers that stream frames keep them in scratch files until the end and read them back a
run of rows at a time (:class:`ScratchRows`), so that memory does not grow with the length.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import BinaryIO, TextIO

import numpy as np

from agent.signals import signals_deferred

#: Prefix of the hidden folder a run writes into before its files are moved into place.
RUN_FOLDER_PREFIX = ".mura-run-"


class OutputFolderError(OSError):
    """An output folder (or file) that cannot be created or written, said in one line."""


def _current_umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


#: The process's file-creation mask, read once at start-up (reading it means setting it).
UMASK = _current_umask()


def publish(temporary: Path, target: Path) -> None:
    """Give ``temporary`` the usual permissions and rename it to ``target``."""
    os.chmod(temporary, 0o666 & ~UMASK)
    with signals_deferred():
        os.replace(temporary, target)


@contextmanager
def staged_text(target: str | os.PathLike[str], encoding: str = "utf-8") -> Iterator[TextIO]:
    """A text stream whose content becomes ``target`` only if the block ends without error."""
    with staged_file(target) as temporary, open(temporary, "w", encoding=encoding, newline="\n") as stream:
        yield stream


@contextmanager
def staged_file(target: str | os.PathLike[str]) -> Iterator[Path]:
    """A fresh hidden file beside ``target`` that becomes ``target`` only if the block ends
    without error (removed otherwise, interrupts included)."""
    path = Path(target)
    handle, name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".part")
    os.close(handle)
    temporary = Path(name)
    try:
        yield temporary
    except BaseException:
        with signals_deferred():
            temporary.unlink(missing_ok=True)
        raise
    try:
        publish(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


@contextmanager
def staged_binary(target: str | os.PathLike[str]) -> Iterator[BinaryIO]:
    """A binary stream whose content becomes ``target`` only if the block ends without error."""
    path = Path(target)
    handle, name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".part")
    temporary = Path(name)
    try:
        with os.fdopen(handle, "wb") as stream:
            yield stream
        publish(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


class Staging:
    """Files written under temporary names in one folder: all published, or all removed."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self._staged: list[tuple[Path, Path | None]] = []

    def temporary(self, target: Path, suffix: str = ".part") -> Path:
        """A fresh hidden file beside ``target``, renamed to it by :meth:`publish`."""
        return self._make(target, target, suffix)

    def scratch(self, target: Path, suffix: str) -> Path:
        """A fresh hidden file named after ``target``, removed by both :meth:`publish` and :meth:`discard`."""
        return self._make(target, None, suffix)

    def publish(self) -> None:
        """Rename every temporary file to its target, then remove the scratch files."""
        with signals_deferred():
            for temporary, target in self._staged:
                if target is not None:
                    publish(temporary, target)
            self.discard()

    def discard(self) -> None:
        """Remove every file still staged."""
        with signals_deferred():
            for temporary, _ in self._staged:
                temporary.unlink(missing_ok=True)
            self._staged = []

    def _make(self, name_from: Path, target: Path | None, suffix: str) -> Path:
        handle, name = tempfile.mkstemp(dir=self.folder, prefix=f".{name_from.name}.", suffix=suffix)
        os.close(handle)
        self._staged.append((Path(name), target))
        return Path(name)


def make_folder(folder: Path) -> list[Path]:
    """Create ``folder`` and its missing parents; returns those created, outermost first.
    Failures are :class:`OutputFolderError` saying what is in the way."""
    missing = [parent for parent in (folder, *folder.parents) if not parent.exists()][::-1]
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        raise OutputFolderError(f"output folder {folder}: a file of that name is in the way") from None
    except NotADirectoryError:
        raise OutputFolderError(f"output folder {folder}: a part of the path is a file, not a folder") from None
    except OSError as error:
        raise OutputFolderError(f"output folder {folder}: cannot create it ({error.strerror or error})") from None
    if not folder.is_dir():
        raise OutputFolderError(f"output folder {folder}: a file of that name is in the way")
    return missing


class StagedRun:
    """The outputs of one command run: written into a hidden folder inside ``output`` and
    moved into ``output`` by :meth:`commit`; anything else (an error, Ctrl-C, SIGTERM)
    removes them, and the folders the run created, on leaving the ``with`` block.

    ``folder`` is where the run's items write their files (under their final names);
    :meth:`beside` stages a file that goes elsewhere (a report).
    """

    def __init__(self, output: str | os.PathLike[str]) -> None:
        self.output = Path(output)
        self._created = make_folder(self.output)
        try:
            self.folder = Path(tempfile.mkdtemp(dir=self.output, prefix=RUN_FOLDER_PREFIX))
        except OSError as error:
            self._remove_created()
            raise OutputFolderError(f"output folder {self.output}: cannot write into it ({error.strerror or error})") from None
        self._elsewhere: list[tuple[Path, Path]] = []
        self._done = False

    def __enter__(self) -> StagedRun:
        return self

    def __exit__(self, *exc_info: object) -> None:
        if not self._done:
            self.abort()

    def beside(self, target: str | os.PathLike[str]) -> Path:
        """A fresh hidden file beside ``target`` (parents created), renamed to it by :meth:`commit`."""
        path = Path(target)
        if path.is_dir():
            raise OutputFolderError(f"{path}: is a folder; give a file name")
        self._created += make_folder(path.parent)
        handle, name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".part")
        os.close(handle)
        self._elsewhere.append((Path(name), path))
        return Path(name)

    def commit(self) -> list[Path]:
        """Move every file the run wrote into ``output`` (and the files staged beside their
        targets into place); returns the final paths."""
        published = []
        with signals_deferred():
            for item in sorted(self.folder.iterdir()):
                if item.name.startswith(".") or not item.is_file():
                    continue
                target = self.output / item.name
                os.replace(item, target)
                published.append(target)
            for temporary, target in self._elsewhere:
                publish(temporary, target)
                published.append(target)
            shutil.rmtree(self.folder, ignore_errors=True)
            self._done = True
        return published

    def abort(self) -> None:
        """Remove everything the run wrote and the folders it created."""
        with signals_deferred():
            shutil.rmtree(self.folder, ignore_errors=True)
            for temporary, _ in self._elsewhere:
                temporary.unlink(missing_ok=True)
            self._remove_created()
            self._done = True

    def _remove_created(self) -> None:
        for folder in reversed(self._created):
            try:
                folder.rmdir()
            except OSError:
                break  # not empty (someone else wrote there): leave it


class ScratchRows:
    """Rows of ``width`` numbers of ``dtype`` (little-endian, as written) in a scratch
    file, read back a run of rows at a time: each run is mapped on its own and unmapped
    once its caller lets go of it. A map of the whole file would count every page it has
    read in the process's resident memory until the end — for the GLB's frames, which
    every glTF channel reads whole, about 470 MB per hour at 60 fps."""

    def __init__(self, path: Path, count: int, width: int, dtype: str) -> None:
        self.path = path
        self.shape = (count, width)
        self.dtype = np.dtype(dtype)

    def __getitem__(self, rows: slice) -> np.ndarray:
        count, width = self.shape
        start, stop, step = rows.indices(count)
        if step != 1:
            raise IndexError("scratch rows are read in runs")
        if stop <= start:
            return np.zeros((0, width), dtype=self.dtype)
        return np.memmap(self.path, dtype=self.dtype, mode="r", offset=start * width * self.dtype.itemsize, shape=(stop - start, width))
