"""A cProfile run written as the two listings the profile documents keep (``docs/profile_*``)."""

from __future__ import annotations

import cProfile
import io
import pstats


def listings(profiler: cProfile.Profile, top: int) -> str:
    """The ``top`` entries by cumulative and by own time, each under a ``--- top N by KEY`` line."""
    out = io.StringIO()
    for key in ("cumulative", "tottime"):
        listing = io.StringIO()
        pstats.Stats(profiler, stream=listing).strip_dirs().sort_stats(key).print_stats(top)
        text = listing.getvalue()
        out.write(f"--- top {top} by {key}\n{text[text.index('   ncalls'):].rstrip()}\n\n")
    return out.getvalue()
