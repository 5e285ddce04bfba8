"""The source masters of a brushed variable font: a variable font's own masters and
intermediate ones where its interpolation and the nib do not commute.

A variable source's glyphs at a normalized location are its own interpolation
(fontTools' glyph set at that location: gvar deltas with IUP, or CFF2 blends),
piecewise multilinear between the breakpoints of its regions (every region's
start, peak and end per axis: :func:`source_grid`).  A brushed font whose masters
lie on the full product of a grid containing those breakpoints blends along a grid
edge between masters A and B the outlines c_A + e(n_A) and c_B + e(n_B), while the
exact sum at a fraction u of the way is c_u + e(n_u): the source part blends
exactly, the nib part does not where the normals turn between A and B (a wider or
slanted master).  :func:`region_blend_error` measures, for every element of a
glyph (:func:`morph.compatible.region_elements`, the same parameters in every
master), the distance between the blended outline point and the exact one at equal
parameter (an upper bound of the distance between the curves), at u = 1/4, 1/2,
3/4 and with every nib of the nib axis.  :func:`refine_sources` halves the grid's
intervals (:func:`morph.fonts.variable_grid.refine_grid`) until it is within the
budget, glyph by glyph: each glyph gets its own grid (its variations are stored over
its own masters), so a glyph whose outline turns fast between the source's masters
does not multiply the masters of every other glyph.
"""

import numpy as np

from .variable_grid import refine_grid

__all__ = ["source_grid", "refine_sources", "region_blend_error", "region_loops",
           "counter_clockwise", "MAX_SOURCE_MASTERS"]

#: at most this many source masters of one glyph after refinement (before the nib
#: axis): a bound on one glyph's cost (its fit at every master, its gvar tuples, at
#: most 4095, and its CFF2 blends), not the font's
MAX_SOURCE_MASTERS = 257

#: fractions of an interval at which the blend is measured
FRACTIONS = (0.25, 0.5, 0.75)

def _region_axes(font):
    """Every region of a variable font's glyph variations as {tag: (start, peak,
    end)} (gvar's tuples, or the CFF2 variation store's regions)."""
    tags = [a.axisTag for a in font["fvar"].axes]
    if "gvar" in font:
        seen = set()
        for variations in font["gvar"].variations.values():
            for v in variations:
                key = tuple(sorted((t, tuple(map(float, r))) for t, r in v.axes.items()))
                if key not in seen:
                    seen.add(key)
                    yield dict(key)
    elif "CFF2" in font:
        store = font["CFF2"].cff.topDictIndex[0].VarStore
        for region in ([] if store is None else store.otVarStore.VarRegionList.Region):
            yield {tags[k]: (float(ax.StartCoord), float(ax.PeakCoord), float(ax.EndCoord))
                   for k, ax in enumerate(region.VarRegionAxis) if ax.PeakCoord != 0}


def source_grid(font):
    """Per axis tag the sorted normalized breakpoints of a variable font's
    interpolation: -1, 0, 1 where the axis reaches them, and every region's start,
    peak and end; ``{}`` for a static font."""
    if "fvar" not in font:
        return {}
    grid = {a.axisTag: {0.0} for a in font["fvar"].axes}
    for region in _region_axes(font):
        for tag, triple in region.items():
            grid[tag].update(round(v, 12) for v in triple)
    return {t: sorted(v) for t, v in grid.items()}


def _locations(grid):
    """The grid's nodes as normalized locations, the default (all 0) first."""
    import itertools

    tags = list(grid)
    combos = sorted(itertools.product(*(grid[t] for t in tags)),
                    key=lambda c: (any(c), c))
    return [dict(zip(tags, c)) for c in combos]


def region_loops(glyph_set, name):
    """A glyph's contours in a glyph set as closed loops of cartesian pieces, in the
    font's direction (:func:`counter_clockwise` turns them)."""
    from ..parse.pens import record_contours

    contours = record_contours(glyph_set[name].draw, "glyph %r" % name, glyph_set)
    loops = []
    for c in contours:
        pieces = [np.asarray(p, float) for p in c.pieces]
        pieces = [p[:, :2] / p[:, 2:] if p.shape[1] == 3 else p for p in pieces]
        if pieces and np.any(pieces[-1][-1] != pieces[0][0]):
            pieces.append(np.array([pieces[-1][-1], pieces[0][0]]))
        if pieces:
            loops.append(pieces)
    return loops


