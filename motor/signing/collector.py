"""Python's cyclic garbage collector paused while a collection of signs is planned or
realized.

Planning or realizing a collection allocates hundreds of thousands of small objects and
keeps most of them until it is done, so the collector's passes over the whole heap cost
time (a tenth of planning; 0.4 s of two full passes while both corpora are realized),
while neither leaves more than a few hundred objects in reference cycles (150 from
planning both corpora, none from realizing them). The price: cyclic garbage made
*before* (a parsed corpus leaves ~42,000 objects) waits until the collector resumes —
24 MB more at the peak when both corpora are planned right after parsing them.
"""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def collector_paused() -> Iterator[None]:
    """The cyclic garbage collector paused for the duration, and resumed only if it was
    running."""
    running = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if running:
            gc.enable()
