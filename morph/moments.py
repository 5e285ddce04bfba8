"""Areas, first moments and centroids of pieces, loops and regions (Green's theorem),
by one rule with one accuracy contract.

``A = 1/2 ∮ x dy - y dx``, ``∬ x dA = 1/3 ∮ x (x dy - y dx)``, ``∬ y dA = 1/3 ∮ y
(x dy - y dx)``.  Polynomial pieces integrate exactly on their control points (each
integrand is a Bernstein polynomial, whose integral over [0, 1] is the mean of its
coefficients).  Rational pieces use adaptive Gauss-Legendre quadrature: QUAD_POINTS
nodes on [0, 1], every interval halved until its halves agree with it to REL_AGREE of
the piece's size times its reach (its distance from the origin, or its size, whichever
is larger; to that power for the moments), all intervals of all pieces of one degree
at once, at most MAX_DEPTH halvings and MAX_INTERVALS open intervals.  So areas and
centroids carry the same contract: ~1e-13 relative to the piece's extent.
"""

import itertools

import numpy as np

from . import bernstein as bz
from .piece import Pieces, degree_groups, end_points, jet_many, kind_groups, start
from .quadrature import gauss_legendre

__all__ = ["area_terms", "moment_terms", "loop_area", "loop_areas", "region_area",
           "region_centroid"]

QUAD_POINTS = 24
REL_AGREE = 1e-13
MAX_DEPTH = 30
MAX_INTERVALS = 1 << 16


def loop_area(pieces, quad_points=QUAD_POINTS):
    """Signed area of a closed loop of pieces (positive counter-clockwise), computed
    about the loop's first point: the sum is the same for any origin, and its
    rounding then scales with the loop's size squared, not with its distance from
    (0, 0) squared (a degenerate loop far from the origin has area 0 to that
    accuracy)."""
    if not len(pieces):
        return 0.0
    return float(np.sum(area_terms(pieces, quad_points, origin=start(pieces[0]))))


def loop_areas(loops, pieces=None):
    """:func:`loop_area` of every loop, (k,): the pieces of all loops moved
    so that each loop's first point is the origin (as ``loop_area`` integrates) and
    integrated together (:func:`area_terms`, by degree and kind).  ``pieces``: the
    loops' pieces in order as a :class:`morph.piece.Pieces` when the caller has
    them stacked already."""
    sizes = np.fromiter(map(len, loops), np.int64, len(loops))
    if pieces is None:
        pieces = list(itertools.chain.from_iterable(loops))
    if not len(pieces):
        return np.zeros(len(sizes))
    owner = np.repeat(np.arange(len(sizes)), sizes)
    origin = end_points([loop[0] for loop in loops if len(loop)])[0]
    origin = origin[np.cumsum(sizes > 0) - 1][owner]
    groups = []
    for ks, h in degree_groups(pieces):
        h = h.copy()
        h[..., :2] -= origin[ks][:, None] * h[..., 2:]
        groups.append((ks, h))
    moved = Pieces(groups, len(pieces))
    return np.bincount(owner, weights=area_terms(moved), minlength=len(sizes))


def region_area(loops):
    """Signed area of a region: outer loops count positive, holes negative."""
    return sum(loop_area(loop) for loop in loops)


def region_centroid(loops):
    """Area centroid (cx, cy) of an oriented region.  Raises ValueError when the
    region has zero area."""
    pieces = [p for loop in loops for p in loop]
    m = moment_terms(pieces).sum(axis=0) if pieces else np.zeros(3)
    if m[0] == 0:
        raise ValueError("region of zero area has no centroid")
    return np.array([m[1] / m[0], m[2] / m[0]])


def area_terms(pieces, quad_points=QUAD_POINTS, origin=None):
    """Each piece's contribution 1/2 ∫ (x y' - y x') dt to the enclosed area, those of
    one degree and kind at once; with ``origin`` (x, y), of the pieces moved by
    -origin."""
    out = np.zeros(len(pieces))
    for ks, h, rational in kind_groups(pieces):
        if origin is not None:
            h[:, :, :2] -= np.asarray(origin, float) * h[:, :, 2:]
        out[ks] = (_adaptive(h, quad_points, _area_integrand, 1)[:, 0] if rational
                   else _poly_moments(h, 1)[:, 0])
    return out


