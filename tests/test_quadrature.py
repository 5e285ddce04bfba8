"""The tabulated Gauss-Legendre rules (morph.quadrature) against numpy's leggauss and
against exact integrals."""

from fractions import Fraction

import numpy as np
import pytest

from morph.quadrature import TABULATED, gauss_legendre


@pytest.mark.parametrize("n", TABULATED + (5, 12))
def test_rules_are_numpys_leggauss(n):
    x, w = gauss_legendre(n)
    ref_x, ref_w = np.polynomial.legendre.leggauss(n)
    assert x.shape == w.shape == (n,)
    np.testing.assert_allclose(x, ref_x, rtol=0, atol=1e-15)
    np.testing.assert_allclose(w, ref_w, rtol=0, atol=1e-15)


@pytest.mark.parametrize("n", TABULATED)
def test_rules_integrate_monomials_to_degree_2n_minus_1(n):
    """An independent check: the n-point rule integrates x^k on [-1, 1] exactly
    (2 / (k + 1) for even k, 0 for odd k) up to k = 2n - 1; a node moved by 1e-13
    breaks it."""
    x, w = gauss_legendre(n)
    for k in range(2 * n):
        exact = float(Fraction(2, k + 1)) if k % 2 == 0 else 0.0
        assert abs(float(np.dot(w, x ** k)) - exact) <= 4e-16 * n, (n, k)
    moved = x.copy()
    moved[-1] -= 1e-13
    worst = max(abs(float(np.dot(w, moved ** k)) - (2 / (k + 1) if k % 2 == 0 else 0.0))
                for k in range(2 * n))
    assert worst > 4e-16 * n


def test_rules_are_shared_and_read_only():
    x, w = gauss_legendre(8)
    assert gauss_legendre(8)[0] is x
    with pytest.raises(ValueError):
        x[0] = 0.0
