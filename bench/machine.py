"""The machine and the software versions a set of benchmark figures was measured with.

Figures mean little without the machine: :func:`machine_info` records the CPU model and
core count, Python and the numerical libraries, the espeak-ng library (asked in a
subprocess: once loaded in this process, pyttsx3 could no longer share it) and the git
commit of the working tree.
"""

from __future__ import annotations

import importlib.metadata
import os
import platform
import subprocess
import sys
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[1]

#: Libraries whose versions change the figures.
LIBRARIES: tuple[str, ...] = ("numpy", "scipy", "lxml")

_ESPEAK_VERSION_SCRIPT = """
import ctypes, espeakng_loader
library = ctypes.CDLL(espeakng_loader.get_library_path())
library.espeak_Info.restype = ctypes.c_char_p
print(library.espeak_Info(None).decode())
"""


def cpu_model(cpuinfo: Path = Path("/proc/cpuinfo")) -> str:
    """The CPU's model name from ``/proc/cpuinfo``, else what :mod:`platform` knows."""
    try:
        for line in cpuinfo.read_text(encoding="utf-8", errors="replace").splitlines():
            key, _, value = line.partition(":")
            if key.strip() == "model name" and value.strip():
                return value.strip()
    except OSError:
        pass
    return platform.processor() or platform.machine() or "unknown"


def library_version(name: str) -> str:
    """The installed version of a distribution, or ``"not installed"``."""
    try:
        return importlib.metadata.version(name)
    except importlib.metadata.PackageNotFoundError:
        return "not installed"


def espeak_version(timeout: float = 20.0) -> str:
    """The espeak-ng library's version string, or why it could not be read."""
    try:
        done = subprocess.run(
            [sys.executable, "-c", _ESPEAK_VERSION_SCRIPT], capture_output=True, text=True, timeout=timeout, check=False
        )
    except (OSError, subprocess.TimeoutExpired) as error:
        return f"unavailable ({error})"
    if done.returncode != 0:
        last = (done.stderr.strip().splitlines() or ["no message"])[-1]
        return f"unavailable ({last})"
    return done.stdout.strip()


def git_commit(repo: Path = REPO_ROOT) -> str:
    """The commit checked out in ``repo`` (with ``+dirty`` if files differ), or ``"unknown"``."""
    try:
        head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=repo, capture_output=True, text=True, timeout=10, check=False)
        status = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no"], cwd=repo, capture_output=True, text=True, timeout=10, check=False
        )
    except (OSError, subprocess.TimeoutExpired):
        return "unknown"
    if head.returncode != 0:
        return "unknown"
    return head.stdout.strip() + ("+dirty" if status.stdout.strip() else "")


def machine_info() -> dict[str, object]:
    """CPU, cores, OS, Python and library versions, espeak-ng, git commit."""
    return {
        "cpu": cpu_model(),
        "cores": os.cpu_count() or 0,
        "os": f"{platform.system()} {platform.release()}",
        "python": platform.python_version(),
        **{name: library_version(name) for name in LIBRARIES},
        "espeak_ng": espeak_version(),
        "git_commit": git_commit(),
    }
