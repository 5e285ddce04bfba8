"""Master grids of variable fonts refined until every instance is within budget.

A variable font built from masters on the full product of per-axis grids
(fontTools' ``VariationModel`` over them) interpolates each cell multilinearly,
so along an edge of the grid an instance is the linear blend of the edge's two
masters.  Where what the masters carry does not blend linearly (the nib part of an
outline whose normals turn between the masters), an edge's *blend error* (measured
by the caller at interior fractions) says how far an instance between them misses;
:func:`refine_grid` halves every interval of an axis whose blend error exceeds the
budget at some node of the other axes, until all hold.
"""

import itertools

import numpy as np

from ..errors import MorphError

__all__ = ["grid_edges", "refine_grid", "grid_size", "grid_model", "grid_supports"]


def grid_size(grid):
    """Masters on the full product of ``grid`` (axis -> values)."""
    return int(np.prod([len(v) for v in grid.values()]))


def grid_edges(grid):
    """Every edge of the product grid: ``(axis, lo, hi, others)``, lo and hi
    neighbouring values of the axis, ``others`` the other axes' values as a tuple of
    (axis, value) pairs."""
    axes = list(grid)
    for a in axes:
        rest = [b for b in axes if b != a]
        for lo, hi in zip(grid[a][:-1], grid[a][1:]):
            for combo in itertools.product(*(grid[b] for b in rest)):
                yield (a, lo, hi, tuple(zip(rest, combo)))


def refine_grid(grid, errors_of, budget, limit, subject, advice):
    """(refined grid, report): ``grid`` (axis -> sorted values) with every interval
    halved whose blend error, the largest over the other axes' nodes, exceeds
    ``budget``, until all are within it.

    ``errors_of(edges)``: the blend error of each edge (:func:`grid_edges`'s tuples),
    called once per round with the edges not measured yet; ``limit``: the most
    masters allowed; ``subject`` and ``advice``: what the error message says needs
    more and what to do about it.
    Report: ``axes`` (values per axis), ``error`` (the largest blend error left),
    ``errors_before`` (per axis with an interval, the largest before refining),
    ``budget``.

    Raises:
        MorphError: more than ``limit`` masters would be needed.
    """
    grid = {a: sorted(v) for a, v in grid.items()}
    known = {}

    def interval_errors():
        edges = list(grid_edges(grid))
        new = [e for e in edges if e not in known]
        if new:
            known.update(zip(new, errors_of(new)))
        worst = {}
        for e in edges:
            worst[e[:3]] = max(worst.get(e[:3], 0.0), known[e])
        return worst

    worst = interval_errors()
    before = {a: max(v for k, v in worst.items() if k[0] == a)
              for a in grid if len(grid[a]) > 1}
    while True:
        bad = [k for k, v in worst.items() if v > budget]
        if not bad:
            break
        for a, lo, hi in bad:
            grid[a] = sorted(set(grid[a]) | {round(0.5 * (lo + hi), 12)})
        if grid_size(grid) > limit:
            raise MorphError("%s needs more than %d masters to keep instances within %g "
                             "units of the exact sum (%s)" % (subject, limit, budget, advice))
        worst = interval_errors()
    return grid, {"axes": {a: len(v) for a, v in grid.items()},
                  "error": max(worst.values(), default=0.0), "errors_before": before,
                  "budget": budget}


def grid_model(locations, tags):
    """fontTools' ``VariationModel`` over masters on a product grid (normalized
    ``locations``, axis ``tags``), its supports made the tents between neighbouring
    grid values (each master's region runs from the grid value before it to the one
    after it on every axis it is off-default on).

    The interpolation is the same, multilinear on every cell of the grid; but every
    master's region is 0 or 1 at every other master (fontTools' own supports run on
    to the axis' end, so a master between others weighs 1/3 or 1/2 at them), so the
    deltas of integer masters are integers and every master is exactly its own
    rounded outline, with no rounding of the deltas: rounded deltas would reproduce
    a master only within 0.5 unit per coordinate, and in a CFF2 charstring, whose
    coordinates are relative, that error would run on along the contour."""
    from fontTools.varLib.models import VariationModel

    model = VariationModel(locations, tags)
    _grid_tents(model)
    return model


def _is_product(locations):
    """Do normalized ``locations`` (fontTools' form: zero coordinates left out) fill
    the full product of their per-axis values?"""
    tags = sorted({t for loc in locations for t in loc})
    values = [sorted({0.0} | {float(loc.get(t, 0.0)) for loc in locations}) for t in tags]
    have = {tuple(float(loc.get(t, 0.0)) for t in tags) for loc in locations}
    return len(have) == len(locations) == int(np.prod([len(v) for v in values]))


def _grid_tents(model):
    """``model``'s supports made the tents between neighbouring grid values (see
    :func:`grid_model`), its delta weights recomputed."""
    tags = sorted({t for loc in model.locations for t in loc})
    values = {t: sorted({0.0} | {float(loc.get(t, 0.0)) for loc in model.locations})
              for t in tags}
    supports = []
    for loc in model.locations:
        support = {}
        for t, c in loc.items():
            if c == 0:
                continue
            vs = values[t]
            i = vs.index(c)
            before = vs[i - 1] if i > 0 else c
            after = vs[i + 1] if i + 1 < len(vs) else c
            support[t] = (before, c, after)
        supports.append(support)
    model.supports = supports
    model._computeDeltaWeights()


def _grid_variation_model():
    """A ``VariationModel`` subclass whose models over masters on a full product grid
    get :func:`grid_model`'s tents (other sets of masters: fontTools' supports)."""
    from fontTools.varLib.models import VariationModel

    class GridVariationModel(VariationModel):
        def __init__(self, locations, *args, **kwargs):
            super().__init__(locations, *args, **kwargs)
            if _is_product(self.locations):
                _grid_tents(self)

    return GridVariationModel


class grid_supports:
    """Within this context fontTools' varLib (and ufo2ft, which compiles through it)
    builds its variation models with :func:`grid_model`'s tents wherever the masters
    fill a product grid: the masters of a stroked designspace (the skeleton's grid
    times the nib axis' masters) are then reproduced exactly by integer deltas, in
    gvar and in CFF2's relative charstring coordinates alike.  It replaces
    ``fontTools.varLib.models.VariationModel`` (the name varLib and its sub-models
    look up) and restores it on exit."""

    def __enter__(self):
        from fontTools.varLib import models

        self._real = models.VariationModel
        models.VariationModel = _grid_variation_model()
        return self

    def __exit__(self, *exc):
        from fontTools.varLib import models

        models.VariationModel = self._real
        return False
