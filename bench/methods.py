"""Regenerate the paper's comparison of convolution methods (Figs. 29-32, Sec. 5.2.3).

    python -m bench.methods            # writes bench/methods.md and gallery/methods/*.png
    python -m bench.methods --md X.md  # the report only, to X.md
    python -m bench.methods --check    # the QAC / QAC* rows of one pair against the report

For each of four test pairs of curves (stated below, coordinates in 0..10 units) the
convolution is cut into compatible pairs (Gauss maps, :mod:`morph.gauss`; pairs whose
common angle range is below 1e-6 rad are skipped), and every pair is approximated with
Algorithm 5.1 (:func:`morph.paper.methods.approximate`) by each method until the sampled
distance error (Eqs. 49-53) is below e_d = 1 ... 1e-4, or the sampled normal deviation
(Eqs. 54-55) below e_n = 10 ... 0.5 degrees.  The number reported is the number of
control points of all output pieces, counted as one C0 chain of Bézier pieces: the sum
of the piece degrees plus one (joints shared, as in a B-spline with full interior
knots).  QAC is reported twice under the distance measure: with the sampled distance
as the paper does for fairness ("QAC"), and with its a-priori bound ("QAC*").

Two extra columns, "LSC-B" and "BIC-B", are not in Algorithm 5.1: one clamped cubic
B-spline per compatible pair with n uniform knots spans in C1's t, fitted by least
squares to 4 n exact convolution points (ends interpolated) or interpolating at the
Greville abscissae, n raised by one control point at a time until the same sampled
measure is met; count = sum over pairs of (n - 1), plus one.  They show what happens
when a method refines a C2 spline one control point at a time instead of splitting
into independent Bézier pieces (see bench/README.md).
"""

import sys
import time
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from morph import convolve, gauss  # noqa: E402 - after sys.path gets the repo root
from morph.paper import methods as M  # noqa: E402 - after sys.path gets the repo root
from morph import piece as pc  # noqa: E402 - after sys.path gets the repo root
from bench.stamp import stamp  # noqa: E402 - after sys.path gets the repo root

DIST_TOLS = (1.0, 0.1, 0.01, 0.001, 0.0001)
NORMAL_TOLS = (10.0, 5.0, 3.0, 1.0, 0.5)
DIST_METHODS = ("ctc", "lsc", "bic", "hic", "qac", "qac*", "lsc-b", "bic-b")
NORMAL_METHODS = ("ctc", "lsc", "bic", "hic", "lrc", "tmc", "src", "lsc-b", "bic-b")
HAUSDORFF_METHODS = ("lsc", "hic", "qac", "lrc", "tmc", "src")
# (key, measure of morph.paper.methods, tolerances, methods, tolerance label, heading)
STUDIES = (
    ("distance", "distance", DIST_TOLS, DIST_METHODS, "e_d",
     "Distance measure of the paper (Eqs. 49-53): C~2 = A - C1 against C2"),
    ("normal", "normal", NORMAL_TOLS, NORMAL_METHODS, "e_n",
     "Normal deviation of the paper (Eqs. 54-55), degrees: tangent of C~2 against C1's"),
    ("hausdorff", "hausdorff", DIST_TOLS, HAUSDORFF_METHODS, "e_h",
     "Not in the paper: distance from A to the exact convolution curve"),
)
MIN_SWEEP = 1e-6
MAX_DEPTH = 30
MAX_SPLINE = 400

# ----------------------------------------------------------------- the test curves

CUBIC_B1 = [(1, 2), (4, 1), (7, 1.5), (9, 4), (7.5, 7), (5, 5.5), (2.5, 7.5), (0.5, 5)]
CUBIC_B2 = [(0, 0), (2, -0.5), (3, 1), (2.5, 2.5), (1, 3), (-0.5, 1.5)]
QUAD_B1 = [(0, 0), (5, 1), (10, 0), (8, 5), (10, 10), (5, 8), (0, 10), (2, 5)]
QUAD_B2 = [(0, 0), (3, 0), (3, 2), (0, 2)]
ARC1 = dict(center=(2.0, 2.0), radius=8.0, start_deg=0.0, sweep_deg=90.0)
ARC2 = dict(center=(0.0, 0.0), radius=1.5, start_deg=0.0, sweep_deg=90.0)
BEZ1 = [(0, 0), (3, 8), (7, -8), (10, 0)]
BEZ2 = [(0, 0), (0, 3), (3, 3), (3, 0)]


