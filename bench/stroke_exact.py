"""Exact-predicate oracle for polyline skeletons stroked with an elliptical nib.

    python -m bench.stroke_exact FONT.otf [--set hanzi-300] [--glyphs uni740A,...]

A second, independent check of the stroke fonts of ``bench/stroke.py`` part 3, which
shares nothing with the Clipper reference (``tests/oracles/stroke_reference.py``) nor
with morph's stroking: the skeletons of the sets are polylines and the nib an exact
ellipse E (semi-axes a, b, turned by theta), so the stroke S = A ⊕ E is decided
exactly by the membership predicate

    x ∈ A ⊕ E  ⇔  A ∩ (x − E) ≠ ∅  ⇔  min over the segments [p, q] of A of
                  | M (x − [p, q]) | <= 1,  M = diag(1/a, 1/b) R(−theta),

a point-to-segment distance in the plane where E is the unit disk.  The boundary of
S lies in the union of the segments' offsets by E's support point on either side
and the ellipses around the vertices; points sampled there every ``spacing`` are on
∂S exactly when no segment holds them strictly inside (the predicate above, > 1 −
1e-9 for all segments): a sampling of the exact boundary, each point with its
outward normal.

Measures (font units) of an outline (shapely polygon in the skeleton's frame):

- ``fwd``: the largest distance from the outline's boundary (sampled every
  ``spacing``) to the sampled exact boundary: above the true distance by at most
  half the sample spacing along the exact boundary;
- ``back``: the largest distance from an exact boundary point to the outline's
  boundary, except at points in a gap of S narrower than ``2 r`` (``r`` given:
  the excused width of :func:`bench.stroke._written_errors`): the ray along the
  point's outward normal re-enters S within 2 r (the predicate, every 0.02 unit),
  i.e. the gap or hole the point faces is narrower than 2 r there;
- ``narrow``: the largest back distance so excused.

The command prints both measures of every chosen glyph of the written font (read
back: integer coordinates, shifted back by the placement the command uses), and
the same measures after the outline is displaced by twice the limit (buffered
outward), which must fail: the oracle can fail.
"""

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.append(str(ROOT))

import shapely  # noqa: E402 - after sys.path gets the repo root
from scipy.spatial import cKDTree  # noqa: E402 - after sys.path gets the repo root

INSIDE = 1.0 - 1e-9
STEP = 0.02


class ExactStroke:
    """The stroke of polylines ``paths`` ((m, 2) arrays) by the ellipse with semi-axes
    a, b turned by ``theta`` (radians), decided by the membership predicate."""

    def __init__(self, paths, a, b, theta):
        c, s = np.cos(theta), np.sin(theta)
        self.R = np.array([[c, -s], [s, c]])
        self.a, self.b = float(a), float(b)
        self.M = np.diag([1.0 / a, 1.0 / b]) @ self.R.T
        self.paths = [np.asarray(p, float) for p in paths]
        segs = []
        for p in self.paths:
            if len(p) == 1:
                segs.append((p[0], p[0]))
            segs += [(p[k], p[k + 1]) for k in range(len(p) - 1)]
        self.p0 = np.array([s[0] for s in segs])
        self.p1 = np.array([s[1] for s in segs])
        self.u0, self.u1 = self.p0 @ self.M.T, self.p1 @ self.M.T

    def metric(self, x, chunk=4096):
        """min over segments of |M (x − segment)|, for points x (n, 2)."""
        x = np.atleast_2d(np.asarray(x, float))
        out = np.empty(len(x))
        d = self.u1 - self.u0
        dd = np.maximum((d * d).sum(1), 1e-300)
        for i in range(0, len(x), chunk):
            u = x[i:i + chunk] @ self.M.T
            w = u[:, None, :] - self.u0[None]
            t = np.clip((w * d[None]).sum(2) / dd[None], 0.0, 1.0)
            r = w - t[..., None] * d[None]
            out[i:i + chunk] = np.sqrt((r * r).sum(2).min(1))
        return out

    def contains(self, x):
        return self.metric(x) <= 1.0

    def _support(self, n):
        """E's support points (k, 2) for unit directions n (k, 2)."""
        w = (n @ self.R) * [self.a, self.b]
        w /= np.linalg.norm(w, axis=1)[:, None]
        return (w * [self.a, self.b]) @ self.R.T

    def boundary(self, spacing):
        """(points, outward unit normals) sampling ∂S every ``spacing`` or closer."""
        pts, nrm = [], []
        for p, q in zip(self.p0, self.p1):
            d = q - p
            length = float(np.hypot(*d))
            if length > 0:
                n = np.array([[d[1], -d[0]], [-d[1], d[0]]]) / length
                t = np.linspace(0.0, 1.0, max(2, int(np.ceil(length / spacing)) + 1))
                for e, nn in zip(self._support(n), n):
                    pts.append(p + t[:, None] * d + e)
                    nrm.append(np.repeat(nn[None], len(t), 0))
        k = max(16, int(np.ceil(2 * np.pi * max(self.a, self.b) / spacing)))
        phi = np.linspace(0.0, 2 * np.pi, k, endpoint=False)
        circ = np.stack([np.cos(phi), np.sin(phi)], 1)
        ell = (circ * [self.a, self.b]) @ self.R.T
        en = (circ / [self.a, self.b]) @ self.R.T
        en /= np.linalg.norm(en, axis=1)[:, None]
        for v in np.unique(np.concatenate([self.p0, self.p1]), axis=0):
            pts.append(v + ell)
            nrm.append(en)
        pts, nrm = np.concatenate(pts), np.concatenate(nrm)
        keep = self.metric(pts) > INSIDE
        return pts[keep], nrm[keep]

    def gap_width_below(self, pts, nrm, width):
        """Mask: the outward normal ray of each boundary point re-enters S within
        ``width`` (the gap or hole it faces is narrower than that there)."""
        hit = np.zeros(len(pts), bool)
        for s in np.arange(2 * STEP, width + STEP / 2, STEP):
            todo = ~hit
            if not todo.any():
                break
            hit[todo] = self.contains(pts[todo] + s * nrm[todo])
        return hit


