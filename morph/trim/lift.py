"""Rings of the polygon engine lifted back to the exact rational pieces.

Each edge of an output ring lies on one input segment (:mod:`.topology`); it is
identified by the tags of its end vertices (exact grid matches of input vertices)
or, for an edge between two crossings, by the nearest input segment.  Consecutive
edges on consecutive segments of one piece form a *run*: the piece restricted to
[t_a, t_b] (reversed when the ring runs against the piece).  Where runs meet at a
joint of two consecutive pieces, their shared end is the junction; elsewhere they
meet at a crossing, refined by Newton iteration on the two exact pieces (the
paper's Fig. 33), all crossings in one batch.  A crossing where Newton does not
converge near the polyline crossing (near-tangent pieces, or a crossing rounded onto
a joint's grid point, so that the ring pairs the wrong pieces) keeps the grid point,
and each of its runs ends at its piece's point nearest to it within the segment's
parameter range (within eps + grid/sqrt(2) of it), not at a parameter interpolated
along the segment.

Rows of multi-dimensional arrays are gathered by ``take`` / ``compress`` (see
:mod:`morph.polyline`).
"""

from functools import lru_cache

import numpy as np

from .. import bernstein as bz
from .. import piece as pc
from .. import moments as mo
from .. import nearest as nr
from .flatten import SEGMENT_REACH
from ..polyline import (BoxGrid, _ranks, _sorted_entries, col_max, col_min, project,
                        segment_distance, unique)

MATCH_UNITS = 2.0  # an edge lies within this many grid units of its segment (rounding)
# The snap-rounding grid's segment boxes reach far enough to hold every segment
# within MATCH_UNITS of a point (half a unit more for the point's own rounding).
assert SEGMENT_REACH >= MATCH_UNITS + 0.5
PARAM_EPS = 1e-9  # parameters this close to 0 or 1 are a piece's end
MIN_SIN_HALF = 1e-3  # crossings shallower than 0.11 degrees get no shallow allowance
#: Newton rows whose step moves their points by at most this share of the accepted
#: error leave the iteration (:func:`newton_crossings`)
SETTLE = 1e-6
#: A ring's crossing where the two pieces meet at sin(alpha / 2) below this is no
#: crossing Newton can place: pieces that touch or run along each other there
#: (coincident convolution pieces) stall it anywhere along the contact, at a point
#: that rounding noise of the coordinates decides (a glyph moved into a packed sum
#: can see such a junction move by up to 0.4 tol), so it stays on its grid point
#: (:func:`_crossing_points`).  sin(alpha / 2) of coincident pieces is the square
#: root of the noise of their tangents' cosine, about 1e-7; a crossing this shallow
#: lies within the polyline crossing's error of the grid point anyway
TANGENT_SIN_HALF = 1e-5


def lift_rings(rings, tg, contract, packed=False):
    """(loops of rational pieces, one per ring (see the module docstring), the index
    of each loop's ring): rings whose runs were all contracted are left out.  With
    ``packed``, a third item: the loops' pieces one loop after another as a
    :class:`morph.piece.Pieces` (the stacks the pieces are views of: what
    :func:`.untangle.untangle` searches, without gathering them again).

    rings: :class:`.topology.Rings` (or a list of integer vertex arrays); tg:
    :class:`.flatten.Tagged`; runs shorter than ``contract`` (control-polygon length)
    are contracted to their start point.
    """
    if not len(rings):
        return ([], [], pc.Pieces([], 0)) if packed else ([], [])
    if hasattr(rings, "sizes"):
        sizes, v = rings.sizes, rings.q
    else:
        sizes, v = np.array([len(r) for r in rings]), np.concatenate(rings)
    first = np.concatenate([[0], sizes.cumsum()[:-1]])
    nx = np.arange(len(v)) + 1
    nx[first + sizes - 1] = first
    vn = v.take(nx, axis=0)
    seg, fwd = _edge_segments(v, vn, tg, nx)
    a, b = tg.q.take(seg, axis=0).astype(float), tg.q.take(tg.nxt[seg], axis=0).astype(float)
    u_p, u_q = project(v, a, b), project(vn, a, b)
    t0, t1 = tg.t0[seg], tg.t1[seg]
    tp, tq = t0 + u_p * (t1 - t0), t0 + u_q * (t1 - t0)
    pid = tg.piece[seg]
    s_n, f_n = seg[nx], fwd[nx]
    step = np.where(fwd, tg.nxt[seg], tg.prv[seg])
    ends_match = np.where(fwd, t1 == tg.t0[s_n], t0 == tg.t1[s_n])
    cont = (pid == pid[nx]) & (fwd == f_n) & ((s_n == seg) | ((s_n == step) & ends_match))
    joint = ~cont & (fwd == f_n) & (s_n == step)
    cross = ~cont & ~joint
    point = _crossing_points(tg, v, nx, cross, pid, t0, t1, tp, tq)
    flat = _ring_runs(rings, first, sizes, nx, cont, pid, tp, tq, fwd, point, tg.pieces)
    reach = 2.0 * tg.grid * MATCH_UNITS
    flagged = _spike_triples(flat, reach)
    if flagged:  # rare: the flagged rings' runs as lists, cut one by one
        flat = _with_spikes_cut(flat, flagged, reach)
    out, stacks = _close_all(flat, contract)
    kept = [k for k, loop in enumerate(out) if loop]
    loops = [out[k] for k in kept]
    if not packed:
        return loops, kept
    if stacks is None:   # some rings closed one by one: their pieces are new
        stacks = pc.Pieces.of([p for loop in loops for p in loop])
    return loops, kept, stacks


