"""The acceptance sweeps' cases and their full check (the oracles of bench/sweep.py).

A case is a string (:func:`parse_case`): a glyph ⊕ nib (``nib/FONT/GLYPH/WxH/ANGLE/
SCALE/TOL``), a glyph pair (``pair/FONT/A/B/TOL``) or a skeleton stroke
(``stroke/FONT/GLYPH/...``).  :func:`run_case` computes it with morph and checks it with
:func:`verify` against the exact membership predicate (:class:`NibOracle`,
:class:`PairOracle`, shapely on operands drawn by fontTools, not morph's parser) and a
polygon reference; :func:`check` is the older full check of the pairs mode.  The checks
are described in bench/sweep.py's docstring, which runs them at scale;
tests/test_sweep_regressions.py reruns every case a sweep found failing.

Fonts: the bundled Noto Sans (``ttf``, ``cff``) and the PyPI font packages of
:data:`OTHER_FONTS`; the stroke mode's skeletons are the Relief SingleLine subset in
tests/data, or the full font named by the environment variable ``MORPH_RELIEF_UFO``.
"""

import math
import os
import string
import time
import traceback
from functools import lru_cache
from pathlib import Path

import numpy as np

from morph import minkowski as _minkowski
from morph import moments as mo
from morph import polyline as pl
from tests.oracles import need

need("shapely", "the sweeps' exact predicate and polygon references")


ROOT = Path(__file__).resolve().parents[2]

UPM = 1000.0
REF_TOL = 0.5          # units: flattening of the coarse Clipper reference (pairs mode)
NIBS = ("disk", "ellipse", "square")

ASPECTS = ((80.0, 30.0), (60.0, 8.0), (40.0, 40.0))   # nib W x H, font units (upm 1000)
ANGLE_STEP = 1.7                                       # degrees
ORACLE_SHARE = 1.0 / 64.0                              # oracle flattening f = tol/64
LADDER = (1.0, 0.5, 0.25, 0.125, 1 / 16, 1 / 32, 1 / 64)
#: half the thinnest feature the sum may merge, x tol: its polylines' flattening and
#: grid rounding (morph.trim's budget)
THIN = _minkowski.FLAT_SHARE + _minkowski.GRID_SHARE
BUFFER_SIMPLIFY = 0.01   # GEOS simplifies a buffer's input by 1 % of the distance
OTHER_FONTS = {"lobster": ("fontpkg_lobster", "Lobster-Regular.ttf"),
               "cormorant": ("fontpkg_cormorant", "Cormorant[wght].ttf"),
               "amiri": ("fontpkg_amiri", "Amiri-Regular.ttf"),
               # not in the defaults: kept for runs on a font the code was not tuned on
               "ebg": ("fontpkg_eb_garamond", "EBGaramond[wght].ttf")}
RANDOM_FONTS = ("ttf", "cff", "lobster", "cormorant", "amiri")
LATIN = string.ascii_uppercase + string.ascii_lowercase + string.digits + "&@"
#: the skeleton font of the stroke mode: the full Relief SingleLine UFO when the
#: environment variable MORPH_RELIEF_UFO names it, else the subset in tests/data
RELIEF = tuple(Path(p) for p in (os.environ.get("MORPH_RELIEF_UFO"),) if p) + (
    ROOT / "tests" / "data" / "relief" / "Relief-SingleLine-subset.ufo",)

_cache = {}


# ============================================================================ fonts

def font_path(font):
    """Path of a font key: ttf, cff (bundled) or one of OTHER_FONTS (PyPI, the
    ``bench`` extra: ``pip install -e '.[bench]'``)."""
    from morph.parse import cubic_test_font_path, default_font_path

    if font == "ttf":
        return str(default_font_path())
    if font == "cff":
        return str(cubic_test_font_path())
    if font in OTHER_FONTS:
        mod, fname = OTHER_FONTS[font]
        try:   # under pytest a missing font package skips the test that needs it
            m = need(mod, "the font %r of the sweeps" % font)
        except ImportError as exc:
            raise SystemExit("bench.sweep: font %r needs %s: pip install -e '.[test]'"
                             % (font, mod.replace("_", "-"))) from exc
        return str(Path(m.__file__).parent / "files" / fname)
    raise ValueError("unknown font %r" % (font,))


@lru_cache(maxsize=None)
def _ttfont(font):
    from fontTools.ttLib import TTFont

    return TTFont(font_path(font))


def glyph_pool(font):
    """Glyphs a random job may pick: A-Z a-z 0-9 & @ (Latin fonts); the Arabic
    letters and presentation forms of the cmap (amiri), by glyph name."""
    cmap = _ttfont(font).getBestCmap()
    if font == "amiri":
        ranges = [(0x0621, 0x064A), (0xFB50, 0xFDFF), (0xFE70, 0xFEFC)]
        names = sorted({cmap[u] for lo, hi in ranges for u in range(lo, hi + 1) if u in cmap})
        return names
    return [c for c in LATIN if ord(c) in cmap]


def glyph(font, name):
    """Region of a glyph (font units), by morph's parser (the operand of the sum)."""
    key = ("glyph", font, name)
    if key not in _cache:
        from morph.parse import glyph_region

        _cache[key] = glyph_region(name, font_path(font)).region
    return _cache[key]


def region_size(region):
    from morph import piece as pc

    pts = np.concatenate([pc.cartesian(p) for loop in region for p in loop])
    return float(np.ptp(pts, axis=0).max())


def scaled_region(region, s):
    return [[np.asarray(p, float) * np.array([s, s, 1.0]) for p in loop] for loop in region]


