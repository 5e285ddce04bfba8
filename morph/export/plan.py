"""All the cuts of a chain chosen at once from a difficulty model, then repaired.

The greedy search (:mod:`.greedy`) finds a chain's segments one after the other: a
chain of n cubics costs n times a segment's tries in rounds, and every round is a
batch of array calls whose cost hardly depends on how many chains share it.
:class:`Plan` instead cuts every chain into all its segments at once and fits them
together:

- **probe**: the chain is cut into ``round(K / PROBE_WIDTH)`` equal parameter spans
  (one span for a short chain), fitted without a certificate (their sampled
  distances, :func:`morph.export.search._fit_batch` with ``need`` infinite; a probe
  of one span is certified at once: if it fits, nothing is shorter);
- **model**: span i with sampled (or certified) distance e_i counts as d_i =
  (e_i / tol)^(1/P) of a segment that just reaches tol (the model bound ~ width^P of
  the greedy search, P = ERROR_POWER), spread evenly over its parameter interval; D
  = sum d_i is the chain's difficulty;
- **cut**: n = ceil(D / AIM^(1/P)) segments are cut at equal shares of D (each then
  predicted at AIM tol), fitted and certified together;
- **repair**: a chain whose segments all certify tries fewer (ceil(D), the number
  the model says reach tol) while that is fewer than it has; a chain with a failing
  segment is cut again from the new measurements (the same count once more, then
  one more); the fewest segments that all certified are kept.

Every chain is a row of arrays and its spans rows of flat arrays sorted by chain, so
that a round is one numpy step for all chains; a chain needs a handful of rounds
(probe, cut, one fewer, sometimes a certificate of a probe that passed), not one
per segment.  A chain that has no certified cut after MAX_ATTEMPTS rounds (a corner
the join test missed, a tolerance at the coordinates' resolution) is handed to the
greedy search, which shrinks its intervals down to the minimal width and raises
where nothing certifies.
"""

import math

import numpy as np

from .greedy import ERROR_POWER
from .refine import interp_rows, ranges, spaced_rows

#: Probe spans are about this many pieces wide (cubics of brushed and stroked
#: outlines span 2 to 3 pieces of a long smooth run).
PROBE_WIDTH = 2.7
#: Segments are cut so that each is predicted at this share of tol.
AIM = 0.9
#: One segment fewer is tried when the model predicts each within this share of tol.
FEWER_SHARE = 1.0
#: A probe span counts as passing when its sampled distance is below this share of
#: tol (the certificate is within a few per cent of it: bench/export_profile.py).
PASS = 0.97
#: A span without a fit counts as this much difficulty (about two segments); a span
#: error below FLOOR tol as FLOOR tol (the model says nothing finer).
UNFITTED = 2.0
FLOOR = 1e-6
#: Rounds a chain may take before it is handed to the greedy search (when it has
#: no certified cut by then) or keeps its best certified cut.
MAX_ATTEMPTS = 8

#: Cells of the difficulty density per piece.
CELLS = 8

#: States of a chain: fitting an attempt, done, handed to the greedy search.
ACTIVE, DONE, HANDED = 0, 1, 2


def _segment_starts(chain, count):
    """Start of each chain's block in a flat array sorted by chain."""
    return np.cumsum(count) - count


