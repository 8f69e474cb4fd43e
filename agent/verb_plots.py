"""Top view of indicating verbs' predicted paths over the arc (like the seed's figures).

One panel per verb, seen from above with the signer at the bottom facing up the page (the
signer's right on the right): the arc of spatial reference points, the subject (S) and
object (O) of two mirrored arrangements, and the right hand's wrist path as recorded and as
predicted by the point, vector and uninflected models fitted *without* that arrangement
(leave-one-arrangement-out). Units: shoulder widths of the signer frame.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from motor.verbs.arc import ARC_RADIUS, CHEST, arc_point  # noqa: E402
from motor.verbs.evaluation import arrangement  # noqa: E402
from motor.verbs.fitting import fit_verb  # noqa: E402
from mura.recordings import RecordingSession  # noqa: E402
from mura.verb_lexicon import VerbLexicon  # noqa: E402

#: The arrangements drawn: subject on the left and object on the right, and the reverse.
ARRANGEMENTS: tuple[tuple[float, float], ...] = ((-2.0 / 3.0, 2.0 / 3.0), (2.0 / 3.0, -2.0 / 3.0))
_STYLES = {"point": ("tab:blue", "-"), "vector": ("tab:orange", "--"), "uninflected": ("tab:green", ":")}
_COLOURS = ("black", "tab:red")


def _top(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Page coordinates of signer-frame points: the signer's right to the right, forward up."""
    points = np.atleast_2d(points)
    return -points[:, 0], points[:, 2]


def plot_verb_paths(session: RecordingSession, lexicon: VerbLexicon, path: str | Path) -> Path:
    """Write the PNG; returns its path."""
    verbs = [v for v in session.verbs if v in lexicon.verbs]
    columns = 4
    rows = max(1, -(-len(verbs) // columns))
    figure, axes = plt.subplots(rows, columns, figsize=(4.0 * columns, 4.2 * rows), squeeze=False)
    arc = arc_point(np.linspace(-1.0, 1.0, 61))
    for axis, verb in zip(axes.flat, verbs):
        entry = lexicon.entry(verb)
        performances = session.of(verb)
        axis.plot(*_top(arc), color="0.75", lw=1)
        axis.add_patch(plt.Circle((0.0, CHEST[2]), 0.36, color="0.9"))
        for colour, wanted in zip(_COLOURS, ARRANGEMENTS):
            key = (round(wanted[0], 6), round(wanted[1], 6))
            held = [p for p in performances if arrangement(p) == key]
            if not held:
                continue
            model = fit_verb(entry, [p for p in performances if arrangement(p) != key])
            for recording in held:
                axis.plot(*_top(recording.hands["right"].location), color="0.5", lw=3, alpha=0.4)
            for kind, (style_colour, line) in _STYLES.items():
                form = model.predict(kind, *key)
                xs, ys = _top(form.locations["right"])
                axis.plot(xs, ys, line, color=style_colour, lw=1.6)
                axis.annotate("", (xs[-1], ys[-1]), (xs[-2], ys[-2]), arrowprops={"arrowstyle": "->", "color": style_colour})
            radius = ARC_RADIUS + (0.15 if colour == _COLOURS[0] else -0.15)
            if not entry.object_only:
                axis.text(*(v[0] for v in _top(arc_point(key[0], radius))), "S", color=colour, ha="center", va="center", fontweight="bold")
            axis.text(*(v[0] for v in _top(arc_point(key[1], radius))), "O", color=colour, ha="center", va="center", fontweight="bold")
        axis.set_title(f"{verb} ({'object only' if entry.object_only else 'subject → object'})")
        axis.set_aspect("equal")
        axis.set_xlim(-ARC_RADIUS - 0.3, ARC_RADIUS + 0.3)
        axis.set_ylim(-0.6, ARC_RADIUS + 0.4)
        axis.set_xlabel("signer's left ← x → signer's right (shoulder widths)")
    for axis in list(axes.flat)[len(verbs) :]:
        axis.axis("off")
    handles = [plt.Line2D([], [], color="0.5", lw=3, alpha=0.4, label="recorded")]
    handles += [plt.Line2D([], [], color=c, ls=s, label=k) for k, (c, s) in _STYLES.items()]
    figure.legend(handles=handles, loc="lower center", ncol=4)
    synthetic = " — SYNTHETIC training data" if session.synthetic else ""
    figure.suptitle(f"Right-hand paths seen from above, held-out arrangements (S/O black: S left, O right; red: reversed){synthetic}")
    figure.tight_layout(rect=(0, 0.04, 1, 0.96))
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(target, dpi=90)
    plt.close(figure)
    return target
