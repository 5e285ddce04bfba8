"""Arithmetic on polynomials in Bernstein form (coefficient arrays, axis 0 = index).

A polynomial of degree n on [0, 1] is ``sum_i c_i B_i^n(t)`` with
``B_i^n(t) = C(n, i) t^i (1 - t)^(n - i)``.  Coefficient arrays have shape
``(n + 1, ...)``; trailing axes are carried along (x, y, w columns, or many curves).
These are the building blocks of the symbolic QAC construction (Sec. 4.4): products
and degree elevation keep every result an exact Bernstein polynomial, no fitting.
"""

from functools import lru_cache

import numpy as np


@lru_cache(maxsize=None)
def _binomials(n):
    """Row n of Pascal's triangle as floats."""
    row = np.ones(n + 1)
    for k in range(1, n + 1):
        row[k] = row[k - 1] * (n - k + 1) / k
    return row


@lru_cache(maxsize=None)
def _product_matrix(m, n):
    """Weights ``C(m,i) C(n,j) / C(m+n,i+j)`` of the Bernstein product formula."""
    bm, bn, bmn = _binomials(m), _binomials(n), _binomials(m + n)
    i, j = np.meshgrid(np.arange(m + 1), np.arange(n + 1), indexing="ij")
    return bm[i] * bn[j] / bmn[i + j]


def multiply(a, b):
    """Product of two Bernstein polynomials, degree m + n.

    ``(sum a_i B_i^m)(sum b_j B_j^n) = sum_k c_k B_k^{m+n}`` with
    ``c_k = sum_{i+j=k} C(m,i) C(n,j) / C(m+n,k) a_i b_j``.
    Trailing axes broadcast (a of shape (m+1, ...), b of shape (n+1, ...)).
    """
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    m, n = len(a) - 1, len(b) - 1
    w = _product_matrix(m, n)
    tail = np.broadcast_shapes(a.shape[1:], b.shape[1:])
    out = np.zeros((m + n + 1,) + tail)
    for i in range(m + 1):
        out[i:i + n + 1] += (w[i].reshape((-1,) + (1,) * len(tail))) * (a[i] * b)
    return out


@lru_cache(maxsize=None)
def _elevation_matrix(n, r):
    """Matrix E with shape (n+r+1, n+1) so that E @ c elevates degree n by r."""
    bn, br, bnr = _binomials(n), _binomials(r), _binomials(n + r)
    e = np.zeros((n + r + 1, n + 1))
    for k in range(n + r + 1):
        for i in range(max(0, k - r), min(n, k) + 1):
            e[k, i] = bn[i] * br[k - i] / bnr[k]
    return e


def elevate(c, r=1):
    """Degree elevation by r: the same polynomial written with degree n + r."""
    c = np.asarray(c, float)
    if r <= 0:
        return c.copy()
    e = _elevation_matrix(len(c) - 1, r)
    return np.tensordot(e, c, axes=(1, 0))


def to_degree(c, n):
    """Elevate c to degree n (n must be >= its degree)."""
    return elevate(c, n - (len(c) - 1))


def derivative(c):
    """Derivative ``n (c_{i+1} - c_i)`` as a Bernstein polynomial of degree n - 1."""
    c = np.asarray(c, float)
    n = len(c) - 1
    if n == 0:
        return np.zeros_like(c)
    return n * np.diff(c, axis=0)


@lru_cache(maxsize=None)
def _basis_coeffs(n):
    return _binomials(n)


def basis(n, t):
    """Bernstein basis matrix of degree n at parameters t: shape (len(t), n + 1)."""
    t = np.asarray(t, float).reshape(-1, 1)
    k = np.arange(n + 1)
    # t**0 and (1-t)**0 are 1 even at t = 0 or 1, as wanted.
    return _basis_coeffs(n) * t ** k * (1.0 - t) ** (n - k)


def evaluate(c, t):
    """Values of a Bernstein polynomial at parameters t: shape (len(t), ...)."""
    c = np.asarray(c, float)
    b = basis(len(c) - 1, t)
    if c.ndim == 2:
        return b @ c
    return np.tensordot(b, c, axes=(1, 0))


