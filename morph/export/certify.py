"""The certificate of a cubic against a rational piece, the reparametrisation fits it
uses, and the same-parameter fallback fitter.

**The certificate.**  For a cubic C fitted to R on the parameter interval [a, b] a
reparametrisation is chosen: an increasing polynomial bijection
``phi: [0, 1] -> [a, b]`` of degree m <= 9 (least-squares fit to the closest-point
feet of C on R, Bernstein coefficients strictly increasing, so phi' > 0), composed
with a Möbius map mu(v) = c v / ((c - 1) v + 1) where no polynomial alone follows
the feet (R o mu is R with its weights scaled by c^i: the same curve, exactly), or,
where that does not follow the two parametrisations closely enough either, a
continuous piecewise one: C is cut exactly (de Casteljau) at s values, R at the
feet of those points, and each panel gets its own map.  On a panel R o mu o phi
is again a rational Bézier curve X~ / W~ (degree n m, weights positive), and the
error

    |R(phi(s)) - C(s)| = |X~(s) - W~(s) C(s)| / W~(s)

is bounded without sampling: E = X~ - W~ C is a Bernstein polynomial, and so are
``|E|^2 = E_x^2 + E_y^2`` and ``W~^2`` (coefficients e_k and v_k > 0).  If
``b^2 v_k - e_k >= 0`` for every k then ``b^2 W~^2 - |E|^2 >= 0`` on [0, 1] (a
non-negative combination of the non-negative Bernstein basis), i.e.

    max_{s in [0,1]} |R(phi(s)) - C(s)| <= b = sqrt(max_k e_k / v_k)     (cubic_bound)

The coefficients are first subdivided (de Casteljau, 2^refine panels, default 8) and
the worst panel taken: the same certificate, tighter because Bernstein coefficients
converge to the polynomial under subdivision.  The curve math is the shared layer's:
R o phi by :func:`morph.bernstein.compose_many`, the certificate by
:func:`morph.nearest.distance_bound_many`, the feet by
:func:`morph.nearest.nearest_params_many`, phi by :func:`morph.bernstein.fit_fixed_ends`.

**The certificate on the fitter's rays.**  Where the fitter's rays give matched
pairs (s_j on C, u_j on R, on one normal of R), :func:`certify_batch` cuts the pair
at every other one into nine panels and maps each [s_j, s_j+2] onto [u_j, u_j+2] by a
Möbius map (:func:`_panel_bounds`): R o mu is R with its weights scaled by c^i, of
R's own degree, so nothing is composed; the bound on each panel squares nothing
either (:func:`hull_bound`: ``|E| <= sum |e_i| B_i <= max_i (|e_i| / w_i) W``).  The
panels' phi is continuous and increasing, so the bound is a Fréchet bound as above.
Pairs whose rays already match at the same parameter take phi = identity on four
equal panels instead.  The feet are the fitter's: nothing is sampled again, and no
Newton step runs on this path.  All panels of a batch, of every degree, are bounded
first without halving (the pieces lifted to the batch's highest degree); only the
panels that can still raise their pair's maximum are refined, at the piece's own
degree (:func:`_worst_panels`, a branch and bound whose result is that of refining
every panel).  Pairs these panels do not certify are tried on panels cut at every
ray, and only then by the composed map.

**What is bounded.**  A bound b of the parametric distance under the monotone
reparametrisation phi bounds the Fréchet distance between C and R restricted to
[a, b], hence the Hausdorff distance: every point of C is within b of R([a, b]) and
every point of R([a, b]) is within b of C.  With phi = identity on [a, b] (no
reparametrisation: :func:`cubic_bound` without ``reparam``) it is the plain
same-parameter distance.  Rounding aside (relative ~1e-15 of the coordinates in the
coefficient products), the bound is rigorous.

Rows of multi-dimensional arrays are gathered by ``take`` / ``compress`` (see
:mod:`morph.polyline`).
"""

import functools
import math
from collections import namedtuple

import numpy as np

from .. import bernstein as bz
from .. import piece as pc
from .. import nearest as nr
from ..polyline import unique
from ..budget import PHI_SHARE


#: (s1 - s0) with these (m+1, 2) [numerator, weight] coefficients: a polynomial
#: composed with a Möbius map, see :func:`_reparams`); see :func:`cubic_bound`.
CubicFit = namedtuple("CubicFit", "t0 t1 cubic bound reparam")


def check_piece(piece):
    piece = np.asarray(piece, float)
    if piece.ndim != 2 or piece.shape[1] != 3 or len(piece) < 2:
        raise ValueError("a piece is an (n+1, 3) array with n >= 1, got shape %r"
                         % (piece.shape,))
    if not np.all(np.isfinite(piece)):
        raise ValueError("export needs finite control points, got %r" % (piece,))
    if np.any(piece[:, 2] <= 0):
        raise ValueError("export needs positive weights, got %r" % (piece[:, 2],))
    return piece


# ------------------------------------------------------------------ the certificate

#: de Casteljau halvings of the certificate's coefficients (2^REFINE panels).
REFINE = 3
#: de Casteljau halvings of each panel of the certificate on the fitter's rays
#: (:func:`hull_bound` on the panels of :func:`_panel_bounds`, a ninth of the cubic
#: each): within 2 % of the squared certificate at two halvings on the brush
#: pairs (one halving: 28 % at worst).
PANEL_REFINE = 2


def homogeneous_reparam(phi):
    """A reparametrisation's coefficients as an (m+1, 2) array [numerator, weight]:
    (m+1,) Bernstein coefficients of a polynomial get weights 1; an (m+1, 2) array
    (a rational Bézier function, value numerator / weight) is checked and returned."""
    phi = np.asarray(phi, float)
    if phi.ndim == 1:
        return np.stack([phi, np.ones_like(phi)], axis=1)
    if phi.ndim != 2 or phi.shape[1] != 2 or not np.all(phi[:, 1] > 0):
        raise ValueError("a reparametrisation is (m+1,) Bernstein coefficients or (m+1, 2) "
                         "[numerator, weight] with positive weights")
    return phi


def affine_reparam(h, a, b):
    """Homogeneous reparametrisation coefficients of a + b phi (h those of phi)."""
    out = h.copy()
    out[:, 0] = a * h[:, 1] + b * h[:, 0]
    return out


def _normalized_reparam(phi, t0, t1):
    """phi on [t0, t1] as increasing homogeneous coefficients on [0, 1] (checked).

    A rational Bézier function with positive weights and increasing values
    numerator_i / weight_i is increasing (its derivative's numerator has
    non-negative Bernstein coefficients)."""
    h = affine_reparam(homogeneous_reparam(phi), -t0 / (t1 - t0), 1.0 / (t1 - t0))
    u = h[:, 0] / h[:, 1]
    if abs(u[0]) > 1e-12 or abs(u[-1] - 1.0) > 1e-12 or np.any(np.diff(u) <= 0):
        raise ValueError("a reparametrisation needs increasing Bernstein coefficients")
    h[0, 0], h[-1, 0] = 0.0, h[-1, 1]
    h[:, 0] = np.clip(h[:, 0], 0.0, h[:, 1])
    return h


def _value(h, i):
    return float(h[i, 0] / h[i, 1])


def _panels(reparam):
    """A reparam argument as a list of (s0, s1, homogeneous phi) panels (checked
    contiguous: values at the panels' joins equal to 1e-12)."""
    if isinstance(reparam, np.ndarray) or (len(reparam) and np.isscalar(reparam[0])):
        return [(0.0, 1.0, homogeneous_reparam(reparam))]
    panels = [(float(a), float(b), homogeneous_reparam(f)) for a, b, f in reparam]
    ok = panels[0][0] == 0.0 and panels[-1][0] < panels[-1][1] == 1.0 and all(
        p[0] < p[1] and p[1] == q[0] and abs(_value(p[2], -1) - _value(q[2], 0)) <= 1e-12
        for p, q in zip(panels, panels[1:]))
    if not ok:
        raise ValueError("reparam panels must cover [0, 1] and join continuously")
    return panels


def same_param_bound(piece, cubic, refine=REFINE):
    """:func:`morph.nearest.distance_bound_many` of one piece and one cubic."""
    return float(nr.distance_bound_many(piece[None], np.asarray(cubic, float)[None],
                                        refine)[0][0])


