"""The corner pass's refined pairs put into a trimmed boundary in place
(:func:`patched`), without trimming the sum again.

A trimmed boundary (:func:`morph.trim.boundary`) is made of sub-pieces of the
convolution pieces joined end to start: at a joint (the end of one convolution
piece and the start of the next, an exact point of both curves) or at a crossing
of two pieces (solved by Newton on the pieces).  When the corner pass approximates
the pairs of a few table rows again, more finely, each output piece that lies on an
old piece of those rows is replaced by the part of the new pieces between its two
junctions, found again the same way: a joint at an end of a row is the row's end
(the new pieces of a row start and end where the old ones did: the pair's ends);
a crossing is solved again by Newton (:func:`morph.trim.lift.newton_crossings`)
between the new pieces and the neighbouring piece's curve, from the old crossing,
and the neighbouring output piece is cut there (shortened or lengthened along its
own convolution piece).  Joints inside a refined row disappear: the output follows
the row's new pieces across.

The trimming decided which parts of the pieces bound the sum; replacing a piece by
one within e + e' of it (the old and new bounds) moves every crossing by at most
(e + e') / sin(alpha / 2) along the pieces (alpha their angle there), which is what
Newton is allowed (``shallow``), and keeps the topology where that stays inside the
pieces.  Anything else, and any case this does not recognise (an output piece
whose convolution piece is not found exactly, a crossing that moves past the end of
a new piece or of the neighbouring convolution piece, Newton not converging), makes
:func:`patched` return None: the caller trims the parts again.
"""

import numpy as np

from . import piece as pc
from .nearest import nearest_params_in_range
from .polyline import member, unique
from .trim.lift import newton_crossings

#: An output piece lies on a convolution piece where its start, middle and end are
#: within ON_SHARE tol of it (sub-pieces are exact restrictions: only rounding
#: separates them; other pieces through three such points coincide with it)
ON_SHARE = 1e-6
#: An output piece lies on a convolution piece where its middle is within
#: MID_SHARE tol of it and its ends within END_SHARE tol: the trimming moves a
#: piece's ends by up to its topology shares (FLAT_SHARE + GRID_SHARE, a junction
#: left on its grid point) and the middle of a piece of degree n by 2^-n of that
MID_SHARE = 0.01
END_SHARE = 0.5
#: Ends of consecutive convolution pieces are chained within JOIN_SHARE tol
#: (:func:`morph.minkowski._trimmed`)
JOIN_SHARE = 0.01
#: Newton's residual at a crossing, in tol (the trimming's: a hundredth of its grid
#: step, 0.1 sqrt(2) tol)
CROSS_ATOL = 0.01 * 0.1 * np.sqrt(2.0)


def patched(out, conv, again, tol):
    """``out`` (loops of the trimmed boundary of the convolution ``conv``) with the
    pieces of the rows of ``again`` (new pieces of some rows of ``conv``, each row's
    in travel order) in place of the old ones of those rows (module docstring), or
    None where that is not recognised."""
    flat = [p for loop in out for p in loop]
    lens = np.fromiter(map(len, out), np.int64, len(out))
    nxt = np.arange(1, len(flat) + 1)
    nxt[np.cumsum(lens) - 1] = np.cumsum(lens) - lens
    prv = np.empty_like(nxt)
    prv[nxt] = np.arange(len(flat))
    rows = unique(again.row)
    old = np.flatnonzero(member(conv.row, rows))
    boxes = pc.bboxes(flat)
    mine = _within(boxes, pc.bboxes(conv.pieces.take(old)), tol)
    cand = np.flatnonzero(mine.any(axis=1))
    src, s0, s1 = _sources(flat, cand, conv, old, mine[cand], tol)
    hit = cand[src >= 0]
    if not len(hit):
        return None
    near = unique(np.concatenate([prv[hit], nxt[hit]]))
    near = near[~member(near, hit)]
    n_src, n_s0, n_s1 = _sources(flat, near, conv, np.arange(len(conv)),
                                 _within(boxes[near], pc.bboxes(conv.pieces), tol), tol)
    if (n_src < 0).any() or member(conv.row[n_src], rows).any():
        return None
    info = _Info(len(flat), conv, again, rows)
    info.set(hit, src[src >= 0], s0[src >= 0], s1[src >= 0], True)
    info.set(near, n_src, n_s0, n_s1, False)
    new = _rebuilt(flat, nxt, info, tol)
    if new is None:
        return None
    pieces, owner = new
    loop_of = np.repeat(np.arange(len(out)), lens)
    touched = np.zeros(len(out), bool)
    touched[loop_of[info.hit | (info.src >= 0)]] = True
    cut = np.searchsorted(loop_of[owner], np.arange(len(out) + 1))
    loops = [pieces[a:b] for a, b in zip(cut[:-1].tolist(), cut[1:].tolist())]
    if not all(loops):
        return None
    fixed = _snapped([loops[i] for i in np.flatnonzero(touched).tolist()], tol)
    if fixed is None:
        return None
    for i, loop in zip(np.flatnonzero(touched).tolist(), fixed):
        loops[i] = loop
    return loops


