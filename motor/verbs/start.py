"""Where the vector model starts a verb: a Gaussian mixture of the verb's hand locations.

The vector model (seed 001, section 2.1 and 3.1) predicts how the right hand moves, not
where; the start is chosen so that the path runs through the region where the verb's right
hand usually is. That region is a Gaussian mixture fitted (scikit-learn's
``GaussianMixture``, full covariances) to every recorded right-hand keyframe location of
the verb; the number of components, 1 to :data:`MAX_COMPONENTS`, is the one with the lowest
BIC.

**Criterion.** For a predicted path — offsets ``c_0 = 0, c_1, …`` from the start, sampled
at :data:`PATH_SAMPLES` evenly spaced points along each straight segment between keyframes
— the start ``x`` maximizes the mean log density along the path,
``J(x) = (1/M) Σ_j log p(x + c_j)``.

**Search.** ``J`` is evaluated for every candidate that puts one path sample on one
component mean (``x = μ_k − c_j``: every component times every sample); the
:data:`REFINED` best are refined by L-BFGS-B on ``−J`` (analytic gradient) and the best
refined start is taken. The mixture is evaluated with numpy from its parameters, so a
saved model needs no pickled estimator.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize
from scipy.special import logsumexp
from sklearn.mixture import GaussianMixture
from threadpoolctl import threadpool_limits

#: Most mixture components tried; the BIC picks among 1 … this.
MAX_COMPONENTS = 4
#: Covariance floor added to the diagonal, shoulder widths squared (σ ≥ 1 cm or so).
REG_COVAR = 1e-3
#: Points sampled along each straight segment of a path, ends included.
PATH_SAMPLES = 9
#: How many of the best candidates are refined.
REFINED = 3


@dataclass(frozen=True, eq=False)
class HandDensity:
    """A Gaussian mixture over locations: ``weights`` ``(C,)``, ``means`` ``(C, 3)``,
    ``covariances`` ``(C, 3, 3)`` (shoulder widths)."""

    weights: np.ndarray
    means: np.ndarray
    covariances: np.ndarray

    @classmethod
    def fit(cls, locations: np.ndarray, seed: int = 0) -> HandDensity:
        """The mixture with the lowest BIC among 1 … :data:`MAX_COMPONENTS` components."""
        points = np.asarray(locations, dtype=float)
        best: GaussianMixture | None = None
        best_bic = np.inf
        for components in range(1, min(MAX_COMPONENTS, max(1, points.shape[0] // 8)) + 1):
            mixture = GaussianMixture(components, covariance_type="full", reg_covar=REG_COVAR, random_state=seed, n_init=1)
            with threadpool_limits(1):  # a few hundred points: threads only contend
                mixture.fit(points)
            bic = mixture.bic(points)
            if bic < best_bic:
                best, best_bic = mixture, bic
        assert best is not None
        return cls(best.weights_.copy(), best.means_.copy(), best.covariances_.copy())

    def log_density(self, points: np.ndarray) -> np.ndarray:
        """``log p`` at points ``(n, 3)``."""
        log_weights, inverse, log_norm = self._terms()
        diff = np.asarray(points, dtype=float)[:, None, :] - self.means[None]
        mahalanobis = np.einsum("nci,cij,ncj->nc", diff, inverse, diff)
        return logsumexp(log_weights + log_norm - 0.5 * mahalanobis, axis=1)

    def gradient(self, points: np.ndarray) -> np.ndarray:
        """``∇ log p`` at points ``(n, 3)``."""
        log_weights, inverse, log_norm = self._terms()
        diff = np.asarray(points, dtype=float)[:, None, :] - self.means[None]
        mahalanobis = np.einsum("nci,cij,ncj->nc", diff, inverse, diff)
        log_parts = log_weights + log_norm - 0.5 * mahalanobis
        responsibility = np.exp(log_parts - logsumexp(log_parts, axis=1, keepdims=True))
        return -np.einsum("nc,cij,ncj->ni", responsibility, inverse, diff)

    def _terms(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        inverse = np.linalg.inv(self.covariances)
        _, log_det = np.linalg.slogdet(self.covariances)
        log_norm = -0.5 * (log_det + 3.0 * np.log(2.0 * np.pi))
        return np.log(self.weights), inverse, log_norm


def path_offsets(steps: np.ndarray) -> np.ndarray:
    """Offsets ``(M, 3)`` from the start of the path made of movement vectors ``(K−1, 3)``:
    :data:`PATH_SAMPLES` points per segment, ends shared."""
    corners = np.concatenate([np.zeros((1, 3)), np.cumsum(np.asarray(steps, dtype=float), axis=0)])
    fractions = np.linspace(0.0, 1.0, PATH_SAMPLES)[:-1]
    inner = corners[:-1, None, :] + fractions[None, :, None] * (corners[1:] - corners[:-1])[:, None, :]
    return np.concatenate([inner.reshape(-1, 3), corners[-1:]])


def path_score(density: HandDensity, starts: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """``J`` for each start ``(n, 3)``: the mean log density along the path."""
    starts = np.atleast_2d(starts)
    points = (starts[:, None, :] + offsets[None]).reshape(-1, 3)
    return density.log_density(points).reshape(starts.shape[0], -1).mean(axis=1)


def best_start(density: HandDensity, steps: np.ndarray) -> np.ndarray:
    """The start ``(3,)`` that maximizes :func:`path_score` (module docstring: the search)."""
    offsets = path_offsets(steps)
    candidates = (density.means[:, None, :] - offsets[None]).reshape(-1, 3)
    scores = path_score(density, candidates, offsets)
    best, best_score = candidates[int(np.argmax(scores))], float(np.max(scores))

    def negative(x: np.ndarray) -> tuple[float, np.ndarray]:
        points = x[None] + offsets
        return -float(density.log_density(points).mean()), -density.gradient(points).mean(axis=0)

    for index in np.argsort(-scores)[:REFINED]:
        result = minimize(negative, candidates[index], jac=True, method="L-BFGS-B")
        if -result.fun > best_score:
            best, best_score = np.asarray(result.x, dtype=float), -float(result.fun)
    return best
