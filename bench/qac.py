"""QAC convolution curves and Minkowski sums of glyphs: size and time vs tolerance.

    python -m bench.qac [--md bench/qac.md]   # 2-5 minutes; prints the tables, writes the report

For each font (bundled Noto Sans: TrueType = quadratic outlines, CFF = cubic
outlines), each case and each tolerance tol = 1e-1 ... 1e-5 em (x 1000 font units,
units per em = 1000):

- ``convolution(a, b, tol)`` (Sec. 3.3, QAC with Algorithm 4.1, type-3 pieces kept so
  the pieces form closed loops): number of pieces, control points, largest degree,
  largest a-priori bound (Eqs. 39-40), sampled error, time;
- ``minkowski_sum(a, b, tol)`` (trimmed boundary): pieces, control points, time.

Control points are counted for closed loops of Bézier pieces with shared joints: the
sum of the piece degrees (a loop of k cubics has 3k).  "sampled err" is the largest
distance measure of Sec. 5.2 (Eqs. 49-53: point minus C1(t), distance to C2, both
roles tried) over 60 random points of the QAC pieces, divided by tol: it shows how
conservative the a-priori bound is.  Times are single runs (perf_counter), fonts
preloaded.

Cases: a glyph swept by a fixed-orientation elliptic nib (Fig. 5: 'S' + ellipse of
semi-axes 40 x 12 units rotated by 30 degrees, exact rational conic), and the glyph
pairs T+M, O+M, S+g.  A last table runs Algorithm 4.1 alone (``convolve_edges``) on
seeded random cubic-cubic compatible pairs (``tests/reference.random_compatible_pair``,
sizes 0.5-4 units, sweeps 10-85 degrees): pieces per pair and sampled error / bound.

Bound ratios: the a-priori bound of Eq. 40 as the paper writes it (max_s |C2(s) -
Q2(s)| at equal parameters: largest coefficient of |X2 - W2 Q2|^2 over the smallest
weight coefficient) against ``qac_error_bound`` (Q2 against C2 reparametrised,
certified the same way) and the sampled distance from Q2 to the curve C2, on the
random pairs (all kinds with a non-quadratic C2, halved 0-4 times) and on the
curve-curve pairs of the glyph cases (CFF), halved 0-4 times in angle.
"""

import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from morph import convolve, gauss, minkowski, parse  # noqa: E402 - after sys.path gets the repo root
from morph import piece as pc  # noqa: E402 - after sys.path gets the repo root
from bench.stamp import stamp  # noqa: E402 - after sys.path gets the repo root
from morph import qac  # noqa: E402 - after sys.path gets the repo root
from tests.oracles import reference as R  # noqa: E402 - after sys.path gets the repo root
from tests.test_convolve import pair_error  # noqa: E402 - after sys.path gets the repo root

TOLS_EM = (1e-1, 1e-2, 1e-3, 1e-4, 1e-5)
UPM = 1000.0
NIB = [pc.ellipse((0.0, 0.0), 40.0, 12.0, np.radians(30.0))]
CASES = [("S + nib", "S", None), ("T + M", "T", "M"), ("O + M", "O", "M"), ("S + g", "S", "g")]
FONTS = [("TrueType", None), ("CFF", parse.cubic_test_font_path())]
SAMPLES = 60


def control_points(pieces):
    """Control points of closed loops of pieces with shared joints: sum of degrees."""
    return int(sum(len(p) - 1 for p in pieces))


def sampled_error(region_a, region_b, conv, rng):
    """Largest sampled distance measure over random points of the QAC pieces."""
    qac = [c for c in conv if c.kind == "qac"]
    if not qac:
        return 0.0
    ga = [gauss.gauss_map(loop) for loop in region_a]
    gb = [gauss.gauss_map(loop) for loop in region_b]
    worst = 0.0
    for w, t in zip(rng.integers(0, len(qac), SAMPLES), rng.uniform(0.0, 1.0, SAMPLES)):
        c = qac[w]
        ia, i, ib, j = c.source
        p, d = R.bezier_eval(c.piece, [t], 1)
        worst = max(worst, float(pair_error(p, d, ga[ia][i], gb[ib][j])[0]))
    return worst


def run_case(region_a, region_b, tol, rng):
    t0 = time.perf_counter()
    conv = convolve.convolution(region_a, region_b, tol, keep_type3=True)
    t_conv = time.perf_counter() - t0
    pieces = [c.piece for c in conv]
    err = sampled_error(region_a, region_b, conv, rng)
    t0 = time.perf_counter()
    loops = minkowski.minkowski_sum(region_a, region_b, tol)
    t_sum = time.perf_counter() - t0
    sum_pieces = [p for loop in loops for p in loop]
    return dict(
        conv_n=len(pieces), conv_cp=control_points(pieces),
        conv_deg=max(len(p) - 1 for p in pieces),
        bound=max(c.bound for c in conv), err=err, t_conv=t_conv,
        sum_n=len(sum_pieces), sum_cp=control_points(sum_pieces), t_sum=t_sum,
        n_qac=sum(1 for c in conv if c.kind == "qac"))