class _Info:
    """Per output piece: its convolution piece (``src``, -1: not looked at), its
    parameter range there (``s0``, ``s1``), whether it is replaced (``hit``); the
    new pieces (``again``) by row: the first of each row and their count."""

    def __init__(self, n, conv, again, rows):
        self.src = np.full(n, -1)
        self.s0, self.s1 = np.zeros(n), np.ones(n)
        self.hit = np.zeros(n, bool)
        self.conv, self.again, self.rows = conv, again, rows
        self.first = np.searchsorted(again.row, rows)
        self.count = np.diff(np.append(self.first, len(again.row)))

    def set(self, idx, src, s0, s1, hit):
        self.src[idx], self.s0[idx], self.s1[idx], self.hit[idx] = src, s0, s1, hit


def _within(inner, outer, tol):
    """(len(inner), len(outer)) bools: control boxes ``inner`` inside ``outer``
    (a sub-piece's control points lie in the convex hull of its piece's), with
    ON_SHARE tol of slack."""
    s = ON_SHARE * tol
    return ((outer[None, :, 0] - s <= inner[:, None, 0])
            & (outer[None, :, 1] - s <= inner[:, None, 1])
            & (inner[:, None, 2] <= outer[None, :, 2] + s)
            & (inner[:, None, 3] <= outer[None, :, 3] + s))


def _sources(flat, idx, conv, cand, mask, tol):
    """(convolution piece, s0, s1) of the output pieces ``idx``: the one of the
    candidates ``cand`` (where ``mask`` (len(idx), len(cand))) through the piece's
    start, middle and end (ON_SHARE tol), with the parameters of its start and end
    there; -1 where none is, or more than one."""
    src = np.full(len(idx), -1)
    s0, s1 = np.zeros(len(idx)), np.ones(len(idx))
    i, j = np.nonzero(mask)
    if not len(i):
        return src, s0, s1
    sub = [flat[k] for k in idx.tolist()]
    starts, ends = pc.end_points(sub)
    mids = pc.end_points(pc.subsegments(sub, np.arange(len(sub)), np.full(len(sub), 0.5),
                                        np.ones(len(sub)), packed=True))[0]
    used = unique(cand[j])
    stacked = pc.stack(conv.pieces.take(used))
    at = np.searchsorted(used, cand[j])
    c = np.concatenate([stacked[at]] * 3)
    pts = np.concatenate([starts[i], mids[i], ends[i]])
    t = nearest_params_in_range(c, pts, np.zeros(len(c)), np.ones(len(c)))
    d = np.hypot(*(pc.jet_many(c, np.arange(len(c)), t)[0] - pts).T).reshape(3, -1)
    # the middle on the piece; the ends as the trimming left them: a junction
    # whose Newton iteration did not converge sits within (FLAT_SHARE + GRID_SHARE)
    # tol of both pieces, and contracted runs move their neighbours' ends
    on = (d[1] <= MID_SHARE * tol) & (d[[0, 2]].max(axis=0) <= END_SHARE * tol)
    count = np.bincount(i[on], minlength=len(idx))
    src[i[on]] = cand[j[on]]
    t = t.reshape(3, -1)
    s0[i[on]], s1[i[on]] = t[0, on], t[2, on]
    src[count != 1] = -1
    return src, s0, s1


def _rebuilt(flat, nxt, info, tol):
    """(pieces, owner): the new pieces of the loops in order, each with the index of
    the old piece it comes from (for the loop it is in); None where not recognised."""
    ja = np.flatnonzero(info.hit | info.hit[nxt])   # junctions: end of ja, start of nxt
    jb = nxt[ja]
    conv, again = info.conv, info.again
    c_start, c_end = pc.end_points(conv.pieces)
    a_end = pc.end_points([flat[k] for k in ja.tolist()])[1]
    join = JOIN_SHARE * tol
    joint = ((np.hypot(*(a_end - c_end[info.src[ja]]).T) <= join)
             & (np.hypot(*(a_end - c_start[info.src[jb]]).T) <= join))
    row_a, row_b = conv.row[info.src[ja]], conv.row[info.src[jb]]
    inner = joint & info.hit[ja] & info.hit[jb] & (row_a == row_b)
    # positions of the junctions: on the new pieces (index into again, t) for replaced
    # sides, on the old convolution piece (t) for the others
    pa_k, pa_t = np.full(len(ja), -1), info.s1[ja].copy()
    pb_k, pb_t = np.full(len(ja), -1), info.s0[jb].copy()
    r_a, r_b = np.searchsorted(info.rows, row_a), np.searchsorted(info.rows, row_b)
    ends = joint & ~inner
    a_new, b_new = ends & info.hit[ja], ends & info.hit[jb]
    # a joint at a replaced side is its row's end (after) or start (before)
    pa_k[a_new] = info.first[r_a[a_new]] + info.count[r_a[a_new]] - 1
    pa_t[a_new] = 1.0
    pb_k[b_new] = info.first[r_b[b_new]]
    pb_t[b_new] = 0.0
    n_start, n_end = pc.end_points(again.pieces)
    if (np.hypot(*(n_end[pa_k[a_new]] - c_end[info.src[ja[a_new]]]).T) > join).any() or \
            (np.hypot(*(n_start[pb_k[b_new]] - c_start[info.src[jb[b_new]]]).T) > join).any():
        return None   # a joint inside a row next to a piece of another row
    cross = np.flatnonzero(~joint)
    if len(cross) and not _crossed(flat, ja[cross], jb[cross], info, tol,
                                   (pa_k, pa_t, pb_k, pb_t), cross):
        return None
    return _assembled(flat, nxt, ja, inner, (pa_k, pa_t, pb_k, pb_t), info)


