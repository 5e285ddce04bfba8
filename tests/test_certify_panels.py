"""The certificate on the fitter's ray pairs (:func:`morph.export.certify._panel_bounds`,
:func:`morph.export.certify.hull_bound`) against independent computations: the
distance |R(phi(s)) - C(s)| on dense samples of every panel, R, C and phi by plain
Bernstein sums (tests/test_export.py), over random rational pieces of the degrees
brushes and strokes give (seeds fixed, not tuned on).  Each check is shown to fail on
a cubic displaced by twice the tolerance.
"""

import math

import numpy as np
import pytest

from morph import piece as pc
from morph.export import certify as certify_mod
from morph.export.bank import Bank
from morph.export.fit import Parts, _quadrature, moment_cubics
from tests.test_export import bernstein, rational, reparam_values


def random_piece(rng, degree):
    """A smooth rational piece of ``degree``: an ellipse arc of up to 1.2 radians
    degree-elevated, its homogeneous control points scaled by random factors in
    [0.8, 1.25] (the curve bends away from the conic) and its weights by c^i (a
    Möbius reparametrisation: uneven speed, the same curve)."""
    arc = pc.ellipse_arc(tuple(rng.uniform(-50, 50, 2)), rng.uniform(20, 200),
                         rng.uniform(20, 200), rng.uniform(0, math.pi),
                         rng.uniform(0, 2 * math.pi), rng.uniform(0.3, 1.2))[0]
    piece = pc.elevate(arc, degree - 2) * rng.uniform(0.8, 1.25, degree + 1)[:, None]
    return piece * (rng.uniform(0.7, 1.4) ** np.arange(degree + 1))[:, None]


def ray_fit(piece, tol):
    """The fitter's cubic for the whole piece as one range, and its rays."""
    bank = Bank([piece])
    parts = Parts(np.zeros(1, int), np.arange(1), np.zeros(1), np.ones(1))
    cubic, dist, fitted, rays = moment_cubics(bank, parts, bank.first[:1], bank.last[-1:],
                                              np.array([1e-12]), tol)
    assert fitted[0]
    return cubic[0], rays


def sampled(piece, cubic, panels, n=801):
    """max |R(phi(s)) - C(s)| over n samples of each panel (plain Bernstein sums)."""
    worst = 0.0
    for s0, s1, phi in panels:
        s = np.linspace(s0, s1, n)
        u = reparam_values(phi, (s - s0) / (s1 - s0))
        worst = max(worst, np.hypot(*(rational(piece)(u) - bernstein(cubic, s)).T).max())
    return worst


def paneled(piece, cubic, rays, tol):
    """certify_batch on the fitter's pairs, the ray panels taken for any degree."""
    pairs = (rays.feet, _quadrature().gx, rays.speed, rays.gap)
    return certify_mod.certify_batch([(np.array([0]), piece[None])], cubic[None], tol,
                                     pairs=pairs)


@pytest.mark.parametrize("seed", range(6))
def test_panel_bound_holds_on_dense_samples(seed, monkeypatch):
    """Degree 3 to 7 rational pieces of uneven speed: the ray panels' bound is never
    below the distance sampled densely on its own panels, and is close to it (the
    panels' certificate squares nothing, yet loses little); the cubic displaced by
    2 tol along its middle normal does not certify."""
    monkeypatch.setattr(certify_mod, "PANEL_DEGREE", 0)
    rng = np.random.default_rng(seed)
    used = 0
    for degree in (3, 4, 6, 7):
        piece = random_piece(rng, degree)
        tol = 0.5
        cubic, rays = ray_fit(piece, tol)
        res = paneled(piece, cubic, rays, tol)
        bound = res.bound[0]
        panels = res.panels(0)
        if res.other[0] < 0:               # certified on the ray panels
            used += 1
            assert len(panels) == 9
        worst = sampled(piece, cubic, panels)
        if res.other[0] < 0 or bound <= tol:   # (above tol the fallback may report a
            assert worst <= bound * (1 + 1e-9) + 1e-12     # sampled distance instead)
        # the ray panels alone, whatever their bound: a bound, and a close one
        b, cuts, moeb = certify_mod._panel_bounds([(np.array([0]), piece[None])],
                                                  cubic[None], rays.feet, _quadrature().gx)
        alone = certify_mod.Certified(b)
        alone.paneled, alone.cuts, alone.moebius = np.ones(1, bool), cuts, moeb
        step = certify_mod.PANEL_STEP
        alone.nodes = np.concatenate([[0.0], _quadrature().gx[step - 1::step], [1.0]])
        worst = sampled(piece, cubic, alone.panels(0))
        assert worst <= b[0] * (1 + 1e-9) + 1e-12
        assert b[0] <= 1.1 * worst + 1e-12
        if res.other[0] < 0:
            assert b[0] == bound
        # displaced by 2 tol along the middle normal: no certificate, either way
        tol = max(bound, 1e-9)
        mid = bernstein(cubic, [0.5])[0] - bernstein(cubic, [0.5 - 1e-6])[0]
        normal = np.array([-mid[1], mid[0]]) / np.hypot(*mid)
        moved = cubic.copy()
        moved[1:3] += 2.0 * tol * normal * 4.0 / 3.0
        assert paneled(piece, moved, rays, tol).bound[0] > tol
    assert used >= 2                       # the panels, not only the fallback, were tested


@pytest.mark.parametrize("seed", range(4))
def test_hull_bound_is_a_bound_and_tightens(seed):
    """hull_bound of random rational pieces (degree 2 to 7, weights 0.3 to 3) against
    random cubics near them: never below the same-parameter distance on dense
    samples, never looser after more halvings, within 10 % of the samples after 4."""
    rng = np.random.default_rng(100 + seed)
    for degree in range(2, 8):
        pts = rng.uniform(-1, 1, (degree + 1, 2))
        piece = pc.from_points(pts, rng.uniform(0.3, 3.0, degree + 1))
        s = np.linspace(0, 1, 4)
        cubic = rational(piece)(s) + rng.normal(0, 0.05, (4, 2))
        t = np.linspace(0, 1, 20001)
        dense = np.hypot(*(rational(piece)(t) - bernstein(cubic, t)).T).max()
        bounds = [certify_mod.hull_bound(piece[None], cubic[None], h)[0] for h in range(5)]
        assert all(b >= dense * (1 - 1e-12) for b in bounds)
        assert all(a >= b * (1 - 1e-12) for a, b in zip(bounds, bounds[1:]))
        assert bounds[-1] <= 1.1 * dense
        moved = cubic + np.array([0.0, 2.0 * bounds[-1]])
        assert certify_mod.hull_bound(piece[None], moved[None], 4)[0] > bounds[-1]
