"""Intermediate skeleton masters: where a skeleton designspace's own interpolation
and the nib do not commute, masters are added until every instance is within its
share of the error budget.

Between two skeleton masters A and B the variable font blends the stroked outlines:
centre c_A + e(n_A) and c_B + e(n_B).  The centre lines blend exactly as the
skeleton's own interpolation does, but the nib points do not: the exact sum at a
fraction u of the way has e(n_u), n_u the normal of the blended centre line, and
(1 - u) e(n_A) + u e(n_B) differs from it wherever the normals differ (a slant or a
change of proportion turns them).  :func:`blend_error` measures that difference for
every element of every stroked glyph (the nib part of pieces at equal parameter,
and of the corner arcs at equal nib parameter: upper bounds of the distance between
the outlines), at u = 1/4, 1/2, 3/4, with each nib of the nib axis.
:func:`refine_skeleton` halves every interval of the skeleton masters' grid (per
axis, at the grid's other nodes; :func:`morph.fonts.variable_grid.refine_grid`)
whose error exceeds the budget, until all hold, and makes the new masters as
instances of the skeleton's own interpolation (fontTools' ``VariationModel`` over
the masters' normalized locations: points, anchors, advances, component offsets and
kerning), so the compiled font interpolates the skeleton as the designspace does
and the nib part within the budget.
"""

import copy
import itertools
from dataclasses import replace

import numpy as np

__all__ = ["blend_error", "refine_skeleton", "normalized_locations", "MAX_SKELETON_MASTERS"]

#: at most this many skeleton masters after refinement
MAX_SKELETON_MASTERS = 65

#: fractions of an interval at which the blend is measured
FRACTIONS = (0.25, 0.5, 0.75)

#: sample parameters per element
_S = np.linspace(0.0, 1.0, 17)


def _triple(ax):
    """(minimum, default, maximum) of a designspace axis in design coordinates."""
    return tuple(float(ax.map_forward(v)) for v in (ax.minimum, ax.default, ax.maximum))


def normalized_locations(skel):
    """Every skeleton master's location normalized to [-1, 1] per axis (by axis
    name), from its design coordinates."""
    out = []
    for loc in skel.locations:
        n = {}
        for ax in skel.axes:
            lo, de, hi = _triple(ax)
            v = float(loc.get(ax.name, de))
            n[ax.name] = 0.0 if v == de else ((v - de) / (hi - de) if v > de
                                              else (v - de) / (de - lo))
        out.append(n)
    return out


def _design(ax, n):
    lo, de, hi = _triple(ax)
    return de + n * (hi - de) if n >= 0 else de + n * (de - lo)


def _glyph_values(font, name):
    """A glyph's interpolable numbers as one flat array: contour points, anchors,
    advance, component offsets."""
    g = font[name]
    vals = [(p.x, p.y) for c in g.contours for p in c.points]
    vals += [(a.x, a.y) for a in g.anchors]
    vals.append((g.width, 0.0))
    vals += [tuple(c.transformation)[4:6] for c in g.components]
    return np.array(vals, float).reshape(-1)


def _set_glyph_values(g, vals):
    vals = iter(np.asarray(vals).reshape(-1, 2))
    for c in g.contours:
        for p in c.points:
            p.x, p.y = (float(v) for v in next(vals))
    for a in g.anchors:
        a.x, a.y = (float(v) for v in next(vals))
    g.width = float(next(vals)[0])
    for c in g.components:
        t = tuple(c.transformation)
        dx, dy = next(vals)
        c.transformation = t[:4] + (float(dx), float(dy))


class _Interpolator:
    """The skeleton's own interpolation of the glyphs ``names`` at any normalized
    location (fontTools' VariationModel over the masters' normalized locations)."""

    def __init__(self, skel, names):
        from fontTools.varLib.models import VariationModel

        self.skel, self.names = skel, names
        self.locs = normalized_locations(skel)
        self.model = VariationModel(self.locs, [ax.name for ax in skel.axes])
        from ..compatible import IncompatibleMasters

        self.deltas = {}
        for n in names:
            vals = [_glyph_values(f, n) for f in skel.fonts]
            for m, v in enumerate(vals):
                if v.shape != vals[0].shape:
                    raise IncompatibleMasters(
                        "glyph %r: master %d has other points, anchors or components than "
                        "master 0 (%d numbers against %d)" % (n, m, len(v), len(vals[0])),
                        "points")
            self.deltas[n] = self.model.getDeltas(vals)
        # kerning: every pair of any master (0 where a master lacks it)
        pairs = sorted(set().union(*(f.kerning.keys() for f in skel.fonts)))
        self.pairs = pairs
        self.kerning = self.model.getDeltas([np.array([f.kerning.get(p, 0.0) for p in pairs],
                                                      float) for f in skel.fonts]) \
            if pairs else None

    def values(self, name, loc):
        return self.model.interpolateFromDeltas(loc, self.deltas[name])

    def font(self, loc, style):
        """A copy of the default master with the glyphs and the kerning at ``loc``."""
        f = copy.deepcopy(self.skel.fonts[self.skel.default])
        for n in self.names:
            _set_glyph_values(f[n], self.values(n, loc))
        if self.kerning is not None:
            values = self.model.interpolateFromDeltas(loc, self.kerning)
            f.kerning.clear()
            f.kerning.update({p: round(float(v), 3) for p, v in zip(self.pairs, values)
                              if round(float(v), 3) != 0})
        f.info.styleName = style
        return f