def _nearest_new(points, rows, info):
    """(index into again, t) of the new piece of each row (position in info.rows)
    nearest to each point, and the distance."""
    cnt = info.count[rows]
    owner = np.repeat(np.arange(len(points)), cnt)
    k = np.repeat(info.first[rows], cnt) + np.arange(cnt.sum()) - \
        np.repeat(np.cumsum(cnt) - cnt, cnt)
    stacked = pc.stack(info.again.pieces.take(k))
    t = nearest_params_in_range(stacked, points[owner], np.zeros(len(k)), np.ones(len(k)))
    d = np.hypot(*(pc.jet_many(stacked, np.arange(len(k)), t)[0] - points[owner]).T)
    d = np.where(np.isnan(d), np.inf, d)
    best = np.full(len(points), np.inf)
    np.minimum.at(best, owner, d)
    pick = np.flatnonzero(d == best[owner])            # owner is sorted: the first of each
    pick = pick[np.searchsorted(owner[pick], np.arange(len(points)))]
    return k[pick], t[pick]


def _crossed(flat, a, b, info, tol, pos, where):
    """Solve the crossings at the junctions end of ``a`` / start of ``b`` (output
    pieces) again by Newton, writing the positions ``pos`` at ``where``; False
    where one is not found inside the pieces."""
    pa_k, pa_t, pb_k, pb_t = pos
    conv, again = info.conv, info.again
    guess = pc.end_points([flat[k] for k in a.tolist()])[1]
    sides = []
    for side, k_arr, t_arr, t_old in ((a, pa_k, pa_t, info.s1), (b, pb_k, pb_t, info.s0)):
        hit = info.hit[side]
        k, t = np.full(len(side), -1), t_old[side].copy()
        if hit.any():
            rows = np.searchsorted(info.rows, conv.row[info.src[side[hit]]])
            k[hit], t[hit] = _nearest_new(guess[hit], rows, info)
        sides.append((k, t, hit))
    # one stack: the old convolution pieces of the kept sides, then the new ones
    n_old = len(conv)
    ids = [np.where(h, n_old + k, info.src[s]) for (k, _, h), s in zip(sides, (a, b))]
    used = unique(np.concatenate(ids))
    olds, news = used[used < n_old], used[used >= n_old] - n_old
    stacked = pc.stack(pc.Pieces.of(conv.pieces.take(olds).rows()
                                    + again.pieces.take(news).rows()))
    ia, ib = np.searchsorted(used, ids[0]), np.searchsorted(used, ids[1])
    e = conv.bound[info.src[a]] + conv.bound[info.src[b]] + \
        np.where(sides[0][2], again.bound[np.maximum(sides[0][0], 0)], 0.0) + \
        np.where(sides[1][2], again.bound[np.maximum(sides[1][0], 0)], 0.0)
    atol = CROSS_ATOL * tol
    s, u, ok = newton_crossings(stacked, ia, sides[0][1], ib, sides[1][1], guess,
                                reach=atol, atol=atol, shallow=e)
    # the crossing must lie inside both pieces (an end: it may go on in the next)
    inside = (s > 0.0) & (s < 1.0) & (u > 0.0) & (u < 1.0)
    if not (ok & inside).all():
        return False
    pa_k[where] = np.where(sides[0][2], sides[0][0], -1)
    pb_k[where] = np.where(sides[1][2], sides[1][0], -1)
    pa_t[where], pb_t[where] = s, u
    return True


