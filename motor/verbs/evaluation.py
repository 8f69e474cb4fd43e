"""Leave-one-arrangement-out cross-validation of the verb models (seed 001).

For every subject/object arrangement of a verb, the models are fitted on the performances
of all *other* arrangements and asked for the held-out one; their prediction is compared
with each held-out performance:

- **location** (cm): distance between predicted and recorded wrist locations, mean over
  hands and keyframes; **start** (cm): the same for the right hand's first keyframe alone
  (where TELL touches the chin, SCOLD starts at the heart);
- **direction** (°): angle between predicted and recorded movement vectors between
  consecutive keyframes, mean over the hands' segments that move at least
  :data:`MIN_STEP` in the recording (a hand that holds still has no direction);
- **orientation** (°): geodesic angle between predicted and recorded hand orientations;
- **left–right** (cm, two-handed verbs): error of the left hand's location relative to
  the right hand's, mean over keyframes;
- **contact** (cm, verbs with a :class:`~mura.verb_lexicon.HandRelation`): EMAIL — the
  closest the right hand's fingertips come to the left hand's C opening while moving
  (both hands interpolated between keyframes, positions linearly, orientations by
  slerp); COPY — the distance between the palm centres at the start; with the share of
  predictions within the lexicon's tolerance.

Centimetres use :data:`motor.verbs.model.REFERENCE_SHOULDER_WIDTH`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation, Slerp

from motor.verbs.arc import site_points
from motor.verbs.fitting import fit_verb
from motor.verbs.model import MODEL_KINDS, REFERENCE_SHOULDER_WIDTH, VerbForm
from motor.verbs.sora import angle_between
from mura.recordings import Performance
from mura.verb_lexicon import VerbEntry, VerbLexicon

#: Shortest recorded movement between keyframes that has a direction, shoulder widths (≈ 3.6 cm).
MIN_STEP = 0.1
#: Samples along each segment when looking for the closest passage.
PASSAGE_SAMPLES = 41


@dataclass(frozen=True)
class Scores:
    """Cross-validated errors of one model on one verb (module docstring); None where the
    measure does not apply."""

    verb: str
    model: str
    folds: int
    location_cm: float
    start_cm: float
    direction_deg: float
    orientation_deg: float
    relation_cm: float | None = None
    contact_cm: float | None = None
    contact_within: float | None = None


def arrangement(performance: Performance) -> tuple[float, float]:
    """The (subject, object) pair a performance was recorded for (subject 0 when absent)."""
    return (round(performance.subject or 0.0, 6), round(performance.object, 6))


def cross_validate(
    entry: VerbEntry, performances: Sequence[Performance], lexicon: VerbLexicon, folds: int | None = None,
) -> list[Scores]:  # fmt: skip
    """Leave-one-arrangement-out scores of every model on one verb; ``folds`` limits the
    held-out arrangements to the first few (for quick checks)."""
    keys = list(dict.fromkeys(arrangement(p) for p in performances))[:folds]
    measured: dict[str, list[dict[str, float]]] = {kind: [] for kind in MODEL_KINDS}
    for key in keys:
        held = [p for p in performances if arrangement(p) == key]
        model = fit_verb(entry, [p for p in performances if arrangement(p) != key])
        for kind in MODEL_KINDS:
            form = model.predict(kind, *key)
            measured[kind].extend(measure(entry, lexicon, form, recording) for recording in held)
    return [_summary(entry, kind, len(keys), measured[kind]) for kind in MODEL_KINDS]


def measure(entry: VerbEntry, lexicon: VerbLexicon, form: VerbForm, recording: Performance) -> dict[str, float]:
    """Every applicable measure of one predicted form against one recording (cm, degrees)."""
    cm = 100.0 * REFERENCE_SHOULDER_WIDTH
    out: dict[str, float] = {}
    location = [np.linalg.norm(form.locations[h] - recording.hands[h].location, axis=1) for h in entry.hands]
    out["location_cm"] = cm * float(np.mean(location))
    out["start_cm"] = cm * float(location[0][0])
    angles = []
    for hand in entry.hands:
        recorded, predicted = np.diff(recording.hands[hand].location, axis=0), np.diff(form.locations[hand], axis=0)
        moving = np.linalg.norm(recorded, axis=1) >= MIN_STEP
        cosine = np.sum(recorded * predicted, axis=1) / np.maximum(np.linalg.norm(recorded, axis=1) * np.linalg.norm(predicted, axis=1), 1e-12)
        angles.extend(np.degrees(np.arccos(np.clip(cosine[moving], -1.0, 1.0))).tolist())
    if angles:
        out["direction_deg"] = float(np.mean(angles))
    turns = [angle_between(form.orientations[h], recording.hands[h].orientation) for h in entry.hands]
    out["orientation_deg"] = float(np.degrees(np.mean(turns)))
    if entry.two_handed:
        predicted = form.locations["left"] - form.locations["right"]
        recorded = recording.hands["left"].location - recording.hands["right"].location
        out["relation_cm"] = cm * float(np.mean(np.linalg.norm(predicted - recorded, axis=1)))
    if entry.relation is not None:
        out["contact_cm"] = cm * contact_distance(entry, lexicon, form)
    return out


def contact_distance(entry: VerbEntry, lexicon: VerbLexicon, form: VerbForm) -> float:
    """How far apart the hands' related sites are (shoulder widths): at the start for
    ``together_at_start``, at the closest passage for ``passes_through``."""
    relation = entry.relation
    assert relation is not None
    right_site, left_site = lexicon.sites[relation.right_site], lexicon.sites[relation.left_site]
    if relation.kind == "together_at_start":
        right = site_points("right", right_site, form.locations["right"][:1], form.orientations["right"][:1])
        left = site_points("left", left_site, form.locations["left"][:1], form.orientations["left"][:1])
        return float(np.linalg.norm(right - left))
    right = site_points("right", right_site, *_interpolated(form.locations["right"], form.orientations["right"]))
    left = site_points("left", left_site, *_interpolated(form.locations["left"], form.orientations["left"]))
    return float(np.min(np.linalg.norm(right - left, axis=1)))


def _interpolated(locations: np.ndarray, orientations: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Locations and orientations along the keyframes, :data:`PASSAGE_SAMPLES` per segment."""
    count = locations.shape[0]
    u = np.linspace(0.0, count - 1.0, (count - 1) * (PASSAGE_SAMPLES - 1) + 1)
    index = np.minimum(np.floor(u).astype(int), count - 2)
    fraction = (u - index)[:, None]
    points = locations[index] * (1.0 - fraction) + locations[index + 1] * fraction
    turns = Slerp(np.arange(count), Rotation.from_quat(orientations))(u).as_quat()
    return points, turns