def closed_uniform_bspline(points, degree):
    """Bézier pieces of a closed (periodic) uniform B-spline of degree 2 or 3."""
    p = np.asarray(points, float)
    n = len(p)
    out = []
    for i in range(n):
        q = p[[(i + k) % n for k in range(degree + 1)]]
        if degree == 3:      # uniform cubic B-spline segment -> Bézier
            b = [(q[0] + 4 * q[1] + q[2]) / 6, (4 * q[1] + 2 * q[2]) / 6,
                 (2 * q[1] + 4 * q[2]) / 6, (q[1] + 4 * q[2] + q[3]) / 6]
        elif degree == 2:    # uniform quadratic: edge midpoints and the corner
            b = [(q[0] + q[1]) / 2, q[1], (q[1] + q[2]) / 2]
        else:
            raise ValueError(degree)
        out.append(pc.from_points(b))
    return out


def circular_arc(center, radius, start_deg, sweep_deg):
    """Exact circular arc (rational quadratic, middle weight cos(sweep / 2))."""
    return pc.ellipse_arc(center, radius, radius, 0.0, np.radians(start_deg),
                          np.radians(sweep_deg))


def test_curves():
    """name -> (description, pieces of C1, pieces of C2, closed).

    As in the paper's Fig. 24 (C1 with 5, C2 with 27 control points), C1 is the
    small convex curve and C2 the larger non-convex one.  The roles matter for the
    paper's normal measure (Eqs. 54-55): where C1 has an inflection, s'(t) = 0 and
    C~2 = A - C1 is stationary, so its tangent is undefined (see bench/README.md).
    """
    return {
        "cubic B-splines": (
            "closed uniform cubic B-splines; C1 (convex) control points %s; "
            "C2 (non-convex) %s" % (CUBIC_B2, CUBIC_B1),
            closed_uniform_bspline(CUBIC_B2, 3), closed_uniform_bspline(CUBIC_B1, 3), True),
        "quadratic B-splines": (
            "closed uniform quadratic B-splines; C1 (convex) control points %s; "
            "C2 (non-convex) %s" % (QUAD_B2, QUAD_B1),
            closed_uniform_bspline(QUAD_B2, 2), closed_uniform_bspline(QUAD_B1, 2), True),
        "circular arcs": (
            "exact circular arcs (rational quadratic, weights 1, cos 45°, 1); C1 centre "
            "%s radius %g from %g° over %g°; C2 centre %s radius %g, same angles"
            % (ARC1["center"], ARC1["radius"], ARC1["start_deg"], ARC1["sweep_deg"],
               ARC2["center"], ARC2["radius"]),
            circular_arc(**ARC1), circular_arc(**ARC2), False),
        "cubic Béziers": (
            "open cubic Béziers; C1 (convex, turning 180°) %s; C2 (S-shaped, one "
            "inflection) %s" % (BEZ2, BEZ1),
            [pc.from_points(BEZ2)], [pc.from_points(BEZ1)], False),
    }


# ------------------------------------------------------------- compatible pairs

def open_edges(pieces):
    """Gauss-map curve edges of an open chain of pieces (no closing vertex)."""
    edges = []
    theta = None
    for p in pieces:
        for part in gauss.split_monotone(np.asarray(p, float)):
            t0, t1 = pc.end_tangents(part)
            a0 = np.arctan2(t0[1], t0[0])
            sweep = gauss._wrap(np.arctan2(t1[1], t1[0]) - a0)
            theta = a0 if theta is None else theta + gauss._wrap(a0 - theta)
            edges.append(gauss.Edge("curve", part, pc.start(part), theta, sweep))
            theta = theta + sweep
    return edges


