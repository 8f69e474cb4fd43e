"""The stand-alone avatar page: one HTML file that plays a BVH with its speech and timeline.

The page inlines the built viewer bundle (``viewer/dist/viewer.js``, made by ``make setup``),
the BVH text and the timeline JSON, and refers to the WAV by a relative file name, so it
works opened straight from the output folder (``file://``) and fetches nothing from the
network. With a face (``face_json``, see :mod:`agent.export.face`) the page carries its
morph weights in ``script#mura-face`` and plays them on the avatar. Query parameters the page honours: ``?t=SECONDS`` opens it paused at that time;
``?live=1`` follows a server's event stream instead (see ``viewer/src/live.js``).

:func:`write_html_stream` writes the same page to an open stream with the BVH text given
in pieces, so that an hour of motion never has to be one string.
"""

from __future__ import annotations

import html
import json
import os
import re
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import TextIO
from urllib.parse import quote

from agent.export.page_model import PageModel, model_tags, write_sidecar
from agent.export.staging import staged_text

REPO_ROOT = Path(__file__).resolve().parents[2]
VIEWER_BUNDLE = REPO_ROOT / "viewer" / "dist" / "viewer.js"

_SCRIPT_END = re.compile(r"</(script)", re.IGNORECASE)
_JSON_UNSAFE = str.maketrans(
    {"<": "\\u003c", ">": "\\u003e", "&": "\\u0026", "\u2028": "\\u2028", "\u2029": "\\u2029"}
)


class ViewerNotBuiltError(FileNotFoundError):
    """The viewer bundle is missing: the web page has not been built (``make setup``)."""


def write_html(
    path: str | os.PathLike[str],
    *,
    name: str,
    bvh_text: str,
    timeline: dict,
    wav_filename: str | None,
    model: PageModel | None = None,
    face_json: str | None = None,
) -> None:
    """Write the avatar page for one performance to ``path``.

    Args:
        path: the HTML file to write, normally ``<out>/<name>.html``.
        name: shown as the page's title.
        bvh_text: the whole BVH file (lengths in centimetres, as ``agent.export.bvh`` writes).
        timeline: the scheduler's timeline (chunks, behaviours, words, ...), JSON-serializable.
        wav_filename: the speech audio, relative to the page's folder, or ``None`` for a
            silent page (a wall clock then drives the animation).
        model: the avatar's own model to draw (its sidecar script is written beside the
            page), or None for the joint-and-capsule figure.
        face_json: the page's face weights (:func:`agent.export.face.page_face_json`), or None.

    Raises:
        ViewerNotBuiltError: the viewer bundle has not been built.
        ValueError: ``timeline`` is not a JSON object of finite numbers, or ``bvh_text``
            does not look like BVH, or ``wav_filename`` is absolute.
    """
    page = render_html(name=name, bvh_text=bvh_text, timeline=timeline, wav_filename=wav_filename, model=model, face_json=face_json)
    if model is not None:
        write_sidecar(model, Path(path).parent)
    with staged_text(path) as stream:
        stream.write(page)


def render_html(
    *, name: str, bvh_text: str, timeline: dict, wav_filename: str | None, model: PageModel | None = None, face_json: str | None = None
) -> str:
    """The page :func:`write_html` writes, as a string (the model's sidecar not written)."""
    _check_bvh_start(bvh_text)
    head, tail = _page_around_bvh(name, timeline, wav_filename, model)
    return head + _script_json(json.dumps(bvh_text)) + "".join(_face_script([face_json] if face_json is not None else None)) + tail


