"""Closest points on rational pieces and the certified distance between a rational
piece and a polynomial curve (as kurbo's ``nearest`` and ``mindist``).

:func:`nearest_params_many` starts from dense samples and refines by Newton
(:func:`closest_params_many`); :func:`distance_bound_many` bounds the same-parameter
distance by Bernstein coefficient ratios, without sampling: the certificate of
:mod:`morph.export.certify`.
"""

import functools

import numpy as np

from . import bernstein as bz
from . import piece as pc
from .piece import jet2_many, jet2_power_many

__all__ = ["closest_params_many", "nearest_params_many", "nearest_params_in_range",
           "distance_bound_many", "PowerJets"]


def closest_params_many(c, pts, s, iters=6, jet=jet2_many):
    """Parameters of a stack of pieces c (k, n+1, 3) nearest to points pts (k, m, 2),
    by Newton's iteration on f(s) = (P(s) - p) . P'(s) = 0 from the parameters s
    (k, m): s -= f / f' with f' = |P'|^2 + (P - p) . P'' (a step is skipped where
    f' <= 0 or it is not finite), clipped to [0, 1], ``iters`` times.  ``jet``
    evaluates P, P', P'' (:func:`jet2_many` or :func:`jet2_power_many`; the latter's
    power coefficients are made once for all the steps, :class:`PowerJets`).

    A local search: it finds the nearest point only from a start in its basin (the
    callers start from the nearest of dense samples or from a close guess).
    """
    s = np.array(s, float)
    with np.errstate(divide="ignore", invalid="ignore"):   # no step where f' <= 0
        if jet is jet2_power_many and np.shape(c)[1] > 2:
            # laid out (m, k), as PowerJets.at makes its sums
            jets, st = PowerJets(c), np.ascontiguousarray(s.T)
            ptx, pty = np.ascontiguousarray(pts[..., 0].T), np.ascontiguousarray(pts[..., 1].T)
            for _ in range(iters):
                (px, py), (dx, dy), (ddx, ddy) = jets.at(st)
                ex, ey = px - ptx, py - pty
                f = ex * dx + ey * dy
                fp = (dx * dx + dy * dy) + (ex * ddx + ey * ddy)
                st = _newton_step(st, f, fp)
            return np.ascontiguousarray(st.T)
        for _ in range(iters):
            p, d, dd = jet(c, s)
            diff = p - pts
            f = np.sum(diff * d, axis=2)
            fp = np.sum(d * d, axis=2) + np.sum(diff * dd, axis=2)
            s = _newton_step(s, f, fp)
    return s


def _newton_step(s, f, fp):
    """s - f / fp clipped to [0, 1]; no step where fp <= 0 or the step is not finite
    (numpy's warnings silenced by the caller, :func:`closest_params_many`)."""
    step = f / fp
    s = s - np.where((fp > 0) & np.isfinite(step), step, 0.0)
    return s.clip(0.0, 1.0, out=s)


class PowerJets:
    """P, P' and P'' of a stack of pieces c (k, n+1, 3), n >= 2, at parameters s (k, m)
    again and again (a Newton iteration): :func:`morph.piece.jet2_power_many`'s
    arithmetic (:func:`morph.piece.power_jets`), its power coefficients made once,
    x and y returned apart (``((x, y), (x', y'), (x'', y''))``, each (k, m)).
    :meth:`at` takes and gives the parameters and values laid out (m, k), the layout
    the sums are made in (an iteration kept in it transposes nothing)."""

    def __init__(self, c):
        c = np.asarray(c, float)
        self.n = c.shape[1] - 1
        self.coef = pc.power_coefficients(c)
        self.exps = {}                      # exponents 2..n per shape of s

    def at(self, st, second=True):
        """The jets at parameters st (m, k), laid out (m, k)."""
        # the exponent array made once per shape of st: a Newton iteration calls with
        # one shape again and again
        exps = self.exps.get(st.shape)
        if exps is None:
            exps = self.exps[st.shape] = pc.power_exponents(self.n, st.shape)
        return pc.power_jets(self.coef, pc.power_table(st, self.n, exps), second)

    def __call__(self, s, second=True):
        jets = self.at(np.asarray(s).T, second)
        return tuple((x.T, y.T) for x, y in jets)


