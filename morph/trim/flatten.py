"""Tagged polylines on an integer grid: the input of the polygon engine.

Every closed loop of rational pieces becomes a closed polyline whose vertices lie
on the pieces (certified flattening, :func:`morph.polyline.flatten_many`: each piece
is within ``eps`` of its polyline by the convex-hull property of positive-weight
rational Béziers, wherever its topology is decided; within up to COARSE eps
along the simple arcs that nothing comes near, the nearer something comes the
finer, :func:`adaptive_starts`), snapped to the
integer grid ``round((p - origin) / grid)``.
Each vertex keeps its tag (piece index, parameter t); each segment runs from its
vertex to the next one of its loop and carries the parameter range [t0, t1] on the
piece of its start vertex.  Vertices that fall into one grid point are merged,
keeping the start of a piece where there is one (a piece shorter than the grid
vanishes and its neighbours meet at the grid point).  Segments are then routed
through the grid points of the other vertices whose pixels they cross (snap
rounding with the vertices' pixels hot): two segments closer than a grid step keep
their order or coincide, where rounding their ends on their own could swap them.

The levels of :func:`adaptive_starts` guarantee (tests/trim/test_flatten.py checks both):

1. every segment's part lies within the tolerance of the level that decided it
   (e for a part decided at level e, eps for the parts the last level leaves):
   a refined stretch takes every vertex of its pieces' flattening at the finer
   tolerance (:func:`_refined`);
2. a part decided at level e is farther than e + 2 (eps + grid) from the part
   of every segment still pending at that level, those cut from its two
   neighbours at that level excepted (they lie beyond the shared vertex: the
   arcs advance along one direction), and those cut from the parts a monotone
   chain joins it to along its loop (:func:`_monotone_chains`: the chain, and
   every polyline with its vertices on it in order, advances along one
   direction, so it meets itself nowhere).  Parts decided at a coarser level
   were held to that level's test.

So a level tests its pending segments among themselves only.  A part's later
polylines have their vertices on the part and their chords in its convex
hull, so they stay inside every capsule the part was in: two segments tested
at level e' apart by more than 2 e' + 2 (eps + grid) have capsules of radius e'
more than 2 (eps + grid) apart, and so have everything cut from them later and
those cuts rounded to the grid.  The reach 2 e + 2 (eps + grid) of level e
bounds the flattening error e of both segments tested, plus eps + grid for
each side's lifted loop (within eps + grid of its rounded polyline).

Rows of point arrays are gathered by ``take`` / ``compress`` (see
:mod:`morph.polyline`).
"""

import numpy as np

from .. import bernstein as bz
from .. import piece as pc
from .. import polyline as pl
from ..polyline import BoxGrid, _sorted_entries, col_max, col_min, unique

#: segments whose topology is certain are flattened up to this many times coarser
#: (:func:`adaptive_starts`)
COARSE = 32.0
#: the tangents of a coarse part lie within this angle of its chord (an arc of a
#: circle flattened within e passes where its radius is at least e / (1 - cos CONE),
#: 4.3 e)
CONE = np.radians(40.0)
#: a chain of arcs in their chords' cones whose chords' directions span at most
#: this advances along one direction (:func:`_monotone_chains`): its tangents span
#: at most CHAIN + 2 CONE = 175 degrees, below 180
CHAIN = np.radians(95.0)
#: the longest chain (in segments from one part to the other) looked along
CHAIN_STEPS = 4
#: a coarse segment's chord turns by at most this into its neighbours' (a part and
#: its neighbour are a chain; a circle's chords within its cone turn by 2 CONE)
TURN = CHAIN
#: the parts not certain at one level are flattened this many times finer and
#: tested again (:func:`adaptive_starts`, :func:`_levels`): 32 eps, 8 eps, then
#: eps.  A part is cut only as finely as what comes near it needs: 29 % fewer
#: vertices than one step from COARSE to eps on chunks of CJK strokes, whose caps
#: and joins turn too fast for COARSE eps but not for 8 eps
LEVEL_STEP = 4.0
#: the cell of :func:`_near_others`' grid, in median segment boxes (the pairs found
#: do not depend on it): boxes in fewer cells, more candidate pairs in each.  The
#: level tests' instructions on CJK and Hershey script strokes, against 4: 2, 23 %
#: more; 3, 5 % more; 5, 1 % fewer
NEAR_CELL = 4.0
#: the snap rounding's grid holds the segments' boxes grown by this many grid units:
#: half a pixel for the hot pixels, and enough for the lift's search for the
#: segments within 2 grid units of a ring's vertex (its MATCH_UNITS, plus half a
#: unit: the segments cut and rounded stay within their unrounded boxes grown by
#: that), which then needs no grid of its own
SEGMENT_REACH = 2.5


