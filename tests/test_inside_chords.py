"""The convolution pieces a sum trims as their chords (:func:`morph.minkowski._inside_chords`):
the concave corners of one operand paired with arcs of the other, convex, operand.

Checked against the exact membership predicate x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅
(tests/oracles/membership.py): every point between such a piece and its chord is in
the sum, and the sums trimmed with the chords pass the oracle's boundary and
membership tests as those trimmed with the pieces do.  Taking the chords of the
convex corners too (round joins, on the boundary) is seen."""

import numpy as np
import pytest

shapely = pytest.importorskip("shapely")
import shapely.affinity  # noqa: E402 - after the importorskip above
from shapely.geometry import LineString, Polygon  # noqa: E402 - after the importorskip above

from morph import minkowski as mk
from morph import piece as pc
from morph.convolve import convolution, gauss_pair_of, with_pair_table
from morph.fonts.brush import ellipse_nib
from morph.stroke import path_loop
from tests.helpers import polygon_region
from tests.oracles import reference as R
from tests.oracles.membership import (Oracle, boundary_samples, inside, sharp_junctions,
                                      straddle_sides)


def _skeleton(rng):
    """A random open polyline (a stroke's centre line: sharp and slight turns,
    both ways) as the degenerate loop of a path traced forward and back, and as a
    shapely line."""
    n = int(rng.integers(4, 9))
    pts = np.cumsum(rng.normal(0, 30, (n, 2)), axis=0)
    return [path_loop([pc.line(pts[k], pts[k + 1]) for k in range(n - 1)])], LineString(pts)


def _star(rng):
    """A random star-shaped polygon, counter-clockwise: concave corners."""
    n = int(rng.integers(5, 10))
    ang = np.sort(rng.uniform(0, 2 * np.pi, n))
    r = rng.uniform(20, 60, n)
    pts = np.column_stack([r * np.cos(ang), r * np.sin(ang)])
    return polygon_region(pts), Polygon(pts)


def _nib(rng):
    """A convex nib: an ellipse at a random angle, or a convex polygon."""
    if rng.random() < 0.7:
        return ellipse_nib(rng.uniform(10, 40), rng.uniform(3, 12), rng.uniform(0, 180))
    ang = np.sort(rng.uniform(0, 2 * np.pi, int(rng.integers(3, 8))))
    return polygon_region(rng.uniform(5, 15) * np.column_stack([np.cos(ang), np.sin(ang)]))


class _Oracle(Oracle):
    """x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅ with A a shapely geometry (a skeleton's line)."""

    def __init__(self, shape, b, flat):
        self.pa = shape
        shapely.prepare(self.pa)
        self.neg_b = shapely.affinity.scale(R.region_to_shapely(b, flat), -1, -1,
                                            origin=(0, 0))


def _cases(n, seed):
    """(A, B, the oracle of A ⊕ B): skeletons and stars with convex nibs."""
    rng = np.random.default_rng(seed)
    for k in range(n):
        a, shape = _skeleton(rng) if k % 3 else _star(rng)
        b = _nib(rng)
        yield a, b, _Oracle(shape, b, 1e-3)


def _check(loops, oracle, tol, rng):
    """The checks of :func:`tests.oracles.membership.check_loops` with ``oracle``:
    every sampled boundary point (and sharp junction) within tol of a point of the
    sum and of one outside it; membership at 60 random points."""
    pts, nrm = boundary_samples(loops)
    sharp = sharp_junctions(loops)
    pts, nrm = np.concatenate([pts, sharp]), np.concatenate([nrm, np.zeros_like(sharp)])
    has_in, has_out = straddle_sides(oracle, pts, nrm, tol)
    assert has_in.all(), "boundary point farther than tol outside"
    assert has_out.all(), "boundary point farther than tol inside"
    lo = np.min([pc.bbox(p)[:2] for lp in loops for p in lp], axis=0) - 20
    hi = np.max([pc.bbox(p)[2:] for lp in loops for p in lp], axis=0) + 20
    x = rng.uniform(lo, hi, size=(60, 2))
    assert np.array_equal(inside(loops, x), oracle(x))


def _marked(a, b, tol, inside=mk._inside_chords):
    gp = with_pair_table(gauss_pair_of(a, b))
    conv = convolution(a, b, tol, keep_type3=True, gauss_pair=gp)
    return conv, inside(gp)(conv)