def _crossing_points(tg, v, nx, cross, pid, t0, t1, tp, tq):
    """The junction point after each ring edge ``i`` where ``cross[i]`` (the edge and
    the next lie on different pieces that cross there; NaN elsewhere), by Newton on
    the exact pieces in one batch; the crossing parameters are written into ``tq``
    (of edge i) and ``tp`` (of the next edge) in place."""
    k = cross.ravel().nonzero()[0]
    guess = tg.to_float(v.take(nx[k], axis=0))
    point = np.full((len(v), 2), np.nan)  # junction point after edge i
    if len(k):
        ids = np.concatenate([pid[k], pid[nx[k]]])
        used = unique(ids)
        inv = np.searchsorted(used, ids)
        stacked = pc.stack(pc.Pieces.of(tg.pieces).take(used))
        ia, ib = inv[:len(k)], inv[len(k):]
        # a polyline crossing is off the exact one by up to (eps + grid / sqrt 2) /
        # sin(alpha / 2) at an angle alpha: far along a shallow crossing
        ta, tb, ok = newton_crossings(stacked, ia, tq[k], ib, tp[nx[k]], guess,
                                      reach=2.0 * tg.grid * MATCH_UNITS, atol=0.01 * tg.grid,
                                      shallow=2.0 * (tg.eps + tg.grid / np.sqrt(2.0)),
                                      settle=SETTLE * 0.01 * tg.grid, tangent=TANGENT_SIN_HALF)
        # where Newton did not converge the junction stays on the grid point, and each
        # run ends at its piece's point nearest to it within its segment's range (not
        # at the parameter interpolated along the segment: where the piece's speed
        # varies that point can lie far from the segment's, and snapping the run's end
        # to the junction would bend the piece that far)
        bad = ~ok
        if bad.any():
            ta[bad] = nr.nearest_params_in_range(stacked[ia[bad]], guess[bad], t0[k[bad]],
                                                 t1[k[bad]])
            tb[bad] = nr.nearest_params_in_range(stacked[ib[bad]], guess[bad],
                                                 t0[nx[k[bad]]], t1[nx[k[bad]]])
        tq[k], tp[nx[k]] = ta, tb
        point[k] = np.where(ok[:, None], pc.jet_many(stacked, ia, ta)[0], guess)
    return point


def _ring_runs(rings, first, sizes, nx, cont, pid, tp, tq, fwd, point, pieces):
    """The runs of all rings held flat: (sub-pieces (a :class:`morph.piece.Pieces`),
    the junction point after each (N, 2) (crossings from Newton; at joints the mean
    of the two ends), the number of runs of each ring).  All rings at once: a run
    goes from the edge after one junction (an edge whose successor ``nx`` is not
    its continuation) to the next junction of its ring, cyclically; a ring without
    junction is one whole piece.  The runs are cut in one call
    (:func:`morph.piece.subsegments`)."""
    n_rings = len(rings)
    ring_of = np.arange(n_rings).repeat(sizes)
    junction = (~cont).ravel().nonzero()[0]                 # sorted: grouped by ring, in order
    jr = ring_of[junction]
    count = np.bincount(jr, minlength=n_rings)
    lo = count.cumsum() - count                    # first junction of each ring
    i = np.arange(len(junction))
    prev = np.where(i == lo[jr], lo[jr] + count[jr] - 1, i - 1)
    e_first, e_last = nx[junction[prev]], junction
    whole = (count == 0).ravel().nonzero()[0]               # a whole single-piece loop
    e = first[whole]
    ring = np.concatenate([jr, whole])
    piece_id = np.concatenate([pid[e_first], pid[e]]).astype(int)
    ta = np.concatenate([tp[e_first], np.where(fwd[e], 0.0, 1.0)])
    tb = np.concatenate([tq[e_last], np.where(fwd[e], 1.0, 0.0)])
    row = np.concatenate([e_last, np.full(len(e), -1)])
    order = np.argsort(ring, kind="stable")          # by ring, runs in ring order
    ring, piece_id, ta, tb, row = ring[order], piece_id[order], ta[order], tb[order], row[order]
    cut = pc.subsegments(pieces, piece_id, ta, tb, packed=True)
    starts, stops = pc.end_points(cut)
    ends = np.where((row >= 0)[:, None], point.take(np.maximum(row, 0), axis=0), starts)
    # junctions at joints (no crossing point): the mean of the two runs' ends
    per = np.bincount(ring, minlength=n_rings)
    base = per.cumsum() - per
    k = np.arange(len(ring))
    after = np.where(k + 1 == base[ring] + per[ring], base[ring], k + 1)
    gap = np.isnan(ends).any(axis=1)
    ends[gap] = 0.5 * (stops.compress(gap, axis=0) + starts.take(after[gap], axis=0))
    return cut, ends, per


