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


@pytest.fixture(scope="session")
def browser():
    """Headless Chromium, driven by the page tests' helper in ``tests/viewer``."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "viewer" / "headless_chromium.py"
    spec = importlib.util.spec_from_file_location("serve_headless_chromium", path)
    helper = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(helper)
    executable = helper.find_chromium()
    if executable is None:
        pytest.skip("Chromium is not installed (apt-get install -y chromium); the page tests need it")
    with helper.Browser(executable) as running:
        yield running
