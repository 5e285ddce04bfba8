"""Arithmetic on polynomials in Bernstein form (coefficient arrays, axis 0 = index).

A polynomial of degree n on [0, 1] is ``sum_i c_i B_i^n(t)`` with
``B_i^n(t) = C(n, i) t^i (1 - t)^(n - i)``.  Coefficient arrays have shape
``(n + 1, ...)``; trailing axes are carried along (x, y, w columns, or many curves).
These are the building blocks of the symbolic QAC construction (Sec. 4.4): products
and degree elevation keep every result an exact Bernstein polynomial, no fitting.

Rows of multi-dimensional arrays are gathered by ``take`` / ``compress`` (see
:mod:`morph.polyline`).
"""

import math
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
    tail = np.broadcast_shapes(a.shape[1:], b.shape[1:])
    a = a.reshape((m + 1,) + (1,) * (len(tail) - a.ndim + 1) + a.shape[1:])
    b = b.reshape((n + 1,) + (1,) * (len(tail) - b.ndim + 1) + b.shape[1:])
    outer = (a[:, None] * b[None, :]).reshape((m + 1) * (n + 1), -1)
    return (_scatter(m, n) @ outer).reshape((m + n + 1,) + tail)


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
    """The binomials C(n, k) and the exponents k and n - k of :func:`basis`, as floats
    (the power of floats by integers casts them to these very floats, in a buffer)."""
    k = np.arange(n + 1, dtype=float)
    return _binomials(n), k, n - k