def _with_spikes_cut(flat, flagged, reach):
    """The runs held flat (pieces, junction ends, runs per ring) with the spikes
    ``flagged`` ((ring, run) pairs, :func:`_spike_triples`) cut out: only the rings
    flagged are taken out as lists and cut (:func:`_cut_flagged`); the others keep
    their rows of the packed pieces, and the cut rings' pieces are put back in
    their places (one gather)."""
    pieces, ends, per = flat
    pieces = pc.Pieces.of(pieces)
    base = per.cumsum() - per
    hit = np.zeros(len(per), bool)
    hit[[r for r, _ in flagged]] = True
    runs = {}
    for r in hit.ravel().nonzero()[0].tolist():
        a, b = int(base[r]), int(base[r] + per[r])
        runs[r] = (pieces.take(np.arange(a, b)).rows(), list(ends[a:b]))
    _cut_flagged(runs, flagged, reach)
    new_per = per.copy()
    for r, (out, _) in runs.items():
        new_per[r] = len(out)
    kept = ~hit.repeat(per)
    new = [p for r in sorted(runs) for p in runs[r][0]]
    new_ends = np.array([e for r in sorted(runs) for e in runs[r][1]], float).reshape(-1, 2)
    # the final order: ring by ring, the kept rows first in the stack, then the new
    cut_row = hit.repeat(new_per)
    where = np.empty(len(cut_row), np.int64)
    where[~cut_row] = np.arange(int(kept.sum()))
    where[cut_row] = kept.sum() + np.arange(len(new))
    both = pieces.take(kept.ravel().nonzero()[0]).then(new)
    kept_ends = np.concatenate([ends.compress(kept, axis=0), new_ends])
    return both.take(where), kept_ends.take(where, axis=0), new_per


def _as_runs(flat):
    """Runs held flat (pieces, junction ends (N, 2), runs per ring) as per ring
    [(pieces, ends)], lists."""
    pieces, ends, per = flat
    rows = list(pieces)
    bounds = np.append(per.cumsum() - per, len(rows)).tolist()
    return [(rows[bounds[r]:bounds[r + 1]], list(ends[bounds[r]:bounds[r + 1]]))
            for r in range(len(per))]


def _flat_runs(runs):
    """:func:`_as_runs` undone: (pieces, ends (N, 2), runs per ring)."""
    pieces = [p for out, _ in runs for p in out]
    ends = np.array([e for _, ends in runs for e in ends], float).reshape(-1, 2)
    return pieces, ends, np.array([len(out) for out, _ in runs], np.int64)


def _close_all(flat, contract):
    """:func:`_close` of every ring's runs (held flat: pieces, junction ends (N, 2),
    runs per ring): the first round (lengths, snapping to the junctions, lengths
    again) for all rings at once; the rings where snapping leaves a short run go on
    one by one.  Returns (the loops, the :class:`morph.piece.Pieces` whose rows
    they are, one loop after another; None where some ring went on alone)."""
    pieces, ends, per_ring = flat
    n_rings = len(per_ring)
    if not len(pieces):
        return [[] for _ in range(n_rings)], pc.Pieces([], 0)
    pieces = pc.Pieces.of(pieces)
    ring = np.arange(n_rings).repeat(per_ring)
    keep = pc.length_bounds(pieces) >= contract
    idx = keep.ravel().nonzero()[0]
    kr = ring[idx]
    per = np.bincount(kr, minlength=n_rings)
    base = per.cumsum() - per
    k = np.arange(len(idx))
    before = np.where(k == base[kr], base[kr] + per[kr] - 1, k - 1)
    snapped = _with_endpoints_many(pieces.take(idx), ends.take(idx[before], axis=0),
                                   ends.take(idx, axis=0), packed=True)
    after = pc.length_bounds(snapped) if len(idx) else np.zeros(0)
    short = np.bincount(kr, weights=((after < contract) | (after == 0.0)),
                        minlength=n_rings) > 0
    rows = snapped.rows()
    bounds = np.append(base, len(idx)).tolist()
    if not short.any():
        return [rows[bounds[r]:bounds[r + 1]] for r in range(n_rings)], snapped
    first = np.append(per_ring.cumsum() - per_ring, len(ring)).tolist()
    whole = pieces.rows()
    return [_close(whole[first[r]:first[r + 1]], list(ends[first[r]:first[r + 1]]), contract)
            if short[r] else rows[bounds[r]:bounds[r + 1]] for r in range(n_rings)], None