def _flat_pen_class():
    from fontTools.pens.basePen import BasePen

    class FlatPen(BasePen):
        """Polylines of a glyph within ``flat``: chord error of a uniform n-split is
        <= h²/8 max|B''|, |B''| <= 2|P0-2P1+P2| (quadratic), <= 6 max second
        difference (cubic)."""

        def __init__(self, glyphset, flat):
            super().__init__(glyphset)
            self.flat, self.loops, self.cur = flat, [], None

        def _moveTo(self, p):
            self.cur = [np.asarray(p, float)]

        def _lineTo(self, p):
            self.cur.append(np.asarray(p, float))

        def _bez(self, ctrl, n):
            t = (np.arange(1, n + 1) / n)[:, None]
            if len(ctrl) == 3:
                p0, p1, p2 = ctrl
                pts = (1 - t) ** 2 * p0 + 2 * t * (1 - t) * p1 + t ** 2 * p2
            else:
                p0, p1, p2, p3 = ctrl
                pts = ((1 - t) ** 3 * p0 + 3 * t * (1 - t) ** 2 * p1
                       + 3 * t ** 2 * (1 - t) * p2 + t ** 3 * p3)
            self.cur.extend(pts)

        def _qCurveToOne(self, p1, p2):
            ctrl = [self.cur[-1], np.asarray(p1, float), np.asarray(p2, float)]
            m = np.hypot(*(ctrl[0] - 2 * ctrl[1] + ctrl[2]))
            self._bez(ctrl, max(1, math.ceil(math.sqrt(m / (4 * self.flat)))))

        def _curveToOne(self, p1, p2, p3):
            ctrl = [self.cur[-1]] + [np.asarray(p, float) for p in (p1, p2, p3)]
            m = max(np.hypot(*(ctrl[0] - 2 * ctrl[1] + ctrl[2])),
                    np.hypot(*(ctrl[1] - 2 * ctrl[2] + ctrl[3])))
            self._bez(ctrl, max(1, math.ceil(math.sqrt(0.75 * m / self.flat))))

        def _closePath(self):
            if self.cur is not None and len(self.cur) >= 3:
                self.loops.append(np.array(self.cur))
            self.cur = None

        _endPath = _closePath

    return FlatPen


def raw_glyph_polygon(font, name, flat, s=1.0):
    """Shapely polygon of a glyph scaled by s, its contours drawn by fontTools (not
    morph), flattened within ``flat`` (scaled units) and united nonzero by Clipper."""
    from tests.oracles.reference import _clipper_union, _to_clipper

    gs = _ttfont(font).getGlyphSet()
    gname = name if len(name) > 1 else _ttfont(font).getBestCmap()[ord(name)]
    pen = _flat_pen_class()(gs, flat / s)
    gs[gname].draw(pen)
    loops = [l * s for l in pen.loops]
    scale = 100.0 / flat
    return _clipper_union(_to_clipper(loops, scale), scale)


# ============================================================================ oracle

class SegmentIndex:
    """Distance from points to a set of segments (k, 2, 2) (shapely STRtree)."""

    def __init__(self, segs):
        import shapely

        self.segs = np.asarray(segs, float).reshape(-1, 2, 2)
        self.tree = shapely.STRtree(shapely.linestrings(self.segs))

    def distance(self, pts):
        import shapely

        pts = np.asarray(pts, float).reshape(-1, 2)
        out = np.full(len(pts), np.inf)
        if len(pts) == 0 or len(self.segs) == 0:
            return out
        idx, dist = self.tree.query_nearest(shapely.points(pts), return_distance=True,
                                            all_matches=False)
        out[idx[0]] = dist
        return out


def _segments_of(geom):
    """Segments (k, 2, 2) of every ring / line of a shapely geometry."""
    import shapely

    lines = shapely.get_parts(shapely.boundary(geom)) if shapely.get_dimensions(geom) == 2 \
        else shapely.get_parts(geom)
    segs = []
    for ln in lines:
        for part in shapely.get_parts(ln):
            c = np.asarray(part.coords)
            if len(c) >= 2:
                segs.append(np.stack([c[:-1], c[1:]], axis=1))
    return np.concatenate(segs) if segs else np.zeros((0, 2, 2))


class NibOracle:
    """x ∈ A ⊕ E ⇔ dist(M⁻¹x, M⁻¹A) ≤ 1 for the ellipse E = M·disk (radii rx, ry,
    rotated by theta); ``geom`` is A (a shapely polygon, or lines for a skeleton)."""

    def __init__(self, geom, rx, ry, theta):
        import shapely
        import shapely.affinity

        c, s = math.cos(theta), math.sin(theta)
        self.minv = np.array([[c / rx, s / rx], [-s / ry, c / ry]])
        self.r_min = min(rx, ry)
        m = self.minv
        self.g = shapely.affinity.affine_transform(geom, [m[0, 0], m[0, 1], m[1, 0],
                                                          m[1, 1], 0.0, 0.0])
        self.areal = shapely.get_dimensions(self.g) == 2
        if self.areal:
            shapely.prepare(self.g)
        self.index = SegmentIndex(_segments_of(self.g))

    def __call__(self, pts):
        import shapely

        q = np.asarray(pts, float).reshape(-1, 2) @ self.minv.T
        inside = shapely.contains_xy(self.g, q[:, 0], q[:, 1]) if self.areal \
            else np.zeros(len(q), bool)
        return inside | (self.index.distance(q) <= 1.0)

    def distance_bound(self, pts):
        """A lower bound of each point's distance to the boundary of A ⊕ E, exact up
        to the flattening of A: in M⁻¹ space the boundary is where the distance d to
        A is 1, so a point at distance d outside A lies |d - 1| from it, one at depth d
        inside A at least d + 1 (triangle inequality); M stretches lengths by at least
        the smaller radius."""
        import shapely

        q = np.asarray(pts, float).reshape(-1, 2) @ self.minv.T
        d = self.index.distance(q)
        inside = shapely.contains_xy(self.g, q[:, 0], q[:, 1]) if self.areal \
            else np.zeros(len(q), bool)
        return self.r_min * np.where(inside, d + 1.0, np.abs(d - 1.0))

    def reference(self, quad_segs=256):
        """Polygon of A ⊕ E: M (M⁻¹A buffered by 1), arcs inscribed (error <= 1 -
        cos(pi / (4 quad_segs)) in M⁻¹ space)."""
        import shapely.affinity

        buf = self.g.buffer(1.0, quad_segs=quad_segs)
        m = np.linalg.inv(self.minv)
        return shapely.affinity.affine_transform(buf, [m[0, 0], m[0, 1], m[1, 0], m[1, 1],
                                                       0.0, 0.0])