class Tagged:
    """Closed polylines of all loops, on the integer grid.

    q (N, 2) int64 grid coordinates; piece (N,) index into ``pieces``; t0, t1 (N,)
    parameter range of segment i (from vertex i to vertex ``nxt[i]``) on
    ``pieces[piece[i]]``; nxt, prv (N,) next / previous vertex of the same loop;
    starts (L+1,) offsets of the loops; origin (2,) and grid: float = origin + grid * q;
    eps: the flattening bound (each segment within eps of its piece before rounding
    where the topology is decided, within COARSE eps along simple arcs apart from
    everything: :func:`adaptive_starts`).  seg_grid, seg_first, seg_count: the snap
    rounding's grid of the segments before hot pixels cut them (boxes of their
    unrounded ends grown by SEGMENT_REACH grid units), the index of each one's first
    segment after, and how many it became (None: no grid).  A plain class:
    processing a dataclass costs every process about half a ms.
    """

    def __init__(self, q, piece, t0, t1, nxt, prv, starts, origin, grid, pieces, eps=0.0,
                 seg_grid=None, seg_first=None, seg_count=None):
        self.q, self.piece, self.t0, self.t1, self.nxt, self.prv = q, piece, t0, t1, nxt, prv
        self.starts, self.origin, self.grid, self.pieces, self.eps = \
            starts, origin, grid, pieces, eps
        self.seg_grid, self.seg_first, self.seg_count = seg_grid, seg_first, seg_count

    def __repr__(self):
        return "Tagged(%d vertices, %d loops, grid=%r, eps=%r)" % (
            len(self.q), len(self.starts) - 1, self.grid, self.eps)

    def to_float(self, q):
        return self.origin + self.grid * np.asarray(q, float)

    def paths(self):
        """The loops as lists of integer points (pyclipper's input)."""
        return [self.q[a:b] for a, b in zip(self.starts[:-1], self.starts[1:])]


def tag_loops(loops, eps, grid, origin=None, pieces=None):
    """:class:`Tagged` polylines of closed loops of pieces (see the module docstring).

    eps: flattening bound where the topology is decided (absolute; COARSE eps along
    simple arcs apart from everything, :func:`adaptive_starts`); grid: size of one
    integer unit.  Loops that
    collapse to fewer than three grid points are dropped (their area is below
    grid^2 times their vertex count).  ``pieces``: the loops' pieces one loop after
    another as a :class:`morph.piece.Pieces`, where the caller has them (else they
    are stacked here).
    """
    if pieces is None:
        pieces = pc.Pieces.of([p for loop in loops for p in loop])
    # a closed loop's polyline: its pieces' polylines without their ends (the next
    # piece's start), in order
    piece_loop = np.arange(len(loops)).repeat([len(loop) for loop in loops])
    pid, ts, xy = adaptive_starts(pieces, piece_loop, eps, grid)
    loop_of = piece_loop[pid]
    if origin is None:
        origin = 0.5 * (col_min(xy) + col_max(xy))
    origin = np.asarray(origin, float)
    x = (xy - origin) / grid   # in grid units
    q = np.rint(x).astype(np.int64)
    keep = _merge_equal(q, ts == 0.0, loop_of)
    # loops with fewer than three vertices enclose nothing on the grid (one gather
    # of the vertices kept)
    kept_loop = loop_of[keep]
    counts = np.bincount(kept_loop, minlength=len(loops))
    keep = keep[counts[kept_loop] >= 3]
    q, pid, ts, loop_of = q.take(keep, axis=0), pid[keep], ts[keep], loop_of[keep]
    x = x.take(keep, axis=0)
    nxt, prv, starts = _links(loop_of)
    cuts = (None, None, None)
    if len(q):
        q, pid, ts, loop_of, cuts = _through_hot_pixels(q, x, pid, ts, loop_of, nxt)
        nxt, prv, starts = _links(loop_of)
    # a segment ends at its next vertex's parameter on the same piece, 1 at a piece's
    # last vertex; a vertex put on a segment at its start (a hot pixel beside it)
    # shares the start's parameter: that range is empty, not [t, 1] (which would lift
    # a one-unit edge as the whole rest of the piece)
    same = (pid[nxt] == pid) & (ts[nxt] >= ts)
    t1 = np.where(same, ts[nxt], 1.0)
    return Tagged(q, pid, ts, t1, nxt, prv, starts, origin, float(grid), pieces, float(eps),
                  *cuts)