def split(c, t):
    """de Casteljau split at t: coefficient arrays of the halves on [0,t] and [t,1]."""
    c = np.asarray(c, float)
    n = len(c) - 1
    left = np.empty_like(c)
    right = np.empty_like(c)
    work = c.copy()
    left[0] = work[0]
    right[n] = work[n]
    for r in range(1, n + 1):
        work = (1.0 - t) * work[:-1] + t * work[1:]
        left[r] = work[0]
        right[n - r] = work[-1]
    return left, right


def subsegment(c, t0, t1):
    """Coefficients of the same polynomial restricted to [t0, t1], reparametrised to [0,1]."""
    if t1 < t0:
        return subsegment(c, t1, t0)[::-1].copy()
    if t1 <= 0.0 or t0 >= 1.0 or t1 - t0 <= 0.0:
        # degenerate request: fall back to the two-split formula anyway
        pass
    _, right = split(c, t0)
    if t0 >= 1.0:
        return right
    u = (t1 - t0) / (1.0 - t0)
    left, _ = split(right, u)
    return left


def roots(c, lo=0.0, hi=1.0, eps=1e-13):
    """Real roots in [lo, hi] of a scalar Bernstein polynomial, sorted.

    Converted to the power basis and solved with numpy's companion matrix, then each
    root polished by Newton on the Bernstein form.  Adequate for the low degrees used
    here (<= 20).  A polynomial that is zero everywhere returns no roots.
    """
    c = np.asarray(c, float)
    n = len(c) - 1
    scale = np.max(np.abs(c)) if c.size else 0.0
    if scale == 0.0 or n == 0:
        return np.empty(0)
    p = to_power(c / scale)
    # strip near-zero leading coefficients (degree drop)
    while len(p) > 1 and abs(p[-1]) < 1e-14:
        p = p[:-1]
    if len(p) <= 1:
        return np.empty(0)
    r = np.roots(p[::-1])
    r = r[np.abs(r.imag) < 1e-7].real
    r = r[(r >= lo - 1e-9) & (r <= hi + 1e-9)]
    if r.size == 0:
        return r
    d = derivative(c / scale)
    for _ in range(3):
        f = evaluate(c / scale, r)
        fp = evaluate(d, r)
        # Newton only where the slope is well above the value's rounding noise;
        # at (near) double roots the quotient of two tiny numbers is meaningless.
        ok = np.abs(fp) > 1e-6
        step = np.where(ok, f / np.where(ok, fp, 1.0), 0.0)
        better = np.abs(evaluate(c / scale, r - step)) <= np.abs(f)
        r = np.where(ok & better, r - step, r)
    r = np.clip(np.sort(r), lo, hi)
    if r.size > 1:
        keep = np.concatenate([[True], np.diff(r) > eps * 10])
        r = r[keep]
    return r


@lru_cache(maxsize=None)
def _to_power_matrix(n):
    """M with power coefficients p = M @ c, p_k the coefficient of t^k."""
    m = np.zeros((n + 1, n + 1))
    bn = _binomials(n)
    for i in range(n + 1):
        # C(n,i) t^i (1-t)^(n-i) = C(n,i) sum_j C(n-i,j) (-1)^j t^(i+j)
        bni = _binomials(n - i)
        for j in range(n - i + 1):
            m[i + j, i] += bn[i] * bni[j] * (-1) ** j
    return m


def to_power(c):
    """Power-basis coefficients (ascending) of a Bernstein polynomial."""
    c = np.asarray(c, float)
    return np.tensordot(_to_power_matrix(len(c) - 1), c, axes=(1, 0))


def reduce_exact(c, r=1):
    """Write a Bernstein polynomial known to be of degree n - r with n - r + 1 coefficients.

    Inverse of :func:`elevate` by least squares (exact when the input really has the
    lower degree, e.g. X'W - XW' of a rational curve whose top terms cancel).
    """
    c = np.asarray(c, float)
    n = len(c) - 1
    if r <= 0 or n - r < 0:
        return c.copy()
    e = _elevation_matrix(n - r, r)
    flat = c.reshape(n + 1, -1)
    low, *_ = np.linalg.lstsq(e, flat, rcond=None)
    return low.reshape((n - r + 1,) + c.shape[1:])
