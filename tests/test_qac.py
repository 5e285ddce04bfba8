"""QAC (Sec. 4.4, morph.qac) on 1000 random compatible pairs against stored references.

What is measured, and how (references in ``tests/reference.py``; none calls morph's
evaluation or root finding):

- the pairs: ``R.random_compatible_pair`` (seed SEED, all kinds; conic C2 by swapping
  the reference's pairs), stored in ``tests/data/qac_reference.npz``;
- Q2 of Eq. 38 from the reference's end derivatives (a 2x2 solve): morph's Q2 agrees;
- the exact QAC curve C1(t) + Q2(s(t)) at t in TS: s solved by the reference's
  Eq. 27 solver for the pair (C1, Q2) (``R.exact_convolution_points``); morph's
  piece passes through those points;
- the distance measure of Sec. 5.2 (Eqs. 49-53, ``R.distance_to_convolution``: the
  point minus C1(t), distance to the curve C2) of those points, and the distance
  from 26 points of Q2 to the curve C2 (``R.point_curve_distance``): both <= the
  a-priori bound ``qac_error_bound`` (Eqs. 39-40 after a reparametrisation of C2),
  which is within 10% of the second on the median;
- live (cheap): the parametric bound of Eqs. 39-40 >= the sampled max |C2(s) - Q2(s)|;
  a polynomial quadratic C2 gives error and bound < 1e-12; the result's tangent is
  C1's tangent at the same t (angle < 1e-9); degree 3d - 2 (polynomial C1), 5d - 4
  (rational).

The references take ~30 s of CPU (33000 bounded minimisations; 60-140 s on a loaded
machine), so they are stored (217 kB): regenerate with ``python -m tests.test_qac``
from the repository root (writes the file); ``test_stored_reference_is_reproducible``
(slow) recomputes them and compares.
"""

from pathlib import Path

import numpy as np
import pytest

from morph import piece as pc
from morph import qac

from tests.oracles import reference as R

SEED = 20240604
N_PAIRS = 1000
TS = np.linspace(0.0, 1.0, 7)
DATA = Path(__file__).resolve().parent / "data" / "qac_reference.npz"

# the reference's kinds are 'C1-C2'; conic C2 (rational, Eq. 40's weight bound) by swapping
SWAPPED = {"quad-conic": "conic-quad", "cubic-conic": "conic-cubic"}
KINDS = R.PAIR_KINDS + tuple(SWAPPED)


# ================================================================ the reference

def random_pairs(n=N_PAIRS, seed=SEED):
    """(kind, c1, c2) of n seeded random compatible pairs, every kind in turn."""
    rng = np.random.default_rng(seed)
    out = []
    for k in range(n):
        kind = KINDS[k % len(KINDS)]
        if kind in SWAPPED:            # a rational C2: the reference's pair, roles swapped
            c2, c1 = R.random_compatible_pair(rng, SWAPPED[kind])
        else:
            c1, c2 = R.random_compatible_pair(rng, kind)
        out.append((kind, c1, c2))
    return out


def reference_quadratic(c2):
    """Q2 of Eq. 38 from the reference's end points and end derivatives."""
    (p0, p1), (d0, d1) = R.bezier_eval(c2, [0.0, 1.0], 1)[:2]
    a, _ = np.linalg.solve(np.column_stack([d0, d1]), p1 - p0)   # p0 + a d0 = p1 - b d1
    return np.array([p0, p0 + a * d0, p1])


def reference_measures(c1, c2):
    """The stored reference of one pair: (q2, s at TS, max error of the exact QAC
    points, max distance from Q2 to the curve C2)."""
    q2 = reference_quadratic(c2)
    q2h = np.column_stack([q2, np.ones(3)])
    pts, s = R.exact_convolution_points(c1, q2h, TS)
    err = R.distance_to_convolution(pts, TS, c1, c2).max()
    q_pts = R.bezier_eval(q2h, np.linspace(0.0, 1.0, 201))[0]
    geo = R.point_curve_distance(q_pts[::8], c2, samples=513)[0].max()
    return q2, s, err, geo


def _padded(pieces):
    out = np.zeros((len(pieces), 4, 3))
    for k, p in enumerate(pieces):
        out[k, :len(p)] = p
    return out


def make_reference(n=N_PAIRS):
    """The reference as arrays (what ``tests/data/qac_reference.npz`` holds)."""
    pairs = random_pairs(n)
    meas = [reference_measures(c1, c2) for _, c1, c2 in pairs]
    return dict(kind=np.array([KINDS.index(k) for k, _, _ in pairs]),
                n1=np.array([len(c1) for _, c1, _ in pairs]),
                n2=np.array([len(c2) for _, _, c2 in pairs]),
                c1=_padded([c1 for _, c1, _ in pairs]), c2=_padded([c2 for _, _, c2 in pairs]),
                q2=np.array([m[0] for m in meas]), s=np.array([m[1] for m in meas]),
                err=np.array([m[2] for m in meas]), geo=np.array([m[3] for m in meas]))


def load_reference(path=DATA):
    with np.load(path) as f:
        return {k: f[k] for k in f.files}


