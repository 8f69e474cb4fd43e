"""Speech backends whose every failure is a SpeechError, and whose calls can be abandoned.

A backend may hang (a driver that never answers, a speech server that stalls) or fail
with an exception of its own. Live, neither may stop the agent: an interrupted utterance
must end within a bound, and a failed chunk must come back as a :class:`SpeechError`
naming the backend so that the scheduler fails that chunk and keeps what was performed.

:class:`InterruptibleSynthesizer` runs each ``synthesize`` call in a worker thread of its
own and waits for it; :meth:`~InterruptibleSynthesizer.cancel` makes every waiting call
raise :class:`SpeechError` at once. Python cannot stop a thread, so a backend that truly
hangs keeps its worker until it returns; the worker is a daemon and holds nothing but the
abandoned call, and :meth:`~InterruptibleSynthesizer.close` waits (within a bound) for the
workers to finish. Offline, :class:`CheckedSynthesizer` does the same conversion of
failures in the calling thread.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field

from tts.speech import SpeechError, SpeechRequest, SpeechSynthesizer, SpeechTiming

#: Longest wait for abandoned workers in :meth:`InterruptibleSynthesizer.close`, seconds.
CLOSE_TIMEOUT = 5.0


def speech_error(backend: str, error: BaseException) -> SpeechError:
    """``error`` as a :class:`SpeechError` naming the backend (itself when it is one)."""
    if isinstance(error, SpeechError):
        return error
    detail = f": {error}" if str(error) else ""
    return SpeechError(f"the {backend} speech backend failed: {type(error).__name__}{detail}")


class CheckedSynthesizer:
    """``backend`` behind the same protocol, every exception of it a :class:`SpeechError`."""

    def __init__(self, backend: SpeechSynthesizer) -> None:
        self.backend = backend
        self.name = getattr(backend, "name", type(backend).__name__)

    def available(self) -> bool:
        return self.backend.available()

    def synthesize(self, request: SpeechRequest) -> SpeechTiming:
        try:
            return self.backend.synthesize(request)
        except Exception as error:  # noqa: BLE001 - said as a SpeechError naming the backend
            raise speech_error(self.name, error) from error


@dataclass(eq=False)
class _Call:
    """One synthesis call: set ``finished`` once it has a result, an error, or was cancelled."""

    request: SpeechRequest
    finished: threading.Event = field(default_factory=threading.Event)
    result: SpeechTiming | None = None
    error: BaseException | None = None
    cancelled: bool = False

    def run(self, backend: SpeechSynthesizer) -> None:
        try:
            self.result = backend.synthesize(self.request)
        except BaseException as error:  # noqa: BLE001 - handed to the waiting caller
            self.error = error
        finally:
            self.finished.set()

    def cancel(self) -> None:
        self.cancelled = True
        self.finished.set()


class InterruptibleSynthesizer:
    """``backend`` behind the same protocol, with :meth:`cancel` and :meth:`close`."""

    def __init__(self, backend: SpeechSynthesizer) -> None:
        self.backend = backend
        self.name = getattr(backend, "name", type(backend).__name__)
        self._lock = threading.Lock()
        self._calls: set[_Call] = set()
        self._workers: list[threading.Thread] = []
        self._closed = False

    def available(self) -> bool:
        return self.backend.available()

    def synthesize(self, request: SpeechRequest) -> SpeechTiming:
        """The backend's timing for ``request``; :class:`SpeechError` when it fails, in
        whatever way, or when the call is cancelled."""
        call = _Call(request)
        worker = threading.Thread(target=call.run, args=(self.backend,), name=f"speech-{self.name}", daemon=True)
        with self._lock:
            if self._closed:
                raise SpeechError(f"the {self.name} speech backend is closed")
            self._calls.add(call)
            self._workers = [w for w in self._workers if w.is_alive()] + [worker]
        worker.start()
        call.finished.wait()
        with self._lock:
            self._calls.discard(call)
        if call.cancelled:
            raise SpeechError(f"speech synthesis ({self.name}) was interrupted")
        if call.error is not None:
            raise speech_error(self.name, call.error) from call.error
        assert call.result is not None
        return call.result

    def cancel(self) -> None:
        """Make every call now waiting raise :class:`SpeechError` at once."""
        with self._lock:
            calls = list(self._calls)
        for call in calls:
            call.cancel()

    def close(self, timeout: float = CLOSE_TIMEOUT) -> tuple[str, ...]:
        """Refuse further calls, cancel those waiting, and wait up to ``timeout`` seconds
        in all for their workers; returns the names of workers still stuck in the backend."""
        with self._lock:
            self._closed = True
            workers = list(self._workers)
        self.cancel()
        end = time.monotonic() + timeout
        for worker in workers:
            worker.join(max(0.0, end - time.monotonic()))
        return tuple(w.name for w in workers if w.is_alive())
