"""``mura serve`` driven by a real WebSocket client: a block's feedback arrives in order,
a REPLACE block interrupts the one playing, bad messages get located errors and the
connection stays usable, observers hear every block, the page is served on the same port.

The server runs as its own process with the fake speech, no audio device and a clock
four times faster than real time; nothing here measures time except the tests' timeout.
"""

from __future__ import annotations

import json
import urllib.error
import urllib.request

import pytest
from websockets.exceptions import InvalidStatus
from serve_process import TIMEOUT
from websockets.sync.client import connect

NS = 'xmlns="http://www.bml-initiative.org/bml/bml-1.0"'


def block(block_id: str, composition: str = "APPEND", words: str = "Take <sync id=\"tm1\"/> this bar, please.") -> str:
    return (f'<bml {NS} id="{block_id}" composition="{composition}"><speech id="s1"><text>{words}</text></speech>'
            f'<gesture id="g1" lexeme="BEAT" stroke="s1:tm1"/><head id="h1" lexeme="NOD" amount="0.5" stroke="g1:strokeEnd"/></bml>')


def until(ws, done, limit: int = 5000) -> list[dict]:
    """Messages received until ``done(message)`` is true (that one included)."""
    messages = []
    for _ in range(limit):
        message = json.loads(ws.recv(timeout=TIMEOUT))
        messages.append(message)
        if done(message):
            return messages
    raise AssertionError(f"no end after {limit} messages")


def ends(block_id: str):
    return lambda m: m.get("type") == "blockProgress" and m["block"] == block_id and m["point"] == "end"


def test_first_line_is_the_address_and_hello_follows(server):
    address, page = server
    assert page == f"avatar page: http://{address.removeprefix('ws://')}/?live=ws"
    with connect(address) as ws:
        hello = json.loads(ws.recv(timeout=TIMEOUT))
    assert hello["type"] == "hello" and hello["protocol"] == 1


def test_block_feedback_arrives_in_order(server):
    with connect(server[0]) as ws:
        ws.recv(timeout=TIMEOUT)
        ws.send(json.dumps({"type": "bml", "xml": block("order"), "request": 7}))
        messages = until(ws, ends("order"))
    kinds = [m["type"] for m in messages]
    assert messages[0] == {"type": "accepted", "block": "order", "request": 7}
    prediction = kinds.index("prediction")
    start = next(i for i, m in enumerate(messages) if m["type"] == "blockProgress" and m["point"] == "start")
    syncs = [i for i, k in enumerate(kinds) if k == "syncPointProgress"]
    assert prediction < start < min(syncs) and max(syncs) < len(messages) - 1
    assert messages[-1]["status"] == "DONE"
    gesture = [m["sync"] for m in messages if m["type"] == "syncPointProgress" and m["behavior"] == "g1"]
    assert gesture == ["start", "ready", "strokeStart", "stroke", "strokeEnd", "relax", "end"]
    speech = [m["sync"] for m in messages if m["type"] == "syncPointProgress" and m["behavior"] == "s1"]
    assert speech == ["start", "tm1", "end"]
    predicted = messages[prediction]["behaviors"]
    assert predicted["h1"]["stroke"] == pytest.approx(predicted["g1"]["strokeEnd"], abs=1e-6)
    assert predicted["g1"]["stroke"] == pytest.approx(predicted["s1"]["tm1"], abs=1e-6)
    assert '<head id="h1"' in messages[prediction]["bml"]
    warnings = [m for m in messages if m["type"] == "warning"]
    assert any(w["kind"] == "NOT_PERFORMED" and w["where"].startswith("<message ") for w in warnings)


def test_replace_interrupts_the_block_playing(server):
    long_words = "This is a long sentence <sync id=\"tm1\"/> that would go on for a good while if nobody stopped it at all."
    with connect(server[0]) as ws:
        ws.recv(timeout=TIMEOUT)
        ws.send(json.dumps({"type": "bml", "xml": block("first", words=long_words)}))
        before = until(ws, lambda m: m["type"] == "syncPointProgress" and m["block"] == "first")
        ws.send(json.dumps({"type": "bml", "xml": block("second", "REPLACE")}))
        after = until(ws, ends("second"))
    messages = before + after
    first_end = next(i for i, m in enumerate(messages) if m["type"] == "blockProgress" and m["id"] == "first:end")
    second_start = next(i for i, m in enumerate(messages) if m["type"] == "blockProgress" and m["id"] == "second:start")
    assert messages[first_end]["status"] == "INTERRUPTED"
    assert first_end < second_start
    assert messages[-1]["status"] == "DONE"
    assert not any(m.get("block") == "first" and m["type"] == "syncPointProgress" for m in messages[first_end:])


