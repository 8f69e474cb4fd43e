"""Runs the ``mura`` command line in a fresh process under the hostile suite's conditions.

``python mura_runner.py CONFIG -- ARGS...`` where CONFIG is JSON:

* ``address_space_mb``: the process's address-space limit (``RLIMIT_AS``), set before
  anything is imported, so that an input that makes mura allocate gigabytes fails with
  MemoryError here instead of swapping the machine — and the test sees whether mura
  refused it cleanly first;
* ``hooks``: ``[{"target": "module:attribute.path", "call": N, "action": ...}]``: the
  named function is wrapped so that its N-th call first does ``action`` — ``"SIGTERM"``
  or ``"SIGINT"`` (the process signals itself: a deterministic point in the middle of a
  run, where a test with a timer would race) or ``"raise:TYPE:MESSAGE"`` (one of
  ``SpeechError``, ``RuntimeError``). The wrapped function then runs as usual.

This is test scaffolding, not part of mura: the code under test is the real command line.
"""

from __future__ import annotations

import functools
import importlib
import json
import os
import resource
import signal
import sys


def _limit_address_space(megabytes: int) -> None:
    limit = megabytes << 20
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))


def _exception(name: str) -> type[BaseException]:
    if name == "SpeechError":
        from tts import SpeechError

        return SpeechError
    return {"RuntimeError": RuntimeError, "KeyError": KeyError}[name]


def _act(action: str) -> None:
    if action in ("SIGTERM", "SIGINT"):
        os.kill(os.getpid(), getattr(signal, action))
        return
    _, name, message = action.split(":", 2)
    raise _exception(name)(message)


def _install(hook: dict) -> None:
    module_name, _, path = hook["target"].partition(":")
    owner = importlib.import_module(module_name)
    *parents, attribute = path.split(".")
    for parent in parents:
        owner = getattr(owner, parent)
    original = getattr(owner, attribute)
    calls = {"count": 0}

    @functools.wraps(original)
    def wrapped(*args, **kwargs):
        calls["count"] += 1
        if calls["count"] == hook["call"]:
            _act(hook["action"])
        return original(*args, **kwargs)

    setattr(owner, attribute, wrapped)


def main() -> int:
    config = json.loads(sys.argv[1])
    argv = sys.argv[sys.argv.index("--") + 1 :]
    if config.get("address_space_mb"):
        _limit_address_space(int(config["address_space_mb"]))
    for hook in config.get("hooks", ()):
        _install(hook)
    from agent.cli import main as mura

    return mura(argv)


if __name__ == "__main__":
    sys.exit(main())
