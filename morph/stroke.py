"""Skeleton paths stroked by a fixed-orientation convex nib (the paper's Fig. 5).

An open path P is the degenerate region traced forward and back: the loop
P, reverse(P) turns through +pi at both ends (:func:`morph.gauss.gauss_map`), so
its convolution with the nib N is both sides of P offset by N plus N's own arcs at
the two ends (the caps are exact nib arcs), and trimming it (winding > 0) gives
P ⊕ N: what a broad nib held at a fixed angle draws, as METAFONT's pens and
FontForge's Expand Stroke do.  A closed path is stroked the same way (its outline,
not its inside); a zero-length path (a dot) gives the nib itself.  Paths of one
call are united (a glyph is the union of its strokes).
"""

import numpy as np

from . import piece as pc
from .gauss import CUSP_ANGLE
from .minkowski import minkowski_sums
from .region import NormalLoops, reverse_loop, translate_region
from .trim import fill_region


def path_loop(pieces):
    """The closed degenerate loop of a path traced forward and back."""
    pieces = [np.asarray(p, float) for p in pieces]
    return pieces + reverse_loop(pieces)


def stroke_paths(paths, nib_region, tol):
    """The region swept by ``nib_region`` along every path: union of path ⊕ nib.

    paths: list of (pieces, closed) with pieces joined end to start (y up);
    nib_region: a convex region (its origin is the pen point); tol absolute, in the
    paths' units, with the budget of :func:`morph.minkowski.minkowski_sum`.
    Returns loops of rational pieces, outer counter-clockwise, holes clockwise.
    """
    return stroke_many([paths], nib_region, tol)[0]


def stroke_many(path_sets, nib_region, tol):
    """:func:`stroke_paths` of several sets of paths (a font's glyphs) with one nib,
    the sums computed together (:func:`morph.minkowski.minkowski_sums`)."""
    if not nib_region:
        raise ValueError("the nib is empty")
    loops, dots = zip(*[_loops_and_dots(paths, nib_region) for paths in path_sets]) \
        if path_sets else ((), ())
    has = [k for k, lp in enumerate(loops) if lp]
    # a path traced out and back winds 0 round every point off it, whatever it
    # crosses: the loops pass the operand's winding test by construction, so they
    # go in marked as such (that test cost 10-17 % of a stroke font's CPU time)
    sums = minkowski_sums([NormalLoops(loops[k]) for k in has], nib_region, tol)
    out = [[] for _ in path_sets]
    for k, region in zip(has, sums):
        out[k] = region
    for k, d in enumerate(dots):
        if d:
            nibs = [loop for x in d for loop in translate_region(nib_region, x)]
            out[k] = fill_region(list(out[k]) + nibs, "nonzero")
    return out


def _loops_and_dots(paths, nib_region):
    """(degenerate loops of the paths, start points of the zero-length ones)."""
    size = _size([p for pieces, _ in paths for p in pieces] + [p for l in nib_region for p in l])
    loops, dots = [], []
    for pieces, _closed in paths:
        long = [np.asarray(p, float) for p in pieces if not _is_point(p, 1e-12 * size)]
        if long:
            loops += [path_loop(part) for part in _split_at_reversals(long)]
        elif len(pieces):
            dots.append(pc.start(np.asarray(pieces[0], float)))
    return loops, dots


def _split_at_reversals(pieces):
    """The path cut where it turns back on itself (a turn within CUSP_ANGLE of pi
    between consecutive pieces): the parts' sums with the nib unite to the path's
    (a sum distributes over a union), and each part traced forward and back turns
    once, where a path running back over its own trace would make its loop turn
    twice (:func:`morph.gauss.gauss_map` reads that tip as cut into the trace)."""
    if len(pieces) < 2:
        return [pieces]
    first, last = pc.end_tangents_many(pieces)  # unit tangents
    cos = np.einsum("ij,ij->i", last[:-1], first[1:])
    cuts = np.flatnonzero(cos < -np.cos(CUSP_ANGLE)) + 1
    return [[pieces[i] for i in part] for part in np.split(np.arange(len(pieces)), cuts)]


def _is_point(piece, eps):
    p = pc.cartesian(np.asarray(piece, float))
    return float(np.ptp(p, axis=0).max()) <= eps


def _size(pieces):
    if not pieces:
        return 1.0
    pts = np.concatenate([pc.cartesian(np.asarray(p, float)) for p in pieces])
    return max(float(np.ptp(pts, axis=0).max()), 1e-300)


__all__ = ["stroke_paths", "stroke_many", "path_loop"]