def adaptive_starts(pieces, piece_loop, eps, grid, coarse=None):
    """The vertices of closed polylines through loops of pieces (``piece_loop``: the
    loop of each piece, loops stored one after another), as :func:`morph.piece.
    flat_starts` gives them: (piece, t, point), sorted by (piece, t).  Within ``eps``
    where the topology is decided, within up to ``coarse`` eps elsewhere (None:
    :data:`COARSE`; 1: within eps everywhere).

    The loops are flattened within e = ``coarse`` eps first; each segment's part of
    its piece lies in the segment grown by e (a capsule).  A segment's part is cut
    finer, within e / LEVEL_STEP (:func:`_levels`; after the last level within eps), unless
    its topology is certain at e; the parts cut are tested again at their new
    tolerance, and so on down to eps.  Certain at e means:

    - no segment of another part (not its neighbour along the loop, nor joined to
      it by a monotone chain of arcs, :func:`_monotone_chains`) comes within
      2 e + 2 (eps + grid) of it: the two parts, their polylines at either
      tolerance and those polylines rounded to the grid stay apart (the lifted
      loops, within eps + grid + contraction of their rings, too);
    - the tangents of its part lie within CONE of its chord (the control polygon's
      legs do, and a positive-weight rational's hodograph is in their cone): the
      part is a simple arc, without a cusp; its neighbours' parts are such arcs too;
    - its chord turns by at most TURN into each neighbour's: with TURN + 2 CONE
      below 180 degrees the two arcs' tangents lie within an open half-plane of
      directions, so the arcs advance along its middle direction and meet only at
      their shared vertex.  (A closed polyline turning at most TURN at every
      vertex has at least 4 segments: the turns of a closed polyline add up to a
      multiple of 360 degrees, and three turns of at most 95 degrees that add up
      to 0 leave the directions within 95 degrees, where they cannot close.
      Smaller loops are cut within eps.)

    Where all of this holds, the parts are simple arcs that neither cross nor come
    near any other: the winding numbers away from them, hence the filled set, are
    those of the finer flattening, and the lifted boundary follows the exact pieces.

    What the result guarantees, and why a level tests its pending segments among
    themselves only: the module's docstring.
    """
    coarse = COARSE if coarse is None else coarse
    levels = _levels(coarse)
    pid, ts, xy = pl.flat_starts(pieces, levels[0] * eps)
    if coarse <= 1.0 or not len(pid):
        return pid, ts, xy
    pending = np.ones(len(pid), bool)   # segments flattened at the level's tolerance
    for k, level in enumerate(levels):
        loop_of = piece_loop[pid]
        nxt, prv, starts = _links(loop_of)
        fine = _uncertain(pieces, pid, ts, xy, loop_of, nxt, prv, starts, pending,
                          level * eps, eps, grid)
        if not fine.any():
            break
        finer = levels[k + 1] if k + 1 < len(levels) else 1.0
        pid, ts, xy, pending = _refined(pieces, pid, ts, xy, fine, prv, finer * eps)
        if finer <= 1.0:
            break
    return pid, ts, xy


def _levels(coarse):
    """The tolerances (in eps) at which :func:`adaptive_starts` tests the parts it
    has not decided yet: ``coarse``, then LEVEL_STEP times finer each time while
    that is at least LEVEL_STEP eps (32 and 8 eps); the parts the last level leaves
    go to eps untested.  A level nearer eps does not pay: at 2 eps a test of all the
    parts left decided a quarter of them on Hershey script strokes, and cost more
    than the vertices it saved."""
    out = [float(coarse)]
    while out[-1] / LEVEL_STEP >= LEVEL_STEP:
        out.append(out[-1] / LEVEL_STEP)
    return out