# ====================================================================== fixture

def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _run(ref, k):
    """morph's QAC of stored pair k, measured against the stored reference."""
    c1, c2 = ref["c1"][k, :ref["n1"][k]], ref["c2"][k, :ref["n2"][k]]
    q2 = qac.quadratic_approximation(c2)
    bound, _ = qac.qac_error_bound(c2, q2)
    pbound, _ = qac.qac_parametric_bound(c2, q2)
    res = qac.convolve_qac_piece(c1, c2)
    pts, d_res = R.bezier_eval(res, TS, 1)
    q2h = np.column_stack([ref["q2"][k], np.ones(3)])
    exact = R.bezier_eval(c1, TS)[0] + R.bezier_eval(q2h, ref["s"][k])[0]
    s = np.linspace(0.0, 1.0, 201)
    q_pts = R.bezier_eval(np.column_stack([q2, np.ones(3)]), s)[0]
    d_c1 = R.bezier_eval(c1, TS, 1)[1]
    return dict(
        kind=KINDS[ref["kind"][k]], c1=c1, c2=c2, bound=bound, pbound=pbound,
        q2_dev=float(np.abs(q2 - ref["q2"][k]).max()),
        # the stored error of the exact QAC points, plus how far morph's points are
        dev=float(np.hypot(*(pts - exact).T).max()),
        err=float(ref["err"][k] + np.hypot(*(pts - exact).T).max()),
        geo=float(ref["geo"][k]), size=float(np.abs(pc.cartesian(c2)).max()),
        param_err=float(np.hypot(*(R.bezier_eval(c2, s)[0] - q_pts).T).max()),
        normal=float(np.arctan2(np.abs(_cross(d_res, d_c1)), np.sum(d_res * d_c1, axis=1)).max()),
        degree=len(res) - 1, weights_positive=bool(np.all(res[:, 2] > 0)))


@pytest.fixture(scope="module")
def qac_runs():
    ref = load_reference()
    return [_run(ref, k) for k in range(len(ref["kind"]))]


def _failures(runs, bad):
    hits = [(k, r["kind"]) for k, r in enumerate(runs) if bad(r)]
    return "%d of %d: %s" % (len(hits), len(runs), hits[:8])


# ======================================================================= tests

def test_qac_pairs_cover_every_kind(qac_runs):
    assert {r["kind"] for r in qac_runs} == set(KINDS)
    assert len(qac_runs) >= 1000


def test_quadratic_and_piece_match_the_reference(qac_runs):
    """Q2 is the reference's tangent intersection, and the QAC piece passes through
    the reference's exact C1 * Q2 points (so the stored errors describe it)."""
    bad = lambda r: not (r["q2_dev"] <= 1e-9 * max(r["size"], 1.0)
                         and r["dev"] <= 1e-9 * max(r["size"], 1.0))
    assert not any(map(bad, qac_runs)), _failures(qac_runs, bad)


def test_qac_error_within_a_priori_bound(qac_runs):
    bad = lambda r: not r["err"] <= r["bound"] + 1e-12
    assert not any(map(bad, qac_runs)), _failures(qac_runs, bad)


def test_qac_parametric_bound_bounds_parametric_distance(qac_runs):
    # Eqs. 39-40 bound max_s |C2(s) - Q2(s)| by the convex hull property
    bad = lambda r: not r["param_err"] <= r["pbound"] * (1 + 1e-9) + 1e-13
    assert not any(map(bad, qac_runs)), _failures(qac_runs, bad)
    # and it is not vacuous: within a factor 3 of the sampled maximum, times
    # max W / min W for a rational C2 (Eq. 40 divides by the smallest weight coefficient)
    def loose(r):
        w = r["c2"][:, 2]
        return r["pbound"] > 3.0 * (w.max() / w.min()) * r["param_err"] + 1e-12
    assert not any(map(loose, qac_runs)), _failures(qac_runs, loose)


def test_qac_bound_bounds_geometric_distance(qac_runs):
    """qac_error_bound >= max over Q2 of the distance to the curve C2 (what the
    convolution's distance measure sees), <= the parametric bound, and tight: within
    a factor 4 of the sampled distance on every pair, within 10% on the median."""
    bad = lambda r: not (r["geo"] <= r["bound"] * (1 + 1e-9) + r["q2_dev"] + 1e-13
                         and r["bound"] <= r["pbound"])
    assert not any(map(bad, qac_runs)), _failures(qac_runs, bad)
    loose = lambda r: r["bound"] > 4.0 * r["geo"] + 1e-12
    assert not any(map(loose, qac_runs)), _failures(qac_runs, loose)
    ratios = [r["bound"] / r["geo"] for r in qac_runs if r["geo"] > 1e-12]
    assert len(ratios) >= 500 and np.median(ratios) < 1.1, np.median(ratios)


def test_qac_exact_for_polynomial_quadratic_c2(qac_runs):
    quad = [r for r in qac_runs if r["kind"].endswith("-quad")]
    assert len(quad) >= 400
    bad = lambda r: not (r["err"] < 1e-12 and r["bound"] < 1e-12)
    assert not any(map(bad, quad)), _failures(quad, bad)