def basis(n, t):
    """Bernstein basis matrix of degree n at parameters t: shape (len(t), n + 1)."""
    t = np.asarray(t, float).reshape(-1, 1)
    binom, k, rest = _basis_coeffs(n)
    # t**0 and (1-t)**0 are 1 even at t = 0 or 1, as wanted.
    return binom * t ** k * (1.0 - t) ** rest


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

    Found in the Bernstein basis (:func:`roots_many`: subdivision isolates each root
    by the sign changes of the coefficients, then a bracketed Newton iteration);
    roots closer than ``10 eps`` are merged.  A root of odd multiplicity (or a
    cluster of roots closer than 2^-40) is returned once; one of even multiplicity
    (no sign change) only where rounding leaves a sign change of the coefficients,
    so it may be missed.  A polynomial that is zero everywhere returns no roots.
    """
    c = np.asarray(c, float)
    if (lo, hi) != (0.0, 1.0):
        c = subsegment(c, lo, hi)
    _, r = roots_many(c[None], eps)
    return lo + (hi - lo) * r if (lo, hi) != (0.0, 1.0) else r


ROOT_DEPTH = 40   # halvings before a cluster of sign changes counts as one root


def _variations(c):
    """Sign changes of each row of c (m, n+1), zero coefficients skipped."""
    s = np.sign(c)
    idx = np.where(s != 0, np.arange(c.shape[1]), 0)
    np.maximum.accumulate(idx, axis=1, out=idx)
    filled = np.take_along_axis(s, idx, axis=1)
    return np.count_nonzero(filled[:, 1:] * filled[:, :-1] < 0, axis=1)


def roots_many(c, eps=1e-13):
    """Real roots in [0, 1] of many Bernstein polynomials of one degree, all at once.

    c: (k, n+1).  Returns (owner, t): the roots of row ``owner[i]`` are the ``t[i]``,
    sorted by (owner, t).  Issue 19: the Bernstein basis all the way, no power basis.
    Each row is scaled to max |c_i| = 1; end coefficients below ``eps`` count as
    zero (a root at that end).  Intervals are halved (de Casteljau, all rows of a
    level together) while their coefficients change sign more than once (Descartes'
    rule for the Bernstein basis: the number of sign changes bounds the number of
    roots, and one change means exactly one root); an interval with one change gets
    a bracketed Newton iteration (:func:`_bracketed_newton`); after ROOT_DEPTH
    halvings an interval still changing sign twice or more counts as one (multiple)
    root at its middle.  Roots of one row closer than ``10 eps`` are merged.
    """
    c = np.asarray(c, float)
    k, n1 = c.shape
    if k == 0 or n1 < 2:
        return np.zeros(0, np.intp), np.zeros(0)
    c, owner, out_o, out_t = _normalised_with_end_roots(c, eps)
    a = np.zeros(len(c))
    w = 1.0
    lmat, rmat = _half_matrices(n1 - 1)
    for depth in range(ROOT_DEPTH + 1):
        if len(c) == 0:
            break
        v = _variations(c)
        one = v == 1
        if one.any():
            u = _bracketed_newton(c.compress(one, axis=0))
            out_o.append(owner[one])
            out_t.append(a[one] + w * u)
        many = v >= 2
        if depth == ROOT_DEPTH:
            out_o.append(owner[many])
            out_t.append(a[many] + 0.5 * w)
            break
        c, owner, a = c.compress(many, axis=0), owner[many], a[many]
        left = _apply(lmat, c)
        right = _apply(rmat, c)
        w *= 0.5
        # a root at the split point: its value is (numerically) zero
        mid = np.abs(left[:, -1]) <= eps * np.abs(c).max(axis=1)
        out_o.append(owner[mid])
        out_t.append(a[mid] + w)
        left[mid, -1] = 0.0
        right[mid, 0] = 0.0
        c = np.concatenate([left, right])
        owner = np.concatenate([owner, owner])
        a = np.concatenate([a, a + w])
    return _sorted_merged(out_o, out_t, 10 * eps)


def _normalised_with_end_roots(c, eps):
    """:func:`roots_many`'s start: rows scaled to max |c_i| = 1 (zero rows dropped),
    end coefficients below eps set to zero; (rows, their owners, and the owners and
    parameters of the end roots as lists of arrays)."""
    scale = np.abs(c).max(axis=1)
    live = scale > 0
    c = c.compress(live, axis=0) / scale[live, None]
    owner = np.nonzero(live)[0]
    c[:, 0] = np.where(np.abs(c[:, 0]) <= eps, 0.0, c[:, 0])
    c[:, -1] = np.where(np.abs(c[:, -1]) <= eps, 0.0, c[:, -1])
    at0, at1 = c[:, 0] == 0.0, c[:, -1] == 0.0
    return c, owner, [owner[at0], owner[at1]], [np.zeros(at0.sum()), np.ones(at1.sum())]


def _sorted_merged(out_o, out_t, gap):
    """Roots (owner, t) sorted by (owner, t), those of one owner closer than gap merged."""
    owner = np.concatenate(out_o).astype(np.intp)
    t = np.clip(np.concatenate(out_t), 0.0, 1.0)
    order = np.lexsort((t, owner))
    owner, t = owner[order], t[order]
    if len(t) > 1:
        keep = np.ones(len(t), bool)
        keep[1:] = (owner[1:] != owner[:-1]) | (np.diff(t) > gap)
        owner, t = owner[keep], t[keep]
    return owner, t


def _bracketed_newton(c, iters=80):
    """The root in [0, 1] of each row of c (m, n+1) whose coefficients change sign
    once: Newton's iteration kept inside a shrinking sign bracket (bisection where a
    step leaves it), until a Newton step falls below 1e-15 (the last one is taken)
    or the bracket is narrower than that.  The rows not done yet go on together
    (each row's steps are its own: the same numbers as iterating every row)."""
    m, n1 = c.shape
    n = n1 - 1
    nz = c != 0
    first = np.take_along_axis(c, nz.argmax(axis=1)[:, None], axis=1)[:, 0]
    # start from the chord of the end coefficients where both are nonzero
    den = c[:, 0] - c[:, -1]
    u = np.where((c[:, 0] != 0) & (c[:, -1] != 0) & (den != 0),
                 c[:, 0] / np.where(den != 0, den, 1.0), 0.5)
    out = u.clip(0.01, 0.99)
    act = np.arange(m)                     # the rows not done, and their state
    cc, dd, s_lo, u = c, n * np.diff(c, axis=1), np.sign(first), out.copy()
    lo, hi = np.zeros(m), np.ones(m)
    # the basis of each degree as :func:`basis` makes it (the same operations in the
    # same order), its binomials and exponents taken once: an iteration's numpy calls
    # are paid once per iteration however many rows go on
    (bn, kn, rn), (bd, kd, rd) = _basis_coeffs(n), _basis_coeffs(n - 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        for _ in range(iters):
            t = u.reshape(-1, 1)
            f = np.add.reduce(bn * t ** kn * (1.0 - t) ** rn * cc, axis=1)
            fp = np.add.reduce(bd * t ** kd * (1.0 - t) ** rd * dd, axis=1)
            same = np.sign(f) == s_lo
            lo = np.where(same, u, lo)
            hi = np.where(~same & (f != 0), u, hi)
            step = f / fp
            un = u - step
            bad = ~((un >= lo) & (un <= hi))
            un = np.where(bad, 0.5 * (lo + hi), un)
            out[act] = un
            done = (f == 0) | (~bad & (np.abs(step) <= 1e-15)) | (hi - lo <= 1e-15)
            go = (~done).nonzero()[0]
            if not len(go):
                break
            act, s_lo = act.take(go), s_lo.take(go)
            cc, dd = cc.take(go, axis=0), dd.take(go, axis=0)
            u, lo, hi = un.take(go), lo.take(go), hi.take(go)
    return out


def solve_bracketed(c, lo=None, hi=None):
    """For each row of c (m, n+1) whose polynomial changes sign on [lo_i, hi_i]
    (default [0, 1]): the root there (bracketed Newton on the subsegment's
    coefficients, :func:`_bracketed_newton`)."""
    c = np.asarray(c, float)
    if lo is None and hi is None:
        return _bracketed_newton(c)
    sub = subsegment_many(c, lo, hi)
    return lo + (hi - lo) * _bracketed_newton(sub)


# ----------------------------------------------------------------- batched forms
# Stacks of polynomials of one degree: axis 0 = which polynomial, axis 1 = index.

@lru_cache(maxsize=None)
def _half_matrices(n):
    """Matrices L, R (n+1, n+1) giving the coefficients on [0, 1/2] and [1/2, 1]."""
    left, right = split(np.eye(n + 1), 0.5)
    return left, right


#: The largest matrix (entries times trailing columns) :func:`_apply` applies by
#: whole-stack multiply-adds instead of numpy's stacked matmul, whose one BLAS call
#: per stack entry costs ~1000 instructions.  Measured by callgrind on stacks of
#: 500-750 rows, instructions a call (stacked matmul -> multiply-adds): (2, 2) x 1
#: column 277k -> 81k, (3, 4) x 2 572k -> 208k, (4, 3) x 3 820k -> 496k, (4, 6) x 2
#: 868k -> 674k, but (18, 9) x 1 590k -> 781k.
APPLY_SUMS = 48


def _apply(mat, c):
    """mat applied along axis 1 of a stack c (k, n+1, ...).

    A small matrix (:data:`APPLY_SUMS`): coefficient-major sums over j of column j of
    mat times row j of the stack, in the order j = 0, 1, ... (whole-stack products
    along rows of the k polynomials); a larger one: numpy's stacked matmul (one small
    product per stack entry: one large one would go to the threaded BLAS, which is
    many times slower on a loaded machine).  Either way a row's numbers do not depend
    on the rows around it."""
    c = np.asarray(c, float)
    k, n1 = c.shape[:2]
    rest = math.prod(c.shape[2:])
    if mat.size * rest > APPLY_SUMS:
        out = np.matmul(mat, c.reshape(k, n1, rest))
        return out.reshape((k, mat.shape[0]) + c.shape[2:])
    rows = np.ascontiguousarray(c.reshape(k, n1, rest).transpose(1, 2, 0))  # (n+1, rest, k)
    out = mat[:, 0, None, None] * rows[0]
    for j in range(1, n1):
        out += mat[:, j, None, None] * rows[j]
    return np.ascontiguousarray(out.transpose(2, 0, 1)).reshape((k, mat.shape[0]) + c.shape[2:])


def evaluate_many(c, t):
    """c_k(t_k) for a stack c (k, n+1, ...) and t (k,): shape (k, ...)."""
    c = np.asarray(c, float)
    b = basis(c.shape[1] - 1, t)
    if c.ndim == 2:
        return np.sum(b * c, axis=1)
    return np.sum(b.reshape(b.shape + (1,) * (c.ndim - 2)) * c, axis=1)


def derivative_many(c):
    """Derivatives of a stack (k, n+1, ...): (k, n, ...)."""
    n = c.shape[1] - 1
    if n == 0:
        return np.zeros_like(c)
    return n * (c[:, 1:] - c[:, :-1])   # np.diff's subtraction


def elevate_many(c, r=1):
    """Degree elevation by r of a stack (k, n+1, ...)."""
    if r <= 0:
        return np.array(c, float)
    e = _elevation_matrix(c.shape[1] - 1, r)
    return _apply(e, c)


@lru_cache(maxsize=None)
def _scatter(m, n):
    """S with S @ (a_i b_j).ravel() = Bernstein product coefficients (degrees m, n)."""
    w = _product_matrix(m, n)
    i, j = np.meshgrid(np.arange(m + 1), np.arange(n + 1), indexing="ij")
    s = np.zeros((m + n + 1, (m + 1) * (n + 1)))
    s[(i + j).ravel(), np.arange((m + 1) * (n + 1))] = w.ravel()
    return s


#: Product degrees m + n from which :func:`multiply_many` convolves the coefficients
#: (:func:`_multiply_direct`, ~(m+n) min(m,n) operations a row) instead of applying
#: the scatter matrix (:func:`_multiply_scatter`, ~(m+n) m n operations), for stacks
#: without and with trailing axes.  ``python -m bench.bernstein_product`` (CPU time
#: per call of both, stacks of 1-64 rows, product degrees 2-114): without trailing
#: axes the direct product was the faster at every degree and stack size (1.0-5x).
#: With trailing axes (two columns), callgrind instructions a call, scatter ->
#: direct: 743 rows of degrees 1 x 2 1.33M -> 0.87M, 272 rows 3 x 4 1.22M -> 0.58M,
#: 436 rows 6 x 7 5.1M -> 1.1M, 50 rows 6 x 7 0.63M -> 0.45M (the scatter matrix is
#: applied by one BLAS call a row from 49 entries on); only a stack of ~10 rows and
#: low degrees is cheaper scattered (0.15M vs 0.25M).
PRODUCT_DIRECT_DEGREE = 2
PRODUCT_DIRECT_DEGREE_TAIL = 2


def multiply_many(a, b, method=None):
    """Products of stacks a (k, m+1, ...) and b (k, n+1, ...), trailing axes broadcast:
    (k, m+n+1, ...), as :func:`multiply` row by row.

    Both methods evaluate ``c_q = sum_{i+j=q} C(m,i) C(n,j) / C(m+n,q) a_i b_j``;
    ``method`` ("scatter" or "direct") forces one, else the product degree picks the
    faster (:data:`PRODUCT_DIRECT_DEGREE`, :data:`PRODUCT_DIRECT_DEGREE_TAIL`).  They
    agree to rounding (relative ~1e-15 of sum |C(m,i) C(n,j) / C(m+n,q) a_i b_j|, the
    same bound for both).
    """
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    m, n = a.shape[1] - 1, b.shape[1] - 1
    tail = ta = a.shape[2:]
    tb = b.shape[2:]
    if ta != tb:   # the trailing axes broadcast: the shorter gets leading ones
        tail = _broadcast_tail(ta, tb)
        a = a.reshape(a.shape[:2] + (1,) * (len(tail) - len(ta)) + ta)
        b = b.reshape(b.shape[:2] + (1,) * (len(tail) - len(tb)) + tb)
    if method is None:
        least = PRODUCT_DIRECT_DEGREE_TAIL if tail else PRODUCT_DIRECT_DEGREE
        method = "direct" if m + n >= least else "scatter"
    if method == "direct":
        return _multiply_direct(a, b, m, n)
    if method != "scatter":
        raise ValueError("unknown product method %r" % (method,))
    return _multiply_scatter(a, b, m, n)


def _multiply_scatter(a, b, m, n):
    """:func:`multiply_many` by the scatter matrix: all (m+1)(n+1) products a_i b_j,
    then one matrix (m+n+1, (m+1)(n+1)) of weights sums them into place."""
    outer = a[:, :, None] * b[:, None, :]
    k = max(len(a), len(b))
    return _apply(_scatter(m, n), outer.reshape((k, (m + 1) * (n + 1)) + outer.shape[3:]))


@lru_cache(maxsize=None)
def _direct_weights(m, n):
    """The product weights C(m,i) C(n,j) / C(m+n,i+j) (:func:`_product_matrix`) laid
    out (n+1, m+1, 1): row j multiplies the coefficients a_0..a_m landing at
    q = j..j+m, broadcast over a stack's polynomials."""
    return np.ascontiguousarray(_product_matrix(m, n).T)[:, :, None]


def _multiply_direct(a, b, m, n):
    """:func:`multiply_many` as a weighted convolution, coefficient-major: for each
    index j of the shorter factor, the longer one's coefficients times their weights
    (:func:`_direct_weights`) times b_j, added into place q = i + j, in the order
    j = 0, 1, ...: whole-stack products along rows of the k polynomials (not k small
    matrix products), ~(m+n) min(m,n) operations a polynomial instead of the scatter
    matrix's ~(m+n) m n.  Trailing axes join the stack axis."""
    if n > m:
        a, b, m, n = b, a, n, m
    if a.ndim > 2:
        shape = (max(len(a), len(b)),) + _broadcast_tail(a.shape[2:], b.shape[2:])
        last = (0,) + tuple(range(2, a.ndim)) + (1,)   # the coefficient axis last
        rows = [_broadcast(x, shape[:1] + (d + 1,) + shape[1:]).transpose(last)
                .reshape(-1, d + 1) for x, d in ((a, m), (b, n))]
        out = _multiply_direct(rows[0], rows[1], m, n)
        return out.reshape(shape + (m + n + 1,)).transpose(
            (0, a.ndim - 1) + tuple(range(1, a.ndim - 1)))
    weighted = _direct_weights(m, n) * np.ascontiguousarray(a.T)   # (n+1, m+1, k)
    b_t = np.ascontiguousarray(b.T)
    out = np.zeros((m + n + 1, max(len(a), len(b))))
    for j in range(n + 1):
        out[j:j + m + 1] += weighted[j] * b_t[j]
    return np.ascontiguousarray(out.T)


def _broadcast_tail(ta, tb):
    """np.broadcast_shapes of two shapes of as many axes (a Python loop over the
    axes: np.broadcast_shapes builds arrays to find it); incompatible axes are left
    to the broadcast that follows to refuse."""
    if len(ta) != len(tb):
        return np.broadcast_shapes(ta, tb)
    return tuple(y if x == 1 else x for x, y in zip(ta, tb))


def _broadcast(x, shape):
    """np.broadcast_to(x, shape), x itself where it has that shape."""
    return x if x.shape == shape else np.broadcast_to(x, shape)


def split_many(c, t, side=None):
    """de Casteljau split of each c_k at t_k: (left, right), each like c; with ``side``
    "left" or "right" only that part (the same numbers, the other not gathered).
    The levels are coefficient-major (n+1, ..., k): each product is t or 1 - t, a
    contiguous row over the k rows, times contiguous coefficients (not a stride-0
    factor on every row's few numbers)."""
    c = np.asarray(c, float)
    left, right = _casteljau(_coefficient_major(c), np.asarray(t, float).reshape(-1), side)
    back = (c.ndim - 1,) + tuple(range(c.ndim - 1))
    if side == "left":
        return np.ascontiguousarray(left.transpose(back))
    if side == "right":
        return np.ascontiguousarray(right.transpose(back))
    return np.ascontiguousarray(left.transpose(back)), np.ascontiguousarray(right.transpose(back))


def _coefficient_major(c):
    """A C-contiguous copy of the stack c (k, n+1, ...) as (n+1, ..., k) (by transpose:
    np.moveaxis makes a dozen Python calls per use)."""
    return c.transpose(tuple(range(1, c.ndim)) + (0,)).copy(order="C")


def _casteljau(work, t, side=None):
    """(left, right): the de Casteljau split at t (k,) of the coefficient-major stack
    ``work`` (n+1, ..., k), overwritten (its levels made in place); only the part
    ``side`` ("left" or "right", the other None) where one is named."""
    s = 1.0 - t
    n = work.shape[0] - 1
    left = np.empty(work.shape) if side != "right" else None
    right = np.empty(work.shape) if side != "left" else None
    for r in range(n + 1):
        if left is not None:
            left[r] = work[0]
        if right is not None:
            right[n - r] = work[-1]
        if r < n:
            nxt = np.multiply(s, work[:-1])
            nxt += np.multiply(t, work[1:], out=work[1:])
            work = nxt
    return left, right


def _casteljau_in_place(work, t, side):
    """The part ``side`` ("left" or "right") of :func:`_casteljau`'s split, made in
    ``work`` itself (the same sums): each level is written over the one before, one
    entry short, on the side that keeps the entry the part needs (the first of each
    level for the left part, the last for the right one), which then stays."""
    s = 1.0 - t
    n = work.shape[0] - 1
    if side == "left":
        for r in range(n):
            np.add(np.multiply(s, work[r:n]), np.multiply(t, work[r + 1:]), out=work[r + 1:])
        return work
    for r in range(n):
        np.add(np.multiply(s, work[:n - r]), np.multiply(t, work[1:n + 1 - r]), out=work[:n - r])
    return work


def cut_many(c, a, b, major=False):
    """Each c_k of a stack c (k, n+1, ...) restricted to [a_k, b_k], a and b float
    arrays (k,) with 0 <= a_k < b_k <= 1 (so a_k < 1): the two de Casteljau splits of
    :func:`subsegment_many` (the right part at a, then its left part at (b - a) /
    (1 - a): the same numbers), without its cases of reversed, whole or empty
    ranges, the split's levels kept coefficient-major from one split to the next.
    With ``major``, (the stack, the same coefficient-major (n+1, ..., k))."""
    work = c.transpose(tuple(range(1, c.ndim)) + (0,)).copy(order="C")
    right = _casteljau_in_place(work, a, "right")
    left = _casteljau_in_place(right, (b - a) / (1.0 - a), "left")
    out = np.ascontiguousarray(left.transpose((c.ndim - 1,) + tuple(range(c.ndim - 1))))
    return (out, left) if major else out


def subsegment_many(c, t0, t1):
    """Each c_k restricted to [t0_k, t1_k] (reversed where t1_k < t0_k), as
    :func:`subsegment` row by row."""
    c = np.asarray(c, float)
    t0 = np.asarray(t0, float)
    t1 = np.asarray(t1, float)
    rev = t1 < t0
    a, b = np.where(rev, t1, t0), np.where(rev, t0, t1)
    whole = (a == 0.0) & (b == 1.0)
    if np.logical_or.reduce(whole, axis=None):   # rows over their whole range are
        out = c.copy()                           # themselves (the splits' bits)
        part = (~whole).ravel().nonzero()[0]
        if len(part):
            out[part] = subsegment_many(c.take(part, axis=0), t0[part], t1[part])
        back = (whole & rev).ravel().nonzero()[0]
        out[back] = out.take(back, axis=0)[:, ::-1]
        return out
    a = a.reshape(-1)
    # the two splits made in place (:func:`_casteljau_in_place`: the same sums)
    right = _casteljau_in_place(_coefficient_major(c), a, "right")
    end = a >= 1.0                 # the right part at a is a point: (b - a) / (1 - a) -> 1
    u = np.where(end, 1.0, (b.reshape(-1) - a) / np.where(end, 1.0, 1.0 - a))
    back = (c.ndim - 1,) + tuple(range(c.ndim - 1))
    kept = np.ascontiguousarray(right.transpose(back))     # the left split overwrites it
    left = np.ascontiguousarray(_casteljau_in_place(right, u, "left").transpose(back))
    out = np.where(end.reshape((-1,) + (1,) * (c.ndim - 1)), kept, left)
    if np.logical_or.reduce(rev, axis=None):
        out[rev] = out[rev][:, ::-1]
    return out


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


def reduce_exact(c, r=1):
    """Write a Bernstein polynomial known to be of degree n - r with n - r + 1 coefficients.

    Inverse of :func:`elevate` by least squares (exact when the input really has the
    lower degree, e.g. X'W - XW' of a rational curve whose top terms cancel).
    """
    c = np.asarray(c, float)
    n = len(c) - 1
    if r <= 0 or n - r < 0:
        return c.copy()
    flat = c.reshape(n + 1, -1)
    low = _reduction_matrix(n, r) @ flat
    return low.reshape((n - r + 1,) + c.shape[1:])


@lru_cache(maxsize=None)
def _reduction_matrix(n, r):
    """Least-squares inverse (pseudo-inverse) of the elevation from n - r to n."""
    return np.linalg.pinv(_elevation_matrix(n - r, r))


# ------------------------------------------------------ composition, ratio certificate

def compose_many(c, r, d=None):
    """Bernstein coefficients of c_k(r_k(s)) for a stack c (k, n+1, ...) and
    polynomials r (k, m+1) (Bernstein coefficients, values in [0, 1]): (k, n m + 1, ...).

    ``B_i^n(r) = C(n, i) r^i (1 - r)^(n - i)``; ``1 - r`` has the coefficients
    ``1 - r_j`` and the powers are Bernstein products (:func:`multiply_many`), so
    ``c(r(s)) = sum_i c_i C(n, i) r^i (1 - r)^(n - i)`` is exact (no fitting).  Used
    on homogeneous control points, a rational curve composes as is; with r's
    coefficients in [0, 1] positive weights stay positive.  With ``d`` (k, m+1),
    positive with d >= r: the rational function r / d instead, on homogeneous
    control points (``sum_i c_i C(n, i) r^i (d - r)^(n - i)``, the common factor
    d^n dropped: the same rational curve).
    """
    c = np.asarray(c, float)
    r = np.asarray(r, float)
    k, n = c.shape[0], c.shape[1] - 1
    if n == 0:
        return c.copy()
    u = 1.0 - r if d is None else np.asarray(d, float) - r
    both = np.concatenate([r, u])                            # powers of r and u together
    pw = [None, both]
    for _ in range(2, n + 1):
        pw.append(multiply_many(pw[-1], both))
    pr, pu = [None] + [p[:k] for p in pw[1:]], [None] + [p[k:] for p in pw[1:]]
    binom = _binomials(n)
    rows = [pu[n]] + [binom[i] * multiply_many(pr[i], pu[n - i]) for i in range(1, n)]
    basis = np.stack(rows + [pr[n]], axis=2)                 # (k, n m + 1, n + 1)
    out = np.matmul(basis, c.reshape(k, n + 1, -1))
    return out.reshape((k, basis.shape[1]) + c.shape[2:])


def compose(c, r):
    """c(r(s)) for one polynomial c (n+1, ...) and r (m+1,): :func:`compose_many`."""
    return compose_many(np.asarray(c, float)[None], np.asarray(r, float)[None])[0]


RATIO_TIE = 1e-9   # ratios within this (relative) of the largest tie; the first wins


@lru_cache(maxsize=None)
def _panel_matrices(n, halvings):
    """de Casteljau onto 2^halvings equal panels, stacked left to right:
    (2^halvings (n+1), n+1)."""
    mats = [np.eye(n + 1)]
    lmat, rmat = _half_matrices(n)
    for _ in range(halvings):
        # einsum, not @: a product this size would go to the threaded BLAS, which on a
        # loaded machine takes ~200 ms of CPU a matrix at degree 84 and up
        mats = [np.einsum("ij,jk->ik", half, m) for m in mats for half in (lmat, rmat)]
    return np.concatenate(mats)


def panels_many(c, halvings):
    """A stack c (k, n+1, ...) on 2^halvings equal panels (de Casteljau), stacked left
    to right along axis 1: (k, 2^halvings (n+1), ...)."""
    c = np.asarray(c, float)
    return _apply(_panel_matrices(c.shape[1] - 1, halvings), c)


def ratio_bound_many(a, b, halvings=1):
    """Certified upper bound of max_s a(s) / b(s) on [0, 1], row by row.

    a, b: (k, n+1) Bernstein coefficients of one degree with b > 0.  The
    coefficient-ratio certificate: sum a_i B_i / sum b_i B_i <= max_i a_i / b_i when
    every b_i > 0 (a mediant inequality, the convex hull property with weights),
    taken on each of 2^halvings equal panels (de Casteljau), which tightens it
    (Bernstein coefficients converge to the polynomial under subdivision).
    Rigorous up to rounding (relative ~1e-15 of the coefficients).  Returns
    (bound (k,), s (k,)): s is where the largest ratio sits (its coefficient's
    Greville abscissa on its panel; the first ratio within RATIO_TIE of the largest,
    so near-ties are decided the same way whatever the rounding); (inf, 0.5) where a
    coefficient of b is not positive.
    """
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    n1 = a.shape[1]
    mat = _panel_matrices(n1 - 1, halvings)
    num, den = _apply(mat, a), _apply(mat, b)
    good = (den > 0).all(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = num / np.where(den > 0, den, 1.0)
    best = r.max(axis=1)
    k = (r >= (best - RATIO_TIE * np.abs(best))[:, None]).argmax(axis=1)
    panel, i = np.divmod(k, n1)
    s = (panel + i / max(n1 - 1, 1)) / 2 ** halvings
    return np.where(good, best, np.inf), np.where(good, s, 0.5)


@lru_cache(maxsize=None)
def _inner_pinv(n, t):
    """Basis of degree n at the parameters t (a tuple) and the pseudo-inverse of its
    inner columns (least squares for c_1 ... c_{n-1})."""
    b = basis(n, np.array(t))
    return b, np.linalg.pinv(b[:, 1:-1])


def fit_fixed_ends(t, values, n, v0, v1):
    """Least-squares Bernstein polynomial of degree n through values at parameters t
    with both ends fixed: coefficients c (n+1, ...) with c_0 = v0, c_n = v1 and
    c_1 ... c_{n-1} minimising sum_k |sum_i c_i B_i^n(t_k) - values_k|^2.

    values: (m,) or (m, d) (d columns fitted at once: coordinates, or many
    polynomials sampled at the same t); v0, v1 broadcast to values' trailing shape.
    """
    values = np.asarray(values, float)
    basis_t, pinv = _inner_pinv(n, tuple(np.asarray(t, float).tolist()))
    c = np.empty((n + 1,) + values.shape[1:])
    c[0], c[-1] = v0, v1
    if n > 1:
        rhs = (values - np.multiply.outer(basis_t[:, 0], c[0])
               - np.multiply.outer(basis_t[:, -1], c[-1]))
        # np.tensordot's product (its reshape to 2-D, then np.dot), without its wrapping
        c[1:-1] = np.dot(pinv, rhs.reshape(len(rhs), -1)).reshape((n - 1,) + rhs.shape[1:])
    return c