def _uncertain(pieces, pid, ts, xy, loop_of, nxt, prv, starts, pending, e, eps, grid):
    """The segments (mask) among the ``pending`` ones (flattened within e) whose
    topology is not certain at e (:func:`adaptive_starts`); the others were decided
    at a coarser level and are simple arcs apart from everything but their
    neighbours and the parts a monotone chain joins them to (which their own test
    proved, for every finer polyline of those)."""
    t_end = np.where((pid[nxt] == pid) & (ts[nxt] > ts), ts[nxt], 1.0)
    chord = xy.take(nxt, axis=0) - xy
    todo = pending.ravel().nonzero()[0]
    arc = ~pending   # decided parts are arcs in their chords' cones
    line = np.zeros(len(pid), bool)
    for k, parts in _segment_parts(pieces, pid[todo], ts[todo], t_end[todo], cut_lines=False):
        if parts.shape[1] == 2:   # lines: their own chords
            arc[todo[k]] = line[todo[k]] = True
        else:
            arc[todo[k]] = _in_cone(parts, chord.take(todo[k], axis=0), np.cos(CONE))
    arc &= (chord[:, 0] != 0.0) | (chord[:, 1] != 0.0)   # a chord of nonzero length
    # the turn from each segment's chord into the next one's, in [-pi, pi)
    angle = np.arctan2(chord[:, 1], chord[:, 0])
    turn = (angle[nxt] - angle + np.pi) % (2.0 * np.pi) - np.pi
    smooth = np.abs(turn) <= TURN
    near = np.zeros(len(pid), bool)
    near[todo] = _near_others(xy, nxt, todo, 2.0 * e + 2.0 * (eps + grid), arc, turn, line)
    return pending & (near | ~(arc & arc[nxt] & arc[prv] & smooth & smooth[prv]))


def _refined(pieces, pid, ts, xy, fine, prv, eps):
    """The coarse vertices (piece, t, point) with the segments marked ``fine`` cut
    within eps: a refined stretch takes the vertices of its pieces' own flattening
    within eps (where two parts run close, both polylines are the ones flattening
    within eps everywhere gives, so near-coincident pieces cross as rarely; only
    the parts that meet a refined segment are cut); the coarse vertices inside a
    stretch go, but a finer vertex at one of them stays; where a coarse vertex
    bounds a stretch, the part between it and the nearest finer vertex is flattened
    within eps on its own.  So every segment of a refined stretch is within eps of
    its part.  A line piece's one vertex, its start, is its flattening at every
    tolerance: only the curved pieces are flattened again.  Returns (piece, t,
    point, whether the segment from the vertex is one of the refined ones)."""
    straight = _straight(pieces)
    of = unique(pid[fine & ~straight[pid]])
    if not len(of):   # refined lines only: each stays its one segment
        return pid, ts, xy, fine
    # keys (piece, t) as one float: t in [0, 1) and flat parameters >= 2^-16 apart
    key = pid * 2.0 + ts
    refined = np.concatenate([[0], fine.cumsum()])

    def overlaps(owner, t0, width):
        """Parts of the pieces' subdivision that meet a refined segment."""
        p = of[owner] * 2.0
        first = pl.search_sorted(key, p + t0, side="right") - 1
        last = pl.search_sorted(key, p + t0 + width, side="left") - 1
        return refined[np.maximum(last, first) + 1] - refined[first] > 0

    fp, fts, fxy = pl.flat_starts(pieces.take(of) if isinstance(pieces, pc.Pieces)
                                  else [pieces[i] for i in of], eps, keep=overlaps)
    fp = of[fp]
    fkey = fp * 2.0 + fts
    seg = np.searchsorted(key, fkey, side="right") - 1  # the coarse segment of each
    keep = ~(fine & fine[prv] & (ts > 0.0))  # coarse vertices between refined segments go
    # the finer vertices inside refined segments, and those at a coarse vertex that goes
    take = fine[seg] & ((fts > ts[seg]) | ~keep[seg])
    at = np.searchsorted(fkey, key)
    on_fine = ((at < len(fkey)) & (fkey[np.minimum(at, len(fkey) - 1)] == key)) | straight[pid]
    # the merged polyline: (piece, t, point, a coarse vertex off the finer flattening's)
    mp = np.concatenate([pid[keep], fp[take]])
    mt = np.concatenate([ts[keep], fts[take]])
    mx = np.concatenate([xy.compress(keep, axis=0), fxy.compress(take, axis=0)])
    loose = np.concatenate([~on_fine[keep], np.zeros(take.sum(), bool)])
    mseg = np.concatenate([keep.ravel().nonzero()[0], seg[take]])
    order = pl.piece_order(mp, mt)
    mp, mt, mx, loose, mseg = (mp[order], mt[order], mx.take(order, axis=0), loose[order],
                               mseg[order])
    mp, mt, mx, mseg = _gaps_filled(pieces, mp, mt, mx, loose, fine[mseg], mseg, eps)
    return mp, mt, mx, fine[mseg]