def _assembled(flat, nxt, ja, inner, pos, info):
    """(pieces, owner) of :func:`_rebuilt` from the junction positions ``pos`` (at
    the junctions end of ``ja`` / start of ``nxt[ja]``; ``inner``: joints inside a
    replaced row, which the new pieces run across)."""
    pa_k, pa_t, pb_k, pb_t = pos
    n = len(flat)
    at_end, at_start = np.full(n, -1), np.full(n, -1)
    at_end[ja], at_start[nxt[ja]] = np.arange(len(ja)), np.arange(len(ja))
    hit = info.hit
    inner_start = np.zeros(n, bool)
    inner_start[nxt[ja]] = inner
    starts = np.flatnonzero(hit & ~inner_start)       # each run of replaced pieces
    last = starts.copy()                                # its last piece
    for _ in range(n):
        more = inner[at_end[last]] if len(last) else np.zeros(0, bool)
        if not more.any():
            break
        last[more] = nxt[last[more]]
    if len(starts) != hit.sum() - inner.sum():
        return None     # a loop all of one row, or runs not recognised
    k0, t0 = pb_k[at_start[starts]], pb_t[at_start[starts]]
    k1, t1 = pa_k[at_end[last]], pa_t[at_end[last]]
    same_row = np.searchsorted(info.first, k0, "right") == np.searchsorted(info.first, k1,
                                                                           "right")
    if (k0 < 0).any() or (k1 < 0).any() or not same_row.all() or \
            ((k1 < k0) | ((k1 == k0) & (t1 <= t0))).any():
        return None
    cnt = k1 - k0 + 1
    ks = np.repeat(k0, cnt) + np.arange(cnt.sum()) - np.repeat(np.cumsum(cnt) - cnt, cnt)
    first = np.cumsum(cnt) - cnt
    lo, hi = np.zeros(len(ks)), np.ones(len(ks))
    lo[first], hi[first + cnt - 1] = t0, t1
    runs = pc.subsegments(info.again.pieces, ks, lo, hi)
    # the kept neighbours, cut at their new junctions (parameters on their own piece)
    kept = np.flatnonzero(~hit & ((at_end >= 0) | (at_start >= 0)))
    v0 = np.where(at_start[kept] >= 0, pb_t[at_start[kept]], info.s0[kept])
    v1 = np.where(at_end[kept] >= 0, pa_t[at_end[kept]], info.s1[kept])
    span = info.s1[kept] - info.s0[kept]
    if (span <= 0).any():
        return None
    cuts = pc.subsegments(flat, kept, (v0 - info.s0[kept]) / span,
                          (v1 - info.s0[kept]) / span)
    return _spliced(flat, starts, runs, np.repeat(np.arange(len(starts)), cnt), kept, cuts,
                    hit)


def _spliced(flat, starts, runs, run_of, kept, cuts, hit):
    """(pieces, owner): ``flat`` with each run of replaced pieces (``hit``) as its new
    pieces ``runs`` (``run_of``: the run of each) at its first piece ``starts``, and
    the pieces ``kept`` as ``cuts``."""
    repl = {int(k): [p] for k, p in zip(kept.tolist(), cuts)}
    for r, p in zip(run_of.tolist(), runs):
        repl.setdefault(int(starts[r]), []).append(p)
    counts = np.ones(len(flat), np.int64)
    counts[hit] = 0
    for k, new in repl.items():
        counts[k] = len(new)
    pieces, prev = [], 0
    changed = sorted(set(np.flatnonzero(hit).tolist()) | set(repl))
    for k in changed:
        pieces += flat[prev:k]
        pieces += repl.get(k, [])
        prev = k + 1
    pieces += flat[prev:]
    return pieces, np.repeat(np.arange(len(flat)), counts)


def _snapped(loops, tol):
    """``loops`` with the ends of consecutive pieces that differ (by rounding, at
    the junctions found again) set to their mean; None where one differs by more
    than JOIN_SHARE tol."""
    flat = [p for loop in loops for p in loop]
    lens = np.fromiter(map(len, loops), np.int64, len(loops))
    nxt = np.arange(1, len(flat) + 1)
    nxt[np.cumsum(lens) - 1] = np.cumsum(lens) - lens
    starts, ends = pc.end_points(flat)
    d = np.hypot(*(ends - starts[nxt]).T)
    if (d > JOIN_SHARE * tol).any():
        return None
    fix = np.flatnonzero(d > 0)
    mean = 0.5 * (ends[fix] + starts[nxt[fix]])
    for k, j, m in zip(fix.tolist(), nxt[fix].tolist(), mean):
        flat[k] = flat[k].copy()
        flat[k][-1, :2] = m * flat[k][-1, 2]
        flat[j] = flat[j].copy() if j != k else flat[k]
        flat[j][0, :2] = m * flat[j][0, 2]
    cut = np.concatenate([[0], np.cumsum(lens)])
    return [flat[a:b] for a, b in zip(cut[:-1].tolist(), cut[1:].tolist())]
