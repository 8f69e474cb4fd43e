"""The page with the avatar's own model (the built skinned GLB, a user's VRM) in headless Chromium."""

from __future__ import annotations

import io
import sys
from pathlib import Path

import numpy as np
import pytest
from headless_chromium import Browser
from matplotlib.image import imread

from agent.agent import Agent
from motor.body.conventions import BUILT_AVATAR_DIR

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "avatar"))
from avatar_fixtures import make_vrm, read_glb  # noqa: E402  (the avatar tests' fixture maker)

REPO = Path(__file__).resolve().parents[2]
#: Joints spanning the right hand in every orientation (its size on screen is their widest spread).
HAND_OUTLINE = ("r_wrist", "r_thumb3", "r_index3", "r_middle3", "r_pinky3")
FIG2 = REPO / "specs" / "utterances" / "fig2_take_this_bar.xml"
BACKGROUND = np.array([0x20, 0x25, 0x2C]) / 255.0
READY = (
    "new Promise((resolve) => { const start = performance.now(); const check = () => window.__muraReady ? resolve(true)"
    " : performance.now() - start > 20000 ? resolve(false) : setTimeout(check, 20); check(); })"
)


def _page(folder: Path, avatar: str) -> tuple[Path, float]:
    performance = Agent(avatar=avatar, tts="fake", fps=30).render(FIG2)
    stroke = next(b for b in performance.timeline["behaviors"] if b["id"] == "gesture_2")["phases"]["stroke"]
    return performance.save(folder).html, stroke


@pytest.fixture(scope="module")
def skinned_page(tmp_path_factory) -> tuple[Path, float]:
    if not (BUILT_AVATAR_DIR / "makehuman.glb").is_file():
        pytest.fail("the built avatar is missing: run `make setup`")
    return _page(tmp_path_factory.mktemp("skinned"), "makehuman")


def _open(browser: Browser, page: Path, t: float) -> None:
    browser.open(f"{page.as_uri()}?t={t:.3f}")
    assert browser.evaluate(READY), "the page never finished its first frame"
    assert browser.evaluate("window.__muraError || null") is None
    assert browser.evaluate("window.__muraModelError || null") is None
    assert browser.exceptions() == []


def _shot(browser: Browser) -> np.ndarray:
    return imread(io.BytesIO(browser.screenshot("#mura-stage")), format="png")[..., :3]


def _body(image: np.ndarray) -> np.ndarray:
    return np.abs(image - BACKGROUND).max(axis=-1) > 0.08


def test_skinned_model_loads_with_its_face(browser: Browser, skinned_page) -> None:
    page, stroke = skinned_page
    _open(browser, page, stroke)
    model = browser.evaluate("window.__mura.model")
    assert model["format"] == "glb" and model["morphs"] >= 40


@pytest.mark.parametrize(("view", "least_rows", "least_cover"), [("front", 0.85, 0.12), ("hands", 0.5, 0.2), ("side", 0.85, 0.06)])
def test_avatar_fills_the_frame(browser: Browser, skinned_page, view: str, least_rows: float, least_cover: float) -> None:
    """A pixel test on the screenshot: the body spans most of the stage's height and
    covers a good part of it, in each camera view."""
    page, stroke = skinned_page
    _open(browser, page, stroke)
    assert browser.evaluate(f"window.__mura.view({view!r})") == view
    body = _body(_shot(browser))
    rows = np.flatnonzero(body.any(axis=1))
    assert (rows.max() - rows.min() + 1) / body.shape[0] >= least_rows, view
    assert body.mean() >= least_cover, view


def test_close_up_shows_the_hands_larger(browser: Browser, skinned_page) -> None:
    page, stroke = skinned_page
    _open(browser, page, stroke)
    sizes = {}
    for view in ("front", "hands"):
        browser.evaluate(f"window.__mura.view({view!r})")
        points = np.array([browser.evaluate(f"window.__mura.screenOf({j!r})") for j in HAND_OUTLINE])
        sizes[view] = float(np.max(np.linalg.norm(points[:, None] - points[None], axis=-1)))
    assert sizes["hands"] > 1.5 * sizes["front"]


def test_legend_names_the_colours(browser: Browser, skinned_page) -> None:
    page, stroke = skinned_page
    _open(browser, page, stroke)
    text = browser.evaluate("document.getElementById('mura-legend').innerText")
    for word in ("InPrep", "Lurking", "InExec", "preparation", "stroke", "retraction", "speech", "affiliate"):
        assert word in text


def test_user_vrm_is_drawn_through_three_vrm(browser: Browser, tmp_path: Path) -> None:
    built = read_glb((BUILT_AVATAR_DIR / "makehuman.glb").read_bytes(), "makehuman.glb")
    vrm = make_vrm(built, tmp_path / "fixture.vrm")
    page, stroke = _page(tmp_path / "out", str(vrm))
    _open(browser, page, stroke)
    assert browser.evaluate("window.__mura.model.format") == "vrm"
    assert _body(_shot(browser)).mean() > 0.08