def _gaps_filled(pieces, mp, mt, mx, loose, fine, mseg, eps):
    """The merged polyline of :func:`_refined` (piece, t, point, whether the vertex
    is loose: a coarse vertex off the finer flattening; ``fine``: whether its segment
    is refined; ``mseg``: its coarse segment) with the gaps flattened within eps: a
    chord within a refined segment with a loose end (to the next vertex of its
    piece, or to the piece's end).  Returns (piece, t, point, coarse segment)."""
    last = np.concatenate((mp[1:] != mp[:-1], [True]))
    t_next = np.where(last, 1.0, np.concatenate((mt[1:], [1.0])))
    loose_next = np.where(last, False, np.concatenate((loose[1:], [False])))
    gap = fine & (loose | loose_next)
    if gap.any():
        g = gap.ravel().nonzero()[0]
        parts = pc.subsegments(pieces, mp[g], mt[g], t_next[g], packed=True)
        owner, s, pts = pl.flat_starts(parts, eps)
        inner = s > 0.0
        owner, s, pts = g[owner[inner]], s[inner], pts.compress(inner, axis=0)
        mp = np.concatenate([mp, mp[owner]])
        mt = np.concatenate([mt, mt[owner] + s * (t_next[owner] - mt[owner])])
        mx = np.concatenate([mx, pts])
        mseg = np.concatenate([mseg, mseg[owner]])
        order = pl.piece_order(mp, mt)
        mp, mt, mx, mseg = mp[order], mt[order], mx.take(order, axis=0), mseg[order]
    return mp, mt, mx, mseg


def _straight(pieces):
    """Whether each piece is a line (two control points), (len(pieces),) bool."""
    out = np.zeros(len(pieces), bool)
    for ks, stack in pc.degree_groups(pieces):
        out[ks] = stack.shape[1] == 2
    return out


def _near_others(xy, nxt, todo, reach, arc=None, turn=None, line=None):
    """Whether each segment ``todo`` (from vertex k to ``nxt[k]``) comes within
    ``reach`` of another of them that is not its neighbour along its loop
    (crossing, touching or nearer), (len(todo),) bool; a segment that shares only a
    point with another (a loop's vertex visited twice) is near it.  The loops of
    one vertex have no segment (as in :func:`morph.polyline.touching_edges`).
    With ``arc`` and ``turn`` (every segment's, :func:`_uncertain`), pairs that a
    monotone chain joins (:func:`_monotone_chains`) are not near either; with
    ``line`` (whether each segment is a whole line piece's part), nor are two
    lines: a line's polyline at every level is the line, so two lines and their
    lifts are where they are, whatever their distance (their rounding is the hot
    pixels' business)."""
    near = np.zeros(len(todo), bool)
    has = (nxt[todo] != todo).ravel().nonzero()[0]
    if len(has) < 2:
        return near
    solo = None   # the boxes from this index on (the lines) are not paired with each other
    if line is not None:
        is_line = line[todo[has]]
        has = np.concatenate((has[~is_line], has[is_line]))
        solo = len(has) - int(np.add.reduce(is_line))
    seg = todo[has]
    a, b = xy.take(seg, axis=0), xy.take(nxt[seg], axis=0)
    grid = BoxGrid(np.minimum(a, b) - 0.5 * reach, np.maximum(a, b) + 0.5 * reach, NEAR_CELL)
    cols = pl._columns(a, b)
    for ki, kj in pl._cell_pair_columns(grid, solo=solo):
        i, j = seg[ki], seg[kj]
        keep = (nxt[i] != j) & (nxt[j] != i)
        ki, kj, i, j = ki[keep], kj[keep], i[keep], j[keep]
        if len(ki):
            keep = pl._within_columns(cols, ki, kj, reach)
            ki, kj, i, j = ki[keep], kj[keep], i[keep], j[keep]
        if len(ki) and arc is not None:
            keep = ~_monotone_chains(i, j, nxt, arc, turn)
            ki, kj = ki[keep], kj[keep]
        near[has[ki]] = True
        near[has[kj]] = True
    return near