def _paths(font, name, keep):
    from ..parse.ufo import component_paths, glyph_paths

    g = font[name]
    paths = glyph_paths(g)
    for c in g.components:
        if not keep(c):
            paths.extend(component_paths(font, c))
    return paths


def blend_error(paths_a, paths_b, paths_us, nibs, label="glyph"):
    """Largest distance, over the elements of a glyph, sample parameters, fractions
    u (:data:`FRACTIONS`, ``paths_us`` the exact skeleton at each) and ``nibs``,
    between the blend (1 - u) E_A + u E_B of the nib parts of masters A and B and the
    nib part E_u of the skeleton at u (font units)."""
    from ..compatible import _nib_part, skeleton_elements

    loops = skeleton_elements([paths_a, paths_b] + list(paths_us), label)
    worst = 0.0
    m = 2 + len(paths_us)
    for nib in nibs:
        for loop in loops:
            for el in loop:
                e = _nib_part(el, [nib] * m, list(range(m)), _S)
                for k, u in enumerate(FRACTIONS):
                    d = (1 - u) * e[0] + u * e[1] - e[2 + k]
                    worst = max(worst, float(np.linalg.norm(d, axis=-1).max()))
    return worst


def refine_skeleton(skel, names, nibs, budget, keep, carry=()):
    """(refined :class:`~morph.fonts.variable.Skeleton`, report) for a designspace
    skeleton: its masters' grid (every axis' master coordinates, the full product)
    with intervals halved (:func:`morph.fonts.variable_grid.refine_grid`) until
    :func:`blend_error` of every stroked glyph (``names``; components kept as
    components by ``keep`` are not stroked here) and nib (``nibs``) is within
    ``budget`` along every axis at every node of the other axes; the glyphs
    ``carry`` (composites that follow) are interpolated into the new masters too.
    The given masters stay first (their indices unchanged); the new ones are
    instances of the skeleton's own interpolation, styled by their user location.
    Report: refine_grid's (``axes``, ``error``, ``errors_before``, ``budget``) and
    ``added``, the masters added.  A skeleton of one master is returned as it is.

    Raises:
        MorphError: more than :data:`MAX_SKELETON_MASTERS` masters would be needed.
    """
    from .variable_grid import grid_size, refine_grid

    if len(skel.fonts) < 2 or not skel.axes:
        return skel, {"axes": {}, "added": 0, "error": 0.0, "errors_before": {},
                      "budget": budget}
    interp = _Interpolator(skel, list(names) + [n for n in carry if n not in names])
    axes = [ax.name for ax in skel.axes]
    grid = {a: sorted({round(loc[a], 12) for loc in interp.locs}) for a in axes}
    edge_error = _edge_errors(interp, axes, names, nibs, keep)
    grid, report = refine_grid(grid, lambda edges: [edge_error(*e) for e in edges], budget,
                               MAX_SKELETON_MASTERS, "the skeleton designspace",
                               "the nib does not follow its interpolation: use masters "
                               "closer in shape or a smaller nib")
    report["added"] = grid_size(grid) - len(skel.fonts)
    return _with_grid(skel, interp, grid), report


def _edge_errors(interp, axes, names, nibs, keep):
    """edge_error(axis, lo, hi, others): the largest :func:`blend_error` of the glyphs
    ``names`` between the skeleton's instances at lo and hi along ``axis`` (the
    other axes at ``others``, (axis, value) pairs; instances cached by location)."""
    cache = {}

    def paths_at(loc):
        key = tuple(round(loc[a], 12) for a in axes)
        if key not in cache:
            f = interp.font(dict(zip(axes, key)), "")
            cache[key] = {n: _paths(f, n, keep) for n in names}
        return cache[key]

    def edge_error(a, lo, hi, others):
        others = dict(others)
        pa = paths_at({**others, a: lo})
        pb = paths_at({**others, a: hi})
        pus = [paths_at({**others, a: lo + u * (hi - lo)}) for u in FRACTIONS]
        return max((blend_error(pa[n], pb[n], [p[n] for p in pus], nibs, "glyph %r" % n)
                    for n in names if pa[n]), default=0.0)

    return edge_error


def _with_grid(skel, interp, grid):
    """``skel`` with a master at every grid node it lacks (instances of its own
    interpolation, design locations, styled by their user values)."""
    axes = list(skel.axes)
    have = {tuple(round(loc[ax.name], 12) for ax in axes) for loc in interp.locs}
    fonts, locations, labels = list(skel.fonts), list(skel.locations), list(skel.labels)
    for combo in itertools.product(*(grid[ax.name] for ax in axes)):
        if combo in have:
            continue
        loc = dict(zip([ax.name for ax in axes], combo))
        design = {ax.name: _design(ax, loc[ax.name]) for ax in axes}
        style = " ".join("%s %g" % (ax.tag, round(float(ax.map_backward(design[ax.name])), 2))
                         for ax in axes)
        fonts.append(interp.font(loc, style))
        locations.append(design)
        labels.append("intermediate %s" % style)
    return replace(skel, fonts=fonts, locations=locations, labels=labels,
                   given=len(skel.fonts))