def compatible_curve_pairs(pieces_a, pieces_b, closed):
    """(c1, c2) compatible pairs of two curves: curve edges with overlapping angles."""
    if closed:
        ea = [e for e in gauss.gauss_map(pieces_a) if e.kind == "curve"]
        eb = [e for e in gauss.gauss_map(pieces_b) if e.kind == "curve"]
    else:
        ea, eb = open_edges(pieces_a), open_edges(pieces_b)
    out = []
    for i, j, lo, hi, k in convolve.compatible_pairs(ea, eb):
        if hi - lo < MIN_SWEEP or ea[i].sweep == 0.0 or eb[j].sweep == 0.0:
            continue
        off = gauss.TWO_PI * k
        c1 = gauss.restrict(ea[i], lo, hi)[0]
        c2 = gauss.restrict(eb[j], lo - off, hi - off)[0]
        out.append((c1, c2))
    return out


# -------------------------------------------------- Algorithm 5.1 tolerance sweeps

def sweep_method(pairs, method, measure, tols):
    """Control points per tolerance (loosest first), memo shared across tolerances."""
    name = "qac" if method.startswith("qac") else method
    certified = method == "qac*"
    methods = [M.method_functions(name, measure, certified, memo={}) for _ in pairs]
    counts = []
    for tol in tols:
        pieces = []
        try:
            for (c1, c2), method in zip(pairs, methods):
                segs = M.subdivide(c1, c2, method, tol, MAX_DEPTH)
                pieces.extend(s.piece for s in segs)
            counts.append(M.control_point_count(pieces))
        except Exception as exc:  # noqa: BLE001 - reported in the table
            counts.append("fail (%s)" % type(exc).__name__)
    return counts


# --------------------------------------------- the B-spline variant of LSC / BIC

def _ratio(num, den):
    """num / den with 0 where den == 0 (the Cox-de Boor convention 0/0 = 0)."""
    out = np.zeros(np.broadcast_shapes(np.shape(num), np.shape(den)))
    np.divide(num, den, out=out, where=np.broadcast_to(den > 0, out.shape))
    return out


def bspline_basis(knots, p, t, deriv=False):
    """Cox-de Boor basis matrix (len(t), len(knots) - p - 1), or its derivative."""
    knots = np.asarray(knots, float)
    t = np.clip(np.atleast_1d(np.asarray(t, float)), knots[0], knots[-1])[:, None]
    nspan = len(knots) - 1
    basis = ((knots[:-1] <= t) & (t < knots[1:])).astype(float)
    last = np.flatnonzero(knots[:-1] < knots[1:])[-1]
    at_end = t[:, 0] >= knots[-1]
    basis[at_end] = 0.0
    basis[at_end, last] = 1.0
    levels = [basis]
    for k in range(1, p + 1):
        prev, m = levels[-1], nspan - k
        a = _ratio(t - knots[:m], knots[k:k + m] - knots[:m])
        b = _ratio(knots[k + 1:k + 1 + m] - t, knots[k + 1:k + 1 + m] - knots[1:1 + m])
        levels.append(a * prev[:, :m] + b * prev[:, 1:m + 1])
    if not deriv:
        return levels[p]
    prev, m = levels[p - 1], nspan - p
    a = _ratio(p, knots[p:p + m] - knots[:m])
    b = _ratio(p, knots[p + 1:p + 1 + m] - knots[1:1 + m])
    return a * prev[:, :m] - b * prev[:, 1:m + 1]


def spline_knots(n, p=3):
    """Clamped uniform knot vector for n control points of degree p."""
    inner = np.linspace(0.0, 1.0, n - p + 1)[1:-1]
    return np.concatenate([np.zeros(p + 1), inner, np.ones(p + 1)])


def fit_spline(c1, c2, n, kind, p=3):
    """Control points (n, 2) of the LSC-B / BIC-B cubic B-spline for a pair."""
    knots = spline_knots(n, p)
    if kind == "lsc-b":
        ts = np.linspace(0.0, 1.0, 4 * n)
        pts, _ = M.convolution_points(c1, c2, ts)
        basis = bspline_basis(knots, p, ts)
        ctrl = np.empty((n, 2))
        ctrl[0], ctrl[-1] = pts[0], pts[-1]
        rhs = pts - np.outer(basis[:, 0], pts[0]) - np.outer(basis[:, -1], pts[-1])
        ctrl[1:-1], *_ = np.linalg.lstsq(basis[:, 1:-1], rhs, rcond=None)
        return knots, ctrl
    greville = np.array([knots[i + 1:i + p + 1].mean() for i in range(n)])
    pts, _ = M.convolution_points(c1, c2, greville)
    return knots, np.linalg.solve(bspline_basis(knots, p, greville), pts)