def cubic_bound(piece, cubic, reparam=None, refine=REFINE):
    """Certified bound on the distance between a piece R and a cubic C.

    Without ``reparam``: ``max_{t in [0,1]} |R(t) - C(t)|`` (same parameter).  With
    ``reparam``: ``max_{s in [0,1]} |R(phi(s)) - C(s)|`` for the continuous increasing
    phi it describes, which bounds the Fréchet and Hausdorff distances between C
    and R on [phi(0), phi(1)].  ``reparam`` is either the coefficients of one
    increasing phi (values in [0, 1]) or, as in :class:`CubicFit`, a sequence of
    panels ``(s0, s1, coefficients)``: phi on [s0, s1] is the function of (s - s0)
    / (s1 - s0) with these coefficients, (m+1,) Bernstein coefficients of a
    polynomial or (m+1, 2) [numerator, weight] of a rational Bézier function
    (:func:`homogeneous_reparam`).  ``cubic`` is a (4, 2) array of Cartesian control
    points.  On each panel R o phi is composed exactly
    (:func:`morph.bernstein.compose`) and the coefficient-ratio certificate
    :func:`morph.nearest.distance_bound_many` applied on 2^refine panels (never below
    the true maximum, rounding aside); on a panel whose phi is a Möbius map (degree
    1, as the panels of :func:`_panel_bounds`) the smaller of that and
    :func:`hull_bound` (PANEL_REFINE halvings), both certificates; the largest over
    the panels is returned.  A :class:`CubicFit`'s stated bound is never below it.

    Raises:
        ValueError: bad piece (shape, weights) or a reparam that is not increasing.
    """
    piece = check_piece(piece)
    cubic = np.asarray(cubic, float)
    if reparam is None:
        return same_param_bound(piece, cubic, refine)
    worst = 0.0
    for s0, s1, phi in _panels(reparam):
        t0, t1 = _value(phi, 0), _value(phi, -1)
        if not 0.0 <= t0 < t1 <= 1.0:
            raise ValueError("reparam must map [0, 1] into [0, 1] increasingly")
        sub = piece if (t0, t1) == (0.0, 1.0) else pc.subsegment(piece, t0, t1)
        h = _normalized_reparam(phi, t0, t1)
        comp = bz.compose_many(sub[None], h[None, :, 0], h[None, :, 1])[0]
        c = cubic if (s0, s1) == (0.0, 1.0) else bz.subsegment(cubic, s0, s1)
        bound = same_param_bound(comp, c, refine)
        if len(h) == 2:         # a Möbius panel (:func:`_panel_bounds`): its own certificate too
            bound = min(bound, float(hull_bound(comp[None], c[None])[0]))
        worst = max(worst, bound)
    return worst


# ------------------------------------------------------------------ fitting

def fit_cubic(piece):
    """Same-parameter cubic with the piece's end points and tangents; (cubic, bound).

    Two candidates are built and the one with the smaller :func:`cubic_bound`
    (same parameter, no reparametrisation) is returned: the Hermite cubic (end
    derivatives matched: P1 = P0 + R'(0)/3, P2 = P3 - R'(1)/3, error O(h^4) under
    subdivision) and the cubic whose two handle lengths minimise the sum of squared
    Bernstein coefficients of E = X - W C (a 2x2 least-squares problem, kept only if
    both lengths are positive so the tangent directions are preserved).  This is the
    fallback of :func:`cubic_segments` where the moment fit does not certify (e.g. near
    a zero derivative, where the parametrisations of R and a fitted cubic differ
    too much for a polynomial reparametrisation).
    """
    piece = check_piece(piece)
    p = pc.cartesian(piece)
    p0, p3 = p[0], p[-1]
    d = pc.derivative(piece, np.array([0.0, 1.0]))
    hermite = np.array([p0, p0 + d[0] / 3.0, p3 - d[1] / 3.0, p3])
    best = (hermite, same_param_bound(piece, hermite))

    n0, n1 = np.hypot(*d[0]), np.hypot(*d[1])
    if n0 > 0 and n1 > 0:
        t0, t1 = d[0] / n0, d[1] / n1
        w = piece[:, 2:3]
        e0 = bz.elevate(piece[:, :2], 3) - bz.multiply(w, np.array([p0, p0, p3, p3]))
        # E(alpha, beta) = e0 - alpha W B1 t0 + beta W B2 t1 (B_i cubic Bernstein basis)
        wb1 = bz.multiply(w, np.array([[0.0], [1.0], [0.0], [0.0]]))
        wb2 = bz.multiply(w, np.array([[0.0], [0.0], [1.0], [0.0]]))
        mat = np.column_stack([(-wb1 * t0).ravel(), (wb2 * t1).ravel()])
        sol, *_ = np.linalg.lstsq(mat, -e0.ravel(), rcond=None)
        alpha, beta = sol
        if alpha > 0 and beta > 0 and np.all(np.isfinite(sol)):
            cand = np.array([p0, p0 + alpha * t0, p3 - beta * t1, p3])
            bound = same_param_bound(piece, cand)
            if bound < best[1]:
                best = (cand, bound)
    return best



def degree_groups(subs):
    """Rows of ``subs`` by degree: [(rows, stacked pieces)] (stacks of one degree, so
    that batched results do not depend on the other pieces of a batch)."""
    groups = {}
    for i, sub in enumerate(subs):
        groups.setdefault(len(sub), []).append(i)
    return [(np.array(rows), np.array([subs[i] for i in rows], float))
            for rows in groups.values()]


#: Fits whose sampled distance exceeds this multiple of tol are not certified: the
#: sampled distance is nearly a lower bound of the certified one, so such a fit would
#: fail anyway (bench/export_profile.py counts the certificates spent).
SCREEN = 1.0

_NODES = 0.5 - 0.5 * np.cos(np.pi * (np.arange(24) + 0.5) / 24)   # Chebyshev nodes
_NODE_BASIS = bz.basis(3, _NODES)
#: Degrees of the reparametrisation phi tried in turn (the lowest that follows the
#: feet within PHI_SHARE * tol).
PHI_DEGREES = (3, 5, 7, 9)
#: Largest |log c| of the Möbius factor of :func:`_reparams`.
MOEBIUS_LOG = 5.0
#: Dense samples of the closest-point start of :func:`_reparams` (the cubic is
#: within about tol of the piece: a coarse start is in Newton's basin), where the
#: fitter gives no start; Newton steps from either start (from the fitter's, 2 steps
#: give the same outlines on the bench sets but leave a straight rational piece of
#: uneven speed two cubics at tol 1e-8).
REPARAM_SAMPLES = 33
REPARAM_ITERS = 4