class PairOracle:
    """x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅ for two shapely polygons
    (tests.oracles.membership.Oracle on glyphs drawn by fontTools)."""

    def __init__(self, pa, pb):
        import shapely
        import shapely.affinity

        self.pa = pa
        shapely.prepare(self.pa)
        self.neg_b = shapely.affinity.scale(pb, -1, -1, origin=(0, 0))

    def __call__(self, pts):
        import shapely

        pts = np.asarray(pts, float).reshape(-1, 2)
        moved = [shapely.affinity.translate(self.neg_b, x, y) for x, y in pts]
        return shapely.intersects(self.pa, np.array(moved, dtype=object))


def straddle_probes(pts, nrm, d, n_ring=24):
    """(len(pts), 2 + n_ring, 2): both normal points and n_ring points of the circle
    of radius d around each point (see tests.oracles.membership.straddle)."""
    ang = np.linspace(0, 2 * np.pi, n_ring, endpoint=False)
    ring = np.column_stack([np.cos(ang), np.sin(ang)])
    d = np.asarray(d, float).reshape(-1, 1, 1) if np.ndim(d) else d
    return np.concatenate([pts[:, None, :] + d * nrm[:, None, :],
                           pts[:, None, :] - d * nrm[:, None, :],
                           pts[:, None, :] + d * ring[None, :, :]], axis=1)


SAMPLE_TS = (0.0, 1 / 6, 0.5, 5 / 6)


def boundary_samples(loops, ts=SAMPLE_TS):
    """Points and unit outward normals (right of travel) at parameters ``ts`` of every
    piece; points where the derivative vanishes get a zero normal (ring probes only)."""
    from morph import piece as pc

    pts, nrm = [], []
    t = np.asarray(ts, float)
    for loop in loops:
        for p in loop:
            d = pc.derivative(p, t)
            n = np.column_stack([d[:, 1], -d[:, 0]])
            ln = np.hypot(n[:, 0], n[:, 1])
            n = np.where(ln[:, None] > 0, n / np.where(ln > 0, ln, 1.0)[:, None], 0.0)
            pts.append(pc.evaluate(p, t))
            nrm.append(n)
    return np.concatenate(pts), np.concatenate(nrm)


def _label_points(geom):
    """Deepest interior point of every part and every hole of a polygonal geometry,
    with its depth: [(point, depth, kind)], kind 'filled' or 'hole'."""
    import shapely
    from shapely.geometry import Polygon
    from shapely.ops import polylabel

    out = []
    for poly in shapely.get_parts(geom):
        if poly.is_empty or poly.area <= 0:
            continue
        for kind, g in [("filled", poly)] + [("hole", Polygon(r)) for r in poly.interiors]:
            if not g.is_valid:
                g = shapely.make_valid(g)
                g = max(shapely.get_parts(g), key=lambda x: x.area)
            if g.area <= 0:
                continue
            try:
                lab = polylabel(g, tolerance=max(g.length * 1e-4, 1e-300))
            except Exception:  # noqa: BLE001 - a degenerate ring: no label
                continue
            depth = g.boundary.distance(lab)
            out.append((np.array([lab.x, lab.y]), depth, kind))
    return out


# ============================================================================ verify

def junction_crossings(loops, tol, limit=3):
    """Where pieces of one loop cross away from their shared ends (each piece flattened
    within tol/4096): 'loop k pieces i/j (adjacent) cross 0.02 tol from a piece end'."""
    import shapely
    from shapely.geometry import LineString

    from morph import piece as pc

    out = []
    for k, loop in enumerate(loops):
        lines = [LineString(pl.flatten(p, tol / 4096)[0]) for p in loop]
        ends = [np.array([pc.start(p), pc.end(p)]) for p in loop]
        n = len(loop)
        pairs = shapely.STRtree(lines).query(lines, predicate="intersects")
        for i, j in sorted({(int(a), int(b)) for a, b in pairs.T if a < b}):
            pts = shapely.get_coordinates(lines[i].intersection(lines[j]))
            e = np.concatenate([ends[i], ends[j]])
            d = [float(np.min(np.hypot(*(e - q).T))) for q in pts]
            d = [v for v in d if v > 1e-6 * tol]
            if d:
                adj = j == i + 1 or (i == 0 and j == n - 1)
                out.append("loop %d pieces %d/%d (%s, degrees %d/%d) cross %.3g tol from "
                           "a piece end" % (k, i, j, "adjacent" if adj else "not adjacent",
                                            len(loop[i]) - 1, len(loop[j]) - 1,
                                            max(d) / tol))
            if len(out) >= limit:
                return "; ".join(out)
    return "; ".join(out)


def _closed_lines(rings):
    from shapely.geometry import LineString, MultiLineString

    return MultiLineString([LineString(np.vstack([r, r[:1]])) for r in rings if len(r) >= 2])


