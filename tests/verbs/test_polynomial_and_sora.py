"""The polynomial basis recovers known coefficients; SORA angles round-trip."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from motor.verbs.polynomial import Polynomial, TooFewExamples, design_matrix, exponents
from motor.verbs.sora import angle_between, from_sora, mean_orientation, to_sora
from motor.verbs.synthetic import arrangements


@pytest.mark.parametrize(
    ("object_only", "terms"),
    [(False, 10), (True, 4)],
)
def test_basis_is_every_monomial_up_to_third_order(object_only, terms):
    basis = exponents(object_only)
    assert len(basis) == terms and len(set(basis)) == terms
    assert all(i + j <= 3 for i, j in basis)
    assert all(i == 0 for i, _ in basis) == object_only


@pytest.mark.parametrize("object_only", [False, True])
@pytest.mark.parametrize("outputs", [1, 3, 12])
def test_fit_recovers_generator_coefficients(object_only, outputs):
    rng = np.random.default_rng(outputs)
    terms = exponents(object_only)
    truth = rng.normal(0.0, 1.0, (len(terms), outputs))
    pairs = np.array(arrangements())
    targets = design_matrix(pairs[:, 0], pairs[:, 1], terms) @ truth
    fitted = Polynomial.fit(pairs[:, 0], pairs[:, 1], targets, terms)
    assert np.allclose(fitted.coefficients, truth, atol=1e-9)
    assert np.allclose(fitted(0.25, -0.5), design_matrix(np.array([0.25]), np.array([-0.5]), terms) @ truth)


def test_noisy_fit_is_least_squares():
    terms = exponents(False)
    pairs = np.array(arrangements())
    rng = np.random.default_rng(3)
    truth = rng.normal(0.0, 1.0, (len(terms), 2))
    basis = design_matrix(pairs[:, 0], pairs[:, 1], terms)
    targets = basis @ truth + rng.normal(0.0, 0.01, (len(pairs), 2))
    fitted = Polynomial.fit(pairs[:, 0], pairs[:, 1], targets, terms)
    residual = targets - basis @ fitted.coefficients
    assert np.allclose(basis.T @ residual, 0.0, atol=1e-9)  # normal equations
    assert np.max(np.abs(fitted.coefficients - truth)) < 0.1


@pytest.mark.parametrize(("object_only", "count"), [(False, 9), (True, 3)])
def test_too_few_arrangements_are_refused(object_only, count):
    pairs = np.array(arrangements())[:count] if not object_only else np.array([(0.0, o) for o in (-1.0, 0.0, 1.0)])
    with pytest.raises(TooFewExamples):
        Polynomial.fit(pairs[:, 0], pairs[:, 1], np.zeros((len(pairs), 3)), exponents(object_only))


@pytest.mark.parametrize("turn", [0.0, 0.5, 1.5, 2.5, 3.0, np.pi - 1e-3])
@pytest.mark.parametrize("axis", [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, -1)])
def test_sora_round_trips(turn, axis):
    mean = Rotation.from_rotvec([0.3, -2.0, 0.4]).as_quat()
    axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    orientation = (Rotation.from_rotvec(turn * axis) * Rotation.from_quat(mean)).as_quat()[None]
    angles = to_sora(orientation, mean)
    assert np.allclose(angles[0], turn * axis, atol=1e-9)
    assert angle_between(from_sora(angles, mean), orientation)[0] < 1e-7


def test_sora_relative_to_the_mean_does_not_wrap():
    # orientations 20 degrees around a mean that is itself a near half turn
    rng = np.random.default_rng(0)
    mean = Rotation.from_rotvec([0.0, 3.1, 0.0])
    scattered = (Rotation.from_rotvec(rng.normal(0.0, np.radians(12.0), (50, 3))) * mean).as_quat()
    centre = mean_orientation(scattered)
    angles = to_sora(scattered, centre)
    assert np.max(np.linalg.norm(angles, axis=1)) < np.radians(60.0)
    assert np.degrees(angle_between(centre[None], mean.as_quat()[None]))[0] < 5.0