class Plan:
    """The cut-all-at-once search of every chain of a batch (module docstring).

    ``chains``: the batch's :class:`~morph.export.fit.ChainArrays`; ``rows``: the
    chains it searches (the others are left alone); ``min_width``: spans narrower
    than this hand the chain to the greedy search.  :meth:`requests` gives a round's
    fits, :meth:`update` takes their results and returns the chains handed over and
    the segments of the chains finished."""

    def __init__(self, chains, tol, min_width, rows=None):
        n = len(chains.k)
        self.tol, self.min_width = tol, min_width
        self.top = np.asarray(chains.k, float)
        self.state = np.full(n, DONE)
        rows = np.arange(n) if rows is None else np.asarray(rows, int)
        self.state[rows] = ACTIVE
        self.attempts = np.zeros(n, int)
        self.floor_n = np.ones(n, int)
        self.fail_n, self.fail_count = np.zeros(n, int), np.zeros(n, int)
        self.best_n = np.zeros(n, int)               # 0: none
        self.best_cert = np.zeros(n, bool)
        self.best = _Spans.empty()
        self.certify = np.zeros(n, bool)             # the attempt is certified
        # the difficulty density: CELLS cells per piece, flat over all chains
        self.base = np.asarray(chains.off, int) * CELLS
        self.rho = np.ones(int(np.sum(chains.k)) * CELLS)
        # the probe: equal spans of about PROBE_WIDTH pieces
        count = np.maximum(1, np.floor(self.top[rows] / PROBE_WIDTH + 0.5)).astype(int)
        self.certify[rows] = count == 1
        cuts = spaced_rows(self.top[rows], count + 1)
        self.cur = _Spans.from_cuts(rows, count, cuts)

    @property
    def active(self):
        return bool(len(self.cur.chain))

    def requests(self):
        """(chain, t0, t1, need) of the round's fits: every span of every chain's
        current attempt; ``need`` 0 (certify) or infinite (sampled only)."""
        c = self.cur
        need = np.where(self.certify[c.chain], 0.0, np.inf)
        return c.chain, c.t0, c.t1, need

    def update(self, fits, offset, round_no):
        """Take the round's results (``fits`` a :class:`~morph.export.search._Fits`,
        this plan's requests from ``offset`` on, made in round ``round_no``).
        Returns (chains handed to the greedy search, finished segments (chain, t0,
        t1, bound, at) sorted by chain and t0, chains finished)."""
        tol, c = self.tol, self.cur
        if not len(c.chain):
            z = np.zeros(0, int)
            return z, (z, np.zeros(0), np.zeros(0), np.zeros(0), np.zeros((0, 2), int)), z
        j = offset + np.arange(len(c.chain))
        e = fits.bound[j]
        certified = fits.cert[j] & (e <= tol)
        ok = certified | (fits.provisional[j] & (e <= PASS * tol))
        at = np.stack([np.full(len(j), round_no), j], axis=1)
        c = c._replace(bound=e, at=at)
        rows, start, count = c.blocks()
        all_ok = np.minimum.reduceat(ok.astype(np.int8), start).astype(bool)
        all_cert = np.minimum.reduceat(certified.astype(np.int8), start).astype(bool)
        d = (np.clip(e, FLOOR * tol, None) / tol) ** (1.0 / ERROR_POWER)
        d = np.where(np.isfinite(e), np.minimum(d, UNFITTED), UNFITTED)
        total = np.add.reduceat(d, start)
        self.attempts[rows] += 1
        n = count
        # passed: the best so far; then fewer where the model says they reach tol
        won = all_ok
        self.best.drop(rows[won])
        self.best.add(c.select(rows[won]))
        self.best_n[rows[won]], self.best_cert[rows[won]] = n[won], all_cert[won]
        fewer = np.ceil(total / FEWER_SHARE).astype(int)
        nxt = np.where(won, np.where(fewer < n, np.maximum(fewer, self.floor_n[rows]), n), 0)
        finish = won & (nxt >= n)
        # failed: the same count once more (cut from the new measurements), then more
        lost = ~won
        again = lost & (self.fail_n[rows] == n)
        self.fail_count[rows[lost]] = np.where(again[lost], self.fail_count[rows[lost]] + 1, 1)
        self.fail_n[rows[lost]] = n[lost]
        self.floor_n[rows] = np.where(lost & (self.fail_count[rows] >= 2),
                                      np.maximum(self.floor_n[rows], n + 1), self.floor_n[rows])
        aim = np.ceil(total / AIM ** (1.0 / ERROR_POWER)).astype(int)
        nxt = np.where(lost, np.maximum(aim, self.floor_n[rows]), nxt)
        has_best = self.best_n[rows] > 0
        finish |= lost & has_best & (nxt >= self.best_n[rows])
        tired = (self.attempts[rows] >= MAX_ATTEMPTS) & ~finish
        finish |= tired & has_best
        hand = tired & ~has_best
        go = ~finish & ~hand
        # the density learns the spans' difficulties; cuts of the chains going on
        # at equal shares of it
        self._learn(c, rows, d)
        cuts, go = self._cuts(rows, total, nxt, go)
        hand |= (~finish & ~go) & ~hand
        # a chain finishing on an uncertified best certifies it first
        recheck = finish & ~self.best_cert[rows]
        done = finish & ~recheck
        self.state[rows[done]] = DONE
        self.state[rows[hand]] = HANDED
        self.best.drop(rows[hand])
        self.best_n[rows[hand]] = 0
        out = self.best.take(rows[done])
        self.best_n[rows[done]] = 0
        more = [_Spans.from_cuts(rows[go], nxt[go], cuts)]
        chk = rows[recheck]
        if len(chk):
            again_spans = self.best.select(chk)
            more.append(again_spans)
            self.best.drop(chk)
            self.best_n[chk] = 0                    # not a best until certified
        self.certify[rows[go]] = True
        self.certify[chk] = True
        self.cur = _Spans.concat(more)
        return rows[hand], out, rows[done]

    def _cum(self):
        return np.concatenate([[0.0], np.cumsum(self.rho)])

    def _learn(self, c, rows, d):
        """Rescale the density of every span's cells (by their centres) so that it
        integrates to the span's difficulty d over the span (the shape within a span
        is what earlier attempts taught)."""
        cum = self._cum()
        grid = np.arange(len(cum), dtype=float)
        a = self.base[c.chain] + c.t0 * CELLS
        b = self.base[c.chain] + c.t1 * CELLS
        have = np.interp(b, grid, cum) - np.interp(a, grid, cum)
        f = d / np.maximum(have, 1e-300)
        cells = ranges(self.base[rows], (self.top[rows] * CELLS).astype(int))
        span = np.minimum(np.searchsorted(b, cells + 0.5), len(b) - 1)
        self.rho[cells] *= f[span]
        np.maximum(self.rho, 1e-300, out=self.rho)

    def _cuts(self, rows, total, nxt, go):
        """The cuts of the chains ``rows[go]`` into ``nxt`` spans at equal shares of
        their difficulty (the density's integral); chains whose cuts come closer
        than the minimal width are not going on.  Returns (cuts flat, go)."""
        sel = np.nonzero(go)[0]
        if not len(sel):
            return np.zeros(0), go
        m, r = nxt[sel], rows[sel]
        cum = self._cum()
        grid = np.arange(len(cum), dtype=float)
        lo = np.interp(self.base[r].astype(float), grid, cum)
        hi = np.interp(self.base[r] + self.top[r] * CELLS, grid, cum)
        row_c = np.repeat(np.arange(len(sel)), m + 1)
        y = spaced_rows(hi - lo, m + 1) + np.repeat(lo, m + 1)
        x = (np.interp(y, cum, grid) - np.repeat(self.base[r], m + 1)) / CELLS
        c_at = np.cumsum(m + 1) - (m + 1)
        x[c_at] = 0.0
        x[c_at + m] = self.top[r]
        step = np.diff(x)
        same = row_c[1:] == row_c[:-1]
        bad = np.zeros(len(sel), bool)
        bad[row_c[1:][same & ~(step >= self.min_width)]] = True
        go = go.copy()
        go[sel[bad]] = False
        return x[~bad[row_c]], go


