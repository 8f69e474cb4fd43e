"""The avatar page in headless Chromium: it draws a body, moves it over time, lists the timeline.

The page is written by ``write_html`` from the synthetic performance and opened from disk
(file://), exactly as a user opens it from the output folder.
"""

from __future__ import annotations

import copy
import io
from pathlib import Path

import numpy as np
import pytest
from headless_chromium import Browser
from matplotlib.image import imread
from scipy.spatial.transform import Rotation

from agent.export.bvh import bvh_text
from agent.export.html import write_html
from motor.motion import Motion

BACKGROUND = np.array([0x20, 0x25, 0x2C]) / 255.0  # the scene's clear colour
TRICKY_TEXT = "and </script><b>this</b> & that"


@pytest.fixture(scope="module")
def page(performance_dir: Path, motion: Motion, timeline: dict) -> Path:
    tricky = copy.deepcopy(timeline)
    tricky["chunks"][1]["text"] = TRICKY_TEXT
    path = performance_dir / "synthetic.html"
    write_html(path, name="synthetic", bvh_text=bvh_text(motion), timeline=tricky, wav_filename="synthetic.wav")
    return path


@pytest.fixture(scope="module")
def shots(browser: Browser, page: Path) -> dict[float, np.ndarray]:
    """RGB screenshots of the 3D stage at two times, opened with ?t=."""
    images = {}
    for t in (0.1, 1.1):
        browser.open(f"{page.as_uri()}?t={t}")
        assert browser.evaluate("window.__muraReady === true"), "the page never finished its first frame"
        assert browser.evaluate("window.__muraError || null") is None
        assert browser.exceptions() == []
        assert browser.evaluate("window.__mura.time()") == pytest.approx(t)
        images[t] = imread(io.BytesIO(browser.screenshot("#mura-stage")), format="png")[..., :3]
    return images


def _warm(image: np.ndarray) -> np.ndarray:
    """Skin-coloured pixels: red above green above blue, clearly warmer than the blue-grey scene."""
    r, g, b = image[..., 0], image[..., 1], image[..., 2]
    return (r > g) & (g > b) & (r - b > 0.15)


@pytest.mark.parametrize("t", [0.1, 1.1])
def test_avatar_is_drawn(shots: dict[float, np.ndarray], t: float) -> None:
    image = shots[t]
    not_background = np.abs(image - BACKGROUND).max(axis=-1) > 0.08
    assert not_background.mean() > 0.05, "the stage is (almost) blank"
    assert _warm(image).mean() > 0.004, "no skin-coloured body parts on the stage"


def test_pose_changes_with_time(shots: dict[float, np.ndarray]) -> None:
    changed = np.abs(shots[0.1] - shots[1.1]).max(axis=-1) > 0.1
    assert changed.sum() > 2000, f"only {changed.sum()} pixels differ between t=0.1 and t=1.1"


def test_skeleton_and_body_built(browser: Browser, shots, motion: Motion) -> None:
    assert browser.evaluate("window.__mura.joints") == len(motion.joint_names)
    assert browser.evaluate("window.__mura.meshes") > 2 * len(motion.joint_names)


def test_timeline_is_listed(browser: Browser, shots, timeline: dict) -> None:
    text = browser.evaluate("document.getElementById('mura-timeline-list').innerText")
    assert timeline["chunks"][0]["text"] in text
    assert TRICKY_TEXT in text, "text with </script> must survive the embedding as text"
    assert "gesture_1 (chunk 0, right): preparation 0.20–0.80 s, stroke 0.80–1.40 s, retraction 1.40–1.90 s" in text
    assert "affiliate 0.90–1.30 s" in text
    assert "InExec 0.20" in text
    assert "t1 0.90" in text
    assert browser.evaluate("document.querySelectorAll('#mura-timeline-list b').length") == 0


def test_audio_is_the_wav_beside_the_page(browser: Browser, shots) -> None:
    duration = browser.evaluate(
        "new Promise((resolve) => { const a = document.getElementById('mura-audio');"
        " if (a.readyState >= 1) resolve(a.duration);"
        " a.addEventListener('loadedmetadata', () => resolve(a.duration));"
        " a.addEventListener('error', () => resolve(-1)); })"
    )
    assert duration == pytest.approx(2.0, abs=0.01)


def test_controls_present(browser: Browser, shots) -> None:
    assert browser.evaluate("document.getElementById('mura-play').textContent") == "Play"
    assert float(browser.evaluate("document.getElementById('mura-scrub').value")) == pytest.approx(1.1)
    assert browser.evaluate("document.getElementById('mura-time').textContent") == "1.10 s / 2.00 s"


def _world_positions(motion: Motion, frame: int) -> dict[str, np.ndarray]:
    """Forward kinematics of one frame in Python, centimetres: the pose the page must draw."""
    rotations = Rotation.from_quat(motion.rotations[frame])
    world: list[Rotation] = []
    positions: list[np.ndarray] = []
    for joint, parent in enumerate(motion.parents):
        if parent < 0:
            world.append(rotations[joint])
            positions.append(motion.root_translation[frame])
            continue
        world.append(world[parent] * rotations[joint])
        positions.append(positions[parent] + world[parent].apply(motion.offsets[joint]))
    return {name: 100.0 * position for name, position in zip(motion.joint_names, positions)}


@pytest.mark.parametrize("joint", ["skullbase", "r_elbow", "r_wrist", "r_index3", "l_wrist", "l_pinky3"])
def test_drawn_pose_matches_forward_kinematics(browser: Browser, shots, motion: Motion, joint: str) -> None:
    """End to end through BVH text and three.js' loader: Euler order and units agree."""
    frame = 66
    browser.evaluate(f"window.__mura.seek({frame / motion.fps!r})")
    drawn = browser.evaluate(f"window.__mura.jointPosition({joint!r})")
    np.testing.assert_allclose(drawn, _world_positions(motion, frame)[joint], atol=0.01)


ADVANCES = (
    "new Promise((resolve) => { const from = window.__mura.time(); const start = performance.now();"
    " const check = () => window.__mura.time() > from + 0.1 ? resolve(true)"
    " : performance.now() - start > 5000 ? resolve(false) : setTimeout(check, 10); check(); })"
)


def test_playing_follows_the_audio_clock(browser: Browser, page: Path) -> None:
    browser.open(f"{page.as_uri()}?t=0.5")
    browser.evaluate("window.__mura.play()")
    assert browser.evaluate(ADVANCES), "time did not advance while playing"
    assert browser.evaluate("document.getElementById('mura-audio').paused") is False
    browser.evaluate("window.__mura.pause()")
    assert browser.evaluate("document.getElementById('mura-audio').paused") is True
    paused_at = browser.evaluate("window.__mura.time()")
    browser.evaluate("new Promise((resolve) => setTimeout(resolve, 100))")
    assert browser.evaluate("window.__mura.time()") == paused_at


def test_silent_page_plays_on_the_wall_clock(browser: Browser, performance_dir: Path, motion: Motion) -> None:
    path = performance_dir / "silent.html"
    write_html(path, name="silent", bvh_text=bvh_text(motion), timeline={}, wav_filename=None)
    browser.open(path.as_uri())
    assert browser.evaluate("document.getElementById('mura-audio')") is None
    assert browser.evaluate("window.__mura.duration()") == pytest.approx((motion.frame_count - 1) / motion.fps)
    browser.evaluate("window.__mura.play()")
    assert browser.evaluate(ADVANCES), "time did not advance while playing without audio"
    assert browser.exceptions() == []
