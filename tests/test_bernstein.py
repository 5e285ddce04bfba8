"""Bernstein arithmetic against direct evaluation, finite differences and known roots."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from morph import bernstein as bz

T = np.linspace(0.0, 1.0, 101)
coeffs = st.integers(0, 7).flatmap(
    lambda n: arrays(float, (n + 1,), elements=st.floats(-10, 10)))


def power_eval(c, t):
    """Direct evaluation of sum c_i C(n,i) t^i (1-t)^(n-i) with math.comb."""
    from math import comb
    n = len(c) - 1
    return sum(c[i] * comb(n, i) * t ** i * (1 - t) ** (n - i) for i in range(n + 1))


@given(coeffs)
def test_evaluate_matches_definition(c):
    assert np.allclose(bz.evaluate(c, T), power_eval(c, T), atol=1e-9)


def test_evaluate_end_values_are_end_coefficients():
    c = np.array([[1.0, 2.0], [5.0, -1.0], [3.0, 7.0]])
    assert np.array_equal(bz.evaluate(c, [0.0, 1.0]), c[[0, -1]])


@given(coeffs, coeffs)
def test_multiply_is_pointwise_product(a, b):
    prod = bz.multiply(a, b)
    assert len(prod) == len(a) + len(b) - 1
    assert np.allclose(bz.evaluate(prod, T), bz.evaluate(a, T) * bz.evaluate(b, T),
                       atol=1e-8 * (1 + np.abs(a).max() * np.abs(b).max()))


def test_multiply_broadcasts_trailing_axes():
    w = np.array([[1.0], [2.0], [1.0]])
    xy = np.array([[0.0, 1.0], [1.0, 1.0]])
    prod = bz.multiply(w, xy)
    assert prod.shape == (4, 2)
    assert np.allclose(bz.evaluate(prod, T), bz.evaluate(w, T) * bz.evaluate(xy, T))


@given(coeffs, st.integers(0, 5))
def test_elevate_keeps_polynomial(c, r):
    e = bz.elevate(c, r)
    assert len(e) == len(c) + r
    assert np.allclose(bz.evaluate(e, T), bz.evaluate(c, T), atol=1e-9)
    assert np.allclose(bz.to_degree(c, len(c) - 1 + r), e)


@given(coeffs)
def test_derivative_matches_finite_differences(c):
    h = 1e-6
    t = np.linspace(0.01, 0.99, 25)
    fd = (bz.evaluate(c, t + h) - bz.evaluate(c, t - h)) / (2 * h)
    assert np.allclose(bz.evaluate(bz.derivative(c), t), fd, atol=1e-4)


def test_derivative_of_constant_is_zero():
    assert np.array_equal(bz.derivative(np.array([3.0])), np.zeros(1))


@given(coeffs, st.floats(0.05, 0.95))
def test_split_reproduces_both_halves(c, t):
    left, right = bz.split(c, t)
    u = np.linspace(0, 1, 21)
    assert np.allclose(bz.evaluate(left, u), bz.evaluate(c, t * u), atol=1e-9)
    assert np.allclose(bz.evaluate(right, u), bz.evaluate(c, t + (1 - t) * u), atol=1e-9)


@given(coeffs, st.floats(0.0, 0.45), st.floats(0.55, 1.0))
def test_subsegment_reparametrises(c, t0, t1):
    u = np.linspace(0, 1, 21)
    sub = bz.subsegment(c, t0, t1)
    assert np.allclose(bz.evaluate(sub, u), bz.evaluate(c, t0 + (t1 - t0) * u), atol=1e-8)
    rev = bz.subsegment(c, t1, t0)
    assert np.allclose(bz.evaluate(rev, u), bz.evaluate(c, t1 + (t0 - t1) * u), atol=1e-8)


@pytest.mark.parametrize("rts", [[0.3], [0.1, 0.5, 0.9], [0.0, 1.0], [0.25, 0.75, 0.8, 0.95]])
def test_roots_of_known_polynomial(rts):
    # product of (t - r) built in Bernstein form: (t - r) = -r B0 + (1 - r) B1
    c = np.array([1.0])
    for r in rts:
        c = bz.multiply(c, np.array([-r, 1.0 - r]))
    got = bz.roots(c)
    assert np.allclose(got, sorted(rts), atol=1e-9)


def test_roots_ignores_complex_and_outside():
    # t^2 + 1 has no real roots; (t - 2) none in [0, 1]
    assert bz.roots(bz.multiply(np.array([-2.0, -1.0]), np.array([1.0, 1.0]))).size == 0
    c = bz.elevate(np.array([1.0, 1.0]), 1) + bz.multiply(np.array([0.0, 1.0]), np.array([0.0, 1.0]))
    assert bz.roots(c).size == 0
    assert bz.roots(np.zeros(4)).size == 0


@given(coeffs)
def test_to_power_matches(c):
    p = bz.to_power(c)
    assert np.allclose(np.polynomial.polynomial.polyval(T, p), bz.evaluate(c, T), atol=1e-8)


@settings(max_examples=30)
@given(coeffs)
def test_basis_is_partition_of_unity(c):
    b = bz.basis(len(c) - 1, T)
    assert np.allclose(b.sum(axis=1), 1.0)
    assert np.all(b >= 0)
