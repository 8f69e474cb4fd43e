"""The face on the page, in headless Chromium: morph weights on the skinned avatar, the
capsule figure's eyes, mouth and lids; pixels that change where the face moves."""

from __future__ import annotations

import io
import json
from pathlib import Path

import numpy as np
import pytest
from headless_chromium import Browser
from matplotlib.image import imread

from agent.agent import Agent
from motor.body.conventions import BUILT_AVATAR_DIR

REPO = Path(__file__).resolve().parents[2]
UTTERANCE = REPO / "specs" / "utterances" / "fig2_take_this_bar.xml"
READY = (
    "new Promise((resolve) => { const start = performance.now(); const check = () => window.__muraReady ? resolve(true)"
    " : performance.now() - start > 20000 ? resolve(false) : setTimeout(check, 20); check(); })"
)


@pytest.fixture(scope="module", params=["makehuman", "max"])
def page(request, tmp_path_factory) -> tuple[str, Path, dict]:
    if request.param == "makehuman" and not (BUILT_AVATAR_DIR / "makehuman.glb").is_file():
        pytest.fail("the built avatar is missing: run `make setup`")
    saved = Agent(avatar=request.param, tts="fake", fps=30).render(UTTERANCE).save(tmp_path_factory.mktemp(request.param))
    return request.param, saved.html, json.loads(saved.face.read_text())


def _times(face: dict) -> dict[str, float]:
    """Utterance times (the motion starts at 0 here) of the widest open mouth and of a closed blink."""
    weights = np.array(face["weights"])
    jaw, blink = (weights[:, face["names"].index(n)] for n in ("jawOpen", "eyeBlinkLeft"))
    return {"mouth": float(np.argmax(jaw - blink)) / face["fps"], "blink": float(np.argmax(blink - jaw)) / face["fps"]}


def _open(browser: Browser, html: Path, t: float) -> None:
    browser.open(f"{html.as_uri()}?t={t:.3f}")
    assert browser.evaluate(READY)
    assert browser.evaluate("window.__muraError || null") is None and browser.exceptions() == []
    assert browser.evaluate("window.__mura.view('face')") == "face"


def _shot(browser: Browser) -> np.ndarray:
    return imread(io.BytesIO(browser.screenshot("#mura-stage")), format="png")[..., :3]


@pytest.mark.parametrize("moment", ["mouth", "blink"])
def test_the_face_changes_the_picture_where_it_moves(browser: Browser, page, moment):
    """The same frame with the face played and held at rest differs by many pixels; an open
    mouth changes the lower part of the head, a blink the upper part."""
    avatar, html, face = page
    t = _times(face)[moment]
    _open(browser, html, t)
    played = _shot(browser)
    assert browser.evaluate("window.__mura.showFace(false)") is False
    still = _shot(browser)
    changed = np.abs(played - still).max(axis=-1) > 0.08
    rows = np.flatnonzero(changed.any(axis=1))
    assert changed.sum() > 150, (avatar, moment, int(changed.sum()))
    eyes_row = browser.evaluate("window.__mura.screenOf('l_eyeball_joint')")[1] * changed.shape[0] / browser.evaluate(
        "document.querySelector('#mura-stage').getBoundingClientRect().height"
    )
    middle = float(np.median(rows))
    assert (middle > eyes_row + 10) if moment == "mouth" else (abs(middle - eyes_row) < 40), (avatar, moment, middle, eyes_row)


def test_the_model_plays_the_weights(browser: Browser, page):
    avatar, html, face = page
    t = _times(face)["mouth"]
    _open(browser, html, t)
    shown = browser.evaluate("window.__mura.face()")
    assert shown["jawOpen"] > 0.3
    morph = browser.evaluate("window.__mura.morph('jawOpen')")
    if avatar == "makehuman":
        assert morph == pytest.approx(shown["jawOpen"], abs=1e-6)
    else:
        assert morph is None and browser.evaluate("window.__mura.jointPosition('l_eyeball_joint')") is not None