def measure(exact, outline, spacing=0.1, r=0.0, tol=0.0, boundary=None):
    """{fwd, back, narrow, at_fwd, at_back} of a shapely outline against the exact
    stroke (see the module docstring); ``boundary``: a precomputed
    ``exact.boundary(spacing)``."""
    pts, nrm = exact.boundary(spacing) if boundary is None else boundary
    line = outline.boundary
    ours = shapely.get_coordinates(shapely.segmentize(line, spacing))
    dist, _ = cKDTree(pts).query(ours)
    back = shapely.distance(shapely.points(pts), line)
    narrow = 0.0
    far = np.flatnonzero(back > tol)
    if r > 0 and len(far):
        excused = exact.gap_width_below(pts[far], nrm[far], 2 * r)
        if excused.any():
            narrow = float(back[far[excused]].max())
        back = back.copy()
        back[far[excused]] = 0.0
    i, j = int(np.argmax(dist)), int(np.argmax(back))
    return {"fwd": float(dist[i]), "back": float(back[j]), "narrow": narrow,
            "at_fwd": ours[i].tolist(), "at_back": pts[j].tolist()}


def skeleton_paths(font, name):
    """The polylines of a skeleton glyph (every piece a line)."""
    from morph import piece as pc
    from morph.parse.ufo import decomposed_paths

    out = []
    for pieces, closed in decomposed_paths(font, name):
        pts = [pc.cartesian(p) for p in pieces]
        if any(len(q) != 2 for q in pts):
            raise ValueError("%s: not a polyline skeleton" % name)
        poly = [pts[0][0]] + [q[1] for q in pts]
        if closed and not np.allclose(poly[0], poly[-1]):
            poly.append(poly[0])
        out.append(np.array(poly, float))
    return out


def main(argv=None):
    import shapely.affinity

    from bench.skeletons import skeleton_ufo
    from bench.stroke import BROAD, MEASURE_FLAT, ROUNDING, nib_region
    from morph.nib import region_extent
    from morph.parse import glyph_region
    from morph.parse.ufo import load_ufo
    from tests.oracles.icons import GAP
    from tests.oracles.reference import region_to_shapely

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("font", help="a font written by `morph stroke` from the set")
    ap.add_argument("--set", default="hanzi-300")
    ap.add_argument("--glyphs", help="comma-separated glyph names (default: all)")
    ap.add_argument("--tol", type=float, default=0.0005, help="em, as the command's")
    ap.add_argument("--spacing", type=float, default=0.1)
    opt = ap.parse_args(argv)
    src = load_ufo(skeleton_ufo(opt.set), lazy=False)
    upm = float(src.info.unitsPerEm or 1000)
    k = upm / 1000.0
    w, h, ang = BROAD[1] * k, BROAD[2] * k, BROAD[3]
    tol = opt.tol * upm
    shift = int(round(-region_extent(nib_region(("ellipse", w, h, ang)))[0]))
    limit = tol + ROUNDING
    r = GAP * tol + ROUNDING
    names = (opt.glyphs.split(",") if opt.glyphs else
             [g.name for g in sorted(src, key=lambda g: g.name)
              if any(len(c) > 1 for c in g.contours)])
    worst, bad, shown = 0.0, [], []
    for n in names:
        exact = ExactStroke(skeleton_paths(src, n), w / 2, h / 2, np.radians(ang))
        bnd = exact.boundary(opt.spacing)
        got = region_to_shapely(glyph_region(n, font=opt.font).region, MEASURE_FLAT)
        got = shapely.affinity.translate(got, -shift, 0.0)
        m = measure(exact, got, opt.spacing, r, tol, bnd)
        moved = measure(exact, got.buffer(2 * limit, quad_segs=16), opt.spacing, r, tol, bnd)
        err = max(m["fwd"], m["back"])
        worst = max(worst, err)
        if err > limit + opt.spacing / 2:
            bad.append(n)
        if moved["fwd"] <= limit + opt.spacing / 2:
            shown.append(n)
        print("%s: fwd %.3f at %s, back %.3f at %s, narrow gaps excused up to %.3f; "
              "displaced by %.2f: fwd %.3f%s" % (
                  n, m["fwd"], np.round(m["at_fwd"], 2).tolist(), m["back"],
                  np.round(m["at_back"], 2).tolist(), m["narrow"], 2 * limit, moved["fwd"],
                  "" if moved["fwd"] > limit else "  (DISPLACED OUTLINE NOT CAUGHT)"),
              flush=True)
    print("%d glyphs: worst %.3f units; over tol + 0.71 (+ half the spacing) = %.3f: %s; "
          "displaced outlines not caught: %s" % (len(names), worst, limit + opt.spacing / 2,
                                                 ", ".join(bad) or "none",
                                                 ", ".join(shown) or "none"))
    return 1 if bad or shown else 0


if __name__ == "__main__":
    sys.exit(main())