def moment_terms(pieces, quad_points=QUAD_POINTS):
    """(k, 3): each piece's (A, Mx, My) contributions, 1/2 ∫ x y' - y x',
    1/3 ∫ x (x y' - y x'), 1/3 ∫ y (x y' - y x')."""
    out = np.zeros((len(pieces), 3))
    for ks, h, rational in kind_groups(pieces):
        out[ks] = (_adaptive(h, quad_points, _moment_integrand, 2) if rational
                   else _poly_moments(h, 3))
    return out


def _poly_moments(h, count):
    """The first ``count`` of (A, Mx, My) of polynomial pieces, exact on their
    control points."""
    p = h[:, :, :2] / h[:, :, 2:]
    if p.shape[1] == 1:
        return np.zeros((len(p), count))
    d = bz.derivative_many(p)
    cross = bz.multiply_many(p[:, :, 0], d[:, :, 1]) - bz.multiply_many(p[:, :, 1], d[:, :, 0])
    out = [0.5 * cross.mean(axis=1)]
    if count > 1:
        out += [bz.multiply_many(p[:, :, i], cross).mean(axis=1) / 3.0 for i in (0, 1)]
    return np.stack(out, axis=1)


def _area_integrand(pt, dp):
    return (0.5 * (pt[:, 0] * dp[:, 1] - pt[:, 1] * dp[:, 0]))[:, None]


def _moment_integrand(pt, dp):
    cross = pt[:, 0] * dp[:, 1] - pt[:, 1] * dp[:, 0]
    return np.stack([0.5 * cross, pt[:, 0] * cross / 3.0, pt[:, 1] * cross / 3.0], axis=1)


def _adaptive(h, quad_points, integrand, power, max_depth=MAX_DEPTH,
              max_intervals=MAX_INTERVALS):
    """Adaptive Gauss-Legendre of ``integrand(P, P')`` (columns) over [0, 1] on a
    stack of one degree: every open interval halved until its halves agree with it
    (all at once), to REL_AGREE of size x reach^power per column (x y' - y x' loses
    digits to |x| |y'|: the agreement asked for is relative to the piece's size
    times its distance from the origin)."""
    x, wts = gauss_legendre(quad_points)
    c = h[:, :, :2] / h[:, :, 2:]
    size = np.ptp(c, axis=1).max(axis=1)
    reach = np.maximum(np.abs(c).max(axis=(1, 2)), size)
    eps = REL_AGREE * np.maximum(size * reach ** power, 1e-300)

    def gauss(idx, t0, t1):
        t = t0[:, None] + (t1 - t0)[:, None] * 0.5 * (x + 1.0)
        pt, dp = jet_many(h, np.repeat(idx, len(x)), t.ravel())
        f = integrand(pt, dp).reshape(t.shape + (-1,))
        return 0.5 * (t1 - t0)[:, None] * np.einsum("inc,n->ic", f, wts)

    whole = gauss(np.arange(len(h)), np.zeros(len(h)), np.ones(len(h)))
    total = np.zeros_like(whole)
    idx = np.arange(len(h))
    t0, t1 = np.zeros(len(h)), np.ones(len(h))
    for depth in range(max_depth + 1):
        tm = 0.5 * (t0 + t1)
        left, right = gauss(idx, t0, tm), gauss(idx, tm, t1)
        done = ((np.abs(left + right - whole) <= eps[idx, None]).all(axis=1)
                | (depth == max_depth) | (len(idx) > max_intervals))
        np.add.at(total, idx[done], (left + right)[done])
        if done.all():
            break
        keep = ~done
        idx = np.concatenate([idx[keep], idx[keep]])
        t0, t1 = np.concatenate([t0[keep], tm[keep]]), np.concatenate([tm[keep], t1[keep]])
        whole = np.concatenate([left[keep], right[keep]])
    return total

