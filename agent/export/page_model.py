"""The avatar's own model on the page: which file, how to drive it, and its sidecar script.

A page opened from disk (``file://``) may not fetch a binary file, but it may run a
``<script src>`` beside it. So the model (the built skinned GLB, or a user's VRM) is
written once per output folder as ``mura-avatar-KEY.js``, which stores its bytes as base64
in ``window.__muraModels[KEY]``; KEY carries a hash of the bytes, so pages of different
avatars (or versions) in one folder never share the wrong model, and pages of the same
avatar share one file. The page names the model in ``script#mura-model`` (see
``viewer/README.md``).
"""

from __future__ import annotations

import base64
import hashlib
import html
import json
from dataclasses import dataclass, field
from pathlib import Path

from agent.export.staging import staged_text
from motor.body.avatar import Avatar

#: Model files the page can draw, by suffix.
MODEL_SUFFIXES = (".glb", ".vrm")


@dataclass(frozen=True)
class PageModel:
    """A model file and what the viewer needs to drive it.

    ``format`` is ``"glb"`` (mura's H-Anim nodes, identity rest rotations) or ``"vrm"``
    (three-vrm normalized humanoid bones: ``bones`` maps H-Anim joint -> VRM bone,
    ``rest`` the rest corrections C (x, y, z, w), ``parents`` each mapped joint's nearest
    mapped ancestor). ``root_height`` lifts the model so its root meets the BVH root.
    """

    path: Path
    format: str
    root_height: float
    bones: dict[str, str] = field(default_factory=dict)
    rest: dict[str, list[float]] = field(default_factory=dict)
    parents: dict[str, str | None] = field(default_factory=dict)

    @property
    def key(self) -> str:
        digest = hashlib.sha256(self.path.read_bytes()).hexdigest()[:12]
        stem = "".join(c if c.isalnum() else "_" for c in self.path.stem)[:40]
        return f"{stem}-{digest}"

    def spec(self) -> dict:
        """The JSON the page reads from ``script#mura-model``."""
        return {"key": self.key, "format": self.format, "root_height": self.root_height,
                "bones": self.bones, "rest": self.rest, "parents": self.parents}  # fmt: skip


def page_model(avatar: Avatar) -> PageModel | None:
    """The model to draw for ``avatar``: its built GLB beside its JSON definition, or the
    user's VRM it was read from; None for skeleton-only avatars (max, kim)."""
    source = Path(avatar.source)
    if source.suffix.lower() == ".json":
        glb = source.with_suffix(".glb")
        return PageModel(glb, "glb", avatar.root_height) if glb.is_file() else None
    if source.suffix.lower() == ".vrm":
        from motor.body.humanoid import read_humanoid  # only user avatars need it

        humanoid = read_humanoid(source)
        return PageModel(source, "vrm", avatar.root_height, humanoid.vrm_bones, humanoid.rest_corrections(), humanoid.mapped_parents())
    return None


def sidecar_name(model: PageModel) -> str:
    return f"mura-avatar-{model.key}.js"


def write_sidecar(model: PageModel, folder: Path) -> Path:
    """Write the model's sidecar script into ``folder`` unless it is there already."""
    path = folder / sidecar_name(model)
    if path.is_file():
        return path
    encoded = base64.b64encode(model.path.read_bytes()).decode("ascii")
    with staged_text(path, encoding="ascii") as stream:
        stream.write(f"(window.__muraModels = window.__muraModels || {{}})[{json.dumps(model.key)}] = \"{encoded}\";\n")
    return path


def model_tags(model: PageModel) -> str:
    """The page's tags for the model: its spec and the sidecar script."""
    spec = json.dumps(model.spec(), separators=(",", ":"), allow_nan=False)
    spec = spec.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")
    return (
        f'<script type="application/json" id="mura-model">{spec}</script>\n'
        f'<script src="{html.escape(sidecar_name(model))}"></script>\n'
    )