def _summary(entry: VerbEntry, kind: str, folds: int, measured: list[dict[str, float]]) -> Scores:
    def mean(key: str) -> float | None:
        values = [m[key] for m in measured if key in m]
        return float(np.mean(values)) if values else None

    within = None
    if entry.relation is not None:
        limit = 100.0 * entry.relation.within
        within = float(np.mean([m["contact_cm"] <= limit for m in measured]))
    return Scores(
        entry.gloss, kind, folds, mean("location_cm") or 0.0, mean("start_cm") or 0.0, mean("direction_deg") or 0.0,
        mean("orientation_deg") or 0.0,
        mean("relation_cm"), mean("contact_cm"), within,
    )  # fmt: skip


def scores_table(scores: Sequence[Scores]) -> str:
    """A Markdown table of scores, one row per verb and model, then the mean per model."""

    def cell(value: float | None, digits: int = 1) -> str:
        return "–" if value is None else f"{value:.{digits}f}"

    lines = [
        "| verb | model | location (cm) | start (cm) | direction (°) | orientation (°) | left–right (cm) | contact (cm) | contact within tolerance |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for s in scores:
        within = "–" if s.contact_within is None else f"{100.0 * s.contact_within:.0f} %"
        lines.append(
            f"| {s.verb} | {s.model} | {cell(s.location_cm)} | {cell(s.start_cm)} | {cell(s.direction_deg)} | {cell(s.orientation_deg)} "
            f"| {cell(s.relation_cm)} | {cell(s.contact_cm)} | {within} |"
        )
    for kind in dict.fromkeys(s.model for s in scores):
        rows = [s for s in scores if s.model == kind]
        lines.append(
            f"| **all verbs** | {kind} | {np.mean([s.location_cm for s in rows]):.1f} | {np.mean([s.start_cm for s in rows]):.1f} "
            f"| {np.mean([s.direction_deg for s in rows]):.1f} "
            f"| {np.mean([s.orientation_deg for s in rows]):.1f} | | | |"
        )
    return "\n".join(lines)
