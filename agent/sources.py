"""Where an utterance comes from: XML text, a file path or an already parsed model."""

from __future__ import annotations

import os
from pathlib import Path

from mura.expansion import check_utterance
from mura.limits import DEFAULT_LIMITS, Limits
from mura.model import Utterance
from mura.murml import load_utterance, parse_utterance

UtteranceSource = str | bytes | os.PathLike[str] | Utterance


def read_utterance(source: UtteranceSource, limits: Limits = DEFAULT_LIMITS) -> tuple[Utterance, str]:
    """An utterance and a name for it, from XML text, a file path or a parsed model,
    checked against ``limits`` (a model built in Python too)."""
    if isinstance(source, Utterance):
        check_utterance(source, limits)
        return source, Path(source.source).stem or "utterance"
    if isinstance(source, bytes) or (isinstance(source, str) and source.lstrip().startswith("<")):
        return parse_utterance(source, file="<utterance>", limits=limits), "utterance"
    path = Path(source)
    return load_utterance(path, limits=limits), path.stem
