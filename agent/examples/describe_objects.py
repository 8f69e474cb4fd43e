"""Utterances built programmatically from data: the agent describes a list of objects,
one chunk per object, showing each object's size with its hands.

The MURML is generated from plain records, so any inventory can be described; sizes are
metres and become the distance of a two-handed iconic gesture (the ``show_size``
function of the lexicon).

    python -m agent.examples.describe_objects -o out/objects [--tts espeak]
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import escape, quoteattr

from agent.agent import Agent


@dataclass(frozen=True)
class Item:
    """Something to describe: its name and its width, metres."""

    name: str
    width: float


INVENTORY: tuple[Item, ...] = (
    Item("the long bar", 0.40),
    Item("the cube", 0.12),
    Item("the wheel", 0.25),
)


def describe(items: tuple[Item, ...]) -> str:
    """A MURML utterance with one chunk per item: "<name> is <t/> this wide <t/>"."""
    if not items:
        raise ValueError("nothing to describe")
    text, behaviors = [], []
    for index, item in enumerate(items, start=1):
        onset, end = f"w{index}a", f"w{index}b"
        border = ' chunkborder="true"' if index < len(items) else ""
        text.append(f'{escape(item.name.capitalize())} is <time id="{onset}"/> this wide <time id="{end}"{border}/>')
        behaviors.append(
            f'<behaviorspec id="size_{index}"><gesture><affiliate onset="{onset}" end="{end}"/>'
            f'<function name="show_size"><param name="size" value={quoteattr(f"{item.width:.3f}m")}/></function>'
            "</gesture></behaviorspec>"
        )
    return "<utterance><specification>" + " ".join(text) + "</specification>" + "".join(behaviors) + "</utterance>"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("-o", "--output", default="out/objects", help="output folder")
    parser.add_argument("--tts", default="fake", help="speech backend: fake, espeak, pyttsx3, default")
    args = parser.parse_args(argv)
    performance = Agent(tts=args.tts).render(describe(INVENTORY), name="inventory")
    files = performance.save(Path(args.output))
    print(f"{len(performance.timeline['chunks'])} chunks, {performance.duration:.1f} s -> {files.html}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
