"""Error and size measures for bench/peers.py that do not trust a coarse polygon.

Nothing here calls ``morph.trim`` (or any of the project's geometry beyond
``morph.polyline.flatten``, used by ``tests.oracles.reference`` to flatten the *inputs*).  Curve
points, tangents and curvature come from ``tests.oracles.reference.bezier_eval`` (explicit
Bernstein sums).

certified_error(samples, oracle)
    Straddle test with the exact membership predicate x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅
    (shapely, operands flattened within ``flat``).  For each boundary sample p with
    outward normal n: if p is in the sum, the smallest e of a geometric ladder with
    p + e n out of the sum; if p is out, the smallest e with p − e n in.  The segment
    then crosses the boundary of the flattened sum, so the distance from p to the
    exact boundary is <= e + 2 flat (each flattened operand is within ``flat`` of the
    exact one).  ``e`` is found by bisection on the ladder index (ratio 10**(1/8)), so
    the bound is certified (up to the sampling of p) and at most ~1.33x loose above
    the resolution 2 flat.  The true error can be anywhere below the bound.

chord_lower_bound(loops, e)
    Fewest vertices of any polygon whose edges stay within e of a curve: an edge can
    deviate by +-e, i.e. sagitta 2e, so it spans at most sqrt(16 e / k) of arc where the
    curvature is k: N >= integral sqrt(k / (16 e)) ds (plus 3 per loop at least).  The
    sqrt(k / (8 e)) integral is the count of a polygon with its vertices on the curve
    (what flatten-then-Clipper produces); both are given.

powerlaw(xs, ns)
    Least-squares fit log n = log c - p log e on measured (error, vertices) pairs.
"""

import numpy as np

from tests.oracles import need

shapely = need("shapely", "the certified error measure")
import shapely.affinity  # noqa: E402 - after the check above

from tests.oracles import reference as R  # noqa: E402

LADDER_RATIO = 10 ** (1 / 8)


# --------------------------------------------------------------------- sampling

def sample_pieces(loops, per_piece=16):
    """Points and outward unit normals (right of travel) on every piece of ``loops``.

    Parameters t = (i + 0.5) / per_piece; pieces with a vanishing derivative at a
    sample are sampled where it does not vanish (those samples are dropped)."""
    pts, nrm = [], []
    t = (np.arange(per_piece) + 0.5) / per_piece
    for loop in loops:
        for p in loop:
            c, d = R.bezier_eval(p, t, 1)
            ln = np.hypot(d[:, 0], d[:, 1])
            ok = ln > 1e-12 * max(1.0, float(np.abs(c).max()))
            pts.append(c[ok])
            nrm.append(np.column_stack([d[ok, 1], -d[ok, 0]]) / ln[ok, None])
    return np.concatenate(pts), np.concatenate(nrm)


def sample_polygon(geom, max_samples=4000, rng=None):
    """Edge midpoints and outward normals of a shapely (Multi)Polygon's rings.

    Exterior rings are made counter-clockwise and holes clockwise, so the right of
    travel is outward.  Edge midpoints are where a chord polygon is farthest from the
    curve it approximates.  When there are more than ``max_samples`` edges, a random
    subset (fixed seed) of that many is returned, plus the ``count`` of edges."""
    pts, nrm = [], []
    for poly in R._polygons(shapely.geometry.polygon.orient(geom, 1.0)
                            if geom.geom_type == "Polygon" else geom):
        poly = shapely.geometry.polygon.orient(poly, 1.0)
        for ring in [poly.exterior] + list(poly.interiors):
            xy = np.asarray(ring.coords)[:-1]
            a, b = xy, np.roll(xy, -1, axis=0)
            d = b - a
            ln = np.hypot(d[:, 0], d[:, 1])
            ok = ln > 0
            pts.append(((a + b) / 2)[ok])
            nrm.append(np.column_stack([d[ok, 1], -d[ok, 0]]) / ln[ok, None])
    pts, nrm = np.concatenate(pts), np.concatenate(nrm)
    if len(pts) > max_samples:
        rng = rng or np.random.default_rng(0)
        pick = rng.choice(len(pts), max_samples, replace=False)
        pts, nrm = pts[pick], nrm[pick]
    return pts, nrm


# ----------------------------------------------------------------------- oracle