def test_the_space_between_a_piece_and_its_chord_is_in_the_sum():
    """At 9 points of each piece taken as its chord, the piece, the chord and the
    points half way between are in the sum (the exact predicate); and such pieces
    occur in every case with a concave corner (skeletons and stars alike)."""
    total = 0
    for a, b, oracle in _cases(12, 3):
        conv, mask = _marked(a, b, 0.05)
        assert mask.any()
        t = np.linspace(0, 1, 9)
        for k in np.flatnonzero(mask):
            h = np.asarray(conv.pieces[k], float)
            on = pc.evaluate(h, t)
            c0, c1 = h[0, :2] / h[0, 2], h[-1, :2] / h[-1, 2]
            chord = c0 + t[:, None] * (c1 - c0)
            x = np.concatenate([on, chord, 0.5 * (on + chord)])
            assert oracle(x).all(), (k, x[~oracle(x)])
        total += int(mask.sum())
    assert total > 50


def _with_convex_corners(gp):
    """An unconservative variant: the convex corners' arcs too (on the boundary)."""
    ta, tb = gp.edge_tables()
    i_of, j_of = gp.table[0], gp.table[1]

    def inside(conv):
        i, j = i_of[conv.row], j_of[conv.row]
        return (ta.vertex[i] & ~tb.vertex[j]) | (tb.vertex[j] & ~ta.vertex[i])

    return inside


@pytest.mark.parametrize("seed", range(3))
def test_sums_with_chords_pass_the_oracle_and_the_convex_corners_would_not(seed, monkeypatch):
    """Sums of random skeletons and stars with convex nibs, trimmed with the chords,
    pass the exact oracle within tol (boundary points straddle the true boundary
    within tol; membership at random points) and fill as those trimmed without
    them at points 2 tol from both; taking the convex corners' arcs as chords
    (round joins cut flat, far more than tol) fails the same oracle."""
    from tests.trim.test_flatten import _membership

    rng = np.random.default_rng(100 + seed)
    tol = 0.05
    failed = 0
    for a, b, oracle in _cases(4, 200 + seed):
        got = mk.minkowski_sum(a, b, tol)
        _check(got, oracle, tol, rng)
        with monkeypatch.context() as m:
            m.setattr(mk, "_inside_chords", lambda gp: (lambda conv: np.zeros(len(conv), bool)))
            want = mk.minkowski_sum(a, b, tol)
        lo = np.min([pc.bbox(p)[:2] for lp in want for p in lp], axis=0)
        hi = np.max([pc.bbox(p)[2:] for lp in want for p in lp], axis=0)
        x = rng.uniform(lo, hi, (4000, 2))
        in_got, far_got = _membership(x, got, "nonzero", 0.1 * tol, 2 * tol)
        in_want, far_want = _membership(x, want, "nonzero", 0.1 * tol, 2 * tol)
        far = far_got & far_want
        assert far.sum() > 2000 and np.array_equal(in_got[far], in_want[far])
        with monkeypatch.context() as m:
            m.setattr(mk, "_inside_chords", _with_convex_corners)
            bad = mk.minkowski_sum(a, b, tol)
        try:
            _check(bad, oracle, tol, rng)
        except AssertionError:
            failed += 1
    assert failed >= 3


def _without_convexity(gp):
    """An unconservative variant: every concave corner's piece, whether the other
    operand is convex or not."""
    ta, tb = gp.edge_tables()
    i_of, j_of = gp.table[0], gp.table[1]

    def inside(conv):
        i, j = i_of[conv.row], j_of[conv.row]
        return (conv.type == 3) & ((ta.vertex[i] & (ta.sign[i] < 0))
                                   | (tb.vertex[j] & (tb.sign[j] < 0)))

    return inside


def test_the_arcs_operand_must_be_convex():
    """Sums of two random stars: the concave corners' pieces are taken as chords
    only where the other operand is convex, and there the chords lie in the sum;
    taking them whatever the other operand, some chords leave the sum (the exact
    predicate sees it)."""
    rng = np.random.default_rng(1)
    t = np.linspace(0, 1, 9)
    out = {True: 0, False: 0}
    for _ in range(30):
        (a, sa), (b, _) = _star(rng), _star(rng)
        oracle = _Oracle(sa, b, 1e-3)
        for inside_of in (mk._inside_chords, _without_convexity):
            conv, mask = _marked(a, b, 0.05, inside_of)
            for k in np.flatnonzero(mask):
                h = np.asarray(conv.pieces[k], float)
                c0, c1 = h[0, :2] / h[0, 2], h[-1, :2] / h[-1, 2]
                out[inside_of is mk._inside_chords] += int(
                    not oracle(c0 + t[:, None] * (c1 - c0)).all())
    assert out[True] == 0 and out[False] > 0