def _with_endpoints_many(pieces, p0, p1, packed=False):
    """:func:`morph.piece.with_endpoints` of many pieces (first and last control
    points moved to p0[k] and p1[k]), those of one degree at once: a list (with
    ``packed`` a :class:`morph.piece.Pieces`)."""
    out = []
    for ks, h in pc.degree_groups(pieces):
        h = h.copy()
        h[:, 0, :2] = p0.take(ks, axis=0) * h[:, 0, 2:]
        h[:, -1, :2] = p1.take(ks, axis=0) * h[:, -1, 2:]
        out.append((ks, h))
    out = pc.Pieces(out, len(pieces))
    return out if packed else out.rows()


def _close(out, ends, contract):
    """Runs shorter than ``contract`` dropped, the rest snapped to the junctions;
    again while snapping leaves a run that short (or of no length at all: both
    ends on one junction)."""
    while True:
        lengths = pc.length_bounds(out) if out else np.zeros(0)
        keep = [j for j in range(len(out)) if lengths[j] >= contract]
        snapped = [pc.with_endpoints(out[j], ends[keep[i - 1]], ends[j])
                   for i, j in enumerate(keep)]
        after = pc.length_bounds(snapped) if snapped else np.zeros(0)
        short = (after < contract) | (after == 0.0)
        if not short.any():
            return snapped
        out = [p for p, s in zip(snapped, short) if not s]
        ends = [ends[j] for j, s in zip(keep, short) if not s]


def _spike_triples(flat, reach):
    """The runs (ring r, run j) between two neighbours that cross each other: spikes.

    Near-tangent pieces turn the polylines' small normal error into a long
    tangential one, so a ring can take a run just past the exact crossing of its
    neighbours: a spike that makes the loop cross itself.  All runs of rings of
    three or more are checked at once (Newton from the ends of the two neighbours
    at the run, within the run's length + ``reach``), on the runs held flat
    (pieces, junction ends, runs per ring: :func:`_ring_runs`).  A real short piece
    between neighbours that do not cross (a nib's tip) is not one."""
    pieces, ends, per = flat
    ring = np.arange(len(per)).repeat(per)
    base = per.cumsum() - per
    i = (per[ring] >= 3).ravel().nonzero()[0]
    if not len(i):
        return []
    r = ring[i]
    j = i - base[r]
    prev, nxt = base[r] + (j - 1) % per[r], base[r] + (j + 1) % per[r]
    pieces = pc.Pieces.of(pieces)
    lim = pc.length_bounds(pieces.take(i)) + reach
    atol = 1e-6 * reach
    # a crossing Newton accepts lies on the neighbour before (in its control box),
    # within atol of the one after (in its box grown by atol) and within lim of the
    # junction: rows whose three boxes (grown by atol, far above rounding) share no
    # point cannot have one, and are not iterated
    box = pc.bboxes(pieces.take(np.concatenate([prev, nxt])))
    m = len(i)
    ei = ends.take(i, axis=0)
    g = np.concatenate([ei - lim[:, None], ei + lim[:, None]], axis=1)
    lo = np.maximum(np.maximum(box[:m, :2], box[m:, :2]) - atol, g[:, :2])
    hi = np.minimum(np.minimum(box[:m, 2:], box[m:, 2:]) + atol, g[:, 2:])
    maybe = ((lo[:, 0] <= hi[:, 0]) & (lo[:, 1] <= hi[:, 1])).ravel().nonzero()[0]
    if not len(maybe):
        return []
    i, r, j, prev, nxt, lim = i[maybe], r[maybe], j[maybe], prev[maybe], nxt[maybe], lim[maybe]
    stacked = pc.stack(pieces.take(np.concatenate([prev, nxt])))
    m = len(i)
    ia, ib = np.arange(m), np.arange(m, 2 * m)
    s, u, ok = newton_crossings(stacked, ia, np.ones(m), ib, np.zeros(m), ends.take(i, axis=0),
                                lim, atol, settle=SETTLE * atol)
    ok &= (s > PARAM_EPS) & (s < 1.0 - PARAM_EPS) & (u > PARAM_EPS) & (u < 1.0 - PARAM_EPS)
    return list(zip(r[ok].tolist(), j[ok].tolist()))


