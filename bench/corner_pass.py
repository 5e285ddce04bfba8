"""What the corner pass of a sum touches and costs (:func:`morph.minkowski._sum`'s
second and later trimming rounds, :func:`morph.minkowski._tip_tolerances`).

    python -m bench.corner_pass [relief:4 relief:0.5:round relief:2:x4 stroke:hershey-sans ...]

``relief:TOL[:NIB][:xN]``: the Relief SingleLine subset stroked as
``bench/relief_profile.py`` strokes it (one chunk of its 62 glyphs, N times over
when ``xN`` is given; NIB ``broad``, the default, or ``round``; the geometry share
of ``plan(TOL)``): the glyphs whose corners are refined are named, and ``xN`` shows
whether a later round's calls grow with the glyphs of a chunk; ``stroke:SET``:
``morph stroke`` of a set of ``bench/stroke_profile.py`` (``--jobs 1``).  Per run:
the sums, the first trimming round's pieces and Python calls, the rounds the corner
pass adds (rows approximated again, packed slots trimmed again with their pieces
and loops), the Python calls and CPU of those rounds' convolution and trimming, and
for every junction the pass refines: its turn (cos(phi / 2)), the a-priori bound
e / cos(phi / 2) of the rule, and its distance to the nearest convolution piece
(about 0 at a crossing of two pieces; more where the trimming's Newton iteration
did not converge and the junction sits on its grid point).  Python calls are
load-independent; CPU times are of one run (with the profiler's overhead).
"""

import collections
import os
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # as the morph command sets it

ROOT = Path(__file__).resolve().parents[1]
sys.path.append(str(ROOT))  # after PYTHONPATH: a checkout named there is measured


def _counted(fn):
    """(fn(), Python-level calls, CPU s): sys.setprofile, nested counts not kept."""
    n = [0]

    def prof(frame, event, arg):
        if event in ("call", "c_call"):
            n[0] += 1

    old = sys.getprofile()
    sys.setprofile(prof)
    t = time.process_time()
    try:
        out = fn()
    finally:
        sys.setprofile(old)
    return out, n[0], time.process_time() - t


def install(stats, tips):
    """Wrap morph.minkowski's _sum, _trimmed, _tip_tolerances and convolution (rows=)
    to count into ``stats`` (a Counter) and list the refined junctions in ``tips``."""
    import morph.minkowski as mk

    sum_, trimmed, rule, conv = mk._sum, mk._trimmed, mk._tip_tolerances, mk.convolution
    state = {"round": 0, "slot_of": None}

    def w_sum(*a, **k):
        state["round"] = 0
        state["slot_of"] = k.get("slot_of", a[5] if len(a) > 5 else None)
        stats["sums"] += 1
        return sum_(*a, **k)

    def w_trimmed(part, *a, **k):
        later = state["round"] > 0
        state["round"] += 1
        out, n, t = _counted(lambda: trimmed(part, *a, **k))
        key = "later rounds" if later else "first round"
        stats[key + ": trims"] += 1
        stats[key + ": pieces"] += len(part)
        stats[key + ": loops out"] += len(out[1])
        stats[key + ": calls"] += n
        stats[key + ": CPU ms"] += 1e3 * t
        return out

    def w_rule(out, part, tol):
        finer = rule(out, part, tol)
        if finer:
            tips.extend(_refined_junctions(out, part, tol))
            stats["rows refined"] += len(finer)
            if state["slot_of"] is not None:
                stats.setdefault("refined slots", set()).update(
                    _refined_slots(part, finer, state["slot_of"]))
        return finer

    def w_conv(*a, **k):
        if k.get("rows") is None:
            return conv(*a, **k)
        out, n, t = _counted(lambda: conv(*a, **k))
        stats["later rounds: convolution calls"] += n
        stats["later rounds: convolution CPU ms"] += 1e3 * t
        return out

    mk._sum, mk._trimmed, mk._tip_tolerances, mk.convolution = w_sum, w_trimmed, w_rule, w_conv


