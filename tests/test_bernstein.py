"""Bernstein arithmetic against direct evaluation, finite differences and known roots."""

import numpy as np
import pytest
pytest.importorskip("hypothesis")
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
    p = _to_power(c)
    assert np.allclose(np.polynomial.polynomial.polyval(T, p), bz.evaluate(c, T), atol=1e-8)


@settings(max_examples=30)
@given(coeffs)
def test_basis_is_partition_of_unity(c):
    b = bz.basis(len(c) - 1, T)
    assert np.allclose(b.sum(axis=1), 1.0)
    assert np.all(b >= 0)


# ------------------------------------------------------- roots in the Bernstein basis

def _bernstein_from_roots(rts, lead=1.0):
    c = np.array([lead])
    for r in rts:
        c = bz.multiply(c, np.array([-r, 1.0 - r]))
    return c


def test_roots_many_matches_companion_matrix_roots():
    """Random degree 1-7 polynomials: the real roots in [0, 1] of the power form by
    numpy's companion matrix (independent), well separated ones compared."""
    rng = np.random.default_rng(7)
    for n in range(1, 8):
        c = rng.normal(size=(300, n + 1))
        owner, t = bz.roots_many(c)
        for k in range(len(c)):
            p = np.polynomial.polynomial.Polynomial(_to_power(c[k]))
            ref = p.roots()
            ref = np.sort(ref[np.abs(ref.imag) < 1e-9].real)
            ref = ref[(ref > 1e-6) & (ref < 1 - 1e-6)]
            got = t[owner == k]
            if len(ref) > 1 and np.diff(ref).min() < 1e-4:
                continue   # near-multiple roots: conditioning, not the method
            assert len(got) == len(ref), (n, k, got, ref)
            assert np.allclose(got, ref, atol=1e-10), (n, k, got, ref)
            # each root is a root: |f(t)| small against the coefficients
            assert np.all(np.abs(bz.evaluate(c[k], got)) <= 1e-12 * np.abs(c[k]).max())


def test_roots_many_rows_agree_with_scalar_roots():
    rng = np.random.default_rng(8)
    c = rng.normal(size=(200, 5))
    owner, t = bz.roots_many(c)
    for k in range(len(c)):
        assert np.array_equal(t[owner == k], bz.roots(c[k]))


@pytest.mark.parametrize("rts,expect", [([0.0, 0.4], [0.0, 0.4]), ([0.3, 1.0], [0.3, 1.0]),
                                        ([0.1, 0.1 + 1e-6], [0.1, 0.1 + 1e-6]),
                                        ([0.35, 0.35, 0.35], [0.35]), ([0.2, 0.7, 0.7, 0.7], [0.2, 0.7])])
def test_roots_at_ends_close_and_odd_multiple(rts, expect):
    """Every sign change is found, a root of odd multiplicity once (to its
    conditioning, eps^(1/3) for a triple root), roots at the ends exactly."""
    got = bz.roots(_bernstein_from_roots(rts, 3.0))
    assert len(got) == len(expect), got
    assert np.allclose(got, expect, atol=1e-5)


@pytest.mark.parametrize("rts,odd", [([0.5, 0.5], []), ([0.2, 0.6, 0.6], [0.2]),
                                     ([0.6, 0.6, 0.9], [0.9])])
def test_roots_even_multiplicity(rts, odd):
    """A root of even multiplicity (no sign change) may be missed when rounding makes
    the polynomial one-signed there (callers only need sign changes); if reported,
    it is accurate.  The sign changes are always found."""
    got = bz.roots(_bernstein_from_roots(rts, 3.0))
    for r in odd:
        assert np.min(np.abs(got - r)) < 1e-12
    assert all(np.min(np.abs(np.array(rts) - g)) < 1e-6 for g in got)


def test_roots_on_subinterval():
    c = _bernstein_from_roots([0.1, 0.45, 0.8])
    assert np.allclose(bz.roots(c, 0.2, 0.9), [0.45, 0.8], atol=1e-12)


def test_solve_bracketed_finds_the_sign_change():
    rng = np.random.default_rng(9)
    r = rng.uniform(0.05, 0.95, 50)
    c = np.array([bz.elevate(np.array([-x, 1.0 - x]), 3) for x in r])
    assert np.allclose(bz.solve_bracketed(c), r, atol=1e-14)
    lo, hi = r - 0.04, r + 0.05
    assert np.allclose(bz.solve_bracketed(c, lo, hi), r, atol=1e-14)