def verify(loops, oracle, tol, f, size, rng, ref=None, ref_err=0.0, n_boundary=600,
           n_random=300, ladder=LADDER):
    """Check one output region against the exact predicate ``oracle`` (module
    docstring).  Returns a dict: fail (list of strings) and measures."""
    import shapely
    from shapely.geometry import Polygon

    from morph import piece as pc
    from tests.oracles import reference as R
    from tests.oracles.membership import sharp_starts

    res = {"fail": [], "thin": 0}
    fail = res["fail"]
    if not loops:
        fail.append("empty result")
        return res
    slack = 2.0 * f
    # closed
    gap = 0.0
    for loop in loops:
        for p, q in zip(loop, loop[1:] + loop[:1]):
            gap = max(gap, float(np.hypot(*(pc.end(p) - pc.start(q)))))
    res["gap/tol"] = gap / tol
    if gap > 1e-9 * size:
        fail.append("open loop: gap %.3g (%.3g tol)" % (gap, gap / tol))
    # simple, no two loops crossing
    rings = [pl.flatten_loop(l, tol / 64) for l in loops]
    lines = _closed_lines(rings)
    if not shapely.is_simple(lines) or any(len(r) < 3 for r in rings):
        # polylines within f of the loops can cross where two strands of the loops
        # pass closer than 2f (a hairpin of a piece whose strands are 2e-4 tol apart
        # crossed at tol/1024 while the pieces do not): the finest level decides
        for f in (tol / 1024, tol / 65536):
            fine = [pl.flatten_loop(l, f) for l in loops]
            lines2 = _closed_lines(fine)
            if shapely.is_simple(lines2) and all(len(r) >= 3 for r in fine):
                break
        if not shapely.is_simple(lines2) or any(len(r) < 3 for r in fine):
            why = "; ".join(shapely.is_valid_reason(Polygon(r)) for r in fine
                            if len(r) >= 3 and not Polygon(r).is_valid)[:160]
            faces = shapely.get_parts(shapely.polygonize(shapely.get_parts(
                shapely.unary_union(lines2))))
            small = min((g.area for g in faces), default=0.0)
            where = junction_crossings(loops, tol)
            fail.append("loops not simple or crossing each other%s (smallest face of the "
                        "linework %.2g tol^2)%s" % (": " + why if why else " (between loops)",
                                                   small / tol ** 2,
                                                   "; " + where if where else ""))
    ours_index = SegmentIndex(np.concatenate([np.stack([r, np.roll(r, -1, axis=0)], axis=1)
                                              for r in rings]))
    if hasattr(oracle, "distance_bound"):
        # every vertex of the polylines within tol/64 (a spike's or a crack's tip is a
        # junction, always a vertex), not a sample: a rigorous lower bound of its
        # distance to the exact boundary (less the oracle's flattening f and the
        # polyline's tol/64) must stay within tol + 2f
        allv = np.concatenate(rings)
        far = oracle.distance_bound(allv) - f - tol / 64
        res["dense/tol"] = float(far.max() / tol)
        if far.max() > tol + slack:
            k = int(np.argmax(far))
            fail.append("dense: %d of %d boundary vertices lie more than tol + 2f from the "
                        "exact boundary (up to %.3g tol), e.g. %s"
                        % ((far > tol + slack).sum(), len(allv), far.max() / tol,
                           np.array2string(allv[k], precision=12, separator=", ")))

    def winding(x):
        return R.winding_number(x, rings)

    # straddle ladder
    pts, nrm = boundary_samples(loops)
    if len(pts) > n_boundary:
        # junctions turning by more than 45 degrees first (a spike's or a crack's
        # tip is one), the rest drawn at random
        sharp = np.flatnonzero(sharp_starts(loops)) * len(SAMPLE_TS)
        if len(sharp) > n_boundary:
            sharp = rng.choice(sharp, n_boundary, replace=False)
        rest = np.setdiff1d(np.arange(len(pts)), sharp)
        more = max(n_boundary - len(sharp), 0)
        pick = np.concatenate([sharp, rng.choice(rest, min(more, len(rest)), replace=False)])
        pts, nrm = pts[pick], nrm[pick]
    res["samples"] = len(pts)
    err = np.full(len(pts), np.inf)       # error bound per point (over tol)
    alive = np.arange(len(pts))
    ref_index = None
    if ref is not None and not ref.is_empty:
        ref_index = SegmentIndex(_segments_of(ref))
        # distance to the polygon reference's boundary: informative only (see above)
        res["ref_dist/tol"] = float(ref_index.distance(pts).max() / tol) if len(pts) else 0.0
    res["probe_misses"] = 0
    for c in ladder:
        d = c * tol + slack
        pr = straddle_probes(pts[alive], nrm[alive], d)
        inside = oracle(pr.reshape(-1, 2)).reshape(len(alive), -1)
        ok = inside.any(axis=1) & (~inside).any(axis=1)
        if c == ladder[0] and not ok.all():
            # 26 probes miss a wedge of the complement narrower than 15 degrees (a
            # hole's sharp tip): probe the disk densely with the exact predicate (8
            # rings of 180 directions: wedges down to 2 degrees).  (Not the polygon
            # reference: GEOS simplifies a buffer's input by 1 % of the distance and
            # can close a notch deeper than that.)
            miss = np.flatnonzero(~ok)
            for i in miss:
                ang = np.linspace(0, 2 * np.pi, 180, endpoint=False)
                rad = d * np.arange(1, 9) / 8
                pr = pts[alive[i]] + (rad[:, None, None] * np.stack([np.cos(ang), np.sin(ang)],
                                                                   axis=1)[None]).reshape(-1, 2)
                ins = oracle(pr)
                if ins.any() and (~ins).any():
                    ok[i] = True
                    res["probe_misses"] += 1
        err[alive[ok]] = d / tol
        if c == ladder[0] and not ok.all():
            bad = alive[~ok]
            out_side = ~inside[~ok].any(axis=1)
            k = int(bad[0])
            fail.append("straddle: %d of %d boundary points farther than tol + 2f = %.4g "
                        "from the exact boundary (%d outside, %d inside the sum; distance to "
                        "the reference boundary up to %s tol), e.g. %s"
                        % (len(bad), len(pts), d, out_side.sum(), (~out_side).sum(),
                           "%.3g" % (ref_index.distance(pts[bad]).max() / tol)
                           if ref_index is not None else "?",
                           np.array2string(pts[k], precision=12, separator=", ")))
        alive = alive[ok]
        if not len(alive):
            break
    finite = err[np.isfinite(err)]
    res["err/tol"] = float(finite.max()) if len(finite) == len(err) and len(err) else float("inf")
    # orientation: winding 0 or 1 at the straddle probes of the first level
    w = winding(straddle_probes(pts[:200], nrm[:200], tol + slack).reshape(-1, 2))
    if w.min() < 0 or w.max() > 1:
        fail.append("winding numbers %d..%d (loops misoriented or nested wrong)"
                    % (w.min(), w.max()))
    # membership: random points, near the reference boundary, labels of features
    lo = np.min([pc.bbox(p)[:2] for l in loops for p in l], axis=0)
    hi = np.max([pc.bbox(p)[2:] for l in loops for p in l], axis=0)
    pad = 0.05 * (hi - lo).max()
    x = [rng.uniform(lo - pad, hi + pad, size=(n_random, 2))]
    ours_poly = R.region_to_shapely(loops, tol / 64)
    geoms = [("ours", ours_poly)] + ([("reference", ref)] if ref is not None else [])
    for _name, g in geoms:
        for p, _depth, _kind in _label_points(g):
            x.append(p[None])
    if ref is not None and not ref.is_empty:
        rs = _segments_of(ref)
        if len(rs):
            pick = rng.choice(len(rs), min(len(rs), 300), replace=False)
            s0, s1 = rs[pick, 0], rs[pick, 1]
            mid = 0.5 * (s0 + s1)
            dv = s1 - s0
            n = np.column_stack([dv[:, 1], -dv[:, 0]])
            n /= np.maximum(np.hypot(n[:, 0], n[:, 1]), 1e-300)[:, None]
            x += [mid + 0.6 * tol * n, mid - 0.6 * tol * n]
    x = np.concatenate(x)
    far = ours_index.distance(x) > tol + slack
    x = x[far]
    if len(x):
        ours = winding(x) != 0
        truth = oracle(x)
        bad = np.flatnonzero(ours != truth)
        if len(bad):
            # the documented rule: features thinner than 2 THIN tol may merge
            r = THIN * tol + slack
            pr = straddle_probes(x[bad], np.zeros((len(bad), 2)), r)
            ins = oracle(pr.reshape(-1, 2)).reshape(len(bad), -1)
            thin = ins.any(axis=1) & (~ins).any(axis=1)
            res["thin"] = int(thin.sum())
            real = bad[~thin]
            if len(real):
                # the worst: farthest from the exact boundary (ladder of straddle radii)
                depth = np.full(len(real), np.inf)
                for cc in (4.0, 2.0, 1.0, 0.5, 0.25):
                    pr = straddle_probes(x[real], np.zeros((len(real), 2)), cc * tol + slack)
                    ins = oracle(pr.reshape(-1, 2)).reshape(len(real), -1)
                    depth[ins.any(axis=1) & (~ins).any(axis=1)] = cc + slack / tol
                k = int(real[np.argmax(depth)])
                fail.append("membership: %d points farther than tol from our boundary on the "
                            "wrong side (ours %s, exact %s), e.g. %s: the exact boundary "
                            "%s tol from it, ours %.3g tol"
                            % (len(real), "in" if ours[k] else "out",
                               "in" if truth[k] else "out",
                               np.array2string(x[k], precision=12, separator=", "),
                               "<= %.3g" % depth.max() if np.isfinite(depth.max()) else "> 4",
                               ours_index.distance(x[k:k + 1])[0] / tol))
    res["membership_points"] = int(len(x))
    # polygon reference: area, distances, counts
    if ref is not None and not ref.is_empty:
        area = mo.region_area(loops)
        per = float(ref.length)
        bound = (tol + ref_err) * per
        res["area_diff/bound"] = abs(area - ref.area) / bound
        if abs(area - ref.area) > bound:
            fail.append("area %.10g vs reference %.10g: differs by %.3g > (tol + ref err) x "
                        "perimeter = %.3g" % (area, ref.area, abs(area - ref.area), bound))
        rs = _segments_of(ref)
        res["ref_to_ours/tol"] = float(ours_index.distance(
            rs[:, 0] if len(rs) <= 20000 else rs[rng.choice(len(rs), 20000, replace=False), 0]
        ).max() / tol) if len(rs) else 0.0
        res["holes"] = sum(mo.loop_area(l) < 0 for l in loops)
        res["ref_holes"] = sum(len(p.interiors) for p in shapely.get_parts(ref))
    return res


