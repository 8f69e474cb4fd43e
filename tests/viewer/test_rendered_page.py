"""A page rendered from a real utterance: the avatar is drawn, it moves, the timeline is listed."""

import io
from pathlib import Path

import numpy as np
import pytest
from matplotlib.image import imread

from agent.agent import Agent

REPO = Path(__file__).resolve().parents[2]
BACKGROUND = np.array([0x20, 0x25, 0x2C]) / 255.0


@pytest.fixture(scope="module")
def fig2_page(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fig2")
    performance = Agent(tts="fake", fps=30).render(REPO / "specs" / "utterances" / "fig2_take_this_bar.xml")
    return performance, performance.save(folder).html


def test_rendered_page_draws_moves_and_lists(browser, fig2_page):
    performance, page = fig2_page
    stroke = next(b for b in performance.timeline["behaviors"] if b["id"] == "gesture_2")["phases"]["stroke"]
    shots = []
    for t in (0.05, stroke):
        browser.open(f"{page.as_uri()}?t={t:.3f}")
        assert browser.evaluate("window.__muraReady === true")
        assert browser.evaluate("window.__muraError || null") is None
        shots.append(imread(io.BytesIO(browser.screenshot("#mura-stage")), format="png")[..., :3])
    assert (np.abs(shots[0] - BACKGROUND).max(axis=-1) > 0.08).mean() > 0.05
    assert (np.abs(shots[0] - shots[1]).max(axis=-1) > 0.1).sum() > 1000
    assert browser.evaluate("window.__mura.joints") == len(performance.motion.joint_names)
    text = browser.evaluate("document.getElementById('mura-timeline-list').innerText")
    assert "And now take this bar" in text and "gesture_1" in text and "gesture_2" in text
