"""The "one segment fewer" refinement of every chain of a batch, as arrays.

The greedy search (:mod:`.greedy`) stops each segment a little short of its longest
reach.  A chain it leaves with two segments or more is refined: while the segments'
bounds say that one segment fewer may fit, that many segments are fitted between
cuts at equal shares of the modelled difficulty (:meth:`Refine._fewer`) and kept if
every one certifies; then a chain left with two segments, the last shorter than
SHORT_LAST of the first, gets one try of a single segment over the whole chain
(:meth:`Refine._whole`).  Neither asks again for the fit of a whole chain that was
made before (by the greedy search's first try) and did not certify: it is the same
fit, and would fail the same way.  A chain whose whole fit failed may also come
here before any greedy segment (:meth:`Refine.split`): it is fitted as segments of
equal length (along its pieces' chords) and kept (then refined as above) if every
one certifies, else given back to the greedy search.

:class:`Refine` holds every refining chain as a row of arrays (its phase; its
segments in one flat array sorted by row; its arc-length table in another); a round
asks the fits of every row that has a plan (:meth:`Refine.requests`) and one numpy
step takes all their results (:meth:`Refine.update`).  No Python step runs per chain
and round: per-row sums and running sums are taken on the rows of equal length
stacked (:func:`per_row`), interpolation in each row's own table by one vectorised
search (:func:`interp_rows`), both with numpy's own arithmetic, so a chain's cuts
are the very numbers that chain alone gives.

Rows of multi-dimensional arrays are gathered by ``take`` / ``compress`` (see
:mod:`morph.polyline`).
"""

import numpy as np

from .. import bernstein as bz
from .fit import _quadrature
from .greedy import ERROR_POWER

#: One segment fewer is tried when the greedy segments' shares add up to at most this
#: many segments fewer than there are (the greedy segments stop short of their reach).
FEWER_SLACK = 1.0
#: A chain left with two segments whose last is shorter than this share of the first
#: gets one try of a single segment for the whole chain (for more segments, n - 1 of
#: equal arc length rarely fit where the model said no).
SHORT_LAST = 0.5

#: An equal cut this many ulps of its chain's parameter length from a join is the
#: join (arc-length interpolation rounds there; a part a few ulps wide gets no
#: certificate: the feet of its ends on the cubic coincide).
CUT_ULPS = 8

#: Phases of a row: plan one segment fewer; check for a short last segment; waiting
#: for the fits of one segment fewer; waiting for the fit of the whole chain; done;
#: plan equal cuts (:meth:`Refine.split`); waiting for their fits; given back.
PLAN, CHECK, FEWER, WHOLE, DONE, SPLIT, CUT, GONE = 0, 1, 2, 3, 4, 5, 6, 7


def ranges(start, count):
    """The concatenated index ranges [start, start + count), as one array."""
    return (start - (count.cumsum() - count)).repeat(count) + np.arange(np.add.reduce(count))


def per_row(values, start, count, func):
    """``func(block, axis=1)`` of each row's block ``values[start:start + count]``, the
    rows of equal count stacked (a sum or a running sum along a row is then the same
    arithmetic as on the row alone; ``func`` np.add.reduce, np.add.accumulate):
    [(rows, result)] over the distinct counts."""
    out = []
    for c in np.bincount(count).nonzero()[0].tolist():      # the distinct counts, sorted
        rows = (count == c).nonzero()[0]
        out.append((rows, func(values[start[rows][:, None] + np.arange(c)[None]], axis=1)))
    return out


def spaced_rows(stop, num):
    """``np.linspace(0, stop[r], num[r])`` of every row r (num >= 2), concatenated: j
    (stop / (num - 1)), the last one stop itself (numpy's arithmetic)."""
    j = np.arange(int(np.add.reduce(num))) - (num.cumsum() - num).repeat(num)
    return np.where(j == num.repeat(num) - 1, stop.repeat(num), j * (stop / (num - 1)).repeat(num))


def knot_keys(xp, lo, hi):
    """The search keys of :func:`interp_rows` for the knots ``xp``, whose blocks
    [lo[r], hi[r]) (in order) cover them: complex numbers, the block's start as the
    real part and the knot as the imaginary part (numpy orders complex numbers by
    real part, then imaginary part: the keys of increasing blocks increase)."""
    keys = np.empty(xp.shape[0], complex)
    keys.real = np.repeat(lo, hi - lo)
    keys.imag = xp
    return keys