# ============================================================================ pairs mode

def nib(name):
    from morph import piece as pc

    if name == "disk":
        return [pc.circle([0.0, 0.0], 30.0)]
    if name == "ellipse":
        return [pc.ellipse([0.0, 0.0], 30.0, 4.0, np.radians(30.0))]
    if name == "square":
        p = [(-20.0, -20.0), (20.0, -20.0), (20.0, 20.0), (-20.0, 20.0)]
        return [[pc.line(p[i], p[(i + 1) % 4]) for i in range(4)]]
    raise ValueError(name)


def shape(font, name):
    key = (font, name)
    if key not in _cache:
        if name.startswith("nib:"):
            _cache[key] = nib(name[4:])
        else:
            _cache[key] = glyph(font, name)
    return _cache[key]


def _closed(loops, eps):
    from morph import piece as pc

    for loop in loops:
        for p, q in zip(loop, loop[1:] + loop[:1]):
            if np.hypot(*(pc.end(p) - pc.start(q))) > eps:
                return False
    return True


def check(font, a_name, b_name, tol, seed=0):
    """Run and check one sum; returns a dict (failures: list of strings)."""
    import shapely
    from shapely.geometry import Polygon

    from morph import piece as pc
    from morph.minkowski import minkowski_sum
    from tests.oracles import reference as R
    from tests.oracles.membership import Oracle, straddle_sides
    from tests.oracles.membership import boundary_samples as _boundary_samples
    from tests.oracles.membership import inside as _inside
    from tests.oracles.membership import sharp_junctions as _sharp_junctions

    a, b = shape(font, a_name), shape(font, b_name)
    res = {"font": font, "a": a_name, "b": b_name, "fail": [], "error": 0.0}
    t0 = time.time()
    try:
        loops = minkowski_sum(a, b, tol)
    except Exception as exc:  # noqa: BLE001 - every crash is a finding
        res["fail"].append("exception %s: %s" % (type(exc).__name__,
                                                  " ".join(str(exc).split())[:200]))
        res["trace"] = traceback.format_exc()
        res["time"] = time.time() - t0
        return res
    res["time_sum"] = time.time() - t0
    res["loops"] = loops
    if not loops:
        res["fail"].append("empty result")
        return res
    scale = max(np.ptp(np.concatenate([pc.cartesian(p) for l in loops for p in l]), axis=0))
    if not _closed(loops, 1e-9 * scale + 1e-9):
        res["fail"].append("open loop")
    for k, loop in enumerate(loops):
        ring = pl.flatten_loop(loop, tol / 4)
        if len(ring) < 3 or not Polygon(ring).is_valid:
            res["fail"].append("loop %d not simple" % k)
            break
    rng = np.random.default_rng(seed)
    slack = 1e-5 * UPM + 2e-3
    d = tol + slack
    oracle = Oracle(a, b, 1e-3)
    pts, nrm = _boundary_samples(loops)
    sharp = _sharp_junctions(loops)
    if len(pts) > 40:
        pick = rng.choice(len(pts), 40, replace=False)
        pts, nrm = pts[pick], nrm[pick]
    # and every junction turning by more than 45 degrees (a spike's or crack's tip)
    pts = np.concatenate([pts, sharp])
    nrm = np.concatenate([nrm, np.zeros_like(sharp)])
    has_in, has_out = straddle_sides(oracle, pts, nrm, d)
    bad_out, bad_in = ~has_in, ~has_out
    if bad_out.any():
        res["fail"].append("straddle: %d boundary points > tol+slack outside the sum, e.g. %s"
                           % (bad_out.sum(), np.round(pts[bad_out][0], 3).tolist()))
    if bad_in.any():
        res["fail"].append("straddle: %d boundary points > tol+slack inside the sum, e.g. %s"
                           % (bad_in.sum(), np.round(pts[bad_in][0], 3).tolist()))
    lo = np.min([pc.bbox(p)[:2] for l in loops for p in l], axis=0) - 20
    hi = np.max([pc.bbox(p)[2:] for l in loops for p in l], axis=0) + 20
    x = rng.uniform(lo, hi, size=(60, 2))
    ours_poly = R.region_to_shapely(loops, tol / 4)
    near = shapely.distance(shapely.points(x), ours_poly.boundary) <= d
    x = x[~near]
    if len(x):
        ours = _inside(loops, x)
        truth = oracle(x)
        if not np.array_equal(ours, truth):
            res["fail"].append("membership differs at %d points, e.g. %s"
                               % ((ours != truth).sum(),
                                  np.round(x[ours != truth][0], 3).tolist()))
    # coarse Clipper reference
    ref = R.polygon_minkowski_sum(a, b, REF_TOL)
    res["ref"] = ref
    area = mo.region_area(loops)
    rel = abs(area - ref.area) / ref.area
    res["area_rel"] = rel
    if rel > 2e-3:
        res["fail"].append("area %.6g vs reference %.6g (rel %.2e)" % (area, ref.area, rel))
    min_area = 100 * tol
    ref_counts = R.count_outer_and_holes(ref, min_area)
    ours_counts = (sum(mo.loop_area(l) > min_area for l in loops),
                   sum(mo.loop_area(l) < -min_area for l in loops))
    if ours_counts != ref_counts:
        res["fail"].append("outer/holes %s vs reference %s" % (ours_counts, ref_counts))
    h, limit = reference_distance(ours_poly, a, b, tol, ref)
    res["error"] = h
    if h > limit:
        res["fail"].append("Hausdorff to reference %.4g > %.4g" % (h, limit))
    res["time"] = time.time() - t0
    return res


