"""Fitting a verb's models from its recorded performances (the same code for real and
synthetic recordings).

:func:`fit_verb` checks the performances against the verb's lexicon entry (its hands and
its number of keyframes) and fits every model of :mod:`motor.verbs.model`.
:func:`fit_session` fits every verb of a session; a verb that cannot be fitted (too few
arrangements for the polynomial basis, performances that do not match its entry) fails
alone with a :class:`SpecError` naming the file and row of its first performance.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from motor.verbs.model import VerbModel
from motor.verbs.polynomial import Polynomial, TooFewExamples, exponents
from motor.verbs.sora import mean_orientation, to_sora
from motor.verbs.start import HandDensity
from mura.errors import SpecError
from mura.recordings import Performance, RecordingSession
from mura.verb_lexicon import VerbEntry, VerbLexicon


@dataclass(frozen=True)
class SessionFit:
    """The models fitted from a session, and the verbs that could not be fitted."""

    models: dict[str, VerbModel]
    failures: tuple[SpecError, ...]


def fit_session(session: RecordingSession, lexicon: VerbLexicon) -> SessionFit:
    """Every verb of ``session`` that the lexicon knows, fitted; failures kept by verb."""
    models, failures = {}, []
    for verb in session.verbs:
        performances = session.of(verb)
        try:
            models[verb] = fit_verb(lexicon.entry(verb), performances, session.synthetic)
        except SpecError as error:
            failures.append(SpecError(error.message, performances[0].where))
    return SessionFit(models, tuple(failures))


def fit_verb(entry: VerbEntry, performances: Sequence[Performance], synthetic: bool = False) -> VerbModel:
    """All models of one verb from its performances (module docstring)."""
    first = performances[0] if performances else None
    if first is None:
        raise SpecError(f"verb {entry.gloss}: no performances")
    for performance in performances:
        if tuple(performance.hands) != entry.hands:
            raise SpecError(
                f"performance {performance.id!r} ({entry.gloss}) has the hands {', '.join(performance.hands)}; "
                f"the lexicon's {entry.gloss} uses {', '.join(entry.hands)}",
                performance.where,
            )
        if performance.keyframes != len(entry.keyframes):
            raise SpecError(
                f"performance {performance.id!r} ({entry.gloss}) has {performance.keyframes} keyframes; "
                f"the lexicon's {entry.gloss} has {len(entry.keyframes)} ({', '.join(entry.keyframes)})",
                performance.where,
            )
        if performance.subject is None and not entry.object_only:
            raise SpecError(f"performance {performance.id!r} ({entry.gloss}) has no subject; {entry.gloss} indicates its subject", performance.where)
    subject = np.array([0.0 if entry.object_only else p.subject for p in performances])
    obj = np.array([p.object for p in performances])
    terms = exponents(entry.object_only)
    locations = np.stack([np.stack([p.hands[h].location for h in entry.hands]) for p in performances])  # (n, H, K, 3)
    orientations = np.stack([np.stack([p.hands[h].orientation for h in entry.hands]) for p in performances])  # (n, H, K, 4)
    count, hands, keys = locations.shape[0], locations.shape[1], locations.shape[2]
    right = locations[:, 0]
    steps = np.diff(right, axis=1).reshape(count, -1)
    vector_targets = steps if hands == 1 else np.concatenate([steps, (locations[:, 1] - right).reshape(count, -1)], axis=1)
    means = np.stack([np.stack([mean_orientation(orientations[:, h, k]) for k in range(keys)]) for h in range(hands)])
    angles = np.stack([to_sora(orientations[:, h, k], means[h, k]) for h in range(hands) for k in range(keys)], axis=1)
    try:
        point = Polynomial.fit(subject, obj, locations.reshape(count, -1), terms)
        vector = Polynomial.fit(subject, obj, vector_targets, terms)
        orientation = Polynomial.fit(subject, obj, angles.reshape(count, -1), terms)
    except TooFewExamples as error:
        what = "object positions" if entry.object_only else "subject/object arrangements"
        raise SpecError(f"verb {entry.gloss}: too few examples to fit: {error}; record more distinct {what}", first.where) from None
    return VerbModel(
        verb=entry.gloss, object_only=entry.object_only, hands=entry.hands, keyframes=keys,
        times=np.mean([p.times - p.times[0] for p in performances], axis=0),
        point=point, vector=vector, start_density=HandDensity.fit(right.reshape(-1, 3)),
        mean_orientations=means, orientation=orientation, citation=locations.mean(axis=0),
        performances=count, synthetic=synthetic,
    )  # fmt: skip
