"""The page writer: one self-contained file, safe embedding, clear errors (no browser needed)."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import pytest

from agent.export import html as html_export
from agent.export.bvh import bvh_text
from agent.export.html import ViewerNotBuiltError, render_html, write_html
from motor.motion import Motion


def _embedded(page: str, element_id: str) -> object:
    match = re.search(rf'<script type="application/json" id="{element_id}">(.*?)</script>', page, re.DOTALL)
    assert match, f"no script#{element_id} in the page"
    return json.loads(match.group(1))


@pytest.fixture(scope="module")
def bvh(motion: Motion) -> str:
    return bvh_text(motion)


def test_page_embeds_bvh_and_timeline_verbatim(bvh: str, timeline: dict) -> None:
    page = render_html(name="fig2", bvh_text=bvh, timeline=timeline, wav_filename="fig2.wav")
    assert _embedded(page, "mura-bvh") == bvh
    assert _embedded(page, "mura-timeline") == timeline
    assert '<audio id="mura-audio" src="fig2.wav" preload="auto"></audio>' in page
    assert "<title>mura — fig2</title>" in page


def test_page_fetches_nothing(bvh: str, timeline: dict) -> None:
    page = render_html(name="fig2", bvh_text=bvh, timeline=timeline, wav_filename="fig2.wav")
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", page)
    assert "<script src" not in page and "<link" not in page


@pytest.mark.parametrize(
    "hostile",
    ["</script><script>alert(1)</script>", "</SCRIPT >", "<!-- <script>", "a & b > c", "\u2028line\u2029"],
)
def test_text_cannot_break_out_of_its_script_element(bvh: str, hostile: str) -> None:
    page = render_html(name="x", bvh_text=bvh, timeline={"chunks": [{"text": hostile}]}, wav_filename=None)
    assert _embedded(page, "mura-timeline") == {"chunks": [{"text": hostile}]}
    assert page.lower().count("</script") == 3  # bvh, timeline and the viewer bundle
    assert hostile not in page


def test_name_is_html_escaped(bvh: str) -> None:
    page = render_html(name='<b>"fig"</b>', bvh_text=bvh, timeline={}, wav_filename=None)
    assert "<title>mura — &lt;b&gt;&quot;fig&quot;&lt;/b&gt;</title>" in page
    assert '<b>"fig"</b>' not in page


def test_silent_page_has_no_audio(bvh: str, timeline: dict) -> None:
    assert "<audio" not in render_html(name="x", bvh_text=bvh, timeline=timeline, wav_filename=None)


def test_wav_name_is_url_quoted(bvh: str) -> None:
    page = render_html(name="x", bvh_text=bvh, timeline={}, wav_filename='take 1 "a".wav')
    assert 'src="take%201%20%22a%22.wav"' in page


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"bvh_text": "ROOT hips"}, "bvh_text is not a BVH file"),
        ({"timeline": [1, 2]}, "timeline must be a dict"),
        ({"timeline": {"duration": float("nan")}}, "finite numbers"),
        ({"timeline": {"when": object()}}, "not JSON-serializable"),
        ({"wav_filename": "/tmp/fig2.wav"}, "must be relative"),
        ({"wav_filename": "https://example.org/fig2.wav"}, "must be relative"),
    ],
    ids=["not-bvh", "timeline-list", "nan", "object", "absolute-wav", "url-wav"],
)
def test_bad_input_is_rejected(bvh: str, kwargs: dict, message: str) -> None:
    arguments = {"name": "x", "bvh_text": bvh, "timeline": {}, "wav_filename": "x.wav", **kwargs}
    with pytest.raises(ValueError, match=message):
        render_html(**arguments)


def test_missing_bundle_says_to_run_make_setup(
    bvh: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(html_export, "VIEWER_BUNDLE", tmp_path / "viewer.js")
    with pytest.raises(ViewerNotBuiltError, match="make setup"):
        write_html(tmp_path / "x.html", name="x", bvh_text=bvh, timeline={}, wav_filename=None)
    assert os.listdir(tmp_path) == []


def test_write_html_leaves_only_the_page(bvh: str, timeline: dict, tmp_path: Path) -> None:
    write_html(tmp_path / "fig2.html", name="fig2", bvh_text=bvh, timeline=timeline, wav_filename="fig2.wav")
    assert os.listdir(tmp_path) == ["fig2.html"]
    assert (tmp_path / "fig2.html").read_text(encoding="utf-8").startswith("<!doctype html>")
