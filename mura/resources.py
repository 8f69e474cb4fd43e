"""Where mura's bundled data lives (avatars, lexicon, schema, example utterances)."""

from pathlib import Path

SPECS_DIR = Path(__file__).resolve().parent.parent / "specs"