@pytest.mark.parametrize(("payload", "line", "column", "words"), [
    (json.dumps({"type": "bml", "xml": f'<bml {NS} id="x">\n<speech id="s1"><text>hi</speech></bml>'}), 2, None, "malformed XML"),
    (json.dumps({"type": "bml", "xml": f'<bml {NS} id="x">\n  <gesture id="g1" lexeme="BEAT" stroke="g9:end"/></bml>'}), 2, 34, "unknown behaviour 'g9'"),
    ('{"type": "bml", "xml": ', 1, 24, "not JSON"),
    (json.dumps({"type": "dance"}), 1, 1, "unknown message type 'dance'"),
])
def test_bad_message_gets_a_located_error_and_the_connection_stays_usable(server, payload, line, column, words):
    with connect(server[0]) as ws:
        ws.recv(timeout=TIMEOUT)
        ws.send(payload)
        error = json.loads(ws.recv(timeout=TIMEOUT))
        assert error["type"] == "error" and words in error["message"]
        assert error["line"] == line and (column is None or error["column"] == column)
        if words in ("malformed XML", "unknown behaviour 'g9'"):  # the BML text's place, named by message
            assert error["where"].startswith("<message ") and error["where"].endswith(f":{line}:{error['column']}")
        ws.send(json.dumps({"type": "ping", "request": "p"}))
        assert json.loads(ws.recv(timeout=TIMEOUT)) == {"type": "pong", "request": "p"}


def test_observers_hear_every_block_and_frames(server):
    with connect(server[0]) as observer, connect(server[0]) as sender:
        observer.recv(timeout=TIMEOUT)
        sender.recv(timeout=TIMEOUT)
        observer.send(json.dumps({"type": "observe", "frames": True}))
        assert "skeleton" in json.loads(observer.recv(timeout=TIMEOUT))
        assert json.loads(observer.recv(timeout=TIMEOUT))["type"] == "observing"
        sender.send(json.dumps({"type": "bml", "xml": block("watched")}))
        seen = until(observer, ends("watched"))
        until(sender, ends("watched"))
    assert any(m.get("type") == "prediction" and m["block"] == "watched" for m in seen)
    assert any("rotations" in m for m in seen)


def test_murml_and_interrupt_messages(server, repo):
    murml = (repo / "specs" / "utterances" / "fig2_take_this_bar.xml").read_text()
    with connect(server[0]) as ws:
        ws.recv(timeout=TIMEOUT)
        ws.send(json.dumps({"type": "murml", "xml": murml, "id": "fig2"}))
        first = until(ws, lambda m: m["type"] == "blockProgress" and m["point"] == "start")
        ws.send(json.dumps({"type": "interrupt", "block": "fig2"}))
        rest = until(ws, ends("fig2"))
    assert first[0] == {"type": "accepted", "block": "fig2"}
    assert {"type": "interrupted", "blocks": ["fig2"]} in rest
    assert rest[-1]["status"] == "INTERRUPTED"


def test_page_is_served_and_foreign_pages_are_refused(server):
    http = "http://" + server[0].removeprefix("ws://")
    with urllib.request.urlopen(http + "/", timeout=TIMEOUT) as response:
        assert response.headers["Content-Type"].startswith("text/html")
        assert b"<html" in response.read()
    with pytest.raises(urllib.error.HTTPError) as missing:
        urllib.request.urlopen(http + "/secret", timeout=TIMEOUT)
    assert missing.value.code == 404
    with pytest.raises(InvalidStatus) as refused:
        connect(server[0], origin="http://evil.example", open_timeout=TIMEOUT)
    assert refused.value.response.status_code == 403
