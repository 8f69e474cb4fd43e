"""A verb's fitted models and the inflected forms they predict (seed 001).

One :class:`VerbModel` holds, for one verb, everything fitted from its recordings:

- **point model**: every coordinate of each hand's location at each keyframe as a
  polynomial of (subject, object) (:mod:`motor.verbs.polynomial`);
- **vector model with relative left hand** (section 3.1): the right hand's movement
  vector between consecutive keyframes and the left hand's location relative to the right
  hand at each keyframe as polynomials, and the Gaussian mixture of right-hand locations
  that chooses the start (:mod:`motor.verbs.start`);
- **orientation** (section 3.2): each hand's SORA angles at each keyframe relative to the
  verb's mean orientation there, as polynomials (:mod:`motor.verbs.sora`); the point and
  the vector model share it;
- **uninflected** baseline: the citation form, which ignores where subject and object
  are: per hand and keyframe the mean location and the mean orientation over all
  recordings (the degree-0 member of the same family);
- the mean keyframe times.

Locations are in the signer frame in shoulder widths (:mod:`mura.recordings`); figures in
centimetres use :data:`REFERENCE_SHOULDER_WIDTH`. Object-only verbs ignore the subject.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from motor.verbs.polynomial import Polynomial
from motor.verbs.sora import from_sora
from motor.verbs.start import HandDensity, best_start

#: The models that predict an inflected form.
MODEL_KINDS: tuple[str, ...] = ("point", "vector", "uninflected")
#: Shoulder width (m) that turns shoulder widths into centimetres in reports.
REFERENCE_SHOULDER_WIDTH = 0.36
#: The ``format`` of a saved model file.
MODEL_FORMAT = "mura verb models"


@dataclass(frozen=True, eq=False)
class VerbForm:
    """An inflected (or citation) form: each hand's wrist locations ``(K, 3)`` (shoulder
    widths, signer frame) and orientations ``(K, 4)``, and the keyframe times ``(K,)``."""

    verb: str
    locations: Mapping[str, np.ndarray]
    orientations: Mapping[str, np.ndarray]
    times: np.ndarray


@dataclass(frozen=True, eq=False)
class VerbModel:
    """Every model of one verb (module docstring). Arrays are per hand in :attr:`hands`
    order, then per keyframe."""

    verb: str
    object_only: bool
    hands: tuple[str, ...]
    keyframes: int
    times: np.ndarray
    point: Polynomial
    vector: Polynomial
    start_density: HandDensity
    mean_orientations: np.ndarray
    orientation: Polynomial
    citation: np.ndarray
    performances: int
    synthetic: bool

    def predict(self, kind: str, subject: float, obj: float) -> VerbForm:
        """The verb inflected for ``subject`` and ``obj`` (arc positions) by model ``kind``."""
        if kind not in MODEL_KINDS:
            raise ValueError(f"unknown model {kind!r} (expected one of {', '.join(MODEL_KINDS)})")
        subject = 0.0 if self.object_only else float(subject)
        hands, count = len(self.hands), self.keyframes
        if kind == "uninflected":
            locations = self.citation
            orientations = self.mean_orientations
        else:
            locations = self.point(subject, obj)[0].reshape(hands, count, 3) if kind == "point" else self._vector_locations(subject, obj)
            angles = self.orientation(subject, obj)[0].reshape(hands, count, 3)
            orientations = np.stack([from_sora(angles[h, k], self.mean_orientations[h, k])[0] for h in range(hands) for k in range(count)])
            orientations = orientations.reshape(hands, count, 4)
        return VerbForm(
            self.verb,
            {hand: np.array(locations[h]) for h, hand in enumerate(self.hands)},
            {hand: np.array(orientations[h]) for h, hand in enumerate(self.hands)},
            self.times.copy(),
        )

    def _vector_locations(self, subject: float, obj: float) -> np.ndarray:
        values = self.vector(subject, obj)[0]
        steps = values[: 3 * (self.keyframes - 1)].reshape(-1, 3)
        right = best_start(self.start_density, steps) + np.concatenate([np.zeros((1, 3)), np.cumsum(steps, axis=0)])
        if len(self.hands) == 1:
            return right[None]
        relative = values[3 * (self.keyframes - 1) :].reshape(self.keyframes, 3)
        return np.stack([right, right + relative])

    # -- files ----------------------------------------------------------------------------

    def as_json(self) -> dict:
        return {
            "verb": self.verb, "object_only": self.object_only, "hands": list(self.hands), "keyframes": self.keyframes,
            "times": self.times.tolist(), "terms": [list(t) for t in self.point.terms],
            "point": self.point.coefficients.tolist(), "vector": self.vector.coefficients.tolist(),
            "start_density": {
                "weights": self.start_density.weights.tolist(), "means": self.start_density.means.tolist(),
                "covariances": self.start_density.covariances.tolist(),
            },
            "mean_orientations": self.mean_orientations.tolist(), "orientation": self.orientation.coefficients.tolist(),
            "citation": self.citation.tolist(), "performances": self.performances, "synthetic": self.synthetic,
        }  # fmt: skip

    @classmethod
    def from_json(cls, data: Mapping) -> VerbModel:
        terms = tuple((int(i), int(j)) for i, j in data["terms"])
        density = data["start_density"]
        return cls(
            verb=str(data["verb"]), object_only=bool(data["object_only"]), hands=tuple(data["hands"]),
            keyframes=int(data["keyframes"]), times=np.asarray(data["times"], dtype=float),
            point=Polynomial(terms, np.asarray(data["point"], dtype=float)),
            vector=Polynomial(terms, np.asarray(data["vector"], dtype=float)),
            start_density=HandDensity(*(np.asarray(density[k], dtype=float) for k in ("weights", "means", "covariances"))),
            mean_orientations=np.asarray(data["mean_orientations"], dtype=float),
            orientation=Polynomial(terms, np.asarray(data["orientation"], dtype=float)),
            citation=np.asarray(data["citation"], dtype=float), performances=int(data["performances"]),
            synthetic=bool(data["synthetic"]),
        )  # fmt: skip


class ModelFileError(ValueError):
    """A model file that cannot be used; the message names the file and what is wrong."""


def models_json(models: Mapping[str, VerbModel], description: str) -> str:
    """A model file: every verb's model, and where its training data came from."""
    synthetic = any(model.synthetic for model in models.values())
    document = {"format": MODEL_FORMAT, "version": 1, "synthetic": synthetic, "description": description,
                "verbs": {verb: model.as_json() for verb, model in models.items()}}  # fmt: skip
    return json.dumps(document, indent=1) + "\n"


def load_models(path: str | Path) -> dict[str, VerbModel]:
    """Every verb model of a file written by :func:`models_json`."""
    try:
        document = json.loads(Path(path).read_text(encoding="utf-8"))
    except OSError as error:
        raise ModelFileError(f"{path}: cannot read: {error.strerror or error}") from None
    except json.JSONDecodeError as error:
        raise ModelFileError(f"{path}:{error.lineno}:{error.colno}: not JSON: {error.msg}") from None
    if not isinstance(document, dict) or document.get("format") != MODEL_FORMAT:
        raise ModelFileError(f'{path}: not a verb model file (expected "format": "{MODEL_FORMAT}")')
    models = {}
    for verb, data in dict(document.get("verbs", {})).items():
        try:
            models[verb] = VerbModel.from_json(data)
        except (KeyError, TypeError, ValueError) as error:
            raise ModelFileError(f"{path}: verb {verb}: malformed model ({type(error).__name__}: {error})") from None
    return models
