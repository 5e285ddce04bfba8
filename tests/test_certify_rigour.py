"""Every path of the certificate on the fitter's rays (:func:`morph.export.certify.certify_batch`
given the pairs: the same-parameter one, the ray panels, the composed-map fallback)
against measurements it does not share any code with: plain Bernstein sums of the
piece R and the cubic C, sampled densely.

- **Hausdorff**: each curve sampled at 4001 parameters, the largest distance from a
  sample of one to the samples of the other, less half the largest gap between
  consecutive samples of the other (so a lower estimate of the Hausdorff distance,
  which the Fréchet distance, and so the certificate, can never be below);
- **Fréchet**: |R(phi(s)) - C(s)| at 801 parameters of every panel of the map phi the
  certificate states (:meth:`Certified.panels`), the quantity the bound bounds.

The pieces are random (seeds fixed, not tuned on): elevated, bent, unevenly
parametrised ellipse arcs of the degrees strokes and brushes give (2, 3, 6, 7), and
near-polynomial ones whose fit keeps the parameter (the same-parameter path).  The
cubics are the fitter's own (:func:`morph.export.fit.moment_cubics`) with its rays.
A cubic displaced by 2 tol must not certify, and a certificate loosened by 3 % (the
bound scaled by 0.97) is caught by these measurements: the oracle can fail.
"""

import math

import numpy as np
import pytest
from scipy.spatial import cKDTree

from morph import piece as pc
from morph.export import certify as certify_mod
from morph.export.fit import _quadrature
from tests.test_certify_panels import random_piece, ray_fit, sampled
from tests.test_export import bernstein, rational

TOL = 0.5


def near_polynomial_piece(rng, degree):
    """A random arch-shaped polynomial cubic (chord 100) elevated to ``degree``, its
    weights 1 +- 0.1 %: the fitter's cubic follows it at nearly the same parameter
    (the same-parameter path)."""
    cub = np.array([[0.0, 0.0], [rng.uniform(20, 40), rng.uniform(20, 60)],
                    [rng.uniform(60, 80), rng.uniform(20, 60)], [100.0, 0.0]])
    piece = pc.elevate(np.concatenate([cub, np.ones((4, 1))], axis=1), degree - 3)
    return piece * rng.uniform(0.999, 1.001, degree + 1)[:, None]


def hausdorff_lower(a, b):
    """A lower estimate of the Hausdorff distance between two curves sampled densely
    in order (``a`` (n, 2), ``b`` (m, 2)): each directed distance to the samples of
    the other, less half the other's largest sample gap."""
    def directed(p, q):
        near = cKDTree(q).query(p)[0]
        return near.max() - 0.5 * np.hypot(*np.diff(q, axis=0).T).max()
    return max(directed(a, b), directed(b, a), 0.0)


def certified(piece, cubic, rays, tol=TOL):
    """certify_batch of one (piece, cubic) pair given the fitter's rays."""
    pairs = (rays.feet, _quadrature().gx, rays.speed, rays.gap)
    return certify_mod.certify_batch([(np.array([0]), piece[None])], cubic[None], tol,
                                     pairs=pairs)


def cases(seed):
    """(piece, cubic, rays) of random pieces of every kind, the fitter's cubics."""
    rng = np.random.default_rng(seed)
    out = []
    for degree in (2, 3, 6, 7):
        for make in (random_piece, near_polynomial_piece):
            if make is near_polynomial_piece and degree < 3:
                continue
            piece = make(rng, degree)
            cubic, rays = ray_fit(piece, TOL)
            out.append((piece, cubic, rays))
    return out


def path_of(res, rays, tol=TOL):
    """Which path certified pair 0: "same", "panels" or "fallback"."""
    if res.other[0] >= 0 or res.half[0] >= 0:
        return "fallback"
    with np.errstate(invalid="ignore"):
        miss = (np.abs(rays.feet - _quadrature().gx) * rays.speed).max()
    return "same" if miss <= certify_mod.PHI_SHARE * tol else "panels"


def check(piece, cubic, res, scale=1.0):
    """(bound, Hausdorff lower estimate, Fréchet on the stated map) of pair 0, the
    bound scaled by ``scale``; asserts nothing."""
    bound = scale * float(res.bound[0])
    t = np.linspace(0.0, 1.0, 4001)
    haus = hausdorff_lower(rational(piece)(t), bernstein(cubic, t))
    return bound, haus, sampled(piece, cubic, res.panels(0))


@pytest.mark.parametrize("seed", range(5))
def test_certificate_is_above_dense_hausdorff_and_frechet(seed):
    """Every pair the certificate passes is within its bound of the piece, measured
    both ways; the same-parameter and ray-panel paths are both exercised."""
    seen = set()
    for piece, cubic, rays in cases(seed):
        res = certified(piece, cubic, rays)
        bound, haus, frechet = check(piece, cubic, res)
        seen.add(path_of(res, rays))
        assert haus <= frechet * (1 + 1e-9) + 1e-9
        assert frechet <= bound * (1 + 1e-9) + 1e-12, (path_of(res, rays), frechet, bound)
        if res.bound[0] <= TOL:
            assert haus <= TOL
    assert {"same", "panels"} <= seen


