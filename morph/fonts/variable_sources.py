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
budget for every brushed glyph.
"""

import numpy as np

from .variable_grid import grid_size, refine_grid

__all__ = ["source_grid", "refine_sources", "region_blend_error", "region_loops",
           "counter_clockwise", "MAX_SOURCE_MASTERS"]

#: at most this many source masters after refinement (before the nib axis)
MAX_SOURCE_MASTERS = 129

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
    """Largest distance, over the elements of a glyph, fractions u
    (:data:`FRACTIONS`) and ``nibs``, between the blend (1 - u) X_A + u X_B of the
    brushed outlines of masters A and B and the brushed outline X_u of the source at
    u (font units).  ``loops_by_master``: the glyph's loops at A, B and each fraction
    (:func:`region_loops`).

    Each element's distance is taken at equal parameter (an upper bound of the
    distance between the curves' points); where that exceeds ``near`` it is measured
    between the curves themselves: both ways, from the points of one to the other
    flattened (:data:`_FINE` chords per element), within :data:`WINDOW` elements
    either side (a short piece whose tangent swings between the masters sweeps the
    nib points of its neighbours' normals: at equal parameter far apart, as curves
    close)."""
    from ..compatible import _nib_part, region_elements

    loops = region_elements(counter_clockwise(loops_by_master), label)
    m = len(loops_by_master)
    worst = 0.0
    for nib in nibs:
        for loop in loops:
            xs = [el.centre(_FINE) + _nib_part(el, [nib] * m, list(range(m)), _FINE)
                  for el in loop]
            for j, x in enumerate(xs):
                for k, u in enumerate(FRACTIONS):
                    blend = (1 - u) * x[0, _EVERY] + u * x[1, _EVERY]
                    d = float(np.linalg.norm(blend - x[2 + k, _EVERY], axis=-1).max())
                    if d > near:
                        d = _curve_distance(xs, j, k, u)
                    worst = max(worst, d)
    return worst


#: elements either side of one whose curve distance is measured (:func:`region_blend_error`)
WINDOW = 2

#: flattening parameters per element (64 chords) and every fourth of them, the
#: sample points
_FINE = np.linspace(0.0, 1.0, 65)
_EVERY = slice(None, None, 4)


def _curve_distance(xs, j, k, u):
    """Two-sided distance between the blend at ``u`` of element ``j``'s masters A
    and B and the exact outline (master 2 + k), each point against the other curve
    flattened within :data:`WINDOW` elements of ``j``."""
    near = [xs[i % len(xs)] for i in range(j - WINDOW, j + WINDOW + 1)]
    blend = np.vstack([(1 - u) * x[0] + u * x[1] for x in near])
    exact = np.vstack([x[2 + k] for x in near])
    mine = slice(WINDOW * len(_FINE), (WINDOW + 1) * len(_FINE))
    return max(_to_polyline(blend[mine], exact), _to_polyline(exact[mine], blend))


def _to_polyline(points, line):
    """Largest distance of ``points`` (n, 2) from the polyline ``line`` (k, 2)."""
    a, d = line[:-1], np.diff(line, axis=0)
    dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    t = np.clip(np.einsum("kij,ij->ki", points[:, None] - a, d) / dd, 0.0, 1.0)
    return float(np.linalg.norm(points[:, None] - (a + t[..., None] * d), axis=-1)
                 .min(axis=1).max())


def refine_sources(font, names, nibs, budget, refine=True):
    """(normalized locations of the source masters, the default first; report) of a
    font brushed into a variable font: the product of :func:`source_grid`, with
    intervals halved until :func:`region_blend_error` of every glyph of ``names``
    with every nib of ``nibs`` is within ``budget`` along every axis at every node
    of the other axes (``refine`` False: the grid as it is, its errors measured).
    Report: :func:`morph.fonts.variable_grid.refine_grid`'s, and ``given`` (the
    source grid's masters) and ``added``.  ``([{}], None)`` for a static font.

    Raises:
        MorphError: more than :data:`MAX_SOURCE_MASTERS` would be needed.
    """
    grid = source_grid(font)
    if not grid:
        return [{}], None
    sets = {}

    def glyph_set(loc):
        key = tuple(sorted(loc.items()))
        if key not in sets:
            sets[key] = font.getGlyphSet(location=dict(key), normalized=True)
        return sets[key]

    def errors_of(edges):
        worst = [0.0] * len(edges)
        for name in names:                  # one glyph's loops in memory at a time
            for k, (a, lo, hi, others) in enumerate(edges):
                at = [{**dict(others), a: lo + u * (hi - lo)} for u in (0.0, 1.0) + FRACTIONS]
                loops = [region_loops(glyph_set(loc), name) for loc in at]
                if loops[0]:
                    worst[k] = max(worst[k], region_blend_error(
                        loops, nibs, "glyph %r" % name, near=budget))
        return worst

    given = grid_size(grid)
    refined, report = refine_grid(grid, errors_of, budget if refine else float("inf"),
                                  MAX_SOURCE_MASTERS, "the variable source",
                                  "the nib does not follow its interpolation: use a "
                                  "smaller nib or a larger tolerance")
    report.update(given=given, added=grid_size(refined) - given)
    return _locations(refined), report