# ----------------------------------------------------------- batched forms vs scalar

def test_batched_forms_match_scalar():
    rng = np.random.default_rng(10)
    for n, m in ((1, 2), (3, 2), (4, 5)):
        a = rng.normal(size=(6, n + 1, 3))
        b = rng.normal(size=(6, m + 1, 1))
        t = rng.uniform(0, 1, 6)
        t0, t1 = rng.uniform(0, 1, 6), rng.uniform(0, 1, 6)
        prod = bz.multiply_many(a, b)
        elev = bz.elevate_many(a, 2)
        left, right = bz.split_many(a, t)
        sub = bz.subsegment_many(a, t0, t1)
        val = bz.evaluate_many(a, t)
        for k in range(6):
            assert np.allclose(prod[k], bz.multiply(a[k], b[k]), atol=1e-13)
            assert np.allclose(elev[k], bz.elevate(a[k], 2), atol=1e-13)
            sl, sr = bz.split(a[k], t[k])
            assert np.allclose(left[k], sl, atol=1e-13) and np.allclose(right[k], sr, atol=1e-13)
            assert np.allclose(sub[k], bz.subsegment(a[k], t0[k], t1[k]), atol=1e-12)
            assert np.allclose(val[k], bz.evaluate(a[k], [t[k]])[0], atol=1e-13)
        # 1-D rows (scalar polynomials) too
        p = bz.multiply_many(a[:, :, 0], b[:, :, 0])
        assert np.allclose(p[2], bz.multiply(a[2, :, 0], b[2, :, 0]), atol=1e-13)


def test_reduce_exact_inverts_elevate():
    rng = np.random.default_rng(11)
    c = rng.normal(size=(4, 2))
    assert np.allclose(bz.reduce_exact(bz.elevate(c, 2), 2), c, atol=1e-12)


def _to_power(c):
    """Power-basis coefficients (ascending) of a Bernstein polynomial."""
    c = np.asarray(c, float)
    return np.tensordot(bz._to_power_matrix(len(c) - 1), c, axes=(1, 0))


def _exact_product_error(a, b, prod):
    """Largest error of ``prod`` (k, m+n+1) against the exact Bernstein product of the
    rows of a (k, m+1) and b (k, n+1), in units of the rounding scale
    sum_{i+j=q} C(m,i) C(n,j) / C(m+n,q) |a_i b_j| (exact rational arithmetic)."""
    from fractions import Fraction
    from math import comb
    m, n = a.shape[1] - 1, b.shape[1] - 1
    worst = 0.0
    for ar, br, pr in zip(a, b, prod):
        fa, fb = [Fraction(x) for x in ar], [Fraction(x) for x in br]
        for q in range(m + n + 1):
            exact, scale = Fraction(0), Fraction(0)
            for i in range(max(0, q - n), min(m, q) + 1):
                term = Fraction(comb(m, i) * comb(n, q - i), comb(m + n, q)) * fa[i] * fb[q - i]
                exact += term
                scale += abs(term)
            err = abs(Fraction(pr[q]) - exact)
            worst = max(worst, float(err / scale) if scale else float(err != 0) * np.inf)
    return worst


# product degrees on both sides of both crossovers of multiply_many
PRODUCT_DEGREES = [(0, 0), (1, 0), (1, 1), (2, 3), (6, 1), (5, 9), (9, 6), (20, 21),
                   (41, 3), (54, 6), (57, 57)]


@pytest.mark.parametrize("method", ["scatter", "direct", None])
def test_product_methods_match_exact(method):
    rng = np.random.default_rng(38)
    for m, n in PRODUCT_DEGREES + [tuple(rng.integers(0, 60, 2)) for _ in range(4)]:
        a = rng.normal(size=(3, m + 1)) * 10.0 ** rng.integers(-3, 4, (3, 1))
        b = rng.normal(size=(3, n + 1))
        prod = bz.multiply_many(a, b, method)
        assert prod.shape == (3, m + n + 1)
        assert _exact_product_error(a, b, prod) < 1e-13, (m, n)
        # with trailing axes (moved into the stack by the direct product)
        xy = np.stack([a, 2.0 * a], axis=2)
        prod2 = bz.multiply_many(xy, b[:, :, None], method)
        assert prod2.shape == (3, m + n + 1, 2)
        assert _exact_product_error(2.0 * a, b, prod2[:, :, 1]) < 1e-13, (m, n)


