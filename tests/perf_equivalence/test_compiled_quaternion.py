"""The compiled quaternion products (:mod:`motor.quaternion`) give the numbers of the
numpy arithmetic they replace (``plain_quaternion.py``, the module before compilation)
bit for bit, over a table of broadcast shapes and inputs: unit and non-unit quaternions,
strided views, lists, zeros."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from motor import quaternion as quat
from tests.perf_equivalence import plain_quaternion as plain

RNG = np.random.default_rng(23)

#: Leading shapes of the two arguments, broadcast together.
SHAPES = [((), ()), ((7,), ()), ((), (7,)), ((7,), (7,)), ((5, 1), (1, 6)), ((5, 6), (6,)), ((3, 4, 2), (4, 1)), ((0,), ())]


def _unit(shape: tuple[int, ...]) -> np.ndarray:
    return plain.normalize(RNG.normal(size=shape + (4,)))


@pytest.mark.parametrize(("left", "right"), SHAPES)
def test_products_are_the_numpy_ones_bit_for_bit(left, right):
    p, q = _unit(left), _unit(right)
    v = RNG.normal(size=right + (3,))
    u = RNG.normal(size=left + (3,))
    for got, expected in (
        (quat.multiply(p, q), plain.multiply(p, q)),
        (quat.multiply(3.0 * p, q), plain.multiply(3.0 * p, q)),
        (quat.rotate(p, v), plain.rotate(p, v)),
        (quat.cross(u, v), plain.cross(u, v)),
    ):
        assert got.shape == expected.shape
        assert np.array_equal(got, expected)


@pytest.mark.parametrize("width", [3, 4])
@pytest.mark.parametrize("shape", [(), (9,), (4, 5), (0,)])
def test_normalize_is_the_numpy_one_bit_for_bit(shape, width):
    q = RNG.normal(size=shape + (width,)) * RNG.uniform(0.01, 100.0, size=shape + (1,))
    assert np.array_equal(quat.normalize(q), plain.normalize(q))


def test_strided_views_lists_and_zeros():
    block = _unit((6, 8))
    strided = block[::2, ::3]
    assert np.array_equal(quat.multiply(strided, strided[::-1]), plain.multiply(strided, strided[::-1]))
    assert np.array_equal(quat.rotate(block[:, 0], [1.0, 2.0, 3.0]), plain.rotate(block[:, 0], np.array([1.0, 2.0, 3.0])))
    with np.errstate(invalid="ignore", divide="ignore"):
        assert np.all(np.isnan(quat.normalize(np.zeros(4))))


def test_products_agree_with_scipy():
    """Independent of the numpy definitions: scipy's composition and application."""
    p, q, v = _unit((50,)), _unit((50,)), RNG.normal(size=(50, 3))
    expected = (Rotation.from_quat(p) * Rotation.from_quat(q)).as_quat()
    got = quat.multiply(p, q)
    assert np.allclose(np.abs(np.sum(got * expected, axis=-1)), 1.0, atol=1e-12)
    assert np.allclose(quat.rotate(p, v), Rotation.from_quat(p).apply(v), atol=1e-12)


def test_a_wrong_last_axis_is_refused():
    with pytest.raises(ValueError, match="last axes of 4 and 4"):
        quat.multiply(np.zeros(3), np.zeros(4))


#: Single vectors, labelled synthetic: ordinary, tiny and huge components, zeros and a
#: −0 (the huge overflow to infinity), a strided view, a quaternion's four components.
VECTORS = {
    "ordinary": np.array([0.3, -1.2, 0.45]),
    "tiny": np.array([1e-160, -3e-170, 2e-155]),
    "huge": np.array([1e150, -3e152, 2e149]),
    "zero": np.zeros(3),
    "negative zero": np.array([-0.0, 0.0, -0.0]),
    "strided view": RNG.normal(size=(4, 6))[1, ::2],
    "four components": RNG.normal(size=4),
}


@pytest.mark.parametrize("case", VECTORS)
def test_the_length_of_one_vector_is_numpys_norm_bit_for_bit(case):
    v = VECTORS[case]
    assert quat.length(v) == np.linalg.norm(v)


def test_the_cross_product_of_single_vectors_is_numpys_bit_for_bit():
    for u, v in zip(RNG.normal(size=(200, 3)) * RNG.uniform(1e-3, 1e3, size=(200, 1)), RNG.normal(size=(200, 3))):
        assert quat.cross(u, v).tobytes() == np.cross(u, v).tobytes()
