"""The models shipped with mura: fitted from the SYNTHETIC session in ``specs/verbs/``.

``specs/verbs/recordings_synthetic.json`` is what :mod:`motor.verbs.synthetic` writes with
its default seed, and ``specs/verbs/models_synthetic.json`` what :mod:`motor.verbs.fitting`
fits from it (``mura verbs synthesize`` and ``mura verbs fit`` remake both; a test checks
that they still agree with the code).
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

from motor.verbs.model import VerbModel, load_models

VERBS_DIR = Path(__file__).resolve().parents[2] / "specs" / "verbs"
RECORDINGS_PATH = VERBS_DIR / "recordings_synthetic.json"
MODELS_PATH = VERBS_DIR / "models_synthetic.json"


@lru_cache(maxsize=4)
def shipped_models(path: Path = MODELS_PATH) -> dict[str, VerbModel]:
    """The verb models of a model file, read once (the shipped ones by default)."""
    return load_models(path)
