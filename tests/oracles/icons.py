"""The icon cases' checks (the oracles of bench/icons.py): an icon's offset, ellipse sum
or inset against a polygon reference (Clipper and shapely on the icon flattened far below
tol), with the gaps and necks narrower than the engine's documented limit allowed to
close or open.  tests/test_sweep_regressions.py reruns the reduced failing cases saved in
tests/data/icons/ with :func:`load_case` and :func:`check_op`; bench/icons.py runs them on
whole icon sets.
"""

import time
from pathlib import Path

import numpy as np

from morph import minkowski as _minkowski
from tests.oracles import need

need("shapely", "the icons' polygon references")


ACCEPT = 1.25  # x tol: tol + the reference's flattening (2 x tol/20) + densification (tol/8)
# x tol: half the narrowest gap the engine may close (twice its convolution share, or
# twice its flattening and grid shares, see minkowski_sum's docstring) plus the
# reference's flattening
GAP = max(_minkowski.CONV_SHARE, _minkowski.FLAT_SHARE + _minkowski.GRID_SHARE) + 0.05
HAIR = 0.1     # x tol: half the widest gap the reference itself may fill (its input is
               # flattened within tol/20 on either side of the gap)


def compare(got, ref, tol):
    """Judge a result (shapely) against the polygon reference, following the contract of
    ``minkowski_sum``: every output boundary point within tol of the exact boundary
    (``fwd``, the certified direction; points in a gap of ours narrower than 2 HAIR tol
    that the reference fills are excused and counted, ``hairline``: where two parts of
    the exact result touch tangentially, e.g. @mdi/svg power-socket-de's offset pins
    touching its rim, the reference's own flattening closes the gap over several tol),
    every reference boundary point within tol of
    ours (``back``) except inside gaps and holes narrower than 2 GAP tol, which the
    engine may close (they are the points inside the reference's morphological closing
    by GAP tol, ``ref_closed``), and numbers of outer loops / holes (parts <= tol² not
    counted) of ours or of ours with hairline gaps closed between those of ``ref``,
    ``ref_closed`` and its opening (parts touching at a point may stay apart).  Returns a dict with fwd,
    back (lengths), topo and, per failed criterion, a message."""
    import shapely

    from tests.oracles import reference as R

    ga, gb = R._linework(got), R._linework(ref)
    pa = R._sample_points(ga, tol / 4)
    pb = R._sample_points(gb, tol / 4)
    da = shapely.distance(shapely.points(pa), gb) if len(pa) else np.zeros(0)
    db = shapely.distance(shapely.points(pb), ga) if len(pb) else np.zeros(0)
    far = np.flatnonzero(da > ACCEPT * tol)
    n_hair = 0
    got_closed = got.buffer(HAIR * tol, quad_segs=16).buffer(-HAIR * tol, quad_segs=16)
    if len(far):  # excused: in a hairline gap of ours (< 2 HAIR tol) the reference filled
        q = shapely.points(pa[far])
        hair = shapely.contains(got_closed, q) & shapely.contains(ref, q) & (
            shapely.distance(q, got_closed.boundary) > tol / 100)
        da[far[hair]] = 0.0
        n_hair = int(hair.sum())
    fwd = float(da.max()) if len(da) else 0.0
    closed = ref.buffer(GAP * tol, quad_segs=16).buffer(-GAP * tol, quad_segs=16)
    opened = ref.buffer(-GAP * tol, quad_segs=16).buffer(GAP * tol, quad_segs=16)
    far = np.flatnonzero(db > ACCEPT * tol)
    if len(far):  # excused: strictly inside the closing (a narrow gap or hole, filled)
        q = shapely.points(pb[far])
        inner = shapely.contains(closed, q) & (shapely.distance(q, closed.boundary)
                                               > tol / 20)
        db[far[inner]] = 0.0
    back = float(db.max()) if len(db) else 0.0
    t_got = R.count_outer_and_holes(got, tol * tol)
    t_ref = R.count_outer_and_holes(ref, tol * tol)
    t_cl = R.count_outer_and_holes(closed, tol * tol)
    t_op = R.count_outer_and_holes(opened, tol * tol)
    res = {"fwd": fwd, "back": back, "topo": (t_got, t_ref), "hairline": n_hair}
    if fwd > ACCEPT * tol:
        res["f"] = "output boundary %.3g tol from the reference's" % (fwd / tol)
        # all of it inside a narrow gap of ours that the reference fills: the tip of a
        # wedge of ours runs on (minkowski_sum's documented limit, 0.5 tol/sin(theta/2))
        far = np.flatnonzero(da > ACCEPT * tol)
        q = shapely.points(pa[far])
        wide = got.buffer(GAP * tol, quad_segs=16).buffer(-GAP * tol, quad_segs=16)
        if np.all(shapely.contains(wide, q) & shapely.contains(ref, q)):
            k = far[int(np.argmax(da[far]))]
            res["limit"] = ("wedge tip: output boundary %.3g tol from the reference's at "
                            "(%.6g, %.6g), in a gap of ours narrower than %.2g tol that the "
                            "reference fills (minkowski_sum's documented wedge-tip limit)"
                            % (fwd / tol, pa[k, 0], pa[k, 1], 2 * GAP))
            del res["f"]
    if back > ACCEPT * tol:
        k = int(np.argmax(db))
        res["b"] = "reference boundary %.3g tol from ours at (%.6g, %.6g)" % (
            back / tol, pb[k, 0], pb[k, 1])
        # all of it on a part of the reference thinner than 2 GAP tol (outside its
        # opening): the engine may drop such a feature (minkowski_sum's documented
        # narrow-feature limit); insets end in such slivers where a stroke is about as
        # wide as the inset's diameter (bootstrap-icons filetype-csv)
        far = np.flatnonzero(db > ACCEPT * tol)
        q = shapely.points(pb[far])
        if np.all(~shapely.contains(opened, q) & (shapely.distance(q, opened) > tol / 20)):
            thin = ("thin feature: reference boundary %.3g tol from ours at (%.6g, %.6g), "
                    "on a part of the reference thinner than %.2g tol (minkowski_sum's "
                    "documented narrow-feature limit)" % (back / tol, pb[k, 0], pb[k, 1],
                                                          2 * GAP))
            res["limit"] = "; ".join(filter(None, [res.get("limit"), thin]))
            del res["b"]
    t_hair = R.count_outer_and_holes(got_closed, tol * tol)
    if not any(all(min(c) <= g <= max(c) for g, c in zip(t, zip(t_ref, t_cl, t_op)))
               for t in (t_got, t_hair)):
        res["t"] = "loops/holes %s (%s with hairline gaps closed) vs reference %s " \
            "(closed over narrow gaps %s, opened at narrow necks %s)" % (
                t_got, t_hair, t_ref, t_cl, t_op)
    return res