class _Spans:
    """Spans of chains as flat arrays sorted by chain, then t0: chain, t0, t1, and
    once fitted their bound and ``at`` (round, request)."""

    __slots__ = ("chain", "t0", "t1", "bound", "at")

    def __init__(self, chain, t0, t1, bound, at):
        self.chain, self.t0, self.t1, self.bound, self.at = chain, t0, t1, bound, at

    @classmethod
    def empty(cls):
        return cls(np.zeros(0, int), np.zeros(0), np.zeros(0), np.zeros(0),
                   np.zeros((0, 2), int))

    @classmethod
    def from_cuts(cls, rows, count, cuts):
        """The spans between the consecutive ``cuts`` (count[r] + 1 per row, flat)."""
        k = int(count.sum())
        first = ranges(np.cumsum(count + 1) - (count + 1), count)
        return cls(np.repeat(rows, count), cuts[first], cuts[first + 1], np.full(k, np.nan),
                   np.zeros((k, 2), int))

    @classmethod
    def concat(cls, parts):
        parts = [p for p in parts if len(p.chain)]
        if not parts:
            return cls.empty()
        chain = np.concatenate([p.chain for p in parts])
        order = np.argsort(chain, kind="stable")
        return cls(chain[order], *(np.concatenate([getattr(p, f) for p in parts])[order]
                                   for f in ("t0", "t1", "bound", "at")))

    def _replace(self, **kw):
        return _Spans(*(kw.get(f, getattr(self, f)) for f in self.__slots__))

    def blocks(self):
        """(chains, start of each one's spans, their count), chains increasing."""
        if not len(self.chain):
            z = np.zeros(0, int)
            return z, z, z
        head = np.ones(len(self.chain), bool)
        head[1:] = self.chain[1:] != self.chain[:-1]
        start = np.nonzero(head)[0]
        return self.chain[start], start, np.diff(np.append(start, len(self.chain)))

    def select(self, rows):
        mine = np.isin(self.chain, rows)
        return _Spans(*(getattr(self, f)[mine] for f in self.__slots__))

    def drop(self, rows):
        if len(rows) and len(self.chain):
            keep = ~np.isin(self.chain, rows)
            for f in self.__slots__:
                setattr(self, f, getattr(self, f)[keep])

    def add(self, other):
        merged = _Spans.concat([self, other])
        for f in self.__slots__:
            setattr(self, f, getattr(merged, f))

    def take(self, rows):
        """(chain, t0, t1, bound, at) of ``rows``, removed."""
        s = self.select(rows)
        self.drop(rows)
        return s.chain, s.t0, s.t1, s.bound, s.at
