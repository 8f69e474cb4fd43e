"""Speech synthesis cost: seconds of compute per second of speech, per available backend.

Not a test: prints figures. ``run(quick)`` returns ``{backend: {...}}`` with the median
over several runs of a fixed paragraph (fewer, shorter runs when ``quick``).
"""

from __future__ import annotations

import statistics
import time

from tts import BACKENDS, SpeechRequest, TextMark

_SENTENCES = (
    "When I saw the little red boat, it was already drifting out to sea.",
    "So I ran along the pier, waved both arms, and shouted as loud as I could.",
    "Nobody heard me, of course; the wind took every word away.",
)


def _request(text: str) -> SpeechRequest:
    words = text.split(" ")
    mark_at = len(" ".join(words[:3])) + 1
    return SpeechRequest(text, marks=(TextMark("t1", mark_at),), emphasis=((mark_at, mark_at + len(words[3])),), with_audio=True)


def _measure(synthesizer, requests: list[SpeechRequest], repeats: int) -> dict[str, float]:
    ratios = []
    speech = 0.0
    for _ in range(repeats):
        started = time.perf_counter()
        speech = sum(synthesizer.synthesize(r).duration for r in requests)
        ratios.append((time.perf_counter() - started) / speech)
    median = statistics.median(ratios)
    return {"seconds_per_speech_second": median, "realtime_factor": 1.0 / median, "speech_seconds": speech, "runs": repeats}


def run(quick: bool) -> dict:
    """Median synthesis time per second of speech for every backend that works here."""
    requests = [_request(s) for s in (_SENTENCES[:1] if quick else _SENTENCES)]
    repeats = 3 if quick else 9
    results: dict[str, dict] = {}
    for name in ("fake", "pyttsx3", "espeak"):  # pyttsx3 first: after espeak loads, it cannot share the library
        backend = BACKENDS[name]
        synthesizer = backend()
        reason = getattr(synthesizer, "unavailable_reason", lambda: None)()
        if reason is not None:
            results[name] = {"unavailable": reason}
            continue
        synthesizer.synthesize(requests[0])  # load the library, warm caches
        results[name] = _measure(synthesizer, requests, repeats)
    return results


if __name__ == "__main__":
    for backend_name, figures in run(quick=False).items():
        if "unavailable" in figures:
            print(f"{backend_name:8s} unavailable: {figures['unavailable']}")
            continue
        print(
            f"{backend_name:8s} {1000 * figures['seconds_per_speech_second']:8.2f} ms per second of speech "
            f"({figures['realtime_factor']:.0f}x real time, {figures['speech_seconds']:.2f} s of speech, "
            f"median of {figures['runs']})"
        )