def _monotone_chains(i, j, nxt, arc, turn):
    """Whether segment j follows segment i along their loop (or i follows j) within
    CHAIN_STEPS steps through segments that are all arcs in their chords' cones
    (``arc``), the chords' directions from the first to the last spanning at most
    CHAIN (``turn``: each chord's turn into the next).  Such a chain's tangents lie
    within CHAIN + 2 CONE < 180 degrees, within CHAIN / 2 + CONE of the middle
    direction d: the chain advances along d, and so does every polyline with its
    vertices on the chain, in order (each chord lies in the cone of its part's
    tangents); it meets itself nowhere, nor do the parts it joins, at any level, nor
    the lifted loops (sub-pieces of it)."""
    m = len(i)
    x, y = np.concatenate((i, j)), np.concatenate((j, i))   # both ways in one pass
    out = np.zeros(2 * m, bool)
    cur, ok = x, arc[x]
    acc = lo = hi = np.zeros(2 * m)
    for _ in range(CHAIN_STEPS):
        acc = acc + turn[cur]
        cur = nxt[cur]
        lo, hi = np.minimum(lo, acc), np.maximum(hi, acc)
        ok = ok & arc[cur] & (hi - lo <= CHAIN)
        out |= ok & (cur == y)
    return out[:m] | out[m:]


def _segment_parts(pieces, pid, t0, t1, cut_lines=True):
    """(segments, their parts) by degree: each segment's piece restricted to its
    range [t0, t1], a stack (k, n+1, 3) of the segments k of one degree; with
    ``cut_lines`` False the line segments' whole pieces (for a caller that asks only
    their degree)."""
    group = np.zeros(len(pieces), np.int64)
    row = np.zeros(len(pieces), np.int64)
    groups = pc.degree_groups(pieces)
    for g, (of, _) in enumerate(groups):
        group[of] = g
        row[of] = np.arange(len(of))
    for g, (_, stack) in sorted(enumerate(groups), key=lambda x: x[1][1].shape[1]):
        k = (group[pid] == g).ravel().nonzero()[0]
        parts = stack.take(row[pid[k]], axis=0)
        # a segment over its whole piece (most at the coarse level) is the piece
        cut = ((t0[k] != 0.0) | (t1[k] != 1.0)).ravel().nonzero()[0]
        if len(cut) and (cut_lines or stack.shape[1] > 2):
            parts[cut] = bz.subsegment_many(parts.take(cut, axis=0), t0[k[cut]], t1[k[cut]])
        yield k, parts


def _in_cone(parts, chord, cos_max):
    """Whether each part's control-polygon legs (those of nonzero length) all lie
    within the angle acos(cos_max) of its chord: a stack of parts (k, n+1, 3) and
    their chords (k, 2), (k,) bool.  Leg by leg on (k,) columns (the (k, n, 2)
    planes would go through numpy's buffered iterator); a stack of at most
    pl.CHORD_PLANES parts all legs at once on the (k, n) planes (the same
    operations on each leg, in a fixed dozen calls where the columns take a dozen
    per leg)."""
    ux, uy = chord[:, 0], chord[:, 1]
    norm = np.hypot(ux, uy)
    if len(parts) <= pl.CHORD_PLANES:
        x, y = parts[:, :, 0] / parts[:, :, 2], parts[:, :, 1] / parts[:, :, 2]
        lx, ly = x[:, 1:] - x[:, :-1], y[:, 1:] - y[:, :-1]
        size = np.hypot(lx, ly) * norm[:, None]
        legs = (lx * ux[:, None] + ly * uy[:, None] >= cos_max * size) | (size == 0)
        return np.logical_and.reduce(legs, axis=1)
    out = np.ones(len(parts), bool)
    x0, y0 = parts[:, 0, 0] / parts[:, 0, 2], parts[:, 0, 1] / parts[:, 0, 2]
    for j in range(1, parts.shape[1]):
        x1, y1 = parts[:, j, 0] / parts[:, j, 2], parts[:, j, 1] / parts[:, j, 2]
        lx, ly = x1 - x0, y1 - y0
        size = np.hypot(lx, ly) * norm
        out &= (lx * ux + ly * uy >= cos_max * size) | (size == 0)
        x0, y0 = x1, y1
    return out


