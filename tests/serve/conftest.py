"""The realizer server as its own process, shared by the tests of this folder."""

from __future__ import annotations

import subprocess
import sys
import threading

import pytest
from serve_process import TIMEOUT


@pytest.fixture(scope="session")
def server():
    process = subprocess.Popen(
        [sys.executable, "-m", "agent.cli", "serve", "--tts", "fake", "--no-audio", "--speedup", "4", "--port", "0"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )
    lines: list[str] = []
    reader = threading.Thread(target=lambda: lines.extend([process.stdout.readline(), process.stdout.readline()]), daemon=True)
    reader.start()
    reader.join(TIMEOUT)
    if not lines or not lines[0].startswith("ws://127.0.0.1:"):
        process.kill()
        pytest.fail(f"mura serve did not print its address: {lines!r} {process.stderr.read() if process.poll() is not None else ''}")
    yield lines[0].strip(), lines[1].strip()
    process.terminate()
    assert process.wait(TIMEOUT) == 0