#: where the coarse reference is too far, a reference this many times finer decides
REFINE = 25.0


def reference_distance(ours_poly, a, b, tol, ref, ref_tol=REF_TOL):
    """(distance, limit): the Hausdorff distance between the boundaries of ours
    (a shapely polygon) and of ``ref``, the polygon reference of a ⊕ b flattened
    within ``ref_tol`` (:func:`tests.oracles.reference.polygon_minkowski_sum`),
    sampled every 2 units, and the limit it must keep, tol + ref_tol + 1.

    A reference flattened within e is within e of the exact sum as a set, but not
    its boundary at the tip of a thin notch: both walls move by up to e, so a
    notch of angle phi ends up to e / sin(phi / 2) farther or nearer (25 e at 4.6
    degrees).  Where the coarse reference is beyond the limit, the reference
    flattened ``REFINE`` times finer decides, against its own limit (its walls, and
    so its tips, move 25 times less)."""
    from tests.oracles import reference as R

    h = R.hausdorff(ours_poly, ref, spacing=2.0)
    if h <= tol + ref_tol + 1.0:
        return h, tol + ref_tol + 1.0
    fine = ref_tol / REFINE
    ref = R.polygon_minkowski_sum(a, b, fine)
    return R.hausdorff(ours_poly, ref, spacing=2.0), tol + fine + 1.0


def parse_case(spec):
    parts = spec.split("/")
    kind = parts[0]
    if kind in ("nib", "stroke") and len(parts) == 7:
        w, h = (float(v) for v in parts[3].split("x"))
        return dict(kind=kind, font=parts[1], glyph=parts[2], w=w, h=h,
                    angle=float(parts[4]), s=float(parts[5]), r=float(parts[6]))
    if kind == "pair" and len(parts) == 5:
        return dict(kind=kind, font=parts[1], a=parts[2], b=parts[3], tol=float(parts[4]))
    raise ValueError("bad case %r (nib/FONT/GLYPH/WxH/ANGLE/S/R, stroke/SRC/NAME/"
                     "WxH/ANGLE/S/R or pair/FONT/A/B/TOL_EM)" % (spec,))


def _nib_region(c):
    from morph import piece as pc

    rx, ry = c["w"] / 2 * c["s"], c["h"] / 2 * c["s"]
    theta = math.radians(c["angle"])
    return [pc.ellipse([0.0, 0.0], rx, ry, theta)], (rx, ry, theta)


@lru_cache(maxsize=2)
def relief_font():
    from morph.parse.ufo import load_ufo

    for p in RELIEF:
        if p.exists():
            return load_ufo(str(p), lazy=False), p
    raise SystemExit("bench.sweep: no Relief SingleLine UFO found (%s)" % (RELIEF,))


def relief_pool():
    font, _ = relief_font()
    return sorted(g.name for g in font if len(g.contours) or len(g.components))


def relief_paths(name):
    from morph.parse.ufo import decomposed_paths

    font, _ = relief_font()
    return decomposed_paths(font, name)


#: stroke-only icons (centre lines: open paths, circles, rects, polylines on a 24-unit
#: grid), fetched from npm into the cache folder (MORPH_BENCH_CACHE, default
#: ~/.cache/morph-bench) on first use; scaled to FEATHER_EM units per 24
FEATHER = "feather-icons@4.29.2"
FEATHER_EM = 1000.0