def _cut_spikes(runs, reach):
    """The spikes of rings' runs given as lists ([(pieces, ends)] per ring) cut out
    in place (:func:`_spike_triples`, :func:`_cut_flagged`)."""
    _cut_flagged(runs, _spike_triples(_flat_runs(runs), reach), reach)


def _cut_flagged(runs, flagged, reach):
    """The spikes of :func:`_spike_triples` cut out of the rings' runs (lists, in
    place): from the last run back, so that the indices still to visit stay valid
    (a cut changes runs j - 1 and j + 1 only); each cut is checked again first."""
    for r, j in sorted(set(flagged), reverse=True):
        out, _ = runs[r]
        if len(out) >= 3 and j < len(out):
            _neighbours_cross(runs, [(r, j)], reach, apply=True)


def _neighbours_cross(runs, tri, reach, apply=False):
    """For runs (ring r, run j): do the runs before and after j cross near j?
    With ``apply`` (one triple) the crossing is cut in place."""
    a_list, b_list, guess, mid = [], [], [], []
    for r, j in tri:
        out, ends = runs[r]
        a_list.append(out[(j - 1) % len(out)])
        b_list.append(out[(j + 1) % len(out)])
        guess.append(ends[j])
        mid.append(out[j])
    lim = pc.length_bounds(mid) + reach
    stacked = pc.stack(a_list + b_list)
    m = len(tri)
    ia, ib = np.arange(m), np.arange(m, 2 * m)
    s, u, ok = newton_crossings(stacked, ia, np.ones(m), ib, np.zeros(m), np.array(guess),
                                lim, 1e-6 * reach)
    # only interior crossings: the neighbours' far ends are junctions of their own
    # (in a ring of three runs they meet each other there)
    ok &= (s > PARAM_EPS) & (s < 1.0 - PARAM_EPS) & (u > PARAM_EPS) & (u < 1.0 - PARAM_EPS)
    if apply and ok[0]:
        _cut_at(runs[tri[0][0]], tri[0][1], s[0], u[0], pc.jet_many(stacked, ia, s)[0][0])
    return ok


def _cut_at(run, j, s, u, x):
    """Split a ring's runs where the neighbours of run j cross (at s on the one
    before, u on the one after, point x) and keep the larger part by area: the
    rest of the ring without run j (a spike at j), or the part through j (the rest
    was the spike: a run between the neighbours' crossing and the ring's far side).
    """
    out, ends = run
    i, k = (j - 1) % len(out), (j + 1) % len(out)
    head_i, tail_i = pc.subsegment(out[i], 0.0, s), pc.subsegment(out[i], s, 1.0)
    head_k, tail_k = pc.subsegment(out[k], 0.0, u), pc.subsegment(out[k], u, 1.0)
    through_j = [tail_i, out[j], head_k]
    part = mo.loop_area(through_j)
    if abs(part) > abs(mo.loop_area(out) - part):
        out[:] = through_j
        ends[:] = [ends[i], ends[j], x]
        return
    ends[i] = x
    out[i], out[k] = head_i, tail_k
    del out[j], ends[j]


def _edge_segments(p, q, tg, nx=None):
    """Input segment and direction (True: along the segment) of each edge p -> q.

    Most edges are input segments whose two ends are input vertices found at no
    other grid point: those are read off directly; the rest are matched by
    :func:`_matched_segments`.  ``nx``: where q = p[nx] (the edges of closed
    rings), each vertex is looked up once."""
    keys = _as_keys(tg.q, tg.q)
    if keys.dtype.names is None:  # integer keys: sorted with their indices as one integer
        sk, order = _sorted_entries(keys, np.arange(len(keys)), len(keys))
    else:
        order = np.argsort(keys, kind="stable")
        sk = keys[order]
    ip = _unique_vertex(sk, order, _as_keys(p, tg.q))
    iq = ip[nx] if nx is not None else _unique_vertex(sk, order, _as_keys(q, tg.q))
    seg = np.zeros(len(p), np.int64)
    direction = np.ones(len(p), bool)
    along = (ip >= 0) & (iq >= 0) & (tg.nxt[np.maximum(ip, 0)] == iq)
    against = (ip >= 0) & (iq >= 0) & (tg.nxt[np.maximum(iq, 0)] == ip) & ~along
    seg[along], seg[against] = ip[along], iq[against]
    direction[against] = False
    rest = (~(along | against)).ravel().nonzero()[0]
    if len(rest):
        pr, qr = p.take(rest, axis=0), q.take(rest, axis=0)
        seg[rest], direction[rest] = _matched_segments(pr, qr, tg, (sk, order))
    return seg, direction