def start_at_nodes(s, u):
    """Starting feet for :func:`_reparams` from the fitter's samples: rows of
    parameters s (k, m) on the cubic paired with parameters u (m,) on the piece
    (where the fitter's rays from R(u_j) met the cubic), completed by the shared end
    points (0, 0) and (1, 1), sorted by s and interpolated linearly at the nodes:
    (k, 24), NaN rows where a row of s has a NaN.  Only a start: Newton's iteration
    then finds the feet of the nodes themselves."""
    k = len(s)
    ss = np.concatenate([np.zeros((k, 1)), np.clip(s, 0.0, 1.0), np.ones((k, 1))], axis=1)
    uu = np.broadcast_to(np.concatenate([[0.0], u, [1.0]]), ss.shape)
    order = np.argsort(ss, axis=1, kind="stable")
    ss = np.take_along_axis(ss, order, axis=1)
    uu = np.take_along_axis(uu, order, axis=1)
    j = np.clip((ss[:, :, None] <= _NODES[None, None]).sum(axis=1) - 1, 0, ss.shape[1] - 2)
    s0, s1 = np.take_along_axis(ss, j, 1), np.take_along_axis(ss, j + 1, 1)
    u0, u1 = np.take_along_axis(uu, j, 1), np.take_along_axis(uu, j + 1, 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        w = np.where(s1 > s0, (_NODES[None] - s0) / (s1 - s0), 0.5)
    return np.clip(u0 + np.clip(w, 0.0, 1.0) * (u1 - u0), 0.0, 1.0)


def _moebius(u, s=_NODES):
    """Per row the factor c of the Möbius map mu(v) = c v / ((c - 1) v + 1) of [0, 1]
    closest to the feet u (k, 24) at the nodes s (or (k, n) at each row's own s):
    the median over the nodes of log(u (1 - s) / (s (1 - u))), c = 1 where it is
    within 5 % of 1 (or undefined)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        logs = np.log(u * (1.0 - s) / (s * (1.0 - u)))
    fine = np.isfinite(logs)
    logs = np.sort(np.where(fine, logs, np.inf), axis=1)         # undefined ones last
    count = fine.sum(axis=1)
    mid = np.where(count > 0, logs[np.arange(len(logs)), np.maximum(count - 1, 0) // 2], 0.0)
    mid = np.clip(mid, -MOEBIUS_LOG, MOEBIUS_LOG)
    return np.where(np.abs(mid) > 0.05, np.exp(mid), 1.0)


def _reparams(groups, cubics, tol, start=None, pairs=None):
    """phi: [0,1] -> [0,1] matching each cubic C(s) to its closest points R(phi(s)).

    ``groups``: the sub-pieces by degree, [(rows, stack)] (:func:`degree_groups`).
    Returns ``(phis, size, c, normal, u)``: for each (sub-piece, cubic) pair phi's
    increasing Bernstein coefficients (``phis`` (k, 10), the first ``size`` of a row
    used) of the lowest degree in 1, 3, 5, 7, 9 whose tangential
    mismatch |phi(s_j) - u_j| |R'(u_j)| at 24 Chebyshev nodes s_j is below
    PHI_SHARE * tol (:func:`_phi_fits`), a Möbius factor c, and the largest foot
    distance |R(u_j) - C(s_j)| (what no reparametrisation can beat), and the feet
    u (k, 24) themselves (NaN on the rows phi was fitted to the fitter's pairs:
    :func:`certify_batch` reads them off the pairs where it needs them).  Where no
    polynomial follows the feet that closely (a rational piece whose speed varies by
    30x along it: QAC pieces of a stroke), phi is fitted again in the parameter v
    of a Möbius map u = mu(v) = c v / ((c - 1) v + 1) (:func:`_moebius`; on
    homogeneous control points R o mu is R with w_i scaled by c^i, the same curve)
    and kept if it follows better; elsewhere c = 1.  The feet u_j of all
    pairs come from one batched Newton search per degree
    (:func:`morph.nearest.closest_params_many`) started at ``start`` (k, 24), the
    feet the fitter already found (:func:`start_at_nodes`), or, for rows without
    one (NaN), at the nearest of dense samples of the piece
    (:func:`morph.nearest.nearest_params_many`); phi from one least-squares solve
    per degree (:func:`morph.bernstein.fit_fixed_ends`, ends fixed at 0 and 1).

    ``pairs`` = (s (k, n), u (n,), speed (k, n), gap (k, n)): what the fitter's rays
    found (:class:`morph.export.fit.Rays`): the ray from the piece's point R(u_j)
    along its normal meets the cubic at C(s_j), |C(s_j) - R(u_j)| = gap, |R'(u_j)| =
    speed.  A row with them gets phi fitted to those pairs (:func:`_phi_fits` at
    its own s_j), its ``normal`` the largest gap and its feet at the nodes read off
    the pairs (:func:`start_at_nodes`): nothing is evaluated on the piece.  Only
    where no polynomial phi follows the pairs within PHI_SHARE * tol does the row
    take the Newton search above, started from those feet.  Either way phi is only
    the map the certificate composes with: the bound (:func:`_composed_bounds`)
    holds for any increasing phi.
    """
    k = len(cubics)
    if pairs is not None:
        ps, pu, pspeed, pgap = pairs
        u = np.full((k, len(_NODES)), np.nan)      # read off the pairs where needed
        known = np.all(np.isfinite(ps), axis=1) & np.all(np.isfinite(pgap), axis=1)
        pu = np.broadcast_to(pu, ps.shape)
        phis, size, miss = _phi_fits(pu, pspeed, tol, at=ps)
        normal = np.where(known, np.max(np.where(known[:, None], pgap, 0.0), axis=1), np.inf)
        c = np.ones(k)
        _moebius_fits(pu, pspeed, tol, phis, size, c, miss, known, ps)
        rest = ~known | (miss > PHI_SHARE * tol)
        if rest.any():
            i = np.nonzero(rest)[0]
            where = np.full(k, -1)
            where[i] = np.arange(len(i))
            sub = [(where[r[rest[r]]], st.compress(rest[r], axis=0)) for r, st in groups
                   if rest[r].any()]
            start = np.where(known[i, None], start_at_nodes(ps.take(i, axis=0), pu[0]), np.nan)
            ri = _newton_reparams(sub, cubics.take(i, axis=0), tol, start)
            phis[i], size[i], c[i], normal[i], u[i] = ri
        return phis, size, c, normal, u
    return _newton_reparams(groups, cubics, tol, start)


def _newton_reparams(groups, cubics, tol, start=None):
    """:func:`_reparams` with the feet found by Newton's iteration on the pieces."""
    pts = np.matmul(_NODE_BASIS, cubics)                        # (k, 24, 2)
    u, speed, gap = np.empty(pts.shape[:2]), np.empty(pts.shape[:2]), np.empty(pts.shape[:2])
    for rows, stack in groups:
        jet = pc.jet2_power_many if stack.shape[1] <= 13 else pc.jet2_many
        known = (np.all(np.isfinite(start[rows]), axis=1) if start is not None
                 else np.zeros(len(rows), bool))
        if known.any():
            u[rows[known]] = nr.closest_params_many(stack[known], pts[rows[known]],
                                                    start[rows[known]], REPARAM_ITERS, jet)
        if not known.all():
            u[rows[~known]] = nr.nearest_params_many(stack[~known], pts[rows[~known]],
                                                     samples=REPARAM_SAMPLES)
        if jet is pc.jet2_power_many and stack.shape[1] > 2:
            (px, py), (dx, dy) = nr.PowerJets(stack)(u[rows], second=False)
        else:
            p, d, _ = jet(stack, u[rows])
            (px, py), (dx, dy) = np.moveaxis(p, -1, 0), np.moveaxis(d, -1, 0)
        speed[rows] = np.hypot(dx, dy)
        gap[rows] = np.hypot(px - pts[rows, :, 0], py - pts[rows, :, 1])
    normal = gap.max(axis=1)
    c = np.ones(len(cubics))
    phis, size, miss = _phi_fits(u, speed, tol)
    _moebius_fits(u, speed, tol, phis, size, c, miss)
    return phis, size, c, normal, u


def _moebius_fits(u, speed, tol, phis, size, c, miss, rows=None, at=None):
    """Where phi misses the feet u by more than PHI_SHARE * tol, fit it again in the
    parameter v of the Möbius map u = mu(v) (:func:`_moebius`) and keep it where it
    follows better: ``phis``, ``size``, ``c``, ``miss`` updated in place.  ``rows``:
    a mask of the rows to try (None: all); ``at``: each row's own parameters s_j
    (None: the nodes)."""
    bad = miss > PHI_SHARE * tol
    if rows is not None:
        bad &= rows
    retry = np.nonzero(bad)[0]
    s = _NODES if at is None else at[retry]
    cm = _moebius(u[retry], s)
    keep = cm != 1.0
    retry, cm = retry[keep], cm[keep]
    if not len(retry):
        return
    v = u[retry] / (cm[:, None] - (cm[:, None] - 1.0) * u[retry])     # mu^-1(u)
    dv = speed[retry] * cm[:, None] / ((cm[:, None] - 1.0) * v + 1.0) ** 2
    again, asize, miss2 = _phi_fits(v, dv, tol, at=None if at is None else at[retry])
    better = miss2 < miss[retry]
    i = retry[better]
    phis[i], size[i], c[i], miss[i] = again[better], asize[better], cm[better], miss2[better]


def _phi_fits(v, speed, tol, at=None):
    """Per row the increasing Bernstein coefficients of phi fitted to the feet v
    (k, 24) at the nodes, of the lowest degree in 1, 3, 5, 7, 9 whose tangential
    mismatch |phi(s_j) - v_j| speed_j is below PHI_SHARE * tol (else the increasing
    one of least mismatch), and that mismatch: (coefficients (k, 10), their number
    (k,), mismatch (k,)).  ``at`` (k, n): each row's own parameters s_j instead of
    the nodes (:func:`_fit_at`; rows with a NaN get the identity, mismatch inf)."""
    if at is not None:
        return _phi_fits_at(v, speed, tol, at)
    miss = (np.abs(_NODES - v) * speed).max(axis=1)
    phis = np.zeros((len(v), PHI_DEGREES[-1] + 1))
    phis[:, 1] = 1.0
    size = np.full(len(v), 2)
    todo = miss > PHI_SHARE * tol
    for m in PHI_DEGREES:
        rows = np.nonzero(todo)[0]
        if not len(rows):
            break
        phi = bz.fit_fixed_ends(_NODES, v[rows].T, m, 0.0, 1.0).T   # (r, m + 1)
        mono = np.all(np.diff(phi, axis=1) > 0, axis=1)
        err = (np.abs(phi @ bz.basis(m, _NODES).T - v[rows]) * speed[rows]).max(axis=1)
        _take_better(phis, size, miss, todo, rows, phi, mono, err, tol)
    return phis, size, miss


def _take_better(phis, size, miss, todo, rows, phi, mono, err, tol):
    """The rows ``rows`` whose fit ``phi`` (one degree, ``err`` its error) is
    increasing and nearer than their best so far take it (in ``phis``, ``size``,
    ``miss``); those within ``PHI_SHARE`` tol leave ``todo``."""
    better = mono & (err < miss[rows])
    i = rows[better]
    phis[i] = 0.0
    phis[i, :phi.shape[1]], size[i], miss[i] = phi[better], phi.shape[1], err[better]
    todo[rows[mono & (err <= PHI_SHARE * tol)]] = False


def _phi_fits_at(v, speed, tol, at):
    """:func:`_phi_fits` with every row's values v_j at its own parameters s_j
    (``at``): each degree's least squares (ends fixed at 0 and 1) solved for all
    rows at once by their normal equations."""
    k, n = v.shape
    ok = np.all(np.isfinite(at), axis=1) & np.all(np.isfinite(speed), axis=1)
    s = np.where(ok[:, None], at, 0.0)
    miss = np.where(ok, (np.abs(s - v) * np.where(ok[:, None], speed, 0.0)).max(axis=1),
                    np.inf)
    phis = np.zeros((k, PHI_DEGREES[-1] + 1))
    phis[:, 1] = 1.0
    size = np.full(k, 2)
    todo = ok & (miss > PHI_SHARE * tol)
    for m in PHI_DEGREES:
        rows = np.nonzero(todo)[0]
        if not len(rows):
            break
        b = bz.basis(m, s[rows].ravel()).reshape(len(rows), n, m + 1)
        a = b[:, :, 1:-1]
        rhs = v[rows] - b[:, :, -1]
        ata = np.matmul(a.transpose(0, 2, 1), a)
        atb = np.matmul(a.transpose(0, 2, 1), rhs[:, :, None])
        # a row whose s_j crowd (an ill-posed fit) gets a tiny ridge, not an error
        ata += (1e-12 * np.trace(ata, axis1=1, axis2=2))[:, None, None] * np.eye(m - 1)
        if m == 3:                     # two unknowns: Cramer's rule, elementwise
            (a00, a01), (a10, a11) = ata[:, 0].T, ata[:, 1].T
            b0, b1 = atb[:, 0, 0], atb[:, 1, 0]
            with np.errstate(divide="ignore", invalid="ignore"):
                det = a00 * a11 - a01 * a10
                inner = np.stack([(a11 * b0 - a01 * b1) / det, (a00 * b1 - a10 * b0) / det], 1)
        else:
            try:
                inner = np.linalg.solve(ata, atb)[:, :, 0]
            except np.linalg.LinAlgError:
                break
        phi = np.concatenate([np.zeros((len(rows), 1)), inner, np.ones((len(rows), 1))], 1)
        mono = np.all(np.diff(phi, axis=1) > 0, axis=1) & np.all(np.isfinite(phi), axis=1)
        err = (np.abs(np.matmul(b, phi[:, :, None])[:, :, 0] - v[rows]) * speed[rows]).max(axis=1)
        _take_better(phis, size, miss, todo, rows, phi, mono, err, tol)
    return phis, size, miss


class Certified:
    """The certificates of a batch of (sub-piece, cubic) pairs (:func:`certify_batch`):
    ``bound`` (k,) and, on demand, pair i's panels (:meth:`panels`).  The panels are
    made only when asked for (writers of outlines need the bounds, not the maps).

    A pair certified on the fitter's ray pairs (:func:`_panel_bounds`: ``paneled[i]``)
    has ``cuts[i]`` (the cubic's parameters s_j of its panels' ends, the piece's
    ``nodes`` u_j) and ``moebius[i]`` (each panel's Möbius factor); one certified at
    the same parameter (``same[i]``) has the identity on the panels of SAME_CUTS.
    A pair certified
    by the composed map has ``phis[i]``, ``size[i]``, ``c[i]``; one certified as
    halves (:func:`_halved`) has ``half[i]`` >= 0: its halves are rows half[i] and
    half[i] + ``sub_n`` of ``sub`` (the Certified of all halved pairs of the batch),
    the sub-piece cut at ``half_u[i]``.  ``other[i]`` >= 0: the pair's certificate
    is row other[i] of ``rest`` (a Certified of the pairs the ray panels did not
    certify)."""

    __slots__ = ("bound", "phis", "size", "c", "half", "half_u", "sub", "sub_n",
                 "paneled", "same", "cuts", "nodes", "moebius", "other", "rest")

    def __init__(self, bound, phis=None, size=None, c=None):
        self.bound, self.phis, self.size, self.c = bound, phis, size, c
        marks = np.empty((2, bound.shape[0]), int)      # half, other: -1, none
        marks[:] = -1
        self.half, self.other = marks
        self.half_u = np.zeros(bound.shape[0])
        self.sub, self.sub_n = None, 0
        self.paneled = self.same = self.cuts = self.nodes = self.moebius = self.rest = None

    def panels(self, i):
        """Pair i's reparametrisation: a list of ``(s0, s1, phi)`` (see
        :func:`certify_many`)."""
        j = int(self.other[i])
        if j >= 0:
            return self.rest.panels(j)
        if self.paneled is not None and self.paneled[i]:
            s, u, c = self.cuts[i], self.nodes, self.moebius[i]
            return [(float(s[p]), float(s[p + 1]),
                     affine_reparam(np.array([[0.0, 1.0], [c[p], c[p]]]), u[p], u[p + 1] - u[p]))
                    for p in range(len(c))]
        if self.same is not None and self.same[i]:
            return [(a, b, affine_reparam(_IDENTITY, a, b - a))
                    for a, b in zip(SAME_CUTS, SAME_CUTS[1:])]
        j = int(self.half[i])
        if j >= 0:
            u = float(self.half_u[i])
            return ([(0.5 * a, 0.5 * b, affine_reparam(f, 0.0, u))
                     for a, b, f in self.sub.panels(j)]
                    + [(0.5 + 0.5 * a, 0.5 + 0.5 * b, affine_reparam(f, u, 1.0 - u))
                       for a, b, f in self.sub.panels(j + self.sub_n)])
        if self.phis is None:
            return [(0.0, 1.0, _IDENTITY)]
        f, c = self.phis[i, :self.size[i]], self.c[i]
        return [(0.0, 1.0, np.stack([c * f, (c - 1.0) * f + 1.0], axis=1))]


#: phi = identity as (2, 2) homogeneous coefficients [numerator, weight].
_IDENTITY = np.array([[0.0, 1.0], [1.0, 1.0]])


def certify_many(subs, cubics, tol, depth=3):
    """Certified bounds of cubics against sub-pieces, all pairs at once: a list of
    (bound, panels), one per pair.

    ``panels`` is a list of ``(s0, s1, phi)``: on s in [s0, s1] the reparametrisation
    is the rational Bézier function with homogeneous coefficients phi (m+1, 2) in
    the local variable (s - s0) / (s1 - s0), values in the sub-piece's [0, 1]: the
    Möbius map of :func:`_reparams` composed with its polynomial; together they
    form one continuous increasing phi.  See :func:`certify_batch` (the same on
    sub-pieces grouped by degree, panels on demand)."""
    res = certify_batch(degree_groups(subs), np.asarray(cubics, float), tol, depth)
    return [(float(b), res.panels(i)) for i, b in enumerate(res.bound)]


def certify_batch(groups, cubics, tol, depth=3, start=None, pairs=None, panel=True):
    """:class:`Certified` bounds of cubics (k, 4, 2) against the sub-pieces
    ``groups`` ([(rows, stack)] by degree: pair ``rows[j]`` is ``stack[j]``);
    ``start``: starting feet of the nodes (:func:`_reparams`), or None; ``pairs``:
    the fitter's rays (:func:`_reparams`: phi fitted to them, the pieces not
    evaluated), or None.

    The bound is the certificate of the module docstring on the exact composition
    R o mu o phi (:func:`_composed_bounds`).  Where it exceeds tol although the
    cubic is within tol of the curve at the nodes (the parametrisations differ more
    than a polynomial of degree 9 follows: rational straight pieces, zero end
    derivatives) the cubic is halved and the halves certified alone
    (:func:`_halved`), ``depth`` times.  A bound <= tol is certified; above tol it
    may be a sampled distance (a cubic farther than tol from the curve at a node is
    not composed at all).
    """
    cubics = np.asarray(cubics, float)
    if pairs is not None and panel and PANEL_RAYS:
        return _ray_certified(groups, cubics, tol, depth, pairs)
    phis, size, cs, normal, feet = _reparams(groups, cubics, tol, start, pairs)
    bound = _composed_bounds(groups, cubics, phis, size, cs, normal, tol)
    out = Certified(bound, phis, size, cs)
    if depth > 0:
        rows = np.nonzero((bound > tol) & (normal <= 0.95 * tol))[0]
        if pairs is not None:                    # their feet at the nodes, from the pairs
            bare = rows[np.isnan(feet[rows]).any(axis=1)]
            feet[bare] = start_at_nodes(pairs[0][bare], pairs[1])
        _halved(groups, cubics, out, rows, feet, tol, depth)
    return out


#: Certify on the fitter's ray pairs (:func:`_ray_certified`) where
#: :func:`certify_batch` is given them (False: the composed map everywhere).
PANEL_RAYS = True
#: Pieces of lower degree (lines) keep the composed map.  Conics take the panels
#: too: as fast as composing on the hanzi set, faster on Relief
#: (bench/export_rounds.py).
PANEL_DEGREE = 2
#: Every PANEL_STEP-th of the fitter's 16 ray pairs ends a panel of
#: :func:`_panel_bounds` (the one halfway between fixes its map): 2, nine panels.
PANEL_STEP = 2
#: A pair whose panels do not certify is tried by the composed map too where the
#: rays' largest gap is at most this share of tol (as :func:`certify_batch` halves
#: only below it): a gap is nearly a lower bound of the Fréchet distance, so above
#: it no reparametrisation certifies much below the gap.
FALLBACK_GAP = 0.95


def _ray_certified(groups, cubics, tol, depth, pairs, step=None):
    """:func:`certify_batch` given the fitter's ray pairs: each pair is certified on
    panels cut at every ``step``-th pair (:func:`_panel_bounds`: nothing is sampled
    again, nothing composed).  Pairs whose parameters already match (phi =
    identity within PHI_SHARE tol at the pairs, as :func:`_phi_fits` decides) take
    phi = identity instead, on SAME_CUTS's four equal panels (no pairs to order, no
    Möbius factor: the same-parameter certificate of :func:`hull_bound` at
    PANEL_REFINE + 2 halvings in all); pieces of degree below PANEL_DEGREE take the
    composed map.  Where the bound exceeds tol although the rays' gaps are within
    FALLBACK_GAP tol (a feet map one Möbius map per panel does not follow: a
    cubic's parameter racing ahead of the piece's near an end) the pair is
    certified again on panels cut at every pair (``step`` 1, each panel's Möbius
    map from its end speeds), and where that fails too, by the composed map of
    :func:`certify_batch`; the smaller bound is kept.  Above FALLBACK_GAP tol no map
    does much better than the gaps, and the pair fails as it is."""
    step = PANEL_STEP if step is None else step
    ps, pu, pspeed, pgap = pairs
    pu = np.asarray(pu, float)
    low = np.zeros(cubics.shape[0], bool)
    for rows, stack in groups:
        low[rows] = stack.shape[1] - 1 < PANEL_DEGREE
    with np.errstate(divide="ignore", invalid="ignore"):
        same = np.maximum.reduce(np.abs(ps - pu) * pspeed, axis=1) <= PHI_SHARE * tol
        same &= step == PANEL_STEP
        gap = np.maximum.reduce(pgap, axis=1)
        paneled = ~(same | low)
        bound, cuts, moeb, out_nodes = _panel_sets(groups, cubics, ps, pu, paneled,
                                                   PANEL_REFINE, step, same)
    out = Certified(bound)
    out.paneled, out.same = paneled, same
    out.cuts, out.moebius = cuts, moeb
    out.nodes = out_nodes
    rest = (~(bound <= tol) & ~(gap > FALLBACK_GAP * tol)).nonzero()[0]
    if not rest.shape[0]:
        return out
    where = np.empty(cubics.shape[0], int)
    where[:] = -1
    where[rest] = np.arange(rest.shape[0])
    sub = [(where[r[where[r] >= 0]], st.compress(where[r] >= 0, axis=0)) for r, st in groups
           if (where[r] >= 0).any()]
    again = (ps.take(rest, axis=0), pu, pspeed.take(rest, axis=0), pgap.take(rest, axis=0))
    c_rest = cubics.take(rest, axis=0)
    again = (_ray_certified(sub, c_rest, tol, depth, again, step=1) if step > 1 else
             certify_batch(sub, c_rest, tol, depth, pairs=again, panel=False))
    won = again.bound < bound[rest]
    out.bound[rest[won]] = again.bound[won]
    out.other[rest[won]] = where[rest[won]]
    out.rest = again
    return out


#: The panels of a pair certified at the same parameter (:func:`_ray_certified`):
#: R and C both cut at these parameters, phi = identity on each, PANEL_REFINE
#: halvings of each (16 equal panels in all: within 0.1 % of the squared
#: certificate of :func:`morph.nearest.distance_bound_many` at 8 panels on the
#: pairs of the bench sets, tighter on some, at a fifth of its CPU).
SAME_CUTS = (0.0, 0.25, 0.5, 0.75, 1.0)

#: One kind of panels of :func:`_panel_bounds` for some pairs: ``rows`` (the pairs,
#: global), ``cuts`` (the piece's parameters of the panels' ends, the same for all),
#: ``cub`` (2, 4, P r): the cubics on their panels, coordinate-major, columns in
#: (panel, pair) order, ``moebius`` (r, P): each panel's Möbius factor, NaN where
#: :func:`_panel_moebius` picks it, None for the identity.
_PanelSet = namedtuple("_PanelSet", "rows cuts cub moebius")


def _panel_bounds(groups, cubics, s, u, todo=None, refine=None, step=None, same=None):
    """Certified bounds of cubics against sub-pieces on panels cut at matched pairs of
    parameters: the cubic's s_j (``s`` (k, 2 m), per pair) with the piece's u_j
    (``u`` (2 m,), increasing, the same for all pairs).  Every ``step``-th pair
    (PANEL_STEP: 2, the odd pairs j = 1, 3, ...), completed by (0, 0) and (1, 1),
    ends a panel; the pair halfway inside a panel fixes its map.

    phi maps [s_j, s_j+2] onto [u_j, u_j+2] by a Möbius map mu(v) = c v / ((c - 1) v
    + 1) of the local parameters, c chosen so that mu takes the panel's inner pair
    to each other (or, where there is none or it is out of place, so that mu's end
    derivatives c and 1 / c are in the ratio of |C'| / |R'| at the panel's ends:
    :func:`_panel_moebius`): on each panel R o phi is the sub-piece R|[u_j, u_j+2]
    with its weights scaled by c^i (degree n, as the piece: nothing is composed),
    and :func:`hull_bound` (2^refine halvings) bounds |R(phi(s)) - C(s)| on the
    panel against C|[s_j, s_j+2].  Any continuous increasing phi gives a bound: the
    pairs (the rays of the fitter: R(u_j) and C(s_j) on one normal of R) make it a
    tight one.  Pairs out of order are moved into it first (:func:`_ordered_pairs`).
    The rows of ``same`` (a mask, None: none) are bounded with phi = identity on the
    panels of SAME_CUTS instead.  All panels of all degrees are bounded together
    first, then only those that can raise a pair's bound are refined
    (:func:`_worst_panels`).  Returns (bound (k,), cuts (k, m + 2), Möbius factors
    (k, m + 1)); bound inf where the cuts s_j are still not strictly increasing in
    (0, 1) and on the rows in neither ``todo`` (a mask; None: all) nor ``same``;
    cuts NaN off ``todo``."""
    todo = np.ones(len(s), bool) if todo is None else np.asarray(todo, bool)
    same = np.zeros(len(s), bool) if same is None else np.asarray(same, bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        return _panel_sets(groups, cubics, s, np.asarray(u, float), todo,
                           PANEL_REFINE if refine is None else refine,
                           PANEL_STEP if step is None else step, same)[:3]


def _panel_sets(groups, cubics, s, u, todo, refine, step, same):
    """:func:`_panel_bounds` (``todo``, ``same`` masks, ``u`` an array, divisions
    by zero and NaN comparisons already silenced by the caller), and the piece's
    parameters of the ray panels' ends (``ucut``)."""
    k = s.shape[0]
    ucut = np.empty(u[step - 1::step].shape[0] + 2)
    ucut[0], ucut[1:-1], ucut[-1] = 0.0, u[step - 1::step], 1.0
    bound, cuts, moeb = np.empty(k), np.empty((k, ucut.shape[0])), np.empty((k, ucut.shape[0] - 1))
    bound[:], cuts[:], moeb[:] = np.inf, np.nan, 1.0
    sets = [_ray_panels(cubics, s, u, todo.nonzero()[0], step, ucut, cuts)]
    srows = same.nonzero()[0]
    if srows.shape[0]:
        sets.append(_PanelSet(srows, SAME_CUTS, _fixed_panels(
            np.ascontiguousarray(cubics.take(srows, axis=0).transpose(2, 1, 0)), SAME_CUTS), None))
    sets = [p for p in sets if p.rows.shape[0]]
    if sets:
        cols = _columns(groups, k, sets, moeb)
        for p, b in zip(sets, _worst_panels(groups, sets, cols, refine)):
            bound[p.rows] = b
    return bound, cuts, moeb, ucut


def _ray_panels(cubics, s, u, rows, step, ucut, cuts):
    """The :class:`_PanelSet` of the pairs ``rows`` on the fitter's rays: their cuts
    s_j written into ``cuts`` (k, P + 1); only the rows whose cuts increase
    strictly are kept."""
    s = _ordered_pairs(s.take(rows, axis=0), u)
    c = np.empty((rows.shape[0], ucut.shape[0]))
    c[:, 0], c[:, 1:-1], c[:, -1] = 0.0, s[:, step - 1::step], 1.0
    cuts[rows] = c
    ok = np.logical_and.reduce((c[:, 1:] - c[:, :-1]) > 0, axis=1)
    rows, s, c = rows[ok], s.compress(ok, axis=0), c.compress(ok, axis=0)
    mid = slice(step // 2 - 1, None, step)
    if step > 1:
        inner = _inner_moebius(s[:, mid], u[mid], c, ucut)
    else:
        inner = np.empty((rows.shape[0], ucut.shape[0] - 1))
        inner[:] = np.nan
    return _PanelSet(rows, tuple(ucut.tolist()), _cubic_panels(cubics.take(rows, axis=0), c), inner)


def _fixed_panels(c, cuts):
    """Coordinate-major Bernstein coefficients c (d, n+1, r) on the panels between
    the fixed parameters ``cuts`` (a tuple): (d, n+1, P r), columns in (panel, row)
    order (one matrix product, :func:`_cut_matrices`)."""
    d, n1, r = c.shape
    sub = (_cut_matrices(n1 - 1, cuts) @ c.transpose(1, 0, 2).reshape(n1, d * r))
    return sub.reshape(-1, n1, d, r).transpose(2, 1, 0, 3).reshape(d, n1, -1)


#: The panel columns of :func:`_panel_bounds`, every panel set's in turn: ``sub``
#: (3, N+1, K) the pieces R o mu on their panels, lifted to the batch's highest
#: degree N, ``cub`` (2, 4, K) the cubics on them, ``pair`` (K,) the pair of each
#: column, ``panel`` (K,) its panel (numbered over the sets: :func:`_native_cuts`),
#: ``c`` (K,) its Möbius factor; per pair its degree group ``group`` and row in the
#: group's stack ``slot``.
_Columns = namedtuple("_Columns", "sub cub pair panel c group slot")


def _columns(groups, k, sets, moeb):
    """The :class:`_Columns` of the panel sets ``sets`` (their Möbius factors written
    into ``moeb``).  Every piece is lifted to the batch's highest degree first
    (degree elevation: the same curve), so that all degrees are cut, mapped and
    bounded together; the lifted columns only screen (:func:`_worst_panels`)."""
    top = max([st.shape[1] for _, st in groups])
    lift = np.empty((top, 3, k))              # coefficient-major: a set's rows gathered
    group, slot = np.empty((2, k), int)       # are one matrix's columns
    group[:], slot[:] = -1, 0
    for g, (rows, stack) in enumerate(groups):
        lift[:, :, rows] = (bz.elevate_many(stack, top - stack.shape[1])
                            if stack.shape[1] < top else stack).transpose(1, 2, 0)
        group[rows], slot[rows] = g, np.arange(rows.shape[0])
    size = [(len(ps.cuts) - 1) * ps.rows.shape[0] for ps in sets]
    total = sum(size)
    sub = np.empty((3, top, total))
    pair, panel = np.empty((2, total), int)
    cols = _Columns(sub, sets[0].cub if len(sets) == 1 else
                    np.concatenate([ps.cub for ps in sets], axis=2), pair, panel,
                    np.empty(total), group, slot)
    lo = first = 0
    for ps, n in zip(sets, size):
        npan, view = len(ps.cuts) - 1, sub[:, :, lo:lo + n]
        x = lift.take(ps.rows, axis=2).reshape(top, -1)
        view.reshape(3, top, npan, -1)[...] = (_cut_matrices(top - 1, ps.cuts) @ x).reshape(
            npan, top, 3, -1).transpose(2, 1, 0, 3)
        cols.pair[lo:lo + n].reshape(npan, -1)[...] = ps.rows         # (panel, pair) order
        cols.panel[lo:lo + n].reshape(npan, -1)[...] = first + _COUNT[:npan, None]
        c = cols.c[lo:lo + n]
        if ps.moebius is None:
            c[...] = 1.0
        else:
            c[...] = ps.moebius.T.ravel()
            bad = np.isnan(c).nonzero()[0]
            if bad.shape[0]:
                c[bad] = _panel_moebius(view[:, :, bad], ps.cub[:, :, bad])
            power = np.empty((top - 1, n))            # c^i: R o mu
            power[...] = c
            view[:, 1:] *= np.multiply.accumulate(power, axis=0)
            moeb[ps.rows] = c.reshape(npan, -1).T
        lo, first = lo + n, first + npan
    return cols


#: 0, 1, 2, ...: the panels of a set numbered (:func:`_columns`).
_COUNT = np.arange(64)


def _worst_panels(groups, sets, cols, refine):
    """Per panel set of ``sets`` the largest :func:`_hull_rows` bound (``refine``
    halvings, each piece at its own degree) over each pair's panels: a list of
    (r,) arrays.

    Branch and bound, with the result of refining every panel: each panel is bounded
    first without halving, lifted (``cols``, :func:`_columns`: a quarter of the
    work, all degrees in one call; elevation and another scaling of the weights
    give other coefficients of the same E / W, so another certificate of the same
    distance).  Its end coefficients are the distances at the panel's ends
    exactly, so the largest of them over a pair's panels, L, is attained and at
    most its refined maximum; the refined bound at the piece's own degree is at
    most its unrefined one at that degree (de Casteljau coefficients are convex
    combinations of the parent's), which the lifted bound screens: only panels
    whose lifted bound exceeds L can raise the maximum, and only those are
    refined (a tenth to a sixth of them on the bench sets: a fitted cubic's error
    is mostly largest at panel ends)."""
    b, ends = _hull_rows(cols.sub, cols.cub, 0, ends=True)
    low = np.empty(ends.shape[0])
    lo = 0
    for ps in sets:
        size = (len(ps.cuts) - 1) * ps.rows.shape[0]
        e = ends[lo:lo + size].reshape(-1, ps.rows.shape[0])
        low[lo:lo + size].reshape(e.shape)[...] = np.fmax.reduce(e, axis=0)
        lo += size
    redo = (~(b <= low)).nonzero()[0]
    if refine > 0 and redo.shape[0]:
        b[redo] = _refined(groups, sets, cols, redo, refine)
    out, lo = [], 0
    for ps in sets:
        size = (len(ps.cuts) - 1) * ps.rows.shape[0]
        out.append(np.maximum.reduce(b[lo:lo + size].reshape(-1, ps.rows.shape[0]), axis=0))
        lo += size
    return out


def _refined(groups, sets, cols, redo, refine):
    """:func:`_hull_rows` at ``refine`` halvings of the columns ``redo`` of ``cols``,
    each piece at its own degree: the columns of the batch's highest degree as
    they are, the others cut again from their stacks (one batched product of each
    column's panel matrix per degree), R o mu by the weights scaled by c^i."""
    out = np.empty(redo.shape[0])
    pair, panel, c = cols.pair[redo], cols.panel[redo], cols.c[redo]
    cut_tuples = tuple([ps.cuts for ps in sets])
    group = cols.group[pair]
    for g in np.bincount(group, minlength=len(groups)).nonzero()[0].tolist():  # not
        # np.unique: it imports numpy.ma, which font workers must not load
        sel = (group == g).nonzero()[0]
        stack = groups[g][1]
        n1 = stack.shape[1]
        if n1 == cols.sub.shape[1]:             # not lifted: the columns themselves
            sub = cols.sub.take(redo[sel], axis=2)
        else:
            sub = np.matmul(_native_cuts(n1 - 1, cut_tuples)[panel[sel]],
                            stack[cols.slot[pair[sel]]])
            # float exponents: integer ones would be cast to these floats in a buffer
            sub *= (c[sel, None] ** np.arange(n1, dtype=float))[:, :, None]
            sub = np.ascontiguousarray(sub.transpose(2, 1, 0))
        out[sel] = _hull_rows(sub, cols.cub.take(redo[sel], axis=2), refine)
    return out


@functools.lru_cache(maxsize=None)
def _native_cuts(n, cut_tuples):
    """The panel matrices (panels, n+1, n+1) of every tuple of cuts in turn (the
    panels numbered as in :class:`_Columns`)."""
    return np.concatenate([_cut_matrices(n, cuts).reshape(-1, n + 1, n + 1)
                           for cuts in cut_tuples])


def _inner_moebius(s_mid, u_mid, cuts, ucut):
    """The Möbius factors c of the panels (``cuts`` (k, panels + 1) on the cubic,
    ``ucut`` on the piece) that take each panel's inner pair (``s_mid``, ``u_mid``) to
    each other: mu(v) = w for the pair's local parameters v, w; NaN where there is no
    inner pair or c is beyond exp(+-MOEBIUS_LOG)."""
    inner = np.empty((cuts.shape[0], cuts.shape[1] - 1))
    inner[:] = np.nan
    # (divisions by zero and NaN comparisons silenced by the caller: _panel_sets runs
    # within the errstate of _panel_bounds or _ray_certified)
    v = (s_mid - cuts[:, :-2]) / (cuts[:, 1:-1] - cuts[:, :-2])
    w = (u_mid - ucut[:-2]) / (ucut[1:-1] - ucut[:-2])
    inner[:, :v.shape[1]] = w * (1.0 - v) / (v * (1.0 - w))
    lim = math.exp(MOEBIUS_LOG)
    return np.where((inner > 1.0 / lim) & (inner < lim), inner, np.nan)


def _ordered_pairs(s, u):
    """The cubic's parameters s (k, m) of the pairs, those out of order replaced: a
    pair is kept where its s_j lies strictly between every s before it (and 0) and
    every s after it (and 1); the others (NaN, clipped to an end by the fitter's rays,
    crossing a neighbour) get s interpolated linearly in u (m,) between the nearest
    kept pairs (or (0, 0), (1, 1)).  Any increasing pairing gives a certificate: the
    kept pairs keep it tight.  Rows already strictly increasing in (0, 1) (nearly
    all) are returned as they are, the others reordered (:func:`_reordered`).  NaN
    comparisons are silenced by the caller (:func:`_panel_sets`)."""
    fine = ((s[:, 0] > 0.0) & (s[:, -1] < 1.0)
            & np.logical_and.reduce(s[:, 1:] > s[:, :-1], axis=1))
    if np.logical_and.reduce(fine):
        return s
    out = s.copy()
    out[~fine] = _reordered(s[~fine], u)
    return out


def _reordered(s, u):
    """:func:`_ordered_pairs` of rows s (k, m) that need it."""
    k, m = s.shape
    ext = np.empty((k, m + 2))
    ext[:, 0], ext[:, 1:-1], ext[:, -1] = 0.0, s, 1.0
    before = np.fmax.accumulate(ext, axis=1)
    after = np.fmin.accumulate(ext[:, ::-1], axis=1)[:, ::-1]
    keep = np.empty(ext.shape, bool)
    keep[:, 0], keep[:, -1] = True, True
    keep[:, 1:-1] = (ext[:, 1:-1] > before[:, :-2]) & (ext[:, 1:-1] < after[:, 2:])
    if np.logical_and.reduce(keep, axis=None):
        return s
    ue = np.empty(m + 2)
    ue[0], ue[1:-1], ue[-1] = 0.0, u, 1.0
    col = np.arange(m + 2)
    prev = np.maximum.accumulate(np.where(keep, col, 0), axis=1)
    nxt = np.minimum.accumulate(np.where(keep, col, m + 1)[:, ::-1], axis=1)[:, ::-1]
    at = np.arange(k)[:, None]
    a, b = ext[at, prev], ext[at, nxt]
    frac = (ue - ue[prev]) / np.where(nxt > prev, ue[nxt] - ue[prev], 1.0)
    return np.where(keep, ext, a + frac * (b - a))[:, 1:-1]


@functools.lru_cache(maxsize=None)
def _cut_matrices(n, cuts):
    """(P (n+1), n+1): the maps of Bernstein coefficients of degree n onto the P panels
    [cuts[p], cuts[p + 1]], stacked (de Casteljau, as
    :func:`morph.bernstein.subsegment_many`)."""
    cuts = np.array(cuts)
    eye = np.broadcast_to(np.eye(n + 1), (len(cuts) - 1, n + 1, n + 1))
    return bz.subsegment_many(eye, cuts[:-1], cuts[1:]).reshape(-1, n + 1)


def _cubic_panels(cubics, cuts):
    """The cubics (k, 4, 2) on the panels [cuts[:, p], cuts[:, p + 1]] (k, P + 1):
    (2, 4, P k) control points, coordinate-major, rows in (panel, cubic) order.
    The control points of C on [a, b] are its blossom's values C(a, a, a), C(a, a,
    b), C(a, b, b), C(b, b, b): de Casteljau's second level at every cut, shared by
    the two panels that meet there, and one more step."""
    npan, k = cuts.shape[1] - 1, len(cubics)
    t = cuts.T[None]                                                 # (1, P + 1, k)
    q = cubics.transpose(1, 2, 0)[:, :, None]                        # (4, 2, 1, k)
    l1 = [q[i] + t * (q[i + 1] - q[i]) for i in range(3)]            # (2, P + 1, k)
    lo = l1[0] + t * (l1[1] - l1[0])
    d = l1[1] + t * (l1[2] - l1[1]) - lo
    out = np.empty((2, 4, npan, k))
    point = lo + t * d
    out[:, 0], out[:, 3] = point[:, :-1], point[:, 1:]
    out[:, 1] = lo[:, :-1] + t[:, 1:] * d[:, :-1]
    out[:, 2] = lo[:, 1:] + t[:, :-1] * d[:, 1:]
    return out.reshape(2, 4, npan * k)


@functools.lru_cache(maxsize=None)
def _hull_matrices(n, m, halvings):
    """The linear maps of :func:`hull_bound`: W's, the elevation of degree n by m
    then the 2^halvings panels; E's, that map and minus the Bernstein product of
    degrees n and m (from the products w_i q_j) side by side, then the panels."""
    panels = bz._panel_matrices(n + m, halvings)
    elev = panels @ bz._elevation_matrix(n, m)
    return elev, np.concatenate([elev, -(panels @ bz._scatter(n, m))], axis=1)


#: Columns of :func:`_hull_rows` per block: its (2^halvings (n + m + 1), block)
#: temporaries then stay in the processor's cache instead of streaming through
#: memory (the hanzi set's batches reach 150,000 columns).
HULL_BLOCK = 2048


def _hull_rows(c, q, halvings, ends=False):
    """:func:`hull_bound` of coordinate-major arrays: c (3, n+1, K), q (2, m+1, K);
    with ``ends``, also |R - Q| at the two ends of each column's [0, 1] (its first
    and last coefficient ratios: exact values), the larger: ((K,), (K,)).

    Per block of columns, both coordinates of E = X - W Q (translated by R's start)
    are one matrix product: [x - w o; w_i (q_j - o)] by [elevation, -product]."""
    n1, m1, k = c.shape[1], q.shape[1], c.shape[2]
    elev, fused = _hull_matrices(n1 - 1, m1 - 1, halvings)
    out = np.empty(k)
    end = np.empty(k) if ends else None
    rows = n1 + n1 * m1
    for lo in range(0, k, HULL_BLOCK):
        cb, qb = c[:, :, lo:lo + HULL_BLOCK], q[:, :, lo:lo + HULL_BLOCK]
        kb = cb.shape[2]
        w = cb[2]
        o = (cb[:2, 0] / w[0])[:, None]                               # (2, 1, kb)
        a = np.empty((rows, 2, kb))
        np.subtract(cb[:2], w * o, out=a[:n1].transpose(1, 0, 2))
        np.multiply(w[:, None, None], (qb - o).transpose(1, 0, 2)[None],
                    out=a[n1:].reshape(n1, m1, 2, kb))
        e = (fused @ a.reshape(rows, 2 * kb)).reshape(-1, 2, kb)
        h = elev @ w
        e *= e
        r2 = (e[:, 0] + e[:, 1]) / (h * h)
        bound = np.sqrt(np.maximum.reduce(r2, axis=0), out=out[lo:lo + kb])
        bound[~(np.minimum.reduce(h, axis=0) > 0)] = np.inf
        if ends:
            end[lo:lo + kb] = np.sqrt(np.fmax(r2[0], r2[-1]))
    return (out, end) if ends else out


def hull_bound(c, q, halvings=PANEL_REFINE):
    """Certified bound of max_s |R_k(s) - Q_k(s)| (same parameter s in [0, 1]) for
    rational pieces c (k, n+1, 3) with positive weights and polynomial curves q
    (k, m+1, 2), without squaring a polynomial: (k,).

    E = X - W Q (degree n + m, X and W elevated by m) and W are Bernstein polynomials
    of one degree with coefficients e_i (vectors) and w_i > 0, so

        |E(s)| <= sum_i |e_i| B_i(s) <= max_i (|e_i| / w_i) sum_i w_i B_i(s)

    (triangle inequality, then the mediant inequality): |R - Q| = |E| / W <= max_i
    |e_i| / w_i, taken on each of 2^halvings equal panels (de Casteljau), which
    tightens it as Bernstein coefficients converge to the polynomial.  Degree n + m,
    where the squared certificate (:func:`morph.nearest.distance_bound_many`) works at
    2 (n + m); both are rigorous up to rounding (relative ~1e-15 of the
    coefficients; both curves are first translated by R's start point).  The
    elevation and the product, each followed by the panels, are one matrix product
    per coordinate for all rows at once.  inf where a weight coefficient is not
    positive."""
    c = np.asarray(c, float)
    q = np.asarray(q, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return _hull_rows(np.ascontiguousarray(c.transpose(2, 1, 0)),
                          np.ascontiguousarray(q.transpose(2, 1, 0)), halvings)


def _panel_moebius(sub, cub):
    """Per panel the factor c of the Möbius map mu(v) = c v / ((c - 1) v + 1) whose end
    derivatives (c at 0, 1 / c at 1) are in the ratio of |C'| / |R'| at the panel's
    two ends (the derivatives of the feet map there): c = 1 where a speed is zero;
    |log c| at most MOEBIUS_LOG.  ``sub`` (3, n+1, K), ``cub`` (2, 4, K):
    coordinate-major."""
    n = sub.shape[1] - 1
    w = sub[2]
    p = sub[:2] / w
    # (divisions by zero silenced by the caller, :func:`_panel_sets`)
    r0 = n * w[1] / w[0] * np.hypot(*(p[:, 1] - p[:, 0]))
    r1 = n * w[-2] / w[-1] * np.hypot(*(p[:, -1] - p[:, -2]))
    c0 = np.hypot(*(cub[:, 1] - cub[:, 0]))
    c1 = np.hypot(*(cub[:, -1] - cub[:, -2]))
    c = np.sqrt((c0 * r1) / (c1 * r0))
    fine = np.isfinite(c) & (c > 0)
    clipped = np.minimum(np.maximum(c, math.exp(-MOEBIUS_LOG)), math.exp(MOEBIUS_LOG))
    return np.where(fine, clipped, 1.0)


def _composed_bounds(groups, cubics, phis, size, cs, normal, tol):
    """Per pair the certificate on R o mu o phi: R with its weights scaled by c^i (the
    Möbius map), composed with phi (:func:`morph.bernstein.compose_many`, one call
    per degree of the pieces and of phi), bounded by
    :func:`morph.nearest.distance_bound_many`; pairs whose foot distance ``normal``
    already exceeds tol keep it (they fail without a composition)."""
    bound = normal.copy()
    for rows, stack in groups:
        n = stack.shape[1]
        near = normal[rows] <= tol
        for m in unique(size[rows[near]]).tolist():
            sel = np.nonzero(near & (size[rows] == m))[0]
            r = rows[sel]
            # R o mu: w_i c^i
            comp = stack.take(sel, axis=0) * (cs[r, None] ** np.arange(n))[:, :, None]
            if m > 2:
                comp = bz.compose_many(comp, phis[r, :m])
            bound[r] = nr.distance_bound_many(comp, cubics.take(r, axis=0), REFINE)[0]
    return bound


def _halved(groups, cubics, out, rows, feet, tol, depth):
    """Certify the pairs ``rows`` of ``out`` (a :class:`Certified`) again as halves:
    the cubic split exactly at s = 1/2 (de Casteljau), the sub-piece at the foot u of
    C(1/2) (pairs whose foot is an end are left), each half certified alone
    (:func:`certify_batch`, ``depth - 1``); the worse half's bound replaces the
    pair's where it is smaller (``out`` updated in place: ``half``, ``half_u``,
    ``sub``).  The feet of the parent's nodes (``feet``, (k, 24)) start every
    Newton search of the halves (:func:`_half_starts`): nothing is sampled again."""
    if not len(rows):
        return
    mids = np.matmul(bz.basis(3, [0.5]), cubics.take(rows, axis=0))   # (r, 1, 2)
    guess = _half_starts(feet.take(rows, axis=0))
    um = np.empty(len(rows))
    where = np.full(len(cubics), -1)
    where[rows] = np.arange(len(rows))
    halves = []
    for grp, stack in groups:
        sel = np.nonzero(where[grp] >= 0)[0]
        if len(sel):
            j = where[grp[sel]]
            jet = pc.jet2_power_many if stack.shape[1] <= 13 else pc.jet2_many
            part = stack.take(sel, axis=0)
            um[j] = nr.closest_params_many(part, mids.take(j, axis=0), guess[j, 24:25],
                                           REPARAM_ITERS, jet)[:, 0]
            halves.append((j, part))
    keep = np.nonzero((um > 0) & (um < 1))[0]                      # positions among rows
    if not len(keep):
        return
    renum = np.full(len(rows), -1)
    renum[keep] = np.arange(len(keep))
    left, right = bz.split_many(cubics.take(rows[keep], axis=0), np.full(len(keep), 0.5))
    sub_groups = []
    for j, stack in halves:
        ok = renum[j] >= 0
        if ok.any():
            lo, hi = bz.split_many(stack.compress(ok, axis=0), um[j[ok]])
            sub_groups += [(renum[j[ok]], lo), (len(keep) + renum[j[ok]], hi)]
    u, g = um[keep, None], guess[keep]
    start = np.concatenate([np.clip(g[:, :24] / u, 0.0, 1.0),
                            np.clip((g[:, 25:] - u) / (1.0 - u), 0.0, 1.0)])
    res = certify_batch(_merged(sub_groups), np.concatenate([left, right]), tol, depth - 1,
                        start=start)
    b = np.maximum(res.bound[:len(keep)], res.bound[len(keep):])
    won = np.nonzero(b < out.bound[rows[keep]])[0]
    i = rows[keep[won]]
    out.bound[i], out.half[i], out.half_u[i] = b[won], won, um[keep[won]]
    out.sub, out.sub_n = res, len(keep)


def _half_starts(feet):
    """The parent's feet (k, 24) at the nodes, read (linearly between the nodes, with
    0 at 0 and 1 at 1) at the parameters of the halves' nodes and at 1/2:
    (k, 49) = [left half's 24, at 1/2, right half's 24], in the parent piece's
    parameter (the caller maps them into each half's)."""
    s = np.concatenate([0.5 * _NODES, [0.5], 0.5 + 0.5 * _NODES])
    x = np.concatenate([[0.0], _NODES, [1.0]])
    u = np.concatenate([np.zeros((len(feet), 1)), feet, np.ones((len(feet), 1))], axis=1)
    j = np.clip(np.searchsorted(x, s, side="right") - 1, 0, len(x) - 2)
    w = (s - x[j]) / (x[j + 1] - x[j])
    return u[:, j] * (1.0 - w) + u[:, j + 1] * w


def _merged(groups):
    """[(rows, stack)] with one entry per degree (the rows of equal-degree entries
    concatenated)."""
    by = {}
    for rows, stack in groups:
        by.setdefault(stack.shape[1], []).append((rows, stack))
    return [(np.concatenate([r for r, _ in g]), np.concatenate([s for _, s in g]))
            for g in by.values()]