def _links(loop_of):
    """(nxt, prv, starts) of closed loops stored one after another (loop_of sorted)."""
    change = np.empty(len(loop_of), bool)     # loop_of >= 0: the first entry starts a loop
    change[:1] = True
    change[1:] = loop_of[1:] != loop_of[:-1]
    first = change.nonzero()[0]
    starts = np.concatenate((first, [len(loop_of)]))
    idx = np.arange(len(loop_of))
    nxt = idx + 1
    nxt[starts[1:] - 1] = starts[:-1]
    prv = idx - 1
    prv[starts[:-1]] = starts[1:] - 1
    return nxt, prv, starts


def _through_hot_pixels(q, x, pid, ts, loop_of, nxt):
    """Each segment routed through the grid points of the vertices whose pixels (unit
    squares around them) its unrounded form crosses: snap rounding (Hobby) with the
    vertices' pixels hot.

    Rounding each vertex on its own can invert two segments closer than a grid
    step (a needle of two near-coincident legs whose ends round apart: its inside
    changes winding, an open crack in a filled region).  Through the same hot
    pixels, such legs round to the same grid path, and near-parallel segments keep
    their order.  x: unrounded positions in grid units; a vertex put on a segment
    gets that segment's piece and a parameter interpolated along it.  The rounded
    polyline stays within sqrt(2) / 2 grid units of the unrounded one.

    Returns (q, pid, ts, loop_of) after the cuts and (the grid of the segments
    before, the index of each one's first segment after, how many it became): the
    lift looks up the segments near a point in that grid (:data:`SEGMENT_REACH`).
    """
    a, b = x, x.take(nxt, axis=0)
    grid = BoxGrid(np.minimum(a, b) - SEGMENT_REACH, np.maximum(a, b) + SEGMENT_REACH)
    hot, hot_of = _unique_rows(q)
    hx, hy = hot[:, 0].astype(float), hot[:, 1].astype(float)
    h, s = grid.at_points(pl.columns(hx, hy))
    # boxes (widened by half a pixel) that hold the pixel's centre, not at own ends
    # (on coordinate columns: gathering rows of (n, 2) arrays costs several times more)
    cx, cy = hx[h], hy[h]
    ax, ay, bx, by = a[:, 0], a[:, 1], b[:, 0], b[:, 1]
    lo_x, lo_y = np.minimum(ax, bx) - 0.5, np.minimum(ay, by) - 0.5
    hi_x, hi_y = np.maximum(ax, bx) + 0.5, np.maximum(ay, by) + 0.5
    hot_end = hot_of[nxt]   # each segment's end pixel, once per segment
    keep = ((lo_x[s] < cx) & (hi_x[s] > cx) & (lo_y[s] < cy) & (hi_y[s] > cy)
            & (hot_of[s] != h) & (hot_end[s] != h)).ravel().nonzero()[0]
    h, s = h[keep], s[keep]
    c = pl.columns(cx[keep], cy[keep])
    as_, bs = a.take(s, axis=0), b.take(s, axis=0)
    keep = _line_crosses_square(as_, bs, c)
    h, s, c = h[keep], s[keep], c.compress(keep, axis=0)
    as_, bs = as_.compress(keep, axis=0), bs.compress(keep, axis=0)
    n = len(q)
    if not len(s):
        return q, pid, ts, loop_of, (grid, np.arange(n), np.ones(n, np.int64))
    d = bs - as_
    u = np.clip(np.einsum("ij,ij->i", c - as_, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300),
                0.0, 1.0)
    t_end = np.where((pid[nxt[s]] == pid[s]) & (ts[nxt[s]] > ts[s]), ts[nxt[s]], 1.0)
    # the new vertices after their segment's start, in order along it: only they are
    # sorted (by segment, then u, ties in the order found), each vertex then moved
    # on by the new ones before it
    new = np.lexsort((u, s))
    s, u, h = s[new], u[new], h[new]
    added = np.bincount(s, minlength=n)
    before = added.cumsum() - added               # new vertices before vertex i's
    at_old = np.arange(n) + before
    at_new = s + 1 + before[s] + (np.arange(len(s)) - np.searchsorted(s, s))
    out = np.empty(n + len(s), np.int64)
    out[at_old], out[at_new] = np.arange(n), n + np.arange(len(s))
    q = np.concatenate([q, hot.take(h, axis=0)]).take(out, axis=0)
    pid = np.concatenate([pid, pid[s]])[out]
    ts = np.concatenate([ts, ts[s] + u * (t_end[new] - ts[s])])[out]
    loop_of = np.concatenate([loop_of, loop_of[s]])[out]
    return q, pid, ts, loop_of, (grid, at_old, added + 1)


