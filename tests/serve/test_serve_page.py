"""The page ``mura serve`` serves is a client of it: it observes, follows the frames and the
feedback, and sends the BML typed into it."""

from __future__ import annotations

import json

from serve_process import TIMEOUT
from websockets.sync.client import connect

NS = 'xmlns="http://www.bml-initiative.org/bml/bml-1.0"'
WAIT = ("new Promise((resolve) => { const check = () => ({condition}) ? resolve(true) : setTimeout(check, 20);"
        " check(); setTimeout(() => resolve(false), {ms}); })")


def wait(browser, condition: str) -> bool:
    return browser.evaluate(WAIT.replace("{condition}", condition).replace("{ms}", str(int(TIMEOUT * 1000))))


def block(block_id: str) -> str:
    return (f'<bml {NS} id="{block_id}" composition="APPEND"><speech id="s1"><text>Look <sync id="tm1"/> here.</text></speech>'
            f'<gesture id="g1" lexeme="BEAT" stroke="s1:tm1"/></bml>')


def test_page_follows_frames_and_feedback_and_sends_bml(server, browser):
    address, _ = server
    browser.open(f"http://{address.removeprefix('ws://')}/?live=ws")
    assert wait(browser, "window.__mura && window.__mura.joints() > 0")
    with connect(address) as observer:
        observer.recv(timeout=TIMEOUT)
        observer.send(json.dumps({"type": "observe"}))
        observer.recv(timeout=TIMEOUT)
        observer.send(json.dumps({"type": "bml", "xml": block("from_client")}))
        assert wait(browser, "document.getElementById('mura-status').textContent.startsWith('from_client: end')")
        assert wait(browser, "window.__mura.time() > 0")
        browser.evaluate(f"document.getElementById('mura-bml').value = {json.dumps(block('from_page'))}")
        browser.evaluate("document.querySelector('#mura-send button').click()")
        ids = []
        while "from_page:end" not in ids:
            message = json.loads(observer.recv(timeout=TIMEOUT))
            if message.get("type") == "blockProgress":
                ids.append(message["id"])
    assert ids[-2:] == ["from_page:start", "from_page:end"]
    assert browser.exceptions() == []
