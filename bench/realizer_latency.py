"""How fast the realizer answers: BML parsing, and ``mura serve``'s first feedback for a block.

Not a test: prints figures. ``python -m bench.realizer_latency`` parses the example block
``specs/bml/take_this_bar.bml`` many times, then starts ``mura serve`` (fake speech, no
audio, real time) and sends it the block several times, each once the previous has
ended, timing from the send to ``accepted``, to the first ``prediction`` and to the
``blockProgress`` start (which includes the scheduler's live margin).
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
import time

from websockets.sync.client import connect

from mura.bml import parse_bml
from mura.resources import SPECS_DIR

BLOCK = SPECS_DIR / "bml" / "take_this_bar.bml"
TIMEOUT = 60.0


def parsing(repeats: int = 200) -> float:
    """Median seconds to read the example block."""
    text = BLOCK.read_text(encoding="utf-8")
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        parse_bml(text)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def serving(blocks: int = 5) -> dict[str, float]:
    """Median seconds from sending a block to each first answer, on an idle server."""
    server = subprocess.Popen([sys.executable, "-m", "agent.cli", "serve", "--tts", "fake", "--no-audio"],
                              stdout=subprocess.PIPE, text=True)
    try:
        address = server.stdout.readline().strip()
        text = BLOCK.read_text(encoding="utf-8")
        waits: dict[str, list[float]] = {"accepted": [], "prediction": [], "start": []}
        with connect(address, open_timeout=TIMEOUT) as ws:
            ws.recv(timeout=TIMEOUT)
            for index in range(blocks):
                block = text.replace('id="take_this_bar"', f'id="latency{index}"')
                sent = time.perf_counter()
                ws.send(json.dumps({"type": "bml", "xml": block}))
                seen: set[str] = set()
                while "end" not in seen:
                    message = json.loads(ws.recv(timeout=TIMEOUT))
                    kind = message.get("point") if message.get("type") == "blockProgress" else message.get("type")
                    if kind in waits and kind not in seen:
                        waits[kind].append(time.perf_counter() - sent)
                    seen.add(kind)
        return {kind: statistics.median(values) for kind, values in waits.items()}
    finally:
        server.terminate()
        server.wait(TIMEOUT)


def main() -> None:
    print(f"parse {BLOCK.name}: {parsing() * 1000:.2f} ms (median)")
    for kind, seconds in serving().items():
        print(f"mura serve, send -> {kind}: {seconds * 1000:.1f} ms (median, idle server)")


if __name__ == "__main__":
    main()