def spline_error(c1, c2, knots, ctrl, measure, p=3):
    """The same sampled measures as morph.paper.methods, on a B-spline approximation."""
    samples = max(M.ERROR_SAMPLES, 8 * len(ctrl) + 1)
    if measure == "distance":
        dist = M._curve_distance(c2)

        def f(t):
            return dist(bspline_basis(knots, p, t) @ ctrl - pc.evaluate(c1, t))
    else:
        def f(t):
            d1 = pc.derivative(c1, t)
            d2 = bspline_basis(knots, p, t, deriv=True) @ ctrl - d1
            return np.degrees(np.arctan2(np.abs(pc.cross2(d1, d2)),
                                         np.abs(np.sum(d1 * d2, axis=1))))
    return M._sampled_max(f, samples)[0]


def sweep_spline(pairs, kind, measure, tols):
    """Smallest n per pair meeting each tolerance (doubling, then bisection on n).

    Assumes the error decreases with n (true in practice up to small wiggles); n is
    capped at MAX_SPLINE, reported as "> count" when a pair does not reach tol.
    """
    caches = [dict() for _ in pairs]

    def err(k, n):
        if n not in caches[k]:
            c1, c2 = pairs[k]
            knots, ctrl = fit_spline(c1, c2, n, kind)
            caches[k][n] = spline_error(c1, c2, knots, ctrl, measure)
        return caches[k][n]

    ns = [4] * len(pairs)
    counts = []
    for tol in tols:
        total, failed = 0, False
        for k in range(len(pairs)):
            lo = ns[k]
            if err(k, lo) > tol:
                hi = lo
                while hi < MAX_SPLINE and err(k, hi) > tol:
                    lo, hi = hi, min(2 * hi, MAX_SPLINE)
                if err(k, hi) > tol:
                    failed, lo = True, hi
                else:
                    while hi - lo > 1:              # err(lo) > tol >= err(hi)
                        mid = (lo + hi) // 2
                        lo, hi = (mid, hi) if err(k, mid) > tol else (lo, mid)
                    lo = hi
            ns[k] = lo
            total += lo - 1
        counts.append(("> %d" % (total + 1)) if failed else total + 1)
    return counts


# ----------------------------------------------------------------------- output

def markdown_table(title, tols, methods, rows, unit):
    head = "| %s | %s |" % (unit, " | ".join(m.upper() for m in methods))
    sep = "|" + "---|" * (len(methods) + 1)
    lines = [title, "", head, sep]
    for tol, row in zip(tols, rows):
        label = ("%g°" % tol) if unit == "e_n" else "%g" % tol
        lines.append("| %s | %s |" % (label, " | ".join(str(v) for v in row)))
    return "\n".join(lines)


COLORS = {
    "ctc": (200, 40, 40), "lsc": (30, 110, 200), "bic": (20, 170, 170),
    "hic": (230, 140, 20), "qac": (120, 60, 170), "qac*": (190, 120, 230),
    "lrc": (90, 90, 90), "tmc": (40, 150, 60), "src": (150, 110, 40),
    "lsc-b": (30, 60, 120), "bic-b": (10, 100, 100),
}


