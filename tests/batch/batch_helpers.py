"""Corpora written for the batch tests, and a renderer with poisoned items.

The signs are small hand-written HamNoSys streams (glosses in several scripts, one
broken). :func:`poisoned_renderer` renders like :func:`agent.batch.render.render_chunk`
except for items whose gloss names a poison: ``POISON-EXIT`` kills the worker process
outright, ``POISON-MEMORY`` raises ``MemoryError`` and ``POISON-SLOW`` runs past the time
limit, each inside the same guard real items are rendered under.
"""

from __future__ import annotations

import os
import time
from collections.abc import Sequence

from agent.batch.items import CorpusItem
from agent.batch.render import ItemResult, RenderOptions, guarded, render_chunk

SIGNS = {
    "HOUSE": "hamsymmlr hamflathand hamextfingeruo hampalmdl hamforehead hamlrat hammoved",
    "नमस्ते": "hamflathand hamextfingeru hampalml hamchest hammoveo",
    "Düren": "hamfinger2 hamextfingeru hampalml hamforehead hamtouch hammover",
    "中文": "hamfist hamextfingero hampalmd hamstomach hamcircleo",
    "a b/c": "hamfinger23 hamextfingero hampalmd hamchest hammover hamrepeatfromstart",
    "A B C": "hamceeall hamextfingero hampalml hamchest hammoveu",
    "broken": "hamfist hamnosuch",
}
POISONS = ("POISON-EXIT", "POISON-MEMORY", "POISON-SLOW")


def sigml(signs: dict[str, str]) -> str:
    """A SiGML collection of ``gloss -> space-separated symbols``."""
    parts = []
    for gloss, symbols in signs.items():
        tags = "".join(f"<{name}/>" for name in symbols.split())
        parts.append(f'<hns_sign gloss="{gloss}"><hamnosys_manual>{tags}</hamnosys_manual></hns_sign>')
    return "<sigml>" + "".join(parts) + "</sigml>"


def poisoned_renderer(items: Sequence[CorpusItem], options: RenderOptions, output: str, done: frozenset[int]) -> list[ItemResult]:
    """``render_chunk`` with the poisons of the module docstring."""
    labels = {item.label for item in items if item.index not in done}
    if "POISON-EXIT" in labels:
        os._exit(13)
    results = render_chunk([item for item in items if item.label not in POISONS], options, output, done)
    for item in items:
        if item.index in done or item.label not in POISONS:
            continue
        results.append(guarded(item, options, lambda label=item.label: _poison(label)))
    return sorted(results, key=lambda result: result.index)


def _poison(label: str) -> ItemResult:
    if label == "POISON-MEMORY":
        raise MemoryError
    while True:  # POISON-SLOW: only the time limit ends it
        time.sleep(0.01)