class Oracle:
    """x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅, on A and B flattened within ``flat``.

    By symmetry (x ∈ A ⊕ B ⇔ B ∩ (x − A) ≠ ∅) the operand with fewer vertices is the
    one translated; translations are vectorised with ``shapely.transform``."""

    def __init__(self, a, b, flat):
        pa = R.region_to_shapely(a, flat)
        pb = R.region_to_shapely(b, flat)
        if shapely.get_num_coordinates(pa) < shapely.get_num_coordinates(pb):
            pa, pb = pb, pa
        self.flat = flat
        self.fixed = pa
        shapely.prepare(self.fixed)
        self.neg = shapely.affinity.scale(pb, -1, -1, origin=(0, 0))
        self.m = int(shapely.get_num_coordinates(self.neg))

    def __call__(self, points, chunk=400):
        points = np.asarray(points, float)
        out = np.empty(len(points), bool)
        for s in range(0, len(points), chunk):
            p = points[s:s + chunk]
            geoms = np.array([self.neg] * len(p), dtype=object)
            off = np.repeat(p, self.m, axis=0)
            moved = shapely.transform(geoms, lambda c, off=off: c + off)
            out[s:s + chunk] = shapely.intersects(self.fixed, moved)
        return out


def certified_error(points, normals, oracle, e_min, e_max, ring=8):
    """Per-sample certified bound on the distance to the exact boundary (see module doc).

    Walks up the ladder e_min * 1.33**k <= e_max.  A sample is settled at the first
    level where its probe p + e n (p in the sum) or p - e n (p out) has the other
    status.  Samples never settled that way (near a concave corner of the sum the
    normal ray can miss the boundary) walk the ladder again with ``ring`` probes on the
    circle of radius e around p: any probe with the other status puts a boundary point
    within e of p.  Returns e + 2 flat per sample, ``inf``
    where nothing straddles up to e_max."""
    k = int(np.ceil(np.log(e_max / e_min) / np.log(LADDER_RATIO)))
    ladder = e_min * LADDER_RATIO ** np.arange(k + 1)
    inside = oracle(points)
    sign = np.where(inside, 1.0, -1.0)  # in: push out along +n; out: push in along -n
    ang = np.linspace(0, 2 * np.pi, ring, endpoint=False)
    circle = np.column_stack([np.cos(ang), np.sin(ang)])
    out = np.full(len(points), np.inf)

    def scan(act, use_ring):
        for e in ladder:
            if not len(act):
                return
            if use_ring:
                q = (points[act][:, None, :] + e * circle[None]).reshape(-1, 2)
                done = (oracle(q).reshape(len(act), ring) != inside[act][:, None]).any(axis=1)
            else:
                q = points[act] + (sign[act] * e)[:, None] * normals[act]
                done = oracle(q) != inside[act]
            out[act[done]] = e + 2 * oracle.flat
            act = act[~done]

    scan(np.arange(len(points)), False)
    if ring:  # the normal ray missed (concave corners): the ring may find a nearer crossing
        scan(np.nonzero(~np.isfinite(out))[0], True)
    return out


# ----------------------------------------------------------------- size measures

def curvature_integral(loops, quad=32):
    """Per loop: integral of sqrt(|curvature|) ds (Gauss-Legendre per piece), and the
    number of loops.  Curvature from ``tests.oracles.reference.bezier_eval``."""
    x, w = np.polynomial.legendre.leggauss(quad)
    t, w = (x + 1) / 2, w / 2
    per_loop = []
    for loop in loops:
        s = 0.0
        for p in loop:
            _, d1, d2 = R.bezier_eval(p, t, 2)
            sp = np.hypot(d1[:, 0], d1[:, 1])
            k = np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.maximum(sp, 1e-300) ** 3
            s += float(np.sum(w * np.sqrt(k) * sp))
        per_loop.append(s)
    return per_loop


def chord_counts(loops, e):
    """(lower bound any polygon within e, inscribed chord count) for morph's boundary."""
    per_loop = curvature_integral(loops)
    lb = sum(max(3.0, s / np.sqrt(16 * e)) for s in per_loop)
    ins = sum(max(3.0, s / np.sqrt(8 * e)) for s in per_loop)
    return int(np.ceil(lb)), int(np.ceil(ins))


def powerlaw(errs, ns):
    """Fit n = c e**(-p) to points with finite positive error; returns (c, p) or None."""
    errs, ns = np.asarray(errs, float), np.asarray(ns, float)
    ok = np.isfinite(errs) & (errs > 0) & (ns > 0)
    if ok.sum() < 2 or np.ptp(np.log(errs[ok])) < 1e-9:
        return None
    slope, icpt = np.polyfit(np.log(errs[ok]), np.log(ns[ok]), 1)
    return float(np.exp(icpt)), float(-slope)
