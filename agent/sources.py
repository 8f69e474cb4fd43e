"""Where an utterance comes from: XML text, a file path or an already parsed model."""

from __future__ import annotations

import os
from pathlib import Path

from mura.lexicon import GestureLexicon
from mura.model import Utterance
from mura.murml import load_utterance, parse_utterance

UtteranceSource = str | bytes | os.PathLike[str] | Utterance


def read_utterance(source: UtteranceSource, lexicon: GestureLexicon | None = None) -> tuple[Utterance, str]:
    """An utterance and a name for it, from XML text, a file path or a parsed model;
    functions are looked up in ``lexicon`` (the bundled one when None)."""
    if isinstance(source, Utterance):
        return source, Path(source.source).stem or "utterance"
    if isinstance(source, bytes) or (isinstance(source, str) and source.lstrip().startswith("<")):
        return parse_utterance(source, file="<utterance>", lexicon=lexicon), "utterance"
    path = Path(source)
    return load_utterance(path, lexicon), path.stem