def interp_rows(x, row, lo, hi, xp, fp, keys=None):
    """``np.interp(x[i], xp[lo[r]:hi[r]], fp[lo[r]:hi[r]])`` with r = row[i], for every
    i at once (each row's xp increasing, at least two long): the last knot j with
    xp[j] <= x by one binary search of all rows together (``keys``: the knots'
    :func:`knot_keys`, made here when lo, hi are every block of xp), then numpy's
    formula (the end values outside, fp[j] at a knot, else slope (x - xp[j]) +
    fp[j], the slope (fp[j+1] - fp[j]) / (xp[j+1] - xp[j]); from the right knot where
    that is NaN), so the values are np.interp's, bit for bit."""
    a, b = lo[row], hi[row]
    if keys is None:
        keys = knot_keys(xp, lo, hi)
    query = np.empty(x.shape[0], complex)
    query.real, query.imag = a, x
    # past the knots <= x of the query's block (a NaN query sorts after every knot)
    left = np.minimum(keys.searchsorted(query, side="right"), b)
    j = left - 1                                   # a - 1: below the first knot
    jj = np.minimum(np.maximum(j, a), b - 2)
    x0, x1, y0, y1 = xp[jj], xp[jj + 1], fp[jj], fp[jj + 1]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        slope = (y1 - y0) / (x1 - x0)
        res = slope * (x - x0) + y0
        nan = np.isnan(res)
        if np.logical_or.reduce(nan):
            alt = slope * (x - x1) + y1
            res = np.where(nan, np.where(np.isnan(alt) & (y0 == y1), y0, alt), res)
    # the end values and the knots: fp[at] (below the first knot at = a, past the
    # last j = b - 1)
    at = np.maximum(j, a)
    res = np.where((j < a) | (j >= b - 1) | (xp[at] == x), fp[at], res)
    return np.where(np.isnan(x), x, res)


def arc_lengths(bank, off, k):
    """Arc-length tables of chains (chain c: the pieces ``bank.order[off[c]:off[c] +
    k[c]]``), flat: chain c's block [lo[c], hi[c]) holds knots T and the arc lengths s
    from the chain's start to them.  Piece j of a chain has the knots j + c_i, c_0 =
    0 and c_i = w_1 + ... + w_i the running sums of the weights w_i of the 16-point
    Gauss-Legendre rule on [0, 1] (the chain's end: T = k); the length of [c_(i-1),
    c_i] is w_i |R'(x_i)|, the piece's speed at the node x_i, which lies in it (the
    Chebyshev-Markov-Stieltjes separation of the nodes by the weights' sums), so each
    piece's length is the 16-point rule's.  The speeds are those the fitter samples
    (:meth:`morph.export.bank.Bank.node_planes`, cached per bank: no piece is
    evaluated again).  Returns (T, s, lo, hi)."""
    quad = _quadrature()
    m = quad.gx.shape[0]
    knots = np.concatenate([[0.0], np.cumsum(quad.gw)[:-1]])       # c_0 ... c_15
    gids = bank.order[ranges(off, k)]
    d = bank.node_planes(gids, quad.gx)[2:]                       # (2, m, len(gids))
    seg = (np.hypot(d[0], d[1]) * quad.gw[:, None]).T.ravel()
    size = k * m + 1
    hi = np.cumsum(size)
    lo = hi - size
    s = np.zeros(int(hi[-1]) if len(hi) else 0)
    for rows, cum in per_row(seg, (np.cumsum(k) - k) * m, k * m, np.add.accumulate):
        s[(lo[rows][:, None] + 1 + np.arange(cum.shape[1])).ravel()] = cum.ravel()
    i = np.arange(len(s)) - np.repeat(lo, size)                   # knot i of its chain
    return i // m + knots[i % m], s, lo, hi