@pytest.mark.parametrize("seed", range(3))
def test_composed_fallback_is_above_dense_frechet(seed, monkeypatch):
    """The composed-map path (taken where the ray panels do not certify), forced on
    every pair: the same measurements hold."""
    monkeypatch.setattr(certify_mod, "PANEL_RAYS", False)
    for piece, cubic, rays in cases(seed):
        res = certified(piece, cubic, rays)
        bound, haus, frechet = check(piece, cubic, res)
        assert frechet <= bound * (1 + 1e-9) + 1e-12
        assert haus <= frechet * (1 + 1e-9) + 1e-9


def displaced(cubic, d):
    """The cubic with its inner control points moved by 4/3 d along its normal at
    s = 1/2: its middle point moves by d."""
    tangent = bernstein(cubic, [0.5])[0] - bernstein(cubic, [0.5 - 1e-6])[0]
    normal = np.array([-tangent[1], tangent[0]]) / math.hypot(*tangent)
    moved = cubic.copy()
    moved[1:3] += d * normal * 4.0 / 3.0
    return moved


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("where", ["middle", "whole"])
def test_cubic_displaced_by_twice_tol_is_rejected(seed, where, monkeypatch):
    """A certified cubic moved by 2 tol (its middle along the normal, or the whole
    cubic, ends included) is measured farther than tol from the piece, and no path
    certifies it, the fitter's rays of the unmoved cubic given (stale pairs still
    give a rigorous bound)."""
    for panel in (True, False):
        monkeypatch.setattr(certify_mod, "PANEL_RAYS", panel)
        for piece, cubic, rays in cases(seed):
            if not certified(piece, cubic, rays).bound[0] <= TOL:
                continue
            if where == "middle":
                moved = displaced(cubic, 2.0 * TOL)
            else:
                moved = cubic + 2.0 * TOL * np.array([0.6, 0.8])
            t = np.linspace(0.0, 1.0, 4001)
            haus = hausdorff_lower(rational(piece)(t), bernstein(moved, t))
            if haus <= TOL:              # not measurably farther than tol: no test
                continue
            assert certified(piece, moved, rays).bound[0] > TOL


def test_a_loosened_certificate_is_caught():
    """The measurements can fail: certificates scaled by 0.97 fall below the Fréchet
    samples on some pair of these cases (every fitted cubic has its error where the
    certificate is tight)."""
    caught = 0
    for piece, cubic, rays in cases(0):
        res = certified(piece, cubic, rays)
        bound, haus, frechet = check(piece, cubic, res, scale=0.97)
        caught += frechet > bound * (1 + 1e-9) + 1e-12
    assert caught >= 1


@pytest.mark.parametrize("seed", range(2))
def test_panels_cut_at_every_ray_are_above_dense_frechet(seed):
    """The retry of pairs whose first panels fail (panels cut at every ray, each
    Möbius map from its end speeds), taken on every pair: the same measurements."""
    for piece, cubic, rays in cases(seed):
        pairs = (rays.feet, _quadrature().gx, rays.speed, rays.gap)
        res = certify_mod._ray_certified([(np.array([0]), piece[None])], cubic[None], TOL,
                                         3, pairs, step=1)
        bound, haus, frechet = check(piece, cubic, res)
        if res.other[0] < 0:
            assert len(res.panels(0)) == 17
        assert frechet <= bound * (1 + 1e-9) + 1e-12
        assert haus <= frechet * (1 + 1e-9) + 1e-9


def test_screened_panels_give_the_bound_of_refining_every_panel(monkeypatch):
    """The branch and bound over panels (all degrees screened together, lifted, then
    only panels that can raise a maximum refined) gives, pair by pair, the bound of
    refining every panel at its own degree, whatever else is in the batch: one
    batch of all cases (degrees 2 to 7) against each pair alone with nothing
    screened."""
    every = [c for seed in range(2) for c in cases(seed)]
    groups = certify_mod.degree_groups([p for p, _, _ in every])
    feet = np.concatenate([r.feet for _, _, r in every])
    cubics = np.array([c for _, c, _ in every])
    batch = certify_mod._panel_bounds(groups, cubics, feet, _quadrature().gx)[0]
    real = certify_mod._hull_rows

    def unscreened(c, q, halvings, ends=False):
        out = real(c, q, halvings, ends)
        if ends:                       # every panel above its ends: all refined
            out[0][:] = np.inf
        return out

    monkeypatch.setattr(certify_mod, "_hull_rows", unscreened)
    for i, (piece, cubic, rays) in enumerate(every):
        alone = certify_mod._panel_bounds([(np.array([0]), piece[None])], cubic[None],
                                          rays.feet, _quadrature().gx)[0][0]
        assert batch[i] == pytest.approx(alone, rel=1e-12, abs=1e-15)
