"""SIGTERM and SIGINT for the command line: both interrupt the run the same way.

Ctrl-C raises :class:`KeyboardInterrupt` in the main thread; ``timeout``, a process
manager or ``kill`` send SIGTERM, which by default ends the process on the spot and
leaves hidden temporary files behind. :func:`sigterm_interrupts` turns SIGTERM into
:class:`Terminated`, a :class:`KeyboardInterrupt`, so that every cleanup written for
Ctrl-C (staged outputs removed, live utterances interrupted, servers closed) runs for
both. :func:`signals_deferred` holds both signals back while a few renames or removals
that must not be cut in half are done, then delivers them.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

#: The signals that interrupt a run.
INTERRUPTS = (signal.SIGINT, signal.SIGTERM)


class Terminated(KeyboardInterrupt):
    """The process received SIGTERM."""


def _raise_terminated(signum: int, frame: FrameType | None) -> None:
    raise Terminated()


@contextmanager
def sigterm_interrupts() -> Iterator[None]:
    """Within the block, SIGTERM raises :class:`Terminated` in the main thread (elsewhere
    the block runs as is); the previous handler comes back after it."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous if previous is not None else signal.SIG_DFL)


def exit_status(interrupt: KeyboardInterrupt) -> int:
    """The shell's status for a process ended by this interrupt: 128 + the signal number."""
    return 128 + (signal.SIGTERM if isinstance(interrupt, Terminated) else signal.SIGINT)


@contextmanager
def signals_deferred() -> Iterator[None]:
    """Hold SIGINT and SIGTERM back for the duration of the block, then deliver them.

    Only the main thread can change signal handlers (and Python runs handlers only
    there); elsewhere the block runs as is.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    received: list[int] = []
    previous = {number: signal.getsignal(number) for number in INTERRUPTS}
    for number in INTERRUPTS:
        signal.signal(number, lambda signum, frame: received.append(signum))
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler if handler is not None else signal.SIG_DFL)
        for number in received:
            signal.raise_signal(number)
