"""An agent in another process: it sends BML blocks to ``mura serve`` and follows the feedback.

Start the realizer, then this client with the address the realizer printed::

    mura serve --port 8765                      # prints ws://127.0.0.1:8765 first
    python -m agent.examples.bml_client ws://127.0.0.1:8765 [BLOCK.bml ...]

Without files it says a short greeting of two blocks (the second appended to the first).
Each block is sent in the protocol's envelope (``{"type": "bml", "xml": …}``); the client
prints the predicted stroke times, block start and end and every sync point as they come,
and ends when every block it sent has ended. Only the ``websockets`` library is needed,
so the same few lines work from any agent framework.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from pathlib import Path

from websockets.exceptions import WebSocketException
from websockets.sync.client import connect

NS = 'xmlns="http://www.bml-initiative.org/bml/bml-1.0"'
GREETING: tuple[str, ...] = (
    f'<bml {NS} id="greet" composition="REPLACE"><speech id="s1"><text>Hello, <sync id="you"/> you over there!</text></speech>'
    '<pointing id="point" target="Loc-User" stroke="s1:you"/><head id="nod" lexeme="NOD" stroke="point:strokeEnd"/></bml>',
    f'<bml {NS} id="offer" composition="APPEND"><speech id="s1"><text>Let me show you <sync id="it"/> something.</text></speech>'
    '<gesture id="offer" lexeme="OFFER" stroke="s1:it"/></bml>',
)
#: Seconds to wait for the next message before giving up.
TIMEOUT = 120.0


def describe(message: dict) -> str | None:
    """One line for a feedback message (None for messages not worth a line)."""
    kind = message.get("type")
    if kind == "prediction":
        strokes = ", ".join(f"{b} {syncs['stroke']:.2f} s" for b, syncs in message["behaviors"].items() if "stroke" in syncs)
        return f"{message['block']}: predicted strokes: {strokes or 'none'}"
    if kind == "blockProgress":
        status = f" ({message['status']})" if message["status"] else ""
        return f"{message['block']}: block {message['point']} at {message['globalTime']:.2f} s{status}"
    if kind == "syncPointProgress":
        return f"{message['block']}: {message['behavior']}:{message['sync']} at {message['time']:.2f} s"
    if kind in ("warning", "error"):
        where = f"{message['where']}: " if message.get("where") else ""
        return f"{message.get('block', '')}: {kind}: {where}{message['message']}"
    return None


def perform(address: str, blocks: Sequence[str], out=None) -> int:
    """Send ``blocks`` to the realizer at ``address`` and print their feedback (to ``out``,
    standard output by default) until all end; returns the number of blocks refused or failed."""
    out = out if out is not None else sys.stdout
    problems = 0
    with connect(address, open_timeout=TIMEOUT) as ws:
        ws.recv(timeout=TIMEOUT)  # hello
        waiting = set()
        for index, xml in enumerate(blocks):
            ws.send(json.dumps({"type": "bml", "xml": xml, "request": index}))
        answered = 0
        while answered < len(blocks) or waiting:
            message = json.loads(ws.recv(timeout=TIMEOUT))
            if message.get("type") == "accepted":
                answered += 1
                waiting.add(message["block"])
            elif message.get("type") == "error":
                answered += 1
                problems += 1
            elif message.get("type") == "blockProgress" and message["point"] == "end":
                waiting.discard(message["block"])
                problems += message["status"] == "FAILED"
            line = describe(message)
            if line is not None:
                print(line, file=out, flush=True)
    return problems


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Send BML blocks to mura serve and print the feedback.")
    parser.add_argument("address", help="the realizer's address, as mura serve prints it (ws://127.0.0.1:PORT)")
    parser.add_argument("blocks", nargs="*", type=Path, help="BML files to send (default: a two-block greeting)")
    args = parser.parse_args(argv)
    try:
        blocks = [path.read_text(encoding="utf-8") for path in args.blocks] or list(GREETING)
    except OSError as error:
        print(f"bml_client: {error}", file=sys.stderr)
        return 2
    try:
        return 1 if perform(args.address, blocks) else 0
    except (OSError, TimeoutError, WebSocketException) as error:
        print(f"bml_client: {args.address}: {error}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