def write_html_stream(
    stream: TextIO,
    *,
    name: str,
    bvh_blocks: Iterable[str],
    timeline: dict,
    wav_filename: str | None,
    model: PageModel | None = None,
    face_blocks: Iterable[str] | None = None,
) -> None:
    """Write the page :func:`render_html` makes to ``stream``, the BVH text (and the face
    JSON, ``face_blocks``) coming in pieces.

    ``bvh_blocks`` concatenated is the whole BVH file; its first piece must hold the header
    up to ``MOTION`` (as ``StreamingBvh.text_blocks`` yields it). Each piece is escaped on
    its own (JSON string escaping works character by character), so the bytes equal
    :func:`write_html`'s. Raises as :func:`write_html` does, before writing anything. The
    model's sidecar is the caller's to write (:func:`~agent.export.page_model.write_sidecar`).
    """
    blocks = iter(bvh_blocks)
    first = next(blocks, "")
    _check_bvh_start(first)
    head, tail = _page_around_bvh(name, timeline, wav_filename, model)
    stream.write(head)
    stream.write('"')
    stream.write(_script_json(_json_string_body(first)))
    for block in blocks:
        stream.write(_script_json(_json_string_body(block)))
    stream.write('"')
    for piece in _face_script(face_blocks):
        stream.write(piece)
    stream.write(tail)


def _face_script(face_blocks: Iterable[str] | None) -> Iterator[str]:
    """``script#mura-face`` (after the BVH's script, which the tail closes first), or nothing."""
    if face_blocks is None:
        return
    yield '</script>\n<script type="application/json" id="mura-face">'
    for block in face_blocks:
        yield _script_json(block)


def _check_bvh_start(bvh_text: str) -> None:
    if not bvh_text.lstrip().startswith("HIERARCHY") or "\nMOTION" not in bvh_text:
        raise ValueError("write_html: bvh_text is not a BVH file (expected HIERARCHY ... MOTION ...)")


def _json_string_body(text: str) -> str:
    """``text`` as the inside of a JSON string literal (without the quotes)."""
    return json.dumps(text)[1:-1]


def _page_around_bvh(name: str, timeline: dict, wav_filename: str | None, model: PageModel | None = None) -> tuple[str, str]:
    """The page before and after the embedded BVH JSON string, checking the arguments."""
    if not isinstance(timeline, dict):
        raise ValueError(f"write_html: timeline must be a dict (a JSON object), got {type(timeline).__name__}")
    try:
        timeline_json = json.dumps(timeline, allow_nan=False, separators=(",", ":"))
    except (TypeError, ValueError) as error:
        raise ValueError(f"write_html: timeline is not JSON-serializable with finite numbers: {error}") from error
    audio = ""
    if wav_filename is not None:
        if Path(wav_filename).is_absolute() or re.match(r"^[a-z][a-z0-9+.-]*:", wav_filename, re.IGNORECASE):
            raise ValueError(f"write_html: wav_filename must be relative to the page, got {wav_filename!r}")
        audio = f'<audio id="mura-audio" src="{html.escape(quote(wav_filename))}" preload="auto"></audio>'
    title = html.escape(name)
    head = (
        "<!doctype html>\n"
        '<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
        f"<title>mura — {title}</title>\n</head>\n<body>\n"
        f'<div id="mura-app" data-name="{title}">{audio}</div>\n'
        '<script type="application/json" id="mura-bvh">'
    )
    tail = (
        "</script>\n"
        f'<script type="application/json" id="mura-timeline">{_script_json(timeline_json)}</script>\n'
        + (model_tags(model) if model is not None else "")
        + f"<script>\n{_script_code(_viewer_bundle())}\n</script>\n"
        "</body>\n</html>\n"
    )
    return head, tail


def _viewer_bundle() -> str:
    if not VIEWER_BUNDLE.is_file():
        raise ViewerNotBuiltError(
            f"the avatar page needs the built viewer at {VIEWER_BUNDLE}; run `make setup` "
            "(or `npm ci && npm run build` in viewer/) first"
        )
    return VIEWER_BUNDLE.read_text(encoding="utf-8")


def _script_json(text: str) -> str:
    """JSON that cannot end its ``<script>`` element early (``<``, ``>``, ``&`` as ``\\u`` escapes)."""
    return text.translate(_JSON_UNSAFE)


def _script_code(code: str) -> str:
    """JavaScript safe inside ``<script>``: a ``</script`` in a string or regex becomes ``<\\/script``."""
    return _SCRIPT_END.sub(r"<\\/\1", code)
