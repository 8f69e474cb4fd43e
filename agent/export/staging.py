"""Files that appear only when complete.

Every output is written under a hidden temporary name beside its target (``.NAME.xxx.part``)
and renamed into place when it is whole — a rename within one folder is atomic — so a
reader never finds a half-written file under the real name, and a failure leaves nothing
that looks finished. Temporary files are created private (mode 0600); a published file
gets the usual permissions (0666 less the process's umask), like any file the user writes.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import BinaryIO, TextIO


def _current_umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


#: The process's file-creation mask, read once at start-up (reading it means setting it).
UMASK = _current_umask()


def publish(temporary: Path, target: Path) -> None:
    """Give ``temporary`` the usual permissions and rename it to ``target``."""
    os.chmod(temporary, 0o666 & ~UMASK)
    os.replace(temporary, target)


@contextmanager
def staged_text(target: str | os.PathLike[str], encoding: str = "utf-8") -> Iterator[TextIO]:
    """A text stream whose content becomes ``target`` only if the block ends without error."""
    path = Path(target)
    handle, name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".part")
    temporary = Path(name)
    try:
        with os.fdopen(handle, "w", encoding=encoding, newline="\n") as stream:
            yield stream
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
        for temporary, target in self._staged:
            if target is not None:
                publish(temporary, target)
        self.discard()

    def discard(self) -> None:
        """Remove every file still staged."""
        for temporary, _ in self._staged:
            temporary.unlink(missing_ok=True)
        self._staged = []

    def _make(self, name_from: Path, target: Path | None, suffix: str) -> Path:
        handle, name = tempfile.mkstemp(dir=self.folder, prefix=f".{name_from.name}.", suffix=suffix)
        os.close(handle)
        self._staged.append((Path(name), target))
        return Path(name)
