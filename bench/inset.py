"""Insets (negative offsets) of random glyphs against shapely's negative buffer.

    python -m bench.inset [--n 60] [--seed 1] [--fonts ttf,cff,lobster,cormorant,amiri]
                          [--tol-em 1e-4] [--md bench/inset.md]

Each case: a random glyph of a random font, turned by a random angle, inset by a
random radius (0.5 % to 6 % of its size) with ``morph.inset_region`` at ``tol-em``
of the em.  Checks, independent of morph's trimming:

- distance: every boundary sample of the inset (12 per piece) lies at the radius
  from the glyph's boundary (shapely distance to the glyph flattened within tol / 20),
  within tol + tol / 20;
- area: the inset and shapely's ``buffer(-r, quad_segs=256)`` of the same flattened
  glyph differ by an area of at most (tol + 2 tol / 20 + the buffer's arc error) x
  the buffer's boundary length (nothing missing, nothing extra);
- loops: the same number of loops as shapely's polygon rings (a part that vanished
  or a hole that opened is counted the same way), unless a feature is within 2 tol of
  closing (shapely's rings at radius +- 2 tol disagree), where either count is right.

Times: morph's inset in-process against shapely's buffer of the flattened glyph (the
flattening not counted) and against the strongest polygon peer, Clipper's offset
(pyclipper, round joins, arc tolerance tol / 4, the glyph flattened within tol / 4:
flattening counted); sizes: morph's control points (rational pieces, before any
export) against the peers' polygon vertices.  Writes a markdown summary with ``--md``.
"""

import argparse
import time

import numpy as np
import shapely
from shapely.geometry import LineString, MultiLineString

from bench.stamp import stamp
from tests.oracles.sweep import OTHER_FONTS, font_path, glyph, glyph_pool, region_size
from morph import piece as pc
from morph.offset import inset_region
from morph.region import transform_region
from tests.oracles.reference import region_polylines, region_to_shapely


def _rings(geom):
    polys = getattr(geom, "geoms", [geom])
    return sum(1 + len(p.interiors) for p in polys if not p.is_empty)


def _upm(font):
    from tests.oracles.sweep import _ttfont

    return float(_ttfont(font)["head"].unitsPerEm)


def run(font, name, angle, frac, tol_em):
    region = glyph(font, name)
    m = np.array([[np.cos(angle), -np.sin(angle), 0.0], [np.sin(angle), np.cos(angle), 0.0]])
    region = transform_region(region, m)
    tol = tol_em * _upm(font)
    r = frac * region_size(region)
    flat = tol / 20
    t0 = time.perf_counter()
    out = inset_region(region, r, tol)
    t_morph = time.perf_counter() - t0
    src = region_to_shapely(region, flat)
    t0 = time.perf_counter()
    ref = src.buffer(-r, quad_segs=256)
    t_shapely = time.perf_counter() - t0
    fails = []
    if out:
        lines = MultiLineString([LineString(np.vstack([p, p[:1]]))
                                 for p in region_polylines(region, flat)])
        pts = np.vstack([pc.evaluate(p, np.linspace(0, 1, 12, endpoint=False))
                         for loop in out for p in loop])
        d = np.abs(shapely.distance(shapely.points(pts), lines) - r).max()
        if d > tol + flat + 1e-9 * r:
            fails.append("distance %.3g tol" % (d / tol))
    mine = region_to_shapely(out, flat) if out else None
    diff = (mine.symmetric_difference(ref).area if mine is not None else ref.area)
    slack = (tol + 2 * flat + r * 2e-5) * max(ref.length, tol)
    if diff > slack:
        fails.append("area %.3g of slack" % (diff / slack))
    n_ref = _rings(ref) if not ref.is_empty else 0
    if len(out) != n_ref:
        near = {_rings(src.buffer(-(r + s), quad_segs=256)) for s in (-2 * tol, 2 * tol)}
        if len(near) == 1:
            fails.append("loops %d, shapely %d" % (len(out), n_ref))
    n_ref_pts = sum(len(ring.coords) - 1 for poly in getattr(ref, "geoms", [ref])
                    if not poly.is_empty for ring in [poly.exterior, *poly.interiors])
    t_clip, n_clip, e_clip = clipper_inset(region, r, tol, ref)
    return dict(case="%s/%s/%.4f/%.4f" % (font, name, angle, frac), loops=len(out),
                t_morph=t_morph, t_shapely=t_shapely, fails=fails,
                pts=sum(len(p) for loop in out for p in loop), ref_pts=n_ref_pts,
                t_clip=t_clip, n_clip=n_clip, e_clip=e_clip / tol)