def plot(results, path, panel=(360, 280)):
    """Log-log plots, one row per test pair and one column per study: control points
    against tolerance (loosest on the left)."""
    names = list(results)
    pw, ph = panel
    ncol = len(STUDIES)
    margin = (58, 30, 16, 40)   # left, top, right, bottom
    img = Image.new("RGB", (ncol * pw, len(names) * ph + 120), "white")
    draw = ImageDraw.Draw(img)
    font = ImageFont.load_default(size=12)
    small = ImageFont.load_default(size=10)
    all_counts = [v for r in results.values() for col in r.values()
                  for counts in col.values() for v in counts if isinstance(v, int)]
    ymin, ymax = np.log10(max(1, min(all_counts))), np.log10(max(all_counts) * 1.2)
    for row, name in enumerate(names):
        for col, (key, _, tols, _, unit, _) in enumerate(STUDIES):
            x0, y0 = col * pw + margin[0], row * ph + margin[1]
            x1, y1 = (col + 1) * pw - margin[2], (row + 1) * ph - margin[3]
            lx = np.log10(np.array(tols))
            xa, xb = lx.max(), lx.min()

            def px(v):
                return x0 + (xa - v) / (xa - xb) * (x1 - x0)

            def py(v):
                return y1 - (v - ymin) / (ymax - ymin) * (y1 - y0)

            draw.rectangle([x0, y0, x1, y1], outline=(0, 0, 0))
            for dec in range(int(np.floor(ymin)), int(np.ceil(ymax)) + 1):
                for mant in (1, 2, 5):
                    v = np.log10(mant * 10.0 ** dec)
                    if ymin <= v <= ymax:
                        draw.line([x0, py(v), x1, py(v)], fill=(225, 225, 225))
                        draw.text((x0 - 6, py(v)), "%g" % (mant * 10.0 ** dec),
                                  fill=(0, 0, 0), font=small, anchor="rm")
            for tol, v in zip(tols, lx):
                draw.line([px(v), y1, px(v), y1 + 4], fill=(0, 0, 0))
                label = ("%g°" % tol) if unit == "e_n" else "%g" % tol
                draw.text((px(v), y1 + 6), label, fill=(0, 0, 0), font=small, anchor="mt")
            label = name.replace("é", "e")      # the default bitmap font has no é
            draw.text((x0, y0 - 16), "%s: %s" % (label, unit), fill=(0, 0, 0), font=font)
            for m, counts in results[name][key].items():
                pts = [(px(v), py(np.log10(c))) for v, c in zip(lx, counts)
                       if isinstance(c, int)]
                color = COLORS[m]
                dashed = m.endswith("-b") or m == "qac*"
                for a, b in zip(pts[:-1], pts[1:]):
                    if dashed:
                        for f in np.linspace(0, 1, 9)[:-1:2]:
                            g = f + 1 / 8
                            draw.line([a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]),
                                       a[0] + g * (b[0] - a[0]), a[1] + g * (b[1] - a[1])],
                                      fill=color, width=2)
                    else:
                        draw.line([a, b], fill=color, width=2)
                for p in pts:
                    draw.ellipse([p[0] - 2.5, p[1] - 2.5, p[0] + 2.5, p[1] + 2.5], fill=color)
    ly = len(names) * ph + 8
    draw.text((10, ly), "control points (log) against tolerance (log, tighter to the right). "
              "e_d: paper's distance, e_n: paper's normal deviation (deg), e_h: distance to "
              "the exact convolution. Dashed: QAC* (a-priori bound), LSC-B / BIC-B.",
              fill=(0, 0, 0), font=font)
    for k, m in enumerate(COLORS):
        x = 10 + (k % 6) * 150
        y = ly + 26 + (k // 6) * 20
        draw.line([x, y + 6, x + 24, y + 6], fill=COLORS[m], width=3)
        draw.text((x + 30, y), m.upper(), fill=(0, 0, 0), font=font)
    path.parent.mkdir(parents=True, exist_ok=True)
    img.save(path)


def plot_pairs(curves, path, size=360):
    """The four test pairs (C1 dark, C2 red) and their LSC convolution at e_d = 0.01."""
    img = Image.new("RGB", (4 * size, size + 24), "white")
    draw = ImageDraw.Draw(img)
    font = ImageFont.load_default(size=12)
    for k, (name, (_, a, b, closed)) in enumerate(curves.items()):
        pairs = compatible_curve_pairs(a, b, closed)
        conv = [s.piece for c1, c2 in pairs for s in M.approximate(c1, c2, "lsc", 0.01)]
        polys = [[pc.sample(p, 64) for p in group] for group in (a, b, conv)]
        allp = np.concatenate([q for g in polys for q in g])
        lo, hi = allp.min(axis=0), allp.max(axis=0)
        scale = (size - 30) / max(hi - lo)
        for group, color, width in zip(polys, ((20, 20, 20), (200, 40, 40), (30, 110, 200)),
                                       (2, 2, 2)):
            for q in group:
                xy = [(k * size + 15 + (x - lo[0]) * scale, size - 15 - (y - lo[1]) * scale)
                      for x, y in q]
                draw.line(xy, fill=color, width=width)
        draw.text((k * size + 10, size + 4), name.replace("é", "e") +
                  " (C1 black, C2 red, LSC convolution blue)", fill=(0, 0, 0), font=font)
    path.parent.mkdir(parents=True, exist_ok=True)
    img.save(path)


def main(md=ROOT / "bench" / "methods.md"):
    """Write the report to ``md``; the plots go to gallery/methods/ with the committed
    report only."""
    start = time.time()
    curves = test_curves()
    results = {}
    out = ["# Convolution methods compared (bench/methods.py)", "", stamp(), "",
           "Number of control points (sum of Bézier piece degrees + 1) needed by "
           "Algorithm 5.1 (split at the mid tangent angle) for each sampled tolerance. "
           "e_d: the paper's distance measure in input units (Eqs. 49-53); e_n: the "
           "paper's normal deviation in degrees (Eqs. 54-55); e_h: distance from the "
           "approximation to the exact convolution curve (not in the paper; it gives "
           "LRC/TMC/SRC a distance column). QAC* = QAC with its a-priori bound (Eqs. "
           "39-40) instead of the sampled distance. LSC-B / BIC-B = one cubic B-spline "
           "per compatible pair, one control point added at a time (not Algorithm 5.1). "
           "LRC, TMC, SRC have no e_d column (their trace is exact, the measure is 0); "
           "QAC has no e_n column (normals exact). Settings: LSC/BIC cubic Béziers, LSC "
           "%d samples; TMC %d tangent samples, SRC %d samples, both s(t) of degree %d; "
           "every error sampled at %d uniform t per piece and refined near the maxima; "
           "at most %d halvings. \"fail\" = a pair did not reach the tolerance."
           % (M.LSC_SAMPLES, M.TMC_SAMPLES, M.SRC_SAMPLES, M.S_DEGREE, M.ERROR_SAMPLES,
              MAX_DEPTH), ""]
    for name, (desc, a, b, closed) in curves.items():
        t0 = time.time()
        pairs = compatible_curve_pairs(a, b, closed)
        res = {}
        out += ["## %s" % name, "", desc + ". %d compatible curve pairs." % len(pairs), ""]
        for key, measure, tols, methods, unit, heading in STUDIES:
            res[key] = {}
            for m in methods:
                sweep = sweep_spline if m.endswith("-b") else sweep_method
                res[key][m] = sweep(pairs, m, measure, tols)
            rows = [[res[key][m][i] for m in methods] for i in range(len(tols))]
            out += [heading + ":", "", markdown_table("", tols, methods, rows, unit).strip(), ""]
        results[name] = res
        dt = time.time() - t0
        out += ["(%.1f s)" % dt, ""]
        print("%s: %.1f s" % (name, dt), file=sys.stderr)
    if Path(md).resolve() == (ROOT / "bench" / "methods.md").resolve():
        plot(results, ROOT / "gallery" / "methods" / "methods.png")
        plot_pairs(curves, ROOT / "gallery" / "methods" / "pairs.png")
    out.append("Total time %.1f s." % (time.time() - start))
    text = "\n".join(out) + "\n"
    Path(md).write_text(text)
    print(text)


def check(case="cubic B-splines"):
    """The report's QAC and QAC* counts under the paper's distance measure for one test
    pair, against what :func:`sweep_method` computes now: [(what, reported, computed)].
    (About 5 s: the pair of the headline conclusion in bench/README.md.)"""
    from bench.mdtable import cell, section, tables

    desc, a, b, closed = test_curves()[case]
    pairs = compatible_curve_pairs(a, b, closed)
    table = tables(section((ROOT / "bench" / "methods.md").read_text(), case))[0]
    out = []
    for m in ("qac", "qac*"):
        counts = sweep_method(pairs, m, "distance", DIST_TOLS)
        for tol, n in zip(DIST_TOLS, counts):
            out.append(("methods.md %s %s at e_d = %g" % (case, m.upper(), tol),
                        cell(table, "%g" % tol, m.upper()), str(n)))
    return out


if __name__ == "__main__":
    if "--check" in sys.argv[1:]:
        bad = [r for r in check() if r[1] != r[2]]
        for what, reported, computed in bad:
            print("%s: report %s, computed %s" % (what, reported, computed))
        sys.exit(1 if bad else 0)
    main(*sys.argv[sys.argv.index("--md") + 1:][:1] if "--md" in sys.argv else ())