def chord_lengths(bank, off, k):
    """Tables of the chains' chord lengths, as :func:`arc_lengths` gives arc lengths
    (chain c: the pieces ``bank.order[off[c]:off[c] + k[c]]``): chain c's block [lo[c],
    hi[c]) holds the knots T = 0 ... k[c] (the joins) and the sums s of its pieces'
    chords (end point to end point) from the chain's start to them (linear between
    knots: a piece's length spread evenly over its parameter).  Returns (T, s, lo,
    hi)."""
    gids = bank.order[ranges(off, k)]
    chord = np.hypot(*(bank.last[gids] - bank.first[gids]).T)
    size = k + 1
    hi = np.cumsum(size)
    lo = hi - size
    s = np.zeros(int(hi[-1]) if len(hi) else 0)
    for rows, cum in per_row(chord, np.cumsum(k) - k, k, np.add.accumulate):
        s[(lo[rows][:, None] + 1 + np.arange(cum.shape[1])).ravel()] = cum.ravel()
    return (np.arange(len(s)) - np.repeat(lo, size)).astype(float), s, lo, hi


def chain_points(chains, chain, t):
    """Points of chains ``chain`` at chain parameters t (piece k on [k, k + 1]): a
    piece's first control point at an integer t, the chain's last point at its end,
    else the piece evaluated at t - floor(t) (:func:`morph.bernstein.basis`, one
    product per row: the values :func:`morph.piece.evaluate` gives the piece alone),
    one gather per degree."""
    bank = chains.bank
    k, off = chains.k[chain], chains.off[chain]
    kk = np.floor(t).astype(int)
    end = t >= k
    gid = bank.order[off + np.minimum(kk, k - 1)]
    out = np.where(end[:, None], bank.last.take(gid, axis=0), bank.first.take(gid, axis=0))
    inner = (~end & (t != kk)).nonzero()[0]
    local = t[inner] - kk[inner]
    for rows, h in bank.gather(gid[inner]):
        v = np.matmul(bz.basis(h.shape[1] - 1, local[rows])[:, None, :], h)[:, 0]
        out[inner[rows]] = v[:, :2] / v[:, 2:3]
    return out


