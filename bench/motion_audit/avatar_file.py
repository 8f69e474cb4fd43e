"""The avatar as the audit needs it, read from its JSON file as plain data (not through mura).

From ``specs/avatars/NAME.json`` (or any avatar file): the joint offsets (metres), to
find the BVH's length unit and to check that a render belongs to this avatar; the joint
limits (the forearm twist limit); the legacy ``torso`` entry; the ``collision`` volumes
when the file has them. :func:`match_avatar` picks, among the known avatars, the one a
BVH skeleton was rendered for.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from bench.motion_audit.bvh_reader import BvhMotion

_REPO = Path(__file__).resolve().parents[2]
#: Where avatar files are looked up by name: the light avatars kept in git, then the ones built at set-up.
AVATAR_DIRS = (_REPO / "specs" / "avatars", _REPO / "build" / "avatars")
#: A BVH bone may differ from the avatar's (after scaling) by this much, metres.
BONE_TOLERANCE = 0.002
#: Length units a BVH file may be written in, as metres per unit (m, cm, mm, inch).
UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001, "inch": 0.0254}
#: Largest avatar file read, bytes.
MAX_AVATAR_BYTES = 8 * 1024 * 1024


class AvatarError(ValueError):
    """An avatar file that cannot be used, or a skeleton that does not match it."""


@dataclass(frozen=True)
class AvatarFile:
    """What the audit reads from an avatar file: ``offsets`` per joint (metres, from the
    parent), ``parents`` per joint, ``limits`` as written (radians), ``torso`` (the
    legacy elliptic cylinder entry) and ``collision`` volumes as written, or None."""

    name: str
    path: str
    offsets: dict[str, np.ndarray]
    parents: dict[str, str | None]
    limits: dict = field(default_factory=dict)
    torso: dict | None = None
    collision: list | None = None

    def twist_limit(self, side: str) -> tuple[float, float]:
        """The forearm (elbow) twist limits, radians; the file's ``{side}_elbow.twist``,
        else ±1.5 rad (pronation/supination of about ±86°)."""
        value = self.limits.get(f"{side}_elbow", {}).get("twist")
        if isinstance(value, list) and len(value) == 2 and all(isinstance(v, (int, float)) for v in value):
            return float(value[0]), float(value[1])
        return -1.5, 1.5


def avatar_path(name_or_path: str) -> Path:
    """``NAME.json`` in the first of :data:`AVATAR_DIRS` that has it for a bare name, else
    the path as given."""
    candidate = Path(name_or_path)
    if candidate.suffix == ".json" or candidate.parent != Path("."):
        return candidate
    found = [folder / f"{name_or_path}.json" for folder in AVATAR_DIRS if (folder / f"{name_or_path}.json").is_file()]
    return found[0] if found else AVATAR_DIRS[0] / f"{name_or_path}.json"


def read_avatar(name_or_path: str) -> AvatarFile:
    """The avatar named (``max``) or at a path; AvatarError naming the file and the field."""
    path = avatar_path(name_or_path)
    try:
        if path.stat().st_size > MAX_AVATAR_BYTES:
            raise AvatarError(f"{path}: larger than {MAX_AVATAR_BYTES} bytes")
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        known = ", ".join(sorted(p.stem for p in _avatar_files()))
        raise AvatarError(f"{path}: no such avatar file (known avatars: {known})") from None
    except (OSError, UnicodeDecodeError) as error:
        raise AvatarError(f"{path}: cannot read: {error}") from None
    except json.JSONDecodeError as error:
        raise AvatarError(f"{path}:{error.lineno}:{error.colno}: not JSON: {error.msg}") from None
    if not isinstance(data, dict) or not isinstance(data.get("joints"), list):
        raise AvatarError(f"{path}: expected an object with a 'joints' list")
    offsets: dict[str, np.ndarray] = {}
    parents: dict[str, str | None] = {}
    for number, joint in enumerate(data["joints"]):
        try:
            name, offset = str(joint["name"]), np.array(joint["offset"], dtype=float)
        except (KeyError, TypeError, ValueError):
            raise AvatarError(f"{path}: joints[{number}] needs a 'name' and an 'offset' of three numbers") from None
        if offset.shape != (3,):
            raise AvatarError(f"{path}: joints[{number}] ({name}): 'offset' must hold three numbers")
        offsets[name] = offset
        parents[name] = joint.get("parent")
    collision = data.get("collision")
    volumes = collision.get("volumes") if isinstance(collision, dict) else None
    if collision is not None and not isinstance(volumes, list):
        raise AvatarError(f"{path}: 'collision' must be an object with a 'volumes' list")
    return AvatarFile(
        name=str(data.get("name", path.stem)),
        path=str(path),
        offsets=offsets,
        parents=parents,
        limits=data.get("limits") if isinstance(data.get("limits"), dict) else {},
        torso=data.get("torso") if isinstance(data.get("torso"), dict) else None,
        collision=volumes,
    )


def known_avatars() -> list[AvatarFile]:
    """Every avatar of :data:`AVATAR_DIRS`, by name."""
    return [read_avatar(str(path)) for path in _avatar_files()]


def _avatar_files() -> list[Path]:
    return sorted((path for folder in AVATAR_DIRS for path in folder.glob("*.json")), key=lambda path: path.stem)


def unit_scale(motion: BvhMotion, avatar: AvatarFile) -> float:
    """The factor that turns the BVH's lengths into metres for ``avatar``: of the
    :data:`UNITS`, the one nearest the ratio of the summed bone lengths of the joints both
    share. AvatarError naming the joint when a bone, scaled, is off the avatar's by more
    than :data:`BONE_TOLERANCE` (so a skeleton scaled as a whole is another avatar)."""
    shared = [joint for joint in motion.joints if joint.name in avatar.offsets]
    if len(shared) < len(motion.joints) // 2 or not shared:
        raise AvatarError(f"{motion.path}: the skeleton shares {len(shared)} of {len(motion.joints)} joints with avatar {avatar.name!r}")
    written = np.array([joint.offset for joint in shared], dtype=float)
    expected = np.array([avatar.offsets[joint.name] for joint in shared])
    total = float(np.linalg.norm(written, axis=1).sum())
    if total <= 0.0:
        raise AvatarError(f"{motion.path}: every bone has zero length")
    ratio = float(np.linalg.norm(expected, axis=1).sum()) / total
    scale = min(UNITS.values(), key=lambda unit: abs(np.log(ratio / unit)) if ratio > 0 else np.inf)
    error = np.linalg.norm(written * scale - expected, axis=1)
    worst = int(np.argmax(error))
    if error[worst] > BONE_TOLERANCE:
        raise AvatarError(
            f"{motion.path}: not avatar {avatar.name!r}: joint {shared[worst].name} is {100 * error[worst]:.1f} cm off the avatar's offset"
        )
    return scale


def match_avatar(motion: BvhMotion, avatars: list[AvatarFile]) -> tuple[AvatarFile, float]:
    """The first of ``avatars`` whose skeleton the BVH matches, and the unit scale;
    AvatarError listing why each one does not."""
    reasons = []
    for avatar in avatars:
        try:
            return avatar, unit_scale(motion, avatar)
        except AvatarError as error:
            reasons.append(str(error).split(": ", 1)[-1])
    raise AvatarError(f"{motion.path}: matches no avatar ({'; '.join(reasons)})")