def _signed_area(loops):
    """Signed area of loops of pieces, their control polygons' (the sign of a glyph's
    total area is its outer contours' direction)."""
    total = 0.0
    for loop in loops:
        pts = np.vstack([p[:-1] for p in loop])
        x, y = pts[:, 0], pts[:, 1]
        total += 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    return total


def counter_clockwise(loops_by_master):
    """Loops turned so that outer ones run counter-clockwise: reversed when the
    glyph's area at the first master is negative (TrueType draws outer contours
    clockwise, CFF counter-clockwise; a font that does not follow its convention
    is read by the sign of the area)."""
    if _signed_area(loops_by_master[0]) >= 0:
        return loops_by_master
    return [[[p[::-1] for p in reversed(loop)] for loop in loops] for loops in loops_by_master]


def region_blend_error(loops_by_master, nibs, label="glyph", near=float("inf")):
    """Largest distance, over fractions u (:data:`FRACTIONS`) and ``nibs``, between
    the blend (1 - u) X_A + u X_B of the brushed outlines of masters A and B and the
    brushed outline X_u of the source at u (font units).  ``loops_by_master``: the
    glyph's loops at A, B and each fraction (:func:`region_loops`).

    Taken at equal parameter over every element (an upper bound of the distance
    between the curves' points); where that exceeds ``near`` it is measured between
    the filled outlines instead (:func:`_fill_distance`): the untrimmed convolution's
    inner loops and swallowtails move between the masters but lie inside the fill,
    where they change nothing a renderer shows."""
    from ..compatible import _nib_part, region_elements

    loops = region_elements(counter_clockwise(loops_by_master), label)
    m = len(loops_by_master)
    worst = 0.0
    for nib in nibs:
        xs = [[el.centre(_FINE) + _nib_part(el, [nib] * m, list(range(m)), _FINE)
               for el in loop] for loop in loops]
        for k, u in enumerate(FRACTIONS):
            d = max((float(np.linalg.norm((1 - u) * x[0] + u * x[1] - x[2 + k],
                                          axis=-1).max()) for loop in xs for x in loop),
                    default=0.0)
            if d > near:
                d = _fill_distance([[(1 - u) * x[0] + u * x[1] for x in loop] for loop in xs],
                                   [[x[2 + k] for x in loop] for loop in xs])
            worst = max(worst, d)
    return worst


#: flattening parameters per element: 32 chords (a half turn of a 60-unit nib
#: within 0.04 units of its arc)
_FINE = np.linspace(0.0, 1.0, 33)

#: Clipper's integer units per font unit
_CLIP = 1000.0


def _fill_distance(blend, exact):
    """Hausdorff distance between the boundaries of the nonzero fills of two
    outlines given as loops of flattened elements ((k, 2) point arrays each),
    filled by Clipper."""
    a, b = _fill(blend), _fill(exact)
    if not a or not b:
        return 0.0 if not a and not b else float("inf")
    return max(_to_polylines(np.vstack(a), b), _to_polylines(np.vstack(b), a))


def _fill(loops):
    """The nonzero fill of closed polylines, as Clipper's closed polygons."""
    import pyclipper

    pc = pyclipper.Pyclipper()
    paths = [np.round(np.vstack([x[:-1] for x in loop]) * _CLIP).astype(np.int64).tolist()
             for loop in loops]
    pc.AddPaths([p for p in paths if len(p) >= 3], pyclipper.PT_SUBJECT, True)
    out = pc.Execute(pyclipper.CT_UNION, pyclipper.PFT_NONZERO, pyclipper.PFT_NONZERO)
    return [np.asarray(p, float) / _CLIP for p in out]


def _to_polylines(points, polygons, chunk=512):
    """Largest distance of ``points`` (n, 2) from the edges of closed ``polygons``."""
    a = np.vstack(polygons)
    b = np.vstack([np.roll(p, -1, axis=0) for p in polygons])
    d = b - a
    dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    worst = 0.0
    for start in range(0, len(points), chunk):
        x = points[start:start + chunk, None]
        t = np.clip(np.einsum("kij,ij->ki", x - a, d) / dd, 0.0, 1.0)
        near = np.linalg.norm(x - (a + t[..., None] * d), axis=-1).min(axis=1)
        worst = max(worst, float(near.max()))
    return worst


