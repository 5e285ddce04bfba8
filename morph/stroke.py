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

from itertools import chain

import numpy as np

from . import piece as pc
from .gauss import CUSP_ANGLE
from .minkowski import minkowski_sums
from .nib import check_convex_nib
from .region import reverse_loop, translate_region, validated
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

    Raises:
        NibError: a nib that is not one convex loop (:func:`morph.nib.check_convex_nib`).
    """
    return stroke_many([paths], nib_region, tol)[0]


def stroke_many(path_sets, nib_region, tol):
    """:func:`stroke_paths` of several sets of paths (a font's glyphs) with one nib,
    the sums computed together (:func:`morph.minkowski.minkowski_sums`)."""
    if not nib_region:
        raise ValueError("the nib is empty")
    check_convex_nib(nib_region)  # NibError: a path ⊕ a non-convex nib is no pen's stroke
    loops, dots, stacked = _loops_and_dots_many(path_sets, nib_region) if path_sets else \
        ((), (), None)
    has = [k for k, lp in enumerate(loops) if lp]
    # a path traced out and back winds 0 round every point off it, whatever it
    # crosses: the loops pass the operand's winding test by construction, so they
    # go in marked as such (that test cost 10-17 % of a stroke font's CPU time)
    sums = minkowski_sums([validated(loops[k], frozen=True) for k in has], nib_region,
                          tol, stacked=stacked, traced=True)
    out = [[] for _ in path_sets]
    for k, region in zip(has, sums):
        out[k] = region
    for k, d in enumerate(dots):
        if d:
            nibs = [loop for x in d for loop in translate_region(nib_region, x)]
            out[k] = fill_region(list(out[k]) + nibs, "nonzero")
    return out


def _loops_and_dots_many(path_sets, nib_region):
    """(degenerate loops of each set of paths, start points of its zero-length
    paths, the pieces of all the loops in order stacked (a :class:`morph.piece.
    Pieces`, taken from the forward and reversed stacks: what
    :func:`morph.minkowski.minkowski_sums` would gather from the loops)): pieces shorter than 1e-12 of their set's size (with the nib's) are
    dropped; a path with none left is a dot.  Each path is cut where it turns back
    on itself (a turn within CUSP_ANGLE of pi between consecutive pieces): the
    parts' sums with the nib unite to the path's (a sum distributes over a union),
    and each part traced forward and back turns once, where a path running back
    over its own trace would make its loop turn twice (:func:`morph.gauss.
    gauss_map` reads that tip as cut into the trace).  Each part becomes
    :func:`path_loop` of it.  The pieces of all sets at once: extents, end
    tangents and reversed copies in array calls by degree; only the parts are
    visited one by one."""
    paths = [(k, pieces) for k, ps in enumerate(path_sets) for pieces, _ in ps]
    raw = list(chain.from_iterable(ps for _, ps in paths))
    # every piece gathered once into stacks by degree; the loops are made of the rows
    # of read-only stacks (what :func:`morph.region.validated` takes as ``frozen``)
    table = pc.Pieces(pc.degree_groups(raw), len(raw))
    nib = [np.asarray(p, float) for loop in nib_region for p in loop]
    n_sets = len(path_sets)
    path_of = np.repeat(np.arange(len(paths)), [len(ps) for _, ps in paths]).astype(np.int64)
    set_of = np.array([k for k, _ in paths], np.int64)[path_of] if len(raw) else \
        np.zeros(0, np.int64)
    lo, hi = _piece_boxes(table)
    nlo, nhi = _piece_boxes(nib)
    set_lo = np.tile(nlo.min(axis=0), (n_sets, 1))
    set_hi = np.tile(nhi.max(axis=0), (n_sets, 1))
    np.minimum.at(set_lo, set_of, lo)
    np.maximum.at(set_hi, set_of, hi)
    size = np.maximum((set_hi - set_lo).max(axis=1), 1e-300)          # :func:`_size`
    long = ~((hi - lo).max(axis=1) <= 1e-12 * size[set_of]) if len(raw) else \
        np.zeros(0, bool)                                              # :func:`_is_point`
    idx = np.flatnonzero(long)
    kept = pc.Pieces(_frozen_groups(table.take(idx).groups), len(idx))
    first, last = pc.end_tangents_many(kept) if len(idx) else (None, None)
    reversed_ = _reversed_many(kept)
    back = reversed_.rows()
    # a cut before long piece m where the path turns back on itself from piece m - 1
    same = path_of[idx[1:]] == path_of[idx[:-1]]
    cos = np.einsum("ij,ij->i", last[:-1], first[1:]) if len(idx) > 1 else np.zeros(0)
    cut = np.zeros(len(idx), bool)
    cut[1:] = ~same | (cos < -np.cos(CUSP_ANGLE))
    if len(idx):
        cut[0] = True
    loops, dots = [[] for _ in range(n_sets)], [[] for _ in range(n_sets)]
    starts = np.flatnonzero(cut).tolist() + [len(idx)]
    forward = kept.rows()
    part_set = set_of[idx[starts[:-1]]].tolist() if len(idx) else []
    for a, b, k in zip(starts[:-1], starts[1:], part_set):      # the parts, in path order
        loops[k].append(forward[a:b] + back[a:b][::-1])
    bounds = np.cumsum([0] + [len(ps) for _, ps in paths])
    has_long = np.bincount(path_of[idx], minlength=len(paths)) > 0 if len(paths) else []
    for j, (k, ps) in enumerate(paths):
        if not has_long[j] and len(ps):
            dots[k].append(pc.start(np.asarray(raw[bounds[j]], float)))
    return loops, dots, _loop_stacks(kept, reversed_, starts)


def _loop_stacks(kept, reversed_, starts):
    """The pieces of all the loops of :func:`_loops_and_dots_many` in order (the
    parts in path order, sets in order: each part's pieces forward, then reversed
    backward) as one :class:`morph.piece.Pieces`, taken from the stacks of the
    pieces (``kept``) and of their reversals (``reversed_``)."""
    a = np.asarray(starts[:-1], np.int64)
    length = np.asarray(starts[1:], np.int64) - a
    n = len(kept)
    both = pc.Pieces([(np.concatenate([ks, n + kr]), np.concatenate([h, hr]))
                      for (ks, h), (kr, hr) in zip(kept.groups, reversed_.groups)], 2 * n)
    part = np.repeat(np.arange(len(a)), 2 * length)
    j = np.arange(len(part)) - np.repeat(np.cumsum(2 * length) - 2 * length, 2 * length)
    ln, start = length[part], a[part]
    return both.take(np.where(j < ln, start + j, n + start + 2 * ln - 1 - j))


def _piece_boxes(pieces):
    """(lo, hi) (k, 2) each: the smallest and largest Cartesian control point
    coordinates of every piece, by degree groups."""
    lo, hi = np.zeros((len(pieces), 2)), np.zeros((len(pieces), 2))
    for ks, h in pc.degree_groups(pieces):
        lo[ks], hi[ks] = pc.column_extremes(pc.cartesian(h))
    return lo, hi


def _reversed_many(pieces):
    """Each piece traversed the other way (:func:`morph.piece.reverse`), by degree, as
    a :class:`morph.piece.Pieces` of read-only stacks."""
    return pc.Pieces(_frozen_groups((ks, h[:, ::-1].copy())
                                    for ks, h in pc.degree_groups(pieces)),
                     len(pieces))


def _frozen_groups(groups):
    """(indices, stack) groups with each stack made read-only (its own copy when it
    was not a new array), so that the rows are."""
    out = []
    for ks, h in groups:
        if h.flags.owndata or h.base is None:
            h.flags.writeable = False
        else:
            h = h.copy()
            h.flags.writeable = False
        out.append((ks, h))
    return out


__all__ = ["stroke_paths", "stroke_many", "path_loop"]