def _unique_vertex(sorted_keys, order, kp):
    """Index of the input vertex at each key, -1 where there is none or several
    (one search: the key at its place, and not the one after it)."""
    n = len(sorted_keys)
    if not n:
        return np.full(len(kp), -1, np.int64)
    lo = np.minimum(np.searchsorted(sorted_keys, kp, "left"), n - 1)
    one = (sorted_keys[lo] == kp) & ((lo == n - 1) | (sorted_keys[np.minimum(lo + 1, n - 1)] != kp))
    return np.where(one, order[lo], -1)


def _matched_segments(p, q, tg, sorted_keys):
    """:func:`_edge_segments` by candidates: segments at the edges' end vertices, the
    best fitting one; edges between crossings by a search over all segments."""
    sa, sb = tg.q, tg.q.take(tg.nxt, axis=0)
    cand_e, cand_s = _vertex_candidates(p, q, tg, sorted_keys)
    best, seg, direction = _best_fits(len(p), cand_e, cand_s, *_fit(
        p.take(cand_e, axis=0), q.take(cand_e, axis=0), sa.take(cand_s, axis=0),
        sb.take(cand_s, axis=0)))
    lost = (best > MATCH_UNITS).ravel().nonzero()[0]
    if len(lost):
        s, f = _nearest_segments(p.take(lost, axis=0), q.take(lost, axis=0), sa, sb, tg)
        seg[lost], direction[lost] = s, f
    return seg, direction