def _unique_rows(q):
    """(distinct rows of an (n, 2) integer array, the index of each row among them).
    The rows in (x, y) order: as one integer key sorted with its index where that
    fits 62 bits (the order of a stable lexsort), else by lexsort."""
    lo, hi = col_min(q), col_max(q)
    height = int(hi[1]) - int(lo[1]) + 1
    if len(q) and (int(hi[0]) - int(lo[0]) + 1) * height * len(q) < 2 ** 62:
        _, o = _sorted_entries((q[:, 0] - lo[0]) * height + (q[:, 1] - lo[1]),
                               np.arange(len(q)), len(q))
    else:
        o = np.lexsort((q[:, 1], q[:, 0]))
    r = q.take(o, axis=0)
    new = np.concatenate(([True], (r[1:, 0] != r[:-1, 0]) | (r[1:, 1] != r[:-1, 1])))
    of = np.empty(len(q), np.int64)
    of[o] = new.cumsum() - 1
    return r.compress(new, axis=0), of


def _line_crosses_square(a, b, c):
    """Whether the lines through a and b cross the unit squares centred at c (not
    just touch): |d x (c - a)| < (|d_x| + |d_y|) / 2, d = b - a.  For a segment
    whose box overlaps the square, the same as the segment crossing it."""
    d, w = b - a, c - a
    return np.abs(d[:, 0] * w[:, 1] - d[:, 1] * w[:, 0]) < 0.5 * (np.abs(d[:, 0]) + np.abs(d[:, 1]))


def _merge_equal(q, is_start, loop_of):
    """Indices to keep: one vertex per run of equal consecutive grid points of a loop
    (cyclic), the last piece start in the run if any, else its first vertex.  All
    loops at once: a vertex's run is that of the last run start at or before it in
    its loop, or the loop's last run (wrapping round) before the loop's first run
    start; a loop that is one grid point has no run start and is dropped."""
    n = len(q)
    if not n:
        return np.zeros(0, np.int64)
    _, prv, starts = _links(loop_of)
    size = np.diff(starts)
    loop = np.arange(len(size)).repeat(size)
    begins = (q[:, 0] != q[prv, 0]) | (q[:, 1] != q[prv, 1])  # a run begins at this vertex
    if not begins.any():
        return np.zeros(0, np.int64)
    count = begins.cumsum()                        # run starts up to and with i
    before = np.concatenate([[0], count])[starts[:-1]]  # ... before each loop
    total = count[starts[1:] - 1] - before           # run starts of each loop
    own = count - before[loop]                       # ... of the loop, up to i
    live = total[loop] > 0
    run = np.where(own > 0, count, before[loop] + total[loop]) - 1
    run_start = begins.ravel().nonzero()[0]               # run r begins at run_start[r]
    idx = np.arange(n)
    r0 = run_start[np.where(live, run, 0)]
    key = np.where(live, (idx - r0) % size[loop], 0)  # position along its run
    best = np.full(len(run_start), -1, np.int64)
    sel = live & is_start
    np.maximum.at(best, run[sel], key[sel])
    runs = np.arange(len(run_start))
    rl = loop[run_start]
    keep = starts[rl] + (run_start - starts[rl] + np.maximum(best, 0)) % size[rl]
    return np.sort(keep[runs])