def clipper_inset(region, r, tol, ref):
    """The strongest polygon peer: Clipper's offset (pyclipper, round joins) by -r of
    the region flattened within tol / 4, arc tolerance tol / 4, 1000 units per tol
    (so that its result is within tol).  Returns (seconds for flattening and offset,
    vertices, the largest distance of its vertices from shapely's reference boundary)."""
    import pyclipper

    scale = 1000.0 / tol
    t0 = time.perf_counter()
    polys = region_polylines(region, tol / 4)
    co = pyclipper.PyclipperOffset(2.0, 0.25 * tol * scale)
    co.AddPaths([np.round(np.asarray(p) * scale).astype(np.int64).tolist() for p in polys],
                pyclipper.JT_ROUND, pyclipper.ET_CLOSEDPOLYGON)
    rings = co.Execute(-r * scale)
    dt = time.perf_counter() - t0
    pts = np.concatenate([np.asarray(q, float) / scale for q in rings]) if rings else None
    err = float(shapely.distance(shapely.points(pts), ref.boundary).max()) if pts is not None \
        and not ref.is_empty else 0.0
    return dt, sum(len(q) for q in rings), err


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=60)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--fonts", default="ttf,cff," + ",".join(sorted(OTHER_FONTS)))
    ap.add_argument("--tol-em", type=float, default=1e-4)
    ap.add_argument("--md")
    args = ap.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    fonts = args.fonts.split(",")
    for f in fonts:
        font_path(f)
    rows = []
    for k in range(args.n):
        font = fonts[rng.integers(len(fonts))]
        pool = glyph_pool(font)
        name = pool[rng.integers(len(pool))]
        res = run(font, name, rng.uniform(0, 2 * np.pi), rng.uniform(0.005, 0.06), args.tol_em)
        rows.append(res)
        print("%3d %-34s loops %2d  morph %5.1f ms %4d pts  shapely %4.1f ms %5d  clipper %4.1f "
              "ms %5d (err %.2f tol)  %s"
              % (k, res["case"], res["loops"], 1e3 * res["t_morph"], res["pts"],
                 1e3 * res["t_shapely"], res["ref_pts"], 1e3 * res["t_clip"], res["n_clip"],
                 res["e_clip"],
                 "FAIL " + "; ".join(res["fails"]) if res["fails"] else "ok"), flush=True)
    bad = [r for r in rows if r["fails"]]
    tm = np.array([r["t_morph"] for r in rows]) * 1e3
    ts = np.array([r["t_shapely"] for r in rows]) * 1e3
    ratio = np.median([r["ref_pts"] / max(r["pts"], 1) for r in rows if r["pts"]])
    tc = np.array([r["t_clip"] for r in rows]) * 1e3
    clip_ratio = np.median([r["n_clip"] / max(r["pts"], 1) for r in rows if r["pts"]])
    summary = ("%d cases (seed %d, fonts %s, tol %g em): %d failed; morph inset median "
               "%.0f ms (max %.0f), shapely buffer of the flattened glyph median %.0f ms; "
               "shapely's vertices / morph's control points: median %.1f; Clipper offset "
               "(flattening included) median %.1f ms, its vertices / morph's control "
               "points median %.1f, its distance to shapely's boundary median %.2f tol, "
               "worst %.2f tol"
               % (len(rows), args.seed, ",".join(fonts), args.tol_em, len(bad),
                  np.median(tm), tm.max(), np.median(ts), ratio, np.median(tc), clip_ratio,
                  np.median([r["e_clip"] for r in rows]), max(r["e_clip"] for r in rows)))
    print(summary)
    for r in bad:
        print("FAIL", r["case"], "; ".join(r["fails"]))
    if args.md:
        with open(args.md, "w") as fh:
            fh.write("# Insets against shapely (bench/inset.py)\n\n%s\n\n" % stamp())
            fh.write("See the script's docstring for the checks.\n\n- %s\n" % summary)
            for r in bad:
                fh.write("  - FAIL `%s`: %s\n" % (r["case"], "; ".join(r["fails"])))
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main())