@functools.lru_cache(maxsize=64)
def _sample_basis(n, samples):
    """Equally spaced parameters and the Bernstein basis of degree n at them."""
    grid = np.linspace(0.0, 1.0, samples)
    return grid, bz.basis(n, grid)


def nearest_params_many(c, pts, samples=65, iters=4):
    """Parameters of a stack of pieces c (k, n+1, 3) nearest to points pts (k, m, 2):
    start at the nearest of ``samples`` equally spaced parameters of each piece
    (one matrix product for all), then :func:`closest_params_many` (Newton on
    (P(s) - p) . P'(s) = 0; jets by :func:`jet2_power_many` up to degree 12).
    Returns s (k, m).

    A sampled start: a branch of the curve narrower than the sample spacing can be
    missed (the Newton step then converges to a local minimum of the distance).
    """
    c = np.asarray(c, float)
    pts = np.asarray(pts, float)
    grid, basis = _sample_basis(c.shape[1] - 1, samples)
    h = np.matmul(basis, c)                                        # (k, samples, 3)
    dense = h[..., :2] / h[..., 2:]
    d2 = ((pts[:, :, None, :] - dense[:, None, :, :]) ** 2).sum(-1)  # (k, m, samples)
    jet = jet2_power_many if c.shape[1] <= 13 else jet2_many
    return closest_params_many(c, pts, grid[np.argmin(d2, axis=2)], iters, jet)


def nearest_params_in_range(c, pts, lo, hi, samples=17):
    """Parameters in [lo, hi] of the pieces of a stack c (k, n+1, 3) nearest to
    points pts (k, 2): the nearest of ``samples`` equally spaced parameters of each
    range, then Newton (:func:`closest_params_many`), kept in the range.  Returns
    s (k,)."""
    lo, hi = np.minimum(lo, hi), np.maximum(lo, hi)
    c = np.asarray(c, float)
    pts = np.asarray(pts, float)
    s = lo[:, None] + (hi - lo)[:, None] * np.linspace(0.0, 1.0, samples)[None]
    p = jet2_many(c, s)[0]
    best = s[np.arange(len(s)), np.argmin(((p - pts[:, None, :]) ** 2).sum(-1), axis=1)]
    s = closest_params_many(c, pts[:, None, :], best[:, None], iters=4)[:, 0]
    return np.clip(s, lo, hi)


def distance_bound_many(c, q, halvings=1):
    """Certified bound of max_s |R_k(s) - Q_k(s)| (same parameter s in [0, 1]) for
    rational pieces c (k, n+1, 3), R = X / W with W > 0, and polynomial curves q
    (k, m+1, 2) (Cartesian Bernstein coefficients): (bound (k,), s_peak (k,)).

    ``E = X - W Q`` is a Bernstein polynomial of degree n + m (X elevated by m, W Q
    a product), and ``|R - Q|^2 = |E|^2 / W^2`` with ``|E|^2 = E_x^2 + E_y^2`` and
    ``W^2`` (elevated by 2m) Bernstein polynomials of degree 2(n + m), W^2 > 0; the
    coefficient-ratio certificate (:func:`morph.bernstein.ratio_bound_many` on
    2^halvings panels) gives

        max_s |R(s) - Q(s)| <= sqrt(max_i e_i / v_i)        (e, v: coefficients)

    rigorous up to rounding.  Both curves are first translated by R's start point
    (the distance is translation invariant; smaller coefficients round less).
    s_peak is where the largest ratio sits (see ratio_bound_many).
    """
    c = np.asarray(c, float)
    q = np.asarray(q, float)
    m = q.shape[1] - 1
    origin = c[:, :1, :2] / c[:, :1, 2:]                           # (k, 1, 2)
    w = c[:, :, 2]
    e = (bz.elevate_many(c[:, :, :2] - w[:, :, None] * origin, m)
         - bz.multiply_many(w, q - origin))
    e2 = bz.multiply_many(e[..., 0], e[..., 0]) + bz.multiply_many(e[..., 1], e[..., 1])
    w2 = bz.elevate_many(bz.multiply_many(w, w), 2 * m)
    r, s = bz.ratio_bound_many(e2, w2, halvings)
    return np.sqrt(np.maximum(r, 0.0)), s