def random_pairs_table(rng, n_pairs=30, tols=(1e-2, 1e-3, 1e-4, 1e-5, 1e-6)):
    """Algorithm 4.1 on random cubic-cubic pairs: pieces per pair, error vs bound."""
    out = ["### Algorithm 4.1 on %d random cubic-cubic pairs per tolerance" % n_pairs, "",
           "| tol | pieces per pair | ctrl pts per pair | max sampled err / tol "
           "| median sampled err / bound | time per pair (ms) |",
           "|---|---|---|---|---|---|"]
    for tol in tols:
        n = cps = 0
        ratios, worst, t_all = [], 0.0, 0.0
        for _ in range(n_pairs):
            c1, c2 = R.random_compatible_pair(rng, "cubic-cubic")
            edges = []
            for c in (c1, c2):
                prof = R.tangent_angle_profile(c, 65)
                edges.append(gauss.Edge("curve", c, pc.start(c), prof[0], prof[-1] - prof[0]))
            ea, eb = edges
            (_, _, lo, hi, shift), = convolve.compatible_pairs([ea], [eb])
            t0 = time.perf_counter()
            res = convolve.convolve_edges(ea, eb, lo, hi, shift, tol)
            t_all += time.perf_counter() - t0
            n += len(res)
            cps += control_points([c.piece for c in res])
            for w in rng.integers(0, len(res), 4):
                piece, bound = res[w].piece, res[w].bound
                p, d = R.bezier_eval(piece, rng.uniform(0, 1, 1), 1)
                e = float(pair_error(p, d, ea, eb)[0])
                worst = max(worst, e)
                ratios.append(e / bound if bound > 0 else 0.0)
        out.append("| %g | %.1f | %.1f | %.2g | %.2g | %.1f |" % (
            tol, n / n_pairs, cps / n_pairs, worst / tol, np.median(ratios),
            1e3 * t_all / n_pairs))
    return "\n".join(out)


def eq40_bound(c2, q2):
    """Eq. 40 as written: same-parameter bound, smallest weight coefficient."""
    from morph import bernstein as bz
    num = bz.elevate(c2[:, :2], 2) - bz.multiply(c2[:, 2:3], q2)
    sq = bz.multiply(num[:, :1], num[:, :1])[:, 0] + bz.multiply(num[:, 1:], num[:, 1:])[:, 0]
    return float(np.sqrt(max(float(sq.max()), 0.0)) / np.min(c2[:, 2]))


def _ratio_row(label, c2s):
    old, new, geo = [], [], []
    for c2 in c2s:
        try:
            q2 = qac.quadratic_approximation(c2)
        except ValueError:
            continue
        b = qac.qac_error_bound(c2, q2)[0]
        if b <= 1e-12 * max(1.0, np.abs(pc.cartesian(c2)).max()):
            continue                       # an exact quadratic C2
        qp = R.bezier_eval(np.column_stack([q2, np.ones(3)]), np.linspace(0, 1, 41))[0]
        old.append(eq40_bound(c2, q2))
        new.append(b)
        geo.append(R.point_curve_distance(qp, c2, samples=513)[0].max())
    old, new, geo = map(np.array, (old, new, geo))
    return "| %s | %d | %.3g | %.3g | %.3g | %.3g | %.3g |" % (
        label, len(old), np.median(old / new), np.min(old / new), np.max(old / new),
        np.median(new / geo), np.max(new / geo))


def _halvings(c, k):
    ts = np.linspace(0.0, 1.0, 2 ** k + 1)
    return [pc.subsegment(c, a, b) for a, b in zip(ts[:-1], ts[1:])]


def bound_ratio_table(rng, glyph_cases):
    """Eq. 40 as written / qac_error_bound, and qac_error_bound / sampled distance."""
    out = ["| C2 pieces | n | Eq. 40 / new: median | min | max "
           "| new / sampled distance: median | max |", "|---|---|---|---|---|---|---|"]
    pairs = []
    for kind in ("cubic-cubic", "conic-cubic", "conic-quad", "cubic-conic"):
        for _ in range(25):
            if kind == "cubic-conic":
                c2, _ = R.random_compatible_pair(rng, "conic-cubic")
            else:
                _, c2 = R.random_compatible_pair(rng, kind)
            pairs.append(c2)
    for k in (0, 2, 4):
        out.append(_ratio_row("random pairs, halved %d times" % k,
                              [s for c in pairs for s in _halvings(c, k)]))
    for label, region_a, region_b in glyph_cases:
        c2s = []
        for la in region_a:
            for lb in region_b:
                ea_, eb_ = gauss.gauss_map(la), gauss.gauss_map(lb)
                for i, j, lo, hi, shift in convolve.compatible_pairs(ea_, eb_):
                    ea, eb = ea_[i], eb_[j]
                    if ea.kind != "curve" or eb.kind != "curve" or hi - lo < 1e-6:
                        continue
                    if ea.sweep == 0.0 or eb.sweep == 0.0:
                        continue
                    off = gauss.TWO_PI * shift
                    c2s.append(gauss.restrict(ea, lo, hi)[0])
                    c2s.append(gauss.restrict(eb, lo - off, hi - off)[0])
        for k in (0, 2, 4):
            out.append(_ratio_row("%s, halved %d times" % (label, k),
                                  [s for c in c2s for s in _halvings(c, k)]))
    return "\n".join(out)