class Refine:
    """The refinement of the chains of a batch (see the module docstring) as rows of
    arrays: ``chain`` (each row's chain), ``phase``; the rows' segments in flat arrays
    sorted by row (``seg_row``, ``t0``, ``t1``, ``bound``, and ``at``: the (round,
    request) of the fit that made each); their arc-length tables (``arc_lo``,
    ``arc_hi``: each row's block of ``arc_t``, ``arc_s``; -1 until made).

    :meth:`add` hands over chains the greedy search left with two segments or more,
    :meth:`requests` gives the round's fits, :meth:`update` takes their results,
    :meth:`finished` returns the segments of the rows done and drops them.
    ``chains``: the batch's :class:`~morph.export.fit.ChainArrays`."""

    def __init__(self, chains, tol, whole_failed=None):
        self.chains, self.tol = chains, tol
        # per chain: a fit of the whole chain was made and did not certify (the same
        # fit again would fail again: no row asks for it)
        self.whole_failed = (np.zeros(len(chains.k), bool) if whole_failed is None
                             else whole_failed)
        self.chain = np.zeros(0, int)
        self.phase = np.zeros(0, int)
        self.arc_lo, self.arc_hi = np.zeros(0, int), np.zeros(0, int)
        self.seg_row = np.zeros(0, int)
        self.t0, self.t1, self.bound = np.zeros(0), np.zeros(0), np.zeros(0)
        self.at = np.zeros((0, 2), int)
        self.arc_t, self.arc_s = np.zeros(0), np.zeros(0)
        self.arc_keys = [np.zeros(0, complex)] * 2     # their knot_keys (interp_rows)
        self.want = np.zeros(0, int)        # a SPLIT row's count of cuts
        self.cuts = [0, 0]                  # how many rows are in SPLIT, in CUT
        self.asked = None

    @property
    def active(self):
        return self.chain.shape[0] > 0

    def add(self, chain, seg_chain, t0, t1, bound, at):
        """Hand over the chains ``chain`` (increasing) and their segments (flat, sorted
        by chain and t0)."""
        if not len(chain):
            return
        row = self.chain.shape[0] + chain.searchsorted(seg_chain)
        fresh = np.empty((3, chain.shape[0]), int)      # phase, arc_lo, arc_hi
        fresh[0], fresh[1:] = PLAN, -1
        self.chain = np.concatenate([self.chain, chain])
        self.phase = np.concatenate([self.phase, fresh[0]])
        self.arc_lo = np.concatenate([self.arc_lo, fresh[1]])
        self.arc_hi = np.concatenate([self.arc_hi, fresh[2]])
        self.want = np.concatenate([self.want, np.zeros(chain.shape[0], int)])
        self._put(row, t0, t1, bound, at)

    def split(self, chain, count):
        """Try the chains ``chain`` (increasing; their fit as one segment failed) as
        ``count`` segments of equal length (the model of :meth:`_fewer`, the one
        segment's difficulty spread evenly over its length: :meth:`_split`), asked in
        the next round; :meth:`update` gives back the chains where one does not certify."""
        m = chain.shape[0]
        if not m:
            return
        fresh = np.empty((3, m), int)      # phase, arc_lo, arc_hi
        fresh[0], fresh[1:] = SPLIT, -1
        self.chain = np.concatenate([self.chain, chain])
        self.phase = np.concatenate([self.phase, fresh[0]])
        self.arc_lo = np.concatenate([self.arc_lo, fresh[1]])
        self.arc_hi = np.concatenate([self.arc_hi, fresh[2]])
        self.want = np.concatenate([self.want, count])
        self.cuts[0] += m

    def _put(self, row, t0, t1, bound, at):
        """Segments of the rows ``row`` (sorted) replace those the rows had."""
        given = np.zeros(self.chain.shape[0], bool)
        given[row] = True
        keep = ~given[self.seg_row]
        rows = np.concatenate([self.seg_row[keep], row])
        order = rows.argsort(kind="stable")
        self.seg_row = rows[order]
        self.t0 = np.concatenate([self.t0[keep], t0])[order]
        self.t1 = np.concatenate([self.t1[keep], t1])[order]
        self.bound = np.concatenate([self.bound[keep], bound])[order]
        self.at = np.concatenate([self.at.compress(keep, axis=0), at]).take(order, axis=0)

    def _blocks(self):
        count = np.bincount(self.seg_row, minlength=self.chain.shape[0])
        return count.cumsum() - count, count

    def _arcs(self, rows):
        """Make the arc-length tables of those rows that have none, in one batch
        (:func:`morph.export.fit.arc_lengths`)."""
        rows = rows[self.arc_lo[rows] < 0]
        if not len(rows):
            return
        c = self.chain[rows]
        t, s, lo, hi = arc_lengths(self.chains.bank, self.chains.off[c], self.chains.k[c])
        self.arc_lo[rows], self.arc_hi[rows] = lo + len(self.arc_t), hi + len(self.arc_t)
        self.arc_t = np.concatenate([self.arc_t, t])
        self.arc_s = np.concatenate([self.arc_s, s])
        lo, hi = lo + len(self.arc_keys[0]), hi + len(self.arc_keys[0])
        self.arc_keys = [np.concatenate([k, knot_keys(v, lo, hi)])
                         for k, v in zip(self.arc_keys, (t, s))]

    def _length(self, rows):
        """Arc length of the rows' chains (their tables made)."""
        return self.arc_s[self.arc_hi[rows] - 1]

    def requests(self):
        """Plan every row that can (:meth:`_fewer`, :meth:`_whole`) and return the
        round's fits: arrays (chain, t0, t1) (a row's fits follow each other: each
        starts where the one before ends)."""
        start, count = self._blocks()
        fewer, cuts = self._fewer((self.phase == PLAN).nonzero()[0], start, count)
        whole = self._whole((self.phase == CHECK).nonzero()[0], start, count)
        n = count[fewer] - 1                                        # segments asked
        if self.cuts[0]:
            split, ends = self._split((self.phase == SPLIT).nonzero()[0])
            n = np.concatenate([n, self.want[split]])
            cuts, fewer = np.concatenate([cuts, ends]), np.concatenate([fewer, split])
        row = np.concatenate([fewer.repeat(n), whole])
        first = ranges((n + 1).cumsum() - (n + 1), n)               # each one's cut
        t0 = np.concatenate([cuts[first], np.zeros(whole.shape[0])])
        t1 = np.concatenate([cuts[first + 1],
                             self.chains.k[self.chain[whole]].astype(float)])
        self.asked = (row, t0, t1)
        return self.chain[row], t0, t1

    def _fewer(self, rows, start, count):
        """Plan one segment fewer for ``rows`` (phase PLAN; two segments or more).

        Segment i (bound b_i) counts as d_i = (b_i / tol)^(1/P) of a segment that
        just reaches tol (model bound ~ L^P, P = ERROR_POWER), spread evenly over its
        arc length; when the d_i add up to at most count - FEWER_SLACK, count - 1
        segments are cut at equal shares of that sum (equal arc lengths where the
        curve is equally hard), their ends at 0 and the chain's end.  Rows for which
        that is implausible (or the cuts do not increase) go on to CHECK; the others
        to FEWER.  Returns (rows asked, their cuts: count per row, flat)."""
        if not len(rows):
            return rows, np.zeros(0)
        tol, cnt = self.tol, count[rows]
        seg = ranges(start[rows], cnt)
        d = (np.maximum(self.bound[seg], 1e-3 * tol) / tol) ** (1.0 / ERROR_POWER)
        at = cnt.cumsum() - cnt                                     # each row's d
        total = np.empty(rows.shape[0])
        for r, s in per_row(d, at, cnt, np.add.reduce):
            total[r] = s
        ok = (total <= cnt - FEWER_SLACK) & ~((cnt == 2) & self.whole_failed[self.chain[rows]])
        self._arcs(rows[ok])
        ok[ok] = self._length(rows[ok]) > 0
        sel = ok.nonzero()[0]
        n, rs = cnt[sel], rows[sel]
        # per row: the arc lengths at the n + 1 segment ends, the running sums of d
        e_at = (n + 1).cumsum() - (n + 1)
        where = np.arange(sel.shape[0]).repeat(n + 1)
        inner = np.empty(int(np.add.reduce(n + 1)), bool)
        inner[:] = True
        inner[e_at] = False
        ends_t = np.empty(len(inner))
        ends_t[e_at] = self.t0[start[rs]]
        ends_t[inner] = self.t1[ranges(start[rs], n)]
        lo, hi = self.arc_lo[rs], self.arc_hi[rs]
        edges = interp_rows(ends_t, where, lo, hi, self.arc_t, self.arc_s, self.arc_keys[0])
        hard = np.zeros(inner.shape[0])
        for r, c in per_row(d, at[sel], n, np.add.accumulate):
            hard[(e_at[r][:, None] + 1 + np.arange(c.shape[1])).ravel()] = c.ravel()
        row_c = np.arange(sel.shape[0]).repeat(n)
        share = interp_rows(spaced_rows(hard[e_at + n], n), row_c, e_at, e_at + n + 1, hard,
                            edges)
        cuts = interp_rows(share, row_c, lo, hi, self.arc_s, self.arc_t, self.arc_keys[1])
        c_at = n.cumsum() - n
        cuts[c_at] = 0.0
        cuts[c_at + n - 1] = self.chains.k[self.chain[rs]]
        step = cuts[1:] - cuts[:-1]
        same = row_c[1:] == row_c[:-1]
        bad = np.zeros(sel.shape[0], bool)
        bad[row_c[1:][same & (step <= 0)]] = True
        self.phase[rows[~ok]] = CHECK
        self.phase[rs[bad]] = CHECK
        self.phase[rs[~bad]] = FEWER
        return rs[~bad], cuts[~bad[row_c]]

    def _split(self, rows):
        """Plan the equal cuts of ``rows`` (phase SPLIT; not empty): ``want`` segments
        of equal length along the chain's pieces' chords (:func:`chord_lengths`: one
        sum per chain, where arc-length tables take the speeds at 16 nodes a piece), an end within
        CUT_ULPS of a join on it (of equal parameter width where those ends do not
        increase).
        Returns (rows, their ends: want + 1 per row, flat); the rows go to CUT."""
        n, c = self.want[rows], self.chain[rows]
        t, s, lo, hi = chord_lengths(self.chains.bank, self.chains.off[c], self.chains.k[c])
        row_c = np.arange(rows.shape[0]).repeat(n + 1)
        ends = interp_rows(spaced_rows(s[hi - 1], n + 1), row_c, lo, hi, s, t)
        top = self.chains.k[c].astype(float)
        join = np.rint(ends)
        ends = np.where(np.abs(ends - join) <= CUT_ULPS * np.spacing(top[row_c]), join, ends)
        at = (n + 1).cumsum() - (n + 1)
        ends[at], ends[at + n] = 0.0, top
        flat = np.ones(ends.shape[0], bool)
        flat[1:] = ~(ends[1:] > ends[:-1])
        flat[at] = False
        even = np.logical_or.reduceat(flat, at)     # rows whose ends do not increase
        ends = np.where(even[row_c], spaced_rows(top, n + 1), ends)
        self.phase[rows] = CUT
        self.cuts = [0, rows.shape[0]]
        return rows, ends

    def _whole(self, rows, start, count):
        """Of ``rows`` (phase CHECK), those left with two segments, the last shorter
        than SHORT_LAST of the first, whose chain has a positive arc length (is not
        one point) go to WHOLE: one segment is fitted to the whole chain; the others
        are done.
        Returns the rows asked."""
        self.phase[rows] = DONE
        rows = rows[(count[rows] == 2) & ~self.whole_failed[self.chain[rows]]]
        w = self.t1 - self.t0
        rows = rows[w[start[rows] + 1] < SHORT_LAST * w[start[rows]]]
        # a positive arc length: a chain that is not one point (no table needed)
        rows = rows[self.chains.extent[self.chain[rows]] > 0]
        self.phase[rows] = WHOLE
        return rows

    def update(self, fits, offset, round_no):
        """Take the results of :meth:`requests` (``fits``, a round's
        :class:`~morph.export.search._Fits`, from request ``offset`` on, made in round
        ``round_no``): a row whose every fit certifies within tol takes them as its
        segments.  Rows of one segment fewer then plan again (to CHECK when it failed,
        done when one segment is left); whole-chain rows are done; rows of equal cuts
        plan one fewer, or are given back where a cut fails.  Returns the rows given
        back: (chains, the end of each one's first cut, that fit's request)."""
        row, t0, t1 = self.asked
        self.asked = None
        j = offset + np.arange(row.shape[0])
        bound = fits.bound[j]
        won = np.zeros(self.chain.shape[0], bool)
        won[row] = True
        won[row[~(bound <= self.tol)]] = False
        take = won[row]
        at = np.empty((row.shape[0], 2), int)
        at[:, 0], at[:, 1] = round_no, j
        self._put(row[take], t0[take], t1[take], bound[take], at[take])
        _, count = self._blocks()
        fewer, whole = self.phase == FEWER, self.phase == WHOLE
        self.phase[fewer & won] = np.where(count[fewer & won] >= 2, PLAN, DONE)
        self.phase[fewer & ~won] = CHECK
        self.phase[whole] = DONE
        if not self.cuts[1]:
            return row[:0], t1[:0], j[:0]
        self.cuts[1] = 0                  # all the rows of CUT are answered here
        cut = self.phase == CUT
        # equal cuts: one fewer may still fit where there are three or more
        self.phase[cut & won] = np.where(count[cut & won] >= 3, PLAN, DONE)
        lost = cut & ~won
        self.phase[lost] = GONE
        first = (lost[row] & (t0 == 0.0)).nonzero()[0]      # each lost row's first cut
        return self.chain[row[first]], t1[first], j[first]

    def finished(self):
        """The rows done, dropped: (chains, segment chains, t0, t1, bound, at), the
        segments sorted by chain and t0."""
        done = self.phase == DONE
        seg = done[self.seg_row]
        out = (self.chain[done], self.chain[self.seg_row[seg]], self.t0[seg], self.t1[seg],
               self.bound[seg], self.at[seg])
        done |= self.phase == GONE                  # given back: no segments
        if np.logical_or.reduce(done):
            renum = (~done).cumsum() - 1
            self.seg_row = renum[self.seg_row[~seg]]
            self.t0, self.t1, self.bound = self.t0[~seg], self.t1[~seg], self.bound[~seg]
            self.at = self.at[~seg]
            self.chain, self.phase = self.chain[~done], self.phase[~done]
            self.arc_lo, self.arc_hi = self.arc_lo[~done], self.arc_hi[~done]
            self.want = self.want[~done]
        return out