def convex_minkowski_sum(poly, nib):
    """poly ⊕ nib for a shapely (Multi)Polygon and a convex polygon nib ((m, 2), about the
    origin, which it contains): poly ∪ ⋃_edges hull(edge ⊕ nib), as A ⊕ B = A ∪ (∂A ⊕ B)
    for B convex and holding 0.  Same polygons as the Clipper reference
    (tests.oracles.reference.polyline_minkowski_sum, ~10x slower on icons), unioned by GEOS."""
    import shapely

    from tests.oracles import reference as R

    hulls = []
    for ring in R._loops_of(poly):
        p0 = np.asarray(ring, float)
        p1 = np.roll(p0, -1, axis=0)
        pts = np.concatenate([p0[:, None, :] + nib[None], p1[:, None, :] + nib[None]], axis=1)
        hulls.append(shapely.convex_hull(shapely.multipoints(pts)))
    if not hulls:
        return poly
    return shapely.union_all(np.concatenate(hulls + [np.array([poly])]))


#: the offsets (radius / icon size) checked against shapely's buffer, and every operation
RADIUS = {"offset": 0.05, "inset": -0.02}
OPS = ("offset", "ellipse", "inset")


def icon_size(region):
    from morph.region import region_bbox

    box = region_bbox(region)
    return float(max(box[2] - box[0], box[3] - box[1]))


