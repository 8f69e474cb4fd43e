"""One viewer for many motions: the corpus index page and the per-item motion files.

``index.html`` inlines the viewer bundle once and lists every item of a corpus (name,
label, source, status, duration, reason); the viewer searches the list by gloss, plays an
item and steps from one to the next (``viewer/src/corpus.js``). Each item's motion is a
small script beside the page, ``NAME.motion.js``, loaded when the item is chosen — a
``<script src>`` works from ``file://`` where ``fetch`` does not — which hands the viewer
its frames::

    window.__muraMotion("NAME", {"fps": 25, "frames": 61, "start": 0.0, "duration": 2.4,
                                  "rotations": "<base64>", "root": "<base64>", "timeline": {…},
                                  "face": {"fps": 25, "names": [...], "weights": [[...], ...]}})

``rotations`` are the frames' local joint quaternions (scalar last) in the page's joint
order, each component as a little-endian int16 of ``round(q · 32767)`` (a resolution of
3·10⁻⁵, far below a visible angle); ``root`` the root positions as little-endian float32
metres. ``face``, present when the motion moves the face, holds the morph weights that
move (ARKit names, :func:`agent.export.face.page_face_json`), which the viewer plays on the
model's morph targets as the item pages do. The page's ``script#mura-corpus`` carries the joint list (name, parent, rest
offset in metres) once for all items. Files are written whole or not at all, and their
bytes depend only on the motion, so a corpus rendered twice gives the same files.
"""

from __future__ import annotations

import base64
import json
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from agent.export.face import page_face_json
from agent.export.html import VIEWER_BUNDLE, ViewerNotBuiltError
from agent.export.page_model import PageModel, model_tags, write_sidecar
from agent.export.staging import staged_text
from motor.motion import Motion

#: Scale of the int16 quaternion components.
QUATERNION_SCALE = 32767

_SCRIPT_END = re.compile(r"</(script)", re.IGNORECASE)
_JSON_UNSAFE = str.maketrans({"<": "\\u003c", ">": "\\u003e", "&": "\\u0026", "\u2028": "\\u2028", "\u2029": "\\u2029"})


@dataclass(frozen=True)
class IndexEntry:
    """One item as the index lists it; ``motion`` and ``audio`` name its motion file and
    speech beside the page, or are None."""

    name: str
    label: str
    source: str
    status: str
    duration: float | None = None
    reason: str | None = None
    motion: str | None = None
    audio: str | None = None

    def as_json(self) -> dict:
        entry = {"name": self.name, "label": self.label, "source": self.source, "status": self.status}
        if self.duration is not None:
            entry["duration"] = round(self.duration, 4)
        if self.reason is not None:
            entry["reason"] = self.reason
        if self.motion is not None:
            entry["motion"] = self.motion
        if self.audio is not None:
            entry["audio"] = self.audio
        return entry


def motion_payload(motion: Motion, timeline: dict | None = None) -> dict:
    """The JSON object a motion file hands the viewer (module docstring)."""
    quantized = np.round(np.clip(motion.rotations, -1.0, 1.0) * QUATERNION_SCALE).astype("<i2")
    payload = {
        "fps": motion.fps,
        "frames": int(motion.frame_count),
        "start": round(float(motion.start_time), 6),
        "duration": round(float(motion.duration), 6),
        "rotations": base64.b64encode(quantized.tobytes()).decode("ascii"),
        "root": base64.b64encode(motion.root_translation.astype("<f4").tobytes()).decode("ascii"),
    }
    if timeline is not None:
        payload["timeline"] = timeline
    face = json.loads(page_face_json(motion))
    if face["names"]:
        payload["face"] = face
    return payload


def write_motion_script(path: str | os.PathLike[str], name: str, motion: Motion, timeline: dict | None = None) -> None:
    """Write ``NAME.motion.js`` for the index page (module docstring)."""
    body = json.dumps(motion_payload(motion, timeline), separators=(",", ":"), allow_nan=False)
    with staged_text(path) as stream:
        stream.write(f"window.__muraMotion({_script_json(json.dumps(name))},{_script_json(body)});\n")


def skeleton_of(motion: Motion) -> list[dict]:
    """The joint list the page builds its skeleton from: name, parent index, offset (m)."""
    return [
        {"name": name, "parent": int(parent), "offset": [round(float(v), 6) for v in offset]}
        for name, parent, offset in zip(motion.joint_names, motion.parents, motion.offsets)
    ]


def write_index(
    path: str | os.PathLike[str],
    *,
    title: str,
    skeleton: list[dict],
    entries: Sequence[IndexEntry],
    model: PageModel | None = None,
) -> None:
    """Write the corpus index page (and the avatar model's sidecar beside it)."""
    corpus = {"title": title, "skeleton": skeleton, "items": [entry.as_json() for entry in entries]}
    text = json.dumps(corpus, separators=(",", ":"), ensure_ascii=False, allow_nan=False)
    title_html = title.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;")
    page = (
        "<!doctype html>\n"
        '<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
        f"<title>mura — {title_html}</title>\n</head>\n<body>\n"
        f'<div id="mura-app" data-name="{title_html}"></div>\n'
        f'<script type="application/json" id="mura-corpus">{_script_json(text)}</script>\n'
        + (model_tags(model) if model is not None else "")
        + f"<script>\n{_script_code(_viewer_bundle())}\n</script>\n"
        "</body>\n</html>\n"
    )
    if model is not None:
        write_sidecar(model, Path(path).parent)
    with staged_text(path) as stream:
        stream.write(page)


def _script_json(text: str) -> str:
    """JSON that cannot end its ``<script>`` element early (``<``, ``>``, ``&`` as ``\\u`` escapes)."""
    return text.translate(_JSON_UNSAFE)


def _script_code(code: str) -> str:
    """JavaScript safe inside ``<script>``: ``</script`` in a string becomes ``<\\/script``."""
    return _SCRIPT_END.sub(r"<\\/\1", code)


def _viewer_bundle() -> str:
    if not VIEWER_BUNDLE.is_file():
        raise ViewerNotBuiltError(f"the corpus index needs the built viewer at {VIEWER_BUNDLE}; run `make setup` first")
    return VIEWER_BUNDLE.read_text(encoding="utf-8")