def test_qac_normals_are_exact(qac_runs):
    bad = lambda r: not r["normal"] < 1e-9
    assert not any(map(bad, qac_runs)), _failures(qac_runs, bad)


def test_qac_degree(qac_runs):
    def expect(r):
        d = len(r["c1"]) - 1
        return 3 * d - 2 if r["kind"].startswith(("quad", "cubic")) else 5 * d - 4
    bad = lambda r: r["degree"] != expect(r) or not r["weights_positive"]
    assert not any(map(bad, qac_runs)), _failures(qac_runs, bad)
    degrees = {r["kind"].split("-")[0]: r["degree"] for r in qac_runs}
    assert degrees == {"quad": 4, "cubic": 7, "conic": 6}


@pytest.mark.slow
def test_stored_reference_is_reproducible():
    """The stored reference is what ``make_reference`` computes today (~30 s CPU):
    the same pairs bit for bit, the measures to 1e-9 (the reference's solvers)."""
    stored, fresh = load_reference(), make_reference()
    for key in ("kind", "n1", "n2", "c1", "c2"):
        assert np.array_equal(stored[key], fresh[key]), key
    for key in ("q2", "s", "err", "geo"):
        assert np.allclose(stored[key], fresh[key], rtol=1e-9, atol=1e-12), key


# ================================================================ small cases

def test_choose_roles_prefers_exact_quadratic():
    rng = np.random.default_rng(SEED + 1)
    for _ in range(50):
        cubic, quad = R.random_compatible_pair(rng, "cubic-quad")
        swap, q2 = qac.choose_roles(cubic, quad)
        assert not swap and np.allclose(q2, pc.cartesian(quad), atol=1e-12)
        swap, q2 = qac.choose_roles(quad, cubic)
        assert swap and np.allclose(q2, pc.cartesian(quad), atol=1e-12)


def test_quadratic_approximation_is_tangent_intersection():
    c = pc.cubic((0.0, 0.0), (1.0, 0.0), (3.0, 1.0), (3.0, 3.0))
    q = qac.quadratic_approximation(c)
    assert np.allclose(q, [[0.0, 0.0], [3.0, 0.0], [3.0, 3.0]], atol=1e-14)
    with pytest.raises(ValueError):
        qac.quadratic_approximation(pc.cubic((0, 0), (1, 0), (2, 0), (3, 0)))
    q2, ok = qac.quadratic_approximation_many(pc.cubic((0, 0), (1, 0), (2, 0), (3, 0))[None])
    assert not ok[0]


def _by_shape(pieces):
    groups = {}
    for k, p in enumerate(pieces):
        groups.setdefault((p.shape, pc.is_polynomial(p)), []).append(k)
    return groups.values()


def test_stacks_match_rows_alone():
    """Q2, both bounds and the QAC piece of a stack of pairs agree row by row with
    the same functions on a stack of one (no mixing between rows)."""
    pairs = random_pairs(240, SEED + 1)
    c1s, c2s = [p[1] for p in pairs], [p[2] for p in pairs]
    for ks in _by_shape(c2s):
        c2 = np.array([c2s[k] for k in ks])
        q2, ok = qac.quadratic_approximation_many(c2)
        assert ok.all()
        par, _ = qac.qac_parametric_bound_many(c2, q2)
        geo, _ = qac.qac_error_bound_many(c2, q2)
        for r, k in enumerate(ks):
            q_ref = qac.quadratic_approximation(c2s[k])
            assert np.allclose(q2[r], q_ref, atol=1e-12)
            assert par[r] == pytest.approx(qac.qac_parametric_bound(c2s[k], q_ref)[0],
                                           rel=1e-9, abs=1e-15)
            assert geo[r] == pytest.approx(qac.qac_error_bound(c2s[k], q_ref)[0],
                                           rel=1e-7, abs=1e-15)
    for ks in _by_shape(c1s):
        c1 = np.array([c1s[k] for k in ks])
        q2 = np.array([qac.quadratic_approximation(c2s[k]) for k in ks])
        res = qac._qac_from_numerator(c1, pc.tangent_numerator_many(c1, not pc.is_polynomial(c1[0])),
                                       q2)
        for r, k in enumerate(ks):
            ref = qac.convolve_qac_piece(c1s[k], c2s[k], q2[r])
            assert res[r].shape == ref.shape
            # same rational curve: same Cartesian control points and weight ratios
            assert np.allclose(pc.cartesian(res[r]), pc.cartesian(ref), atol=1e-9)
            assert np.allclose(res[r][:, 2] / res[r][0, 2], ref[:, 2] / ref[0, 2], rtol=1e-9)


if __name__ == "__main__":
    # regenerate tests/data/qac_reference.npz: python -m tests.test_qac (~30 s CPU)
    DATA.parent.mkdir(exist_ok=True)
    np.savez_compressed(DATA, **make_reference())
    print("wrote", DATA, DATA.stat().st_size, "bytes")