@lru_cache(maxsize=1)
def feather_dir():
    import subprocess

    cache = Path(os.environ.get("MORPH_BENCH_CACHE", Path.home() / ".cache" / "morph-bench"))
    folder = cache / FEATHER.replace("@", "-")
    icons = folder / "package" / "dist" / "icons"
    if not icons.is_dir():
        folder.mkdir(parents=True, exist_ok=True)
        try:
            tgz = subprocess.run(["npm", "pack", FEATHER, "--silent"], cwd=cache, check=True,
                                 capture_output=True, text=True).stdout.split()[-1]
            subprocess.run(["tar", "xzf", str(cache / tgz), "-C", str(folder)], check=True)
        except (OSError, subprocess.CalledProcessError, IndexError) as exc:
            raise SystemExit("bench.sweep: cannot fetch %s with npm: %s" % (FEATHER, exc))
    return icons


def feather_pool():
    return sorted(f.stem for f in feather_dir().glob("*.svg"))


def feather_paths(name):
    from morph.parse import svg_paths

    scale = np.array([FEATHER_EM / 24.0, FEATHER_EM / 24.0, 1.0])
    return [([np.asarray(p, float) * scale for p in pieces], closed)
            for pieces, closed in svg_paths(str(feather_dir() / (name + ".svg")))]


#: skeleton sources of stroke cases: font key -> (pool, paths of one name)
SKELETONS = {"relief": (relief_pool, relief_paths), "feather": (feather_pool, feather_paths)}


def _paths_size(paths):
    from morph import piece as pc

    pts = np.concatenate([pc.cartesian(np.asarray(p, float)) for pieces, _ in paths
                          for p in pieces])
    return float(np.ptp(pts, axis=0).max())


def case_inputs(spec):
    """Arguments of the call a case makes: (region_a, nib, tol) for ``nib`` cases
    (``morph.minkowski.minkowski_sum(*case_inputs(spec))``), (paths, nib, tol) for
    ``stroke`` cases (``morph.stroke.stroke_paths(*case_inputs(spec))``)."""
    c = parse_case(spec)
    if c["kind"] == "nib":
        a = glyph(c["font"], c["glyph"])
        tol = c["r"] * region_size(a) * c["s"]
        return scaled_region(a, c["s"]), _nib_region(c)[0], tol
    if c["kind"] == "stroke":
        paths = SKELETONS[c["font"]][1](c["glyph"])
        tol = c["r"] * _paths_size(paths) * c["s"]
        paths = [([np.asarray(p, float) * np.array([c["s"], c["s"], 1.0]) for p in pieces], cl)
                 for pieces, cl in paths]
        return paths, _nib_region(c)[0], tol
    if c["kind"] == "pair":
        return shape(c["font"], c["a"]), shape(c["font"], c["b"]), c["tol"] * UPM
    raise ValueError(spec)


def _timed_sum(res, fn, a, b, tol):
    """fn(a, b, tol) timed into res (time_sum, pieces); None, with the exception
    recorded as a failure, when it raises (every exception is a finding)."""
    t0 = time.perf_counter()
    try:
        loops = fn(a, b, tol)
    except Exception as exc:  # noqa: BLE001 - every exception is a finding
        res["time_sum"] = time.perf_counter() - t0
        res["fail"].append("exception %s: %s" % (type(exc).__name__,
                                                  " ".join(str(exc).split())[:300]))
        res["trace"] = traceback.format_exc()
        if getattr(exc, "suggestion", None) and "refused" not in res:
            res["refused"] = float(exc.suggestion)  # a LimitError naming a tolerance
        return None
    res["time_sum"] = time.perf_counter() - t0
    res["pieces"] = sum(len(l) for l in loops)
    return loops


#: Set (by ``--packed``) in the environment of the case processes: each case's
#: region is computed in one packed call (``minkowski_sums`` / ``stroke_many``)
#: together with COMPANIONS transformed copies of itself, and only its own result
#: is checked.
PACKED_ENV = "MORPH_SWEEP_PACKED"
#: The copies: mirrored in x, turned by 90 degrees, scaled by 1/2 (affine maps).
COMPANIONS = ([[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0]],
              [[0.5, 0.0, 0.0], [0.0, 0.5, 0.0]])


def _packed_call(kind):
    """fn(a, nib, tol) returning a's result of one packed call with its companions."""
    from morph import piece as pc
    from morph.minkowski import minkowski_sums
    from morph.region import transform_region
    from morph.stroke import stroke_many

    if kind == "nib":
        return lambda a, b, tol: minkowski_sums(
            [a] + [transform_region(a, m) for m in COMPANIONS], b, tol)[0]

    def moved(paths, m):
        return [([pc.transform(p, np.asarray(m)) for p in pieces], cl) for pieces, cl in paths]

    return lambda a, b, tol: stroke_many([a] + [moved(a, m) for m in COMPANIONS], b, tol)[0]