def test_exact_product_check_catches_an_off_by_one_weight(monkeypatch):
    """The oracle above fails a product whose weights are shifted by one place."""
    rng = np.random.default_rng(1)
    a, b = rng.normal(size=(2, 31)), rng.normal(size=(2, 5))
    good = bz.multiply_many(a, b, "direct")
    assert _exact_product_error(a, b, good) < 1e-13
    w = bz._direct_weights(30, 4).copy()
    w[2, [14, 15]] = w[2, [15, 14]]                      # a_14, a_15 swap weights with b_2
    monkeypatch.setattr(bz, "_direct_weights", lambda m, n: w)
    assert _exact_product_error(a, b, bz.multiply_many(a, b, "direct")) > 1e-3
    s = bz._scatter(30, 4).copy()
    s[[17, 18]] = s[[18, 17]]                            # two output rows swapped
    monkeypatch.setattr(bz, "_scatter", lambda m, n: s)
    assert _exact_product_error(a, b, bz.multiply_many(a, b, "scatter")) > 1e-3


def test_subsegment_many_over_whole_ranges_is_the_rows_and_the_splits():
    """Rows over [0, 1] (or [1, 0], reversed) come out as themselves, which is what
    the two de Casteljau splits give them; the other rows of the same call are
    split as before."""
    rng = np.random.default_rng(59)
    c = rng.uniform(-5, 5, (60, 4, 3))
    t0, t1 = rng.uniform(0, 1, 60), rng.uniform(0, 1, 60)
    t0[::3], t1[::3] = 0.0, 1.0
    t0[1::6], t1[1::6] = 1.0, 0.0
    got = bz.subsegment_many(c, t0, t1)
    rev = t1 < t0
    a, b = np.where(rev, t1, t0), np.where(rev, t0, t1)
    _, right = bz.split_many(c, a)
    left, _ = bz.split_many(right, np.where(a >= 1.0, 1.0, (b - a) / (1.0 - a)))
    left[rev] = left[rev][:, ::-1]
    assert np.array_equal(got, left)
    whole = (a == 0.0) & (b == 1.0)
    assert np.array_equal(got[whole & ~rev], c[whole & ~rev])
    assert np.array_equal(got[whole & rev], c[whole & rev][:, ::-1])


def _bracketed_newton_row(c, iters=80):
    """bernstein._bracketed_newton of one row written plainly: Newton on the row's
    polynomial (values and derivatives by bz.basis), bisection where a step leaves
    the sign bracket, until f = 0, a step of at most 1e-15 or a bracket that narrow."""
    n = len(c) - 1
    first = c[np.flatnonzero(c != 0)[0]] if np.any(c != 0) else 0.0
    den = c[0] - c[-1]
    u = c[0] / den if (c[0] != 0 and c[-1] != 0 and den != 0) else 0.5
    u = min(max(u, 0.01), 0.99)
    lo, hi, dc = 0.0, 1.0, n * np.diff(c)
    for _ in range(iters):
        f = np.sum(bz.basis(n, [u])[0] * c)
        fp = np.sum(bz.basis(n - 1, [u])[0] * dc)
        if np.sign(f) == np.sign(first):
            lo = u
        elif f != 0:
            hi = u
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.float64(f) / fp
        un = u - step
        bad = not (lo <= un <= hi)
        u_next = 0.5 * (lo + hi) if bad else un
        if f == 0 or (not bad and abs(step) <= 1e-15) or hi - lo <= 1e-15:
            return u_next
        u = u_next
    return u


@pytest.mark.parametrize("n", [1, 2, 3, 5, 8, 12])
def test_bracketed_newton_of_a_stack_is_each_row_iterated_alone(n):
    """All rows iterated together (the rows not done going on) give each row's
    root as iterating it alone does, to the bit."""
    rng = np.random.default_rng(n)
    c = rng.normal(size=(60, n + 1))
    c[:, 0], c[:, -1] = np.abs(c[:, 0]), -np.abs(c[:, -1])
    c[:, 1:-1] = -np.sort(-c[:, 1:-1], axis=1)    # one sign change a row
    c[::7, 0] = 0.0                                 # a root at 0
    c[3::11] *= -1.0                                # falling and rising rows
    got = bz._bracketed_newton(c)
    want = np.array([_bracketed_newton_row(row) for row in c])
    assert np.array_equal(got, want)
    # the comparison can fail: a root moved by an ulp is another root
    assert not np.array_equal(np.nextafter(got, 2.0), want)