def refine_sources(font, names, nibs, budget, refine=True):
    """(normalized locations of the source masters, the default first; per glyph of
    ``names`` the indices of its own masters among them; report) of a font brushed
    into a variable font.

    Every glyph gets its own master grid: the product of :func:`source_grid`, with
    intervals halved until :func:`region_blend_error` of that glyph with every nib
    of ``nibs`` is within ``budget`` along every axis at every node of the other
    axes (``refine`` False: the grid as it is, its errors measured).  The variable
    font stores each glyph's variations over its own masters (gvar's tuples are per
    glyph; CFF2 selects a VarData per glyph by vsindex; HVAR maps each glyph to its
    own row): the sparse masters of a designspace, where a glyph is absent from the
    intermediate masters it does not need.  So a glyph whose outline turns fast
    between the source's masters adds masters to itself only, and the cost is the
    sum of the glyphs' own grids, not the product of every glyph's refinements.
    Report: ``given`` (the source grid's masters), ``added`` (locations added over
    all glyphs), ``axes`` (values per axis, the most any glyph has), ``error`` (the
    largest blend error left), ``errors_before`` (per axis, the largest before
    refining), ``budget``, ``most`` (the most masters of one glyph) and
    ``hardest`` (that glyph), ``refined`` (glyphs given masters of their own).
    ``([{}], {name: [0]}, None)`` for a static font.  Raises MorphError where a glyph
    would need more than :data:`MAX_SOURCE_MASTERS` masters.
    """
    grid = source_grid(font)
    if not grid:
        return [{}], {n: [0] for n in names}, None
    sets = {}

    def glyph_set(loc):
        key = tuple(sorted(loc.items()))
        if key not in sets:
            sets[key] = font.getGlyphSet(location=dict(key), normalized=True)
        return sets[key]

    def errors_of(name):
        def errors(edges):
            worst = [0.0] * len(edges)
            for k, (a, lo, hi, others) in enumerate(edges):
                at = [{**dict(others), a: lo + u * (hi - lo)} for u in (0.0, 1.0) + FRACTIONS]
                loops = [region_loops(glyph_set(loc), name) for loc in at]
                if loops[0]:
                    worst[k] = region_blend_error(loops, nibs, "glyph %r" % name, near=budget)
            return worst
        return errors

    locations = _locations(grid)
    index = {_key(loc): k for k, loc in enumerate(locations)}
    given = len(locations)
    per_glyph, report = {}, {"given": given, "budget": budget, "error": 0.0,
                             "errors_before": {}, "axes": {a: len(v) for a, v in grid.items()},
                             "most": given, "hardest": None, "refined": 0}
    for name in names:
        refined, rep = refine_grid(grid, errors_of(name), budget if refine else float("inf"),
                                   MAX_SOURCE_MASTERS, "glyph %r of the variable source" % name,
                                   "the nib does not follow its interpolation: use a "
                                   "smaller nib or a larger tolerance")
        per_glyph[name] = own = _indices(_locations(refined), index, locations)
        _merge_report(report, rep, name, len(own), given)
    report["added"] = len(locations) - given
    return locations, per_glyph, report


def _indices(own, index, locations):
    """The indices of the locations ``own`` in ``locations``, those not there yet
    appended (``index``: each location's key -> its index, kept up to date)."""
    out = []
    for loc in own:
        k = index.setdefault(_key(loc), len(locations))
        if k == len(locations):
            locations.append(loc)
        out.append(k)
    return out


def _key(loc):
    return tuple(sorted((t, round(float(v), 12)) for t, v in loc.items()))


def _merge_report(report, rep, name, masters, given):
    """One glyph's refine_grid report folded into the font's."""
    report["error"] = max(report["error"], rep["error"])
    for a, v in rep["errors_before"].items():
        report["errors_before"][a] = max(report["errors_before"].get(a, 0.0), v)
    for a, v in rep["axes"].items():
        report["axes"][a] = max(report["axes"][a], v)
    if masters > report["most"]:
        report["most"], report["hardest"] = masters, name
    report["refined"] += masters > given
