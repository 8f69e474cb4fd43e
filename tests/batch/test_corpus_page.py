"""The corpus index page in headless Chromium: one viewer for many motions.

It lists every item, searches by gloss (any script), loads an item's motion file when
chosen, steps through the items found, and draws each item as that item's own page draws
it (the same joint positions at the same times)."""

from __future__ import annotations

import sys
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from batch_helpers import SIGNS, sigml

from agent.cli import main
from motor.body.conventions import BUILT_AVATAR_DIR

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "viewer"))
from headless_chromium import Browser, find_chromium  # noqa: E402  (the viewer tests' browser driver)

READY = (
    "new Promise((resolve) => { const start = performance.now(); const check = () => window.__muraReady ? resolve(true)"
    " : performance.now() - start > 40000 ? resolve(false) : setTimeout(check, 20); check(); })"
)
JOINTS = ("r_wrist", "l_wrist", "r_index3", "skullbase")


@pytest.fixture(scope="module")
def corpus_folder(tmp_path_factory) -> Path:
    if not (BUILT_AVATAR_DIR / "makehuman.glb").is_file():
        pytest.fail("the built avatar is missing: run `make setup`")
    folder = tmp_path_factory.mktemp("corpus")
    source = folder / "signs.sigml"
    source.write_text(sigml(SIGNS), encoding="utf-8")
    assert main(["sign", str(source), "-o", str(folder / "out"), "--no-glb", "--pages"]) == 1  # the broken sign fails
    return folder / "out"


@pytest.fixture(scope="module")
def browser() -> Iterator[Browser]:
    executable = find_chromium()
    if executable is None:
        pytest.fail("headless Chromium is missing (/usr/bin/chromium)")
    browser = Browser(executable)
    yield browser
    browser.close()


def _open(browser: Browser, page: Path) -> None:
    browser.open(page.as_uri())
    assert browser.evaluate(READY), "the page never finished its first frame"
    assert browser.evaluate("window.__muraError || null") is None
    assert browser.evaluate("window.__muraModelError || null") is None
    assert browser.exceptions() == []


def _positions(browser: Browser, t: float) -> np.ndarray:
    browser.evaluate(f"window.__mura.pause(); window.__mura.seek({t})")
    return np.array([browser.evaluate(f"window.__mura.jointPosition('{joint}')") for joint in JOINTS])


def test_lists_every_item_and_opens_the_first(browser: Browser, corpus_folder: Path) -> None:
    _open(browser, corpus_folder / "index.html")
    assert browser.evaluate("window.__mura.items()") == ["HOUSE", "नमस्ते", "Düren", "中文", "a_b_c", "A_B_C_2", "broken"]
    assert browser.evaluate("window.__mura.current()") == "HOUSE"
    assert browser.evaluate("window.__mura.model()")["format"] == "glb"
    failed = browser.evaluate("[...document.querySelectorAll('#mura-items li.failed')].map((li) => li.dataset.name)")
    assert failed == ["broken"]


@pytest.mark.parametrize(("query", "found"), [("नम", ["नमस्ते"]), ("dü", ["Düren"]), ("a b", ["a_b_c", "A_B_C_2"]), ("", None), ("zzz", [])])
def test_search_by_gloss(browser: Browser, corpus_folder: Path, query: str, found: list[str] | None) -> None:
    _open(browser, corpus_folder / "index.html")
    count = browser.evaluate(f"window.__mura.search({query!r})")
    visible = browser.evaluate("window.__mura.visible()")
    assert visible == (found if found is not None else browser.evaluate("window.__mura.items()"))
    assert count == len(visible)


def test_steps_through_the_items_found(browser: Browser, corpus_folder: Path) -> None:
    _open(browser, corpus_folder / "index.html")
    browser.evaluate("window.__mura.search('a')")  # HOUSE, a_b_c, A_B_C (and the unplayable broken one is not 'a')
    visible = browser.evaluate("window.__mura.visible()")
    assert browser.evaluate("window.__mura.select(window.__mura.visible()[0])") == visible[0]
    stepped = [browser.evaluate("window.__mura.next()") for _ in range(len(visible))]
    assert stepped == visible[1:] + visible[:1]  # round to the first again
    assert browser.evaluate("window.__mura.prev()") == visible[-1]


@pytest.mark.parametrize("name", ["नमस्ते", "a_b_c"])
def test_draws_an_item_as_its_own_page_does(browser: Browser, corpus_folder: Path, name: str) -> None:
    _open(browser, corpus_folder / "index.html")
    assert browser.evaluate(f"window.__mura.select({name!r})") == name
    duration = browser.evaluate("window.__mura.duration()")
    times = np.linspace(0.1, duration - 0.1, 5)
    index = np.array([_positions(browser, t) for t in times])
    _open(browser, corpus_folder / f"{name}.html")
    own = np.array([_positions(browser, t) for t in times])
    assert np.ptp(index[:, 0], axis=0).max() > 5.0  # the wrist moves (cm)
    assert np.max(np.abs(index - own)) < 0.2  # cm: the int16 quaternions draw what the BVH draws


def test_plays_the_face_of_an_item_as_its_own_page_does(browser: Browser, tmp_path: Path) -> None:
    source = tmp_path / "face.sigml"
    source.write_text(
        '<sigml><hns_sign gloss="NO"><hamnosys_nonmanual><hnm_head tag="NO"/><hnm_mouthpicture picture="hVlU"/></hamnosys_nonmanual>'
        "<hamnosys_manual><hamflathand/><hamextfingeru/><hampalml/><hamchest/><hammoveo/></hamnosys_manual></hns_sign></sigml>",
        encoding="utf-8",
    )
    assert main(["sign", str(source), "-o", str(tmp_path / "out"), "--no-glb", "--pages"]) == 0
    _open(browser, tmp_path / "out" / "index.html")
    assert browser.evaluate("window.__mura.faceNames()") > 0
    duration = browser.evaluate("window.__mura.duration()")
    times = np.linspace(0.1, duration - 0.1, 7)

    def faces() -> list[dict]:
        return [browser.evaluate(f"window.__mura.pause(); window.__mura.seek({t}); window.__mura.face()") for t in times]

    index = faces()
    _open(browser, tmp_path / "out" / "NO.html")
    own = faces()
    assert any(max(weights.values(), default=0) > 0.1 for weights in index)  # the mouth moves
    assert index == own