def table(font_label, case_label, rows):
    out = ["### %s, %s" % (case_label, font_label), "",
           "| tol (em) | tol (units) | conv pieces (QAC) | conv ctrl pts | max deg "
           "| max bound / tol | sampled err / tol | conv time (s) "
           "| sum pieces | sum ctrl pts | sum time (s) |",
           "|---|---|---|---|---|---|---|---|---|---|---|"]
    for tol_em, r in rows:
        tol = tol_em * UPM
        out.append("| %g | %g | %d (%d) | %d | %d | %.2g | %.2g | %.2f | %d | %d | %.2f |" % (
            tol_em, tol, r["conv_n"], r["n_qac"], r["conv_cp"], r["conv_deg"],
            r["bound"] / tol, r["err"] / tol, r["t_conv"], r["sum_n"], r["sum_cp"], r["t_sum"]))
    return "\n".join(out)


def main(md=ROOT / "bench" / "qac.md"):
    start = time.perf_counter()
    rng = np.random.default_rng(1998)
    sections = []
    summary = ["| case | font | conv ctrl pts at 1e-1 ... 1e-5 em | sum ctrl pts at 1e-1 ... 1e-5 em "
               "| total time (s) |", "|---|---|---|---|---|"]
    for font_label, font in FONTS:
        parse.load_font(font)
        for case_label, a, b in CASES:
            region_a = parse.glyph_region(a, font).region
            region_b = NIB if b is None else parse.glyph_region(b, font).region
            rows = []
            for tol_em in TOLS_EM:
                rows.append((tol_em, run_case(region_a, region_b, tol_em * UPM, rng)))
            text = table(font_label, case_label, rows)
            print(text + "\n", flush=True)
            sections.append(text)
            summary.append("| %s | %s | %s | %s | %.1f |" % (
                case_label, font_label,
                " / ".join(str(r["conv_cp"]) for _, r in rows),
                " / ".join(str(r["sum_cp"]) for _, r in rows),
                sum(r["t_conv"] + r["t_sum"] for _, r in rows)))
    pairs = random_pairs_table(rng)
    print(pairs + "\n", flush=True)
    cff = parse.cubic_test_font_path()
    ratios = bound_ratio_table(np.random.default_rng(7), [
        ("%s (CFF)" % lab, parse.glyph_region(a, cff).region,
         NIB if b is None else parse.glyph_region(b, cff).region)
        for lab, a, b in CASES if lab != "T + M"])
    print(ratios + "\n", flush=True)
    elapsed = time.perf_counter() - start
    header = __doc__.strip().splitlines()
    text = "\n".join([
        "# " + header[0],
        "",
        "\n".join(header[1:]),
        "",
        stamp(seconds=elapsed),
        "",
        "## Summary",
        "",
        "\n".join(summary),
        "",
        "## Per case",
        "",
        "\n\n".join(sections),
        "",
        "## Algorithm 4.1 alone",
        "",
        pairs,
        "",
        "## Bound ratios",
        "",
        ratios,
        "",
    ])
    Path(md).write_text(text)
    print("\n".join(summary))
    print("\nwrote %s in %.0f s" % (md, elapsed))


def check(cases=("T + M", "O + M", "S + g")):
    """The summary rows of bench/qac.md for ``cases`` in the TrueType font (control points
    of the convolution and of the sum at every tolerance) against what the code gives
    now: [(what, reported, computed)].  (About 2 s.)"""
    from bench.mdtable import section, tables

    table = tables(section((ROOT / "bench" / "qac.md").read_text(encoding="utf-8"),
                           "Summary"))[0]
    out = []
    for label, a, b in CASES:
        if label not in cases:
            continue
        region_a, region_b = parse.glyph_region(a).region, parse.glyph_region(b).region
        conv, summ = [], []
        for tol_em in TOLS_EM:
            tol = tol_em * UPM
            conv.append(control_points([c.piece for c in convolve.convolution(
                region_a, region_b, tol, keep_type3=True)]))
            loops = minkowski.minkowski_sum(region_a, region_b, tol)
            summ.append(control_points([p for loop in loops for p in loop]))
        row = [r for r in table[1:] if r[0] == label and r[1] == "TrueType"][0]
        out.append(("qac.md %s TrueType: convolution control points" % label, row[2],
                    " / ".join(map(str, conv))))
        out.append(("qac.md %s TrueType: sum control points" % label, row[3],
                    " / ".join(map(str, summ))))
    return out


if __name__ == "__main__":
    main(*sys.argv[sys.argv.index("--md") + 1:][:1] if "--md" in sys.argv else ())
