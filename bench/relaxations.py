"""What the scheduler relaxed, and where strokes sit against the audio, on the real inputs.

``python -m bench.relaxations`` performs the example utterances and the published MURML
files (avatar ``max``, 60 fps) with fake speech and with espeak-ng, and prints:

* per speech backend and input set, each relaxation step taken: how many gestures, in
  how many files, and the range of its amounts;
* with espeak-ng, for every affiliate of the example utterances, the planned lead of the
  stroke onset over the acoustic onset of the affiliate's first word, and the lead it
  would have had anchored on the SSML mark (``0.2 s + acoustic onset − mark``).

Not a test: prints figures (the README quotes them).
"""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

from blackboard import Scheduler, VirtualClock
from motor.body.avatar import load_avatar
from motor.control import MotorControl
from mura.model import Affiliate
from mura.murml import load_utterance
from tts import make_synthesizer

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = sorted((REPO / "specs" / "utterances").glob("*.xml"))
PUBLISHED = sorted((REPO.parent / "shared" / "corpora" / "murml").glob("*.us"))
LEAD = 0.2


def perform(path: Path, backend: str) -> tuple[object, dict]:
    """The utterance and its timeline JSON."""
    utterance = load_utterance(path)
    result = Scheduler(make_synthesizer(backend), MotorControl(load_avatar("max")), VirtualClock()).run(utterance, name=path.stem)
    if result.failed_chunk is not None:
        raise RuntimeError(f"{path.name}: {result.error}")
    return utterance, result.timeline.to_json()


def relaxations(paths: list[Path], backend: str) -> dict[str, dict]:
    """Per step: gestures, files and the amounts (min, max, unit)."""
    found: dict[str, list] = defaultdict(list)
    for path in paths:
        _, timeline = perform(path, backend)
        for behavior in timeline["behaviors"]:
            for r in behavior["relaxations"]:
                found[r["step"]].append((path.name, r["amount"], r["unit"]))
    return {step: {"gestures": len(rows), "files": len({name for name, _, _ in rows}),
                   "min": min(a for _, a, _ in rows), "max": max(a for _, a, _ in rows), "unit": rows[0][2]}
            for step, rows in found.items()}


def leads(paths: list[Path]) -> list[tuple[str, str, float, float]]:
    """With espeak-ng: (file, behaviour, lead over the acoustic onset, lead had the mark been the anchor), seconds."""
    rows = []
    for path in paths:
        utterance, timeline = perform(path, "espeak")
        specs = {b.id: b for b in utterance.behaviors}
        for behavior in timeline["behaviors"]:
            timing = specs[behavior["id"]].timing
            if not isinstance(timing, Affiliate):
                continue
            anchor = timeline["tag_anchors"][timing.onset]
            rows.append((path.stem, behavior["id"], anchor["acoustic_onset"] - behavior["phases"]["stroke_start"],
                         LEAD + anchor["acoustic_onset"] - anchor["mark"]))
    return rows


def main() -> None:
    for backend in ("fake", "espeak"):
        for label, paths in (("examples", EXAMPLES), ("published MURML", PUBLISHED)):
            print(f"{backend}, {label} ({len(paths)} files):")
            for step, row in sorted(relaxations(paths, backend).items()):
                print(f"  {step:24s} {row['gestures']:3d} gestures in {row['files']:2d} files, "
                      f"{row['min']:.3f}–{row['max']:.3f} {row['unit']}")
    rows = leads(EXAMPLES)
    now = [r[2] for r in rows]
    marked = [r[3] for r in rows]
    print(f"espeak-ng, {len(rows)} affiliates of the examples: stroke lead over the acoustic onset "
          f"{min(now) * 1000:.1f}–{max(now) * 1000:.1f} ms (anchored on the marks it would be "
          f"{min(marked) * 1000:.1f}–{max(marked) * 1000:.1f} ms)")


if __name__ == "__main__":
    main()