def check_op(region, op, s, rec):
    """One operation ("offset", "ellipse" or "inset") on a region with the icon's size
    s (tol = 1e-3 s, radius 0.05 s, ellipse 0.04 x 0.015 s at 30°, inset 0.02 s), judged by
    :func:`compare`; figures go into rec, a failure into rec["wrong"].  True on a pass."""
    from morph import piece as pc
    from morph.offset import offset_region
    from morph.minkowski import minkowski_sum
    from tests.oracles import reference as R

    tol = 1e-3 * s
    rec["stage"] = op
    t0, c0 = time.perf_counter(), time.process_time()
    if op in RADIUS:
        out = offset_region(region, RADIUS[op] * s, tol)
    else:
        nib = [pc.ellipse((0.0, 0.0), 0.04 * s, 0.015 * s, np.radians(30))]
        out = minkowski_sum(region, nib, tol)
    rec[op + "_s"] = time.perf_counter() - t0
    rec[op + "_cpu"] = time.process_time() - c0
    if op in RADIUS:
        # an inset keeps the input's cracks narrower than tol (the exact input's, a 2 r
        # channel each): their tips, where two sides cross at a small angle, move far
        # along the crack under a flattening of tol / 20 (bootstrap-icons zoom-out: the
        # handle's arc 1e-4 off the ring's, its channel's end 3.7 tol off); the inset's
        # reference flattens ten times finer
        flat = tol / (200 if RADIUS[op] < 0 else 20)
        ref = R.region_to_shapely(region, flat).buffer(RADIUS[op] * s, quad_segs=64)
    else:
        ref = convex_minkowski_sum(R.region_to_shapely(region, tol / 20),
                                   R.region_polylines(nib, tol / 20)[0])
    got = R.region_to_shapely(out, tol / 20)
    wrong = compare(got, ref, tol)
    rec[op + "_err"] = wrong.pop("fwd") / tol
    rec[op + "_back"] = wrong.pop("back") / tol
    rec[op + "_topo"] = wrong.pop("topo")
    rec[op + "_hairline"] = wrong.pop("hairline")
    if "limit" in wrong:
        rec.setdefault("limit", []).append("%s: %s" % (op, wrong.pop("limit")))
    if wrong:
        rec["wrong"] = "%s: %s" % (op, "; ".join(wrong.values()))
        return False
    return True


def check_filled(path, rec):
    from morph.parse import svg_region

    t0 = time.perf_counter()
    region = svg_region(path)
    s = icon_size(region)
    rec["parse_s"] = time.perf_counter() - t0
    for op in OPS:
        if not check_op(region, op, s, rec):
            return rec
    rec["stage"] = "done"
    return rec


# =========================================================================== reproducers

def save_case(path, region, op, s, **meta):
    """A failing input as json: the region (loops of pieces, homogeneous control points,
    floats written exactly), the operation and the icon's size (which fixes tol etc.)."""
    import json

    data = dict(meta, op=op, size=s,
                region=[[np.asarray(p, float).tolist() for p in loop] for loop in region])
    Path(path).write_text(json.dumps(data) + "\n")


def load_case(path):
    """(region, op, size, meta) of a case written by :func:`save_case`."""
    import json

    data = json.loads(Path(path).read_text())
    region = [[np.array(p, float) for p in loop] for loop in data.pop("region")]
    return region, data.pop("op"), data.pop("size"), data