def _nearest_segments(p, q, sa, sb, tg=None):
    """For edges p -> q: the segment sa -> sb that fits both ends best, and whether
    the edge runs along it.  Candidates are the segments whose boxes, widened by
    MATCH_UNITS, hold p (:class:`morph.polyline.BoxGrid`), in ascending order for
    each edge; an edge with no candidate within MATCH_UNITS is matched against every
    segment.  With ``tg``'s snap-rounding grid (:attr:`.flatten.Tagged.seg_grid`,
    boxes grown by SEGMENT_REACH >= MATCH_UNITS + 1/2) the candidates are the
    segments cut from the ones it gives, and no grid is built here: every segment
    within MATCH_UNITS of p is among them, and the best fit is the first of those
    with the least score either way."""
    if tg is not None and tg.seg_grid is not None:
        e, old = tg.seg_grid.at_points(p)
        cnt = tg.seg_count[old]
        e = e.repeat(cnt)
        s = tg.seg_first[old].repeat(cnt) + _ranks(cnt)
    else:
        grid = BoxGrid(np.minimum(sa, sb) - MATCH_UNITS, np.maximum(sa, sb) + MATCH_UNITS)
        e, s = grid.at_points(p)
    best, seg, direction = _best_fits(len(p), e, s, *_fit(
        p.take(e, axis=0), q.take(e, axis=0), sa.take(s, axis=0), sb.take(s, axis=0)))
    far = (best > MATCH_UNITS).ravel().nonzero()[0]
    for chunk in np.array_split(far, max(1, len(far) // 64)):
        if len(chunk):
            sc, fw = _fit(p[chunk, None], q[chunk, None], sa[None], sb[None])
            i = np.argmin(sc, axis=1)
            seg[chunk], direction[chunk] = i, fw[np.arange(len(chunk)), i]
    return seg, direction


def _best_fits(n, e, s, score, fwd):
    """(score, segment, direction) of the best scoring candidate pair (e, s) of each
    of n edges (score inf, segment 0 where an edge has none)."""
    best = np.full(n, np.inf)
    seg = np.zeros(n, np.int64)
    direction = np.ones(n, bool)
    # each edge's least score, then its first candidate at that score (ties go to
    # the first, as a stable sort by (edge, score) takes them): two unbuffered
    # reductions, no sort
    np.fmin.at(best, e, score)
    hit = (score == best[e]).ravel().nonzero()[0]
    first = np.full(n, len(e))
    np.minimum.at(first, e[hit], hit)
    take = first[first < len(e)]
    seg[e[take]], direction[e[take]] = s[take], fwd[take]
    return best, seg, direction


def _vertex_candidates(p, q, tg, sorted_keys):
    """(edge, segment) pairs from exact grid matches of the edges' end vertices;
    ``sorted_keys``: (the keys of the input vertices sorted, their order)."""
    sk, order = sorted_keys
    es, ss = [], []
    for pts, rel in ((p, (lambda i: i, tg.prv.__getitem__)),
                     (q, (tg.prv.__getitem__, lambda i: i))):
        kp = _as_keys(pts, tg.q)
        lo = np.searchsorted(sk, kp, "left")
        hi = np.searchsorted(sk, kp, "right")
        cnt = hi - lo
        e = np.arange(len(pts)).repeat(cnt)
        idx = order[lo.repeat(cnt) + (np.arange(cnt.sum()) - (cnt.cumsum() - cnt).repeat(cnt))]
        for f in rel:
            es.append(e)
            ss.append(f(idx))
    return np.concatenate(es), np.concatenate(ss)


def _as_keys(q, ref):
    """One sortable key per grid point: x * height + y inside the box of ``ref``
    (-1 outside it: such a point matches no vertex of ``ref``); structured
    (x, y) keys where the box has more than 2^62 points."""
    q = np.ascontiguousarray(q, np.int64)
    lo, hi = col_min(ref), col_max(ref)
    height = int(hi[1]) - int(lo[1]) + 1
    if (int(hi[0]) - int(lo[0]) + 1) * height >= 2 ** 62:
        return q.view([("x", np.int64), ("y", np.int64)]).ravel()
    inside = (q[:, 0] >= lo[0]) & (q[:, 0] <= hi[0]) & (q[:, 1] >= lo[1]) & (q[:, 1] <= hi[1])
    return np.where(inside, (q[:, 0] - lo[0]) * height + (q[:, 1] - lo[1]), -1)


def _fit(p, q, a, b):
    """Largest distance of p and q to segment ab, and whether p -> q runs along it."""
    ab = b - a
    pq = q - p
    fwd = pq[..., 0] * ab[..., 0] + pq[..., 1] * ab[..., 1] >= 0
    return np.maximum(segment_distance(p, a, b), segment_distance(q, a, b)), fwd


def newton_step(ha, dha, s, hb, dhb, u):
    """One Newton step on F(s, u) = A(s) - B(u) for rows of stacked homogeneous
    pieces ``ha``, ``hb`` (their hodographs ``dha``, ``dhb``), kept in [0, 1]^2; a
    row whose Jacobian is singular stays where it is."""
    return _newton_step(np.concatenate([ha, hb]), np.concatenate([dha, dhb]), s, u)[:2]


def _newton_step(hab, dhab, s, u):
    """:func:`newton_step` of the rows A, B stacked one after the other (``hab`` the
    m rows of A then those of B, ``dhab`` their hodographs), and how far it moved
    each row's points (|A'| |ds| and |B'| |du|, the larger).  A and B evaluated in
    one :func:`_jet_rows`."""
    m = len(s)
    p, d = _jet_rows(hab, np.concatenate([s, u]), dhab)
    da, db = d[:m], d[m:]
    f = p[:m] - p[m:]
    det = da[:, 0] * (-db[:, 1]) - da[:, 1] * (-db[:, 0])
    ok = np.abs(det) > 1e-300
    safe = np.where(ok, det, 1.0)
    ds = np.where(ok, (f[:, 0] * (-db[:, 1]) - f[:, 1] * (-db[:, 0])) / safe, 0.0)
    du = np.where(ok, (da[:, 0] * f[:, 1] - da[:, 1] * f[:, 0]) / safe, 0.0)
    # kept in [0, 1] (np.clip's result, in two ufunc calls)
    s2, u2 = np.minimum(np.maximum(s - ds, 0.0), 1.0), np.minimum(np.maximum(u - du, 0.0), 1.0)
    speed = np.hypot(d[:, 0], d[:, 1])
    moved = np.maximum(speed[:m] * np.abs(s2 - s), speed[m:] * np.abs(u2 - u))
    return s2, u2, moved


def _jet_rows(h, t, dh):
    """:func:`morph.piece.jet_rows` of rows h (m, n+1, 3) at t with their hodographs
    dh: the Bernstein sums sum_i C(n, i) t^i (1 - t)^(n - i) h[:, i] with the powers
    of t and 1 - t by running products (:func:`_powers`) and the terms added one
    control point after another (a sum over the middle axis: the same bits as a
    loop over them), a fixed number of numpy calls whatever the degree (a Newton
    iteration pays them every step)."""
    n = h.shape[1] - 1
    tp, sp = _powers(t, n), _powers(1.0 - t, n)
    val = _bernstein_sum(h, _binomials(n)[:, None] * tp * sp[::-1])
    dval = _bernstein_sum(dh, _binomials(n - 1)[:, None] * tp[:n] * sp[n - 1::-1])
    w = val[:, 2:3]
    return val[:, :2] / w, (dval[:, :2] * w - val[:, :2] * dval[:, 2:3]) / w ** 2


def _powers(t, n):
    """(n+1, m): t^0 .. t^n of each t, by running products."""
    out = np.empty((n + 1, len(t)))
    out[0] = 1.0
    out[1:] = t
    return np.multiply.accumulate(out, axis=0, out=out)


@lru_cache(maxsize=None)
def _binomials(n):
    """Row n of Pascal's triangle (:func:`morph.bernstein._binomials`), made once."""
    return bz._binomials(n)


def _bernstein_sum(c, basis):
    """sum_i basis[i] c[:, i] of rows c (m, n+1, k) and basis values (n+1, m): (m, k)."""
    return np.add.reduce(basis.T[:, :, None] * c, axis=1)


def newton_crossings(stacked, ia, ta, ib, tb, guess, reach, atol, iters=12, shallow=0.0,
                     settle=0.0, tangent=0.0):
    """Crossings A(s) = B(u) of pairs of rational pieces, all at once (Fig. 33).

    ``stacked``: pieces from :func:`morph.piece.stack`; A = stacked[ia[i]],
    B = stacked[ib[i]].  Newton iteration on F(s, u) = A(s) - B(u) from (ta, tb),
    kept in [0, 1]^2.  Returns (s, u, ok); ok where |F| <= atol and the crossing
    lies within ``reach`` + ``shallow`` / sin(alpha / 2) of ``guess``, alpha the
    angle between the two pieces there (two lines each moved by d across cross
    up to d / sin(alpha / 2) from where they did), the allowance only for
    crossings inside both pieces at sin(alpha / 2) >= MIN_SIN_HALF.  A row leaves
    the iteration once a step leaves (s, u) as they are, and with ``settle`` > 0
    once a step moves both points by at most ``settle`` (rounding noise: the next
    step of a converging iteration is far smaller still; far from the origin the
    iterates wander by ~1e-13 for ever).  Not ok: ending at sin(alpha/2) < ``tangent``.
    """
    if len(ia) == 0:
        return ta, tb, np.zeros(0, bool)
    s, u = np.array(ta, float), np.array(tb, float)
    ha, hb = stacked.take(ia, axis=0), stacked.take(ib, axis=0)
    n = stacked.shape[1] - 1
    dha, dhb = n * (ha[:, 1:] - ha[:, :-1]), n * (hb[:, 1:] - hb[:, :-1])
    # a row whose step leaves (s, u) as they are is at a fixed point of the
    # iteration (a root to the last bit, or clamped at an end): it leaves the batch,
    # the others go on; without ``settle`` the result is the same bits as iterating
    # every row.  The live rows' pieces: A's then B's, stacked once (again when rows leave)
    live, rows = np.arange(len(s)), (np.concatenate([ha, hb]), np.concatenate([dha, dhb]))
    sl, ul = s.copy(), u.copy()
    for _ in range(iters):
        if not len(live):
            break
        s2, u2, moved = _newton_step(rows[0], rows[1], sl, ul)
        s[live], u[live] = s2, u2
        going = (s2 != sl) | (u2 != ul)
        if settle > 0.0:
            going &= moved > settle
        keep = going.nonzero()[0]
        if len(keep) == len(going):
            sl, ul = s2, u2
            continue
        both = np.concatenate([keep, keep + len(going)])
        live, sl, ul = live[keep], s2[keep], u2[keep]
        rows = (rows[0][both], rows[1][both])
    pa, da = _jet_rows(ha, s, dha)
    pb, db = _jet_rows(hb, u, dhb)
    err = np.hypot(*(pa - pb).T)
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = np.abs(np.einsum("ij,ij->i", da, db)) / (np.hypot(*da.T) * np.hypot(*db.T))
    # np.clip(0.5 (1 - nan_to_num(cos, nan=1)), 0, 1): an infinite cos clips to 0 either way
    sin_half = np.sqrt(np.minimum(np.maximum(0.5 * (1.0 - np.where(cos != cos, 1.0, cos)), 0.0),
                                  1.0))
    # the allowance only for crossings inside both pieces (Newton clamps to [0, 1],
    # and consecutive pieces meet at their ends) and not near-tangent: where two
    # pieces touch or continue each other, Newton stalls anywhere along the contact
    real = ((s > PARAM_EPS) & (s < 1.0 - PARAM_EPS) & (u > PARAM_EPS) & (u < 1.0 - PARAM_EPS)
            & (sin_half >= MIN_SIN_HALF))
    allow = np.where(real, shallow / np.maximum(sin_half, MIN_SIN_HALF), 0.0)
    near = np.hypot(*(pa - guess).T) <= reach + allow
    ok = (err <= atol) & near & np.isfinite(err) & (sin_half >= tangent)
    return s, u, ok