def _refined_slots(conv, finer, slot_of):
    """The packed slots (regions of a packed sum) of the pieces of the rows ``finer``
    refines."""
    import numpy as np

    from morph import piece as pc

    k = np.flatnonzero(np.isin(conv.row, sorted(finer)))
    return np.unique(slot_of(pc.end_points(conv.pieces.take(k))[0])).tolist()


def _refined_junctions(out, conv, tol):
    """[(cos(phi / 2), e / cos(phi / 2), distance to the nearest piece, tol)] of the
    junctions of ``out`` with a piece the rule of
    :func:`morph.minkowski._tip_tolerances` refines; the distance is from the
    junction to the nearest convolution piece near it (0 up to rounding where the
    junction is a crossing that the trimming's Newton iteration found; where that
    did not converge the junction sits on its grid point)."""
    import numpy as np

    import morph.minkowski as mk
    from morph import piece as pc
    from morph.nearest import nearest_params_in_range

    pts, cos_half = mk._corners(out)
    sharp = np.flatnonzero(cos_half < float(conv.bound.max()) / (mk.CONV_SHARE * tol))
    want = mk.CONV_SHARE * tol * mk.TIP_MARGIN * np.maximum(cos_half[sharp], mk.TIP_FLOOR)
    corner, piece = mk._corners_near(pts[sharp], pc.bboxes(conv.pieces), mk.TIP_REACH * tol)
    at = np.unique(corner[conv.bound[piece] > want[corner]])
    e = np.zeros(len(sharp))
    np.maximum.at(e, corner, conv.bound[piece])
    stacked = pc.stack(conv.pieces.take(piece))
    p = pts[sharp[corner]]
    t = nearest_params_in_range(stacked, p, np.zeros(len(p)), np.ones(len(p)), samples=257)
    d = np.hypot(*(pc.jet_many(stacked, np.arange(len(p)), t)[0] - p).T)
    off = np.full(len(sharp), np.inf)
    np.minimum.at(off, corner, d)
    c = cos_half[sharp[at]]
    return list(zip(c.tolist(), (e[at] / np.maximum(c, mk.TIP_FLOOR)).tolist(),
                    off[at].tolist(), [tol] * len(at)))


def run(what, stats, tips):
    """Count one run (module docstring) into ``stats`` and ``tips`` (those that
    :func:`install` was given, emptied first)."""
    stats.clear()
    del tips[:]
    if what.startswith("relief:"):
        from bench.relief_profile import SUBSET, _inputs, _pass
        from morph.fonts.brush import parse_glyph_spec
        from morph.parse.ufo import glyph_names_for, load_ufo

        tol, *opts = what.split(":")[1:]
        copies = int(next((o[1:] for o in opts if o.startswith("x")), 1))
        sets, nib = _inputs(next((o for o in opts if not o.startswith("x")), "broad"))
        _pass(sets * copies, nib, float(tol))
        names = glyph_names_for(load_ufo(SUBSET, lazy=False), parse_glyph_spec("A-Z,a-z,0-9"))
        slots = stats.pop("refined slots", ())
        if slots:
            stats["refined glyphs (slots)"] = " ".join(
                "%s(%d)" % (names[k % len(sets)], k) for k in sorted(slots))
    else:
        import morph.cli as cli
        from bench.stroke_profile import run_args

        with tempfile.TemporaryDirectory() as d:
            args, _ = run_args(what, d)
            cli.main(args, standalone_mode=False)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    stats, tips = collections.Counter(), []
    install(stats, tips)
    for what in argv or ["relief:4", "relief:0.5"]:
        run(what, stats, tips)
        print("%s:" % what)
        for k in sorted(stats):
            v = stats[k]
            v = " ".join(map(str, sorted(v))) if isinstance(v, set) else v
            print("  %-34s %s" % (k, ("%.1f" % v) if isinstance(v, float) else v))
        for c, apriori, off, tol in tips:
            print("  refined junction: cos(phi/2) %.3f, e/cos %.3f tol, %.2g tol off the "
                  "nearest piece" % (c, apriori / tol, off / tol))


if __name__ == "__main__":
    main()