def run_case(spec, seed=0):
    """Run and check one case; returns a dict (``fail``: list of strings, empty when
    the case passes; measures: err/tol, times ...)."""
    c = parse_case(spec)
    if c["kind"] == "pair" and c["font"] in OTHER_FONTS:
        return _run_font_pair(spec, c, seed)
    if c["kind"] == "pair":
        res = check(c["font"], c["a"], c["b"], c["tol"] * UPM, seed)
        res.pop("loops", None)
        res.pop("ref", None)
        res.pop("trace", None)
        res["spec"] = spec
        return res
    from morph.minkowski import minkowski_sum
    from morph.stroke import stroke_paths

    res = {"spec": spec, "fail": []}
    rng = np.random.default_rng(seed)
    a, nib_region, tol = case_inputs(spec)
    rx, ry, theta = _nib_region(c)[1]
    res["tol"] = tol
    fn = minkowski_sum if c["kind"] == "nib" else stroke_paths
    if os.environ.get(PACKED_ENV):
        fn = _packed_call(c["kind"])
    loops = _timed_sum(res, fn, a, nib_region, tol)
    if loops is None and res.get("refused") and res["refused"] < tol:
        # a documented refusal (LimitError with a suggested tolerance) passes when the
        # suggested tolerance works: the case is checked again at it
        tol = res["tol"] = res["refused"]
        res["fail"] = []
        loops = _timed_sum(res, fn, a, nib_region, tol)
    if loops is None:
        return res
    res["loops"] = len(loops)
    t1 = time.perf_counter()
    f = ORACLE_SHARE * tol
    if c["kind"] == "nib":
        size = region_size(a)
        geom = raw_glyph_polygon(c["font"], c["glyph"], f, c["s"])
        oracle = NibOracle(geom, rx, ry, theta)
        ref = oracle.reference()
        ref_err = f + (1 - math.cos(math.pi / 1024) + BUFFER_SIMPLIFY) * max(rx, ry)
    else:
        from shapely.geometry import LineString, MultiLineString

        from tests.oracles.stroke_reference import path_polyline, stroke_polygon

        size = _paths_size(a)
        lines = [path_polyline(pieces, f) for pieces, _ in a]
        # a dot (zero-length path) is a degenerate segment
        geom = MultiLineString([LineString(ln if len(ln) >= 2 else np.vstack([ln, ln]))
                                for ln in lines])
        oracle = NibOracle(geom, rx, ry, theta)
        # the polygon reference of the issue: Clipper MinkowskiSum of the flattened
        # path with the nib polygon, united; flattened within ref_tol / 2 each
        ref_tol = max(tol / 2, 5e-5 * size)
        clip = stroke_polygon(a, nib_region, ref_tol)
        clip_err = ref_tol + 2 * ref_tol / 100
        ref = oracle.reference()
        ref_err = f + (1 - math.cos(math.pi / 1024) + BUFFER_SIMPLIFY) * max(rx, ry)
    res["size"] = size
    chk = verify(loops, oracle, tol, f, size, rng, ref=ref, ref_err=ref_err)
    if c["kind"] == "stroke":
        chk["fail"] += _compare_clipper(loops, clip, clip_err, oracle, tol, f, chk)
    res["fail"] += chk.pop("fail")
    res.update(chk)
    res["time_check"] = time.perf_counter() - t1
    return res


def _compare_clipper(loops, ref, ref_err, oracle, tol, f, chk):
    """Area and Hausdorff distance against the Clipper stroke reference; where they
    disagree, the exact predicate arbitrates at a point of every part of the symmetric
    difference larger than tol²: a part where ours agrees with the predicate is the
    reference's error (counted in ``clipper_wrong``), one in a feature thinner than
    2 THIN tol is allowed; only the others fail."""
    import shapely

    from tests.oracles.reference import hausdorff, region_to_shapely

    msgs = []
    area = mo.region_area(loops)
    bound = (tol + ref_err) * float(ref.length)
    chk["clipper_area_diff/bound"] = abs(area - ref.area) / bound
    if abs(area - ref.area) > bound:
        msgs.append("area %.10g vs Clipper reference %.10g: differs by %.3g > (tol + ref "
                    "err) x perimeter = %.3g" % (area, ref.area, abs(area - ref.area), bound))
    ours = region_to_shapely(loops, tol / 64)
    spacing = max(ref.length / 20000, tol / 4)
    h = hausdorff(ours, ref, spacing=spacing)
    chk["hausdorff/tol"] = h / tol
    hb = tol + ref_err + tol / 64
    if h > hb:
        msgs.append("Hausdorff to the Clipper reference %.4g > tol + ref err = %.4g" % (h, hb))
    if not msgs:
        return []
    parts = [g for g in shapely.get_parts(shapely.symmetric_difference(ours, ref))
             if g.area > tol * tol]
    pts = np.array([[q.x, q.y] for q in (g.representative_point() for g in parts)]) \
        if parts else np.zeros((0, 2))
    if not len(pts):
        return msgs
    ours_in = shapely.contains_xy(ours, pts[:, 0], pts[:, 1])
    truth = oracle(pts)
    wrong = ours_in != truth
    if wrong.any():
        r = THIN * tol + 2 * f
        pr = straddle_probes(pts[wrong], np.zeros((wrong.sum(), 2)), r)
        ins = oracle(pr.reshape(-1, 2)).reshape(wrong.sum(), -1)
        thin = ins.any(axis=1) & (~ins).any(axis=1)
        wrong[np.flatnonzero(wrong)[thin]] = False
    chk["clipper_wrong"] = int((~wrong).sum())
    if wrong.any():
        k = int(np.flatnonzero(wrong)[0])
        return msgs + ["the exact predicate sides with the reference at %d of %d parts of "
                       "the difference, e.g. %s (ours %s)"
                       % (wrong.sum(), len(pts), np.array2string(pts[k], precision=10,
                                                                  separator=", "),
                          "in" if ours_in[k] else "out")]
    return []


def _run_font_pair(spec, c, seed):
    """glyph ⊕ glyph of another font: verify() with the translation oracle on glyphs
    drawn by fontTools (both flattened within f = tol/64, so the slack is 4f), 150
    boundary samples at one straddle radius, no polygon reference (a Clipper sum of
    two flattened Arabic ligatures takes minutes)."""
    from morph.minkowski import minkowski_sum

    res = {"spec": spec, "fail": []}
    a, b = glyph(c["font"], c["a"]), glyph(c["font"], c["b"])
    tol = c["tol"] * UPM
    res["tol"] = tol
    loops = _timed_sum(res, minkowski_sum, a, b, tol)
    if loops is None:
        return res
    t1 = time.perf_counter()
    f = ORACLE_SHARE * tol
    oracle = PairOracle(raw_glyph_polygon(c["font"], c["a"], f),
                        raw_glyph_polygon(c["font"], c["b"], f))
    chk = verify(loops, oracle, tol, 2 * f, region_size(a) + region_size(b),
                 np.random.default_rng(seed), n_boundary=150, n_random=100, ladder=(1.0,))
    res["fail"] += chk.pop("fail")
    res.update(chk)
    res["time_check"] = time.perf_counter() - t1
    return res
