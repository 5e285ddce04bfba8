"""The greedy search for certified cubics along a chain of pieces.

**Search.**  Per piece (or per run of pieces with smooth joins, see below),
segments are chosen greedily from the start: the longest parameter interval whose
certified bound is <= tol is looked for with a few fits (error predicted from the
previous fits as ~ h^p, a segment accepted once its bound reaches 0.7 tol), then one
segment fewer is tried while the segments' bounds say it may fit (cuts at equal
shares of the modelled difficulty), or one for the whole run after a short last
segment (:mod:`morph.export.refine`).  The searches of all runs go in lockstep
(:func:`_drive`), over all loops of a region or of many glyphs
(:func:`morph.export.loops.loops_to_beziers`: the pieces of the whole batch live in
one :class:`morph.export.bank.Bank`, one stack per degree): each round fits the
pending ranges of every run with a few array calls
(:func:`morph.export.fit.moment_cubics`: all ranges' parts sampled in one
evaluation per degree, all candidates measured at once) and certifies all their
cubics in one batch (:func:`morph.export.certify.certify_batch`, phi fitted to the
pairs of parameters the fitter's rays found: the pieces are not sampled again; a
cubic whose sampled distance exceeds SCREEN tol is not certified, nor is a try whose sampled
distance is below PROVISIONAL tol: the search extends it anyway, and certifies it
only if it ends there).  bench/export.py compares the cubic counts with kurbo's and
with the classic circle cubic.  Where the fit finds no cubic, or its cubic does not
certify, the same-parameter fit of :func:`morph.export.certify.fit_cubic` (Hermite /
least squares) is tried, and the interval shrinks until one certifies.

**Two stages.**  The greedy search of every chain is one array state machine
(:class:`morph.export.greedy.Greedy`): each chain's range, try, bracket and mode are
rows of arrays, a round asks one fit of every chain still searching, and one numpy
step takes all their results.  A long chain is searched from both ends at once (two
rows, each stopping where the other has come; :class:`_Join` joins them), which
halves its rounds.  A chain searched one way whose first try, the whole chain,
fails is tried next as equal cuts along its chords (two for most), its greedy row waiting:
a chain of two segments is then done in two rounds, not a round for each try of its
first segment; where a cut fails, the greedy row resumes with the first cut's fit as
its try.  A chain the greedy search leaves with two segments or
more is refined by a second one (:class:`morph.export.refine.Refine`: one segment
fewer where the bounds say it may fit), its chains rows of arrays too.
:func:`_drive` fits the requests of both machines of a round together
(:func:`_fit_batch`, arrays in, arrays out), and repeats until every chain is done:
the numerical work is O(rounds) array calls, and no Python step runs per chain and
round; the accepted segments stay arrays until each chain's list of
:class:`~morph.export.certify.CubicFit` is made at the end.

Rows of multi-dimensional arrays are gathered by ``take`` / ``compress`` (see
:mod:`morph.polyline`).
"""

import contextlib
import math
from collections import namedtuple
from functools import partial

import numpy as np

from .. import bernstein as bz
from .. import piece as pc
from .. import nearest as nr
from ..errors import ToleranceNotMetError
from ..polyline import unique
from .bank import Bank
from .certify import (SCREEN, CubicFit, affine_reparam, certify_batch, check_piece, fit_cubic,
                      same_param_bound)
from .fit import Parts, _quadrature, cut_pieces, make_chains, moment_cubics
from .greedy import DONE, ERROR_POWER, Greedy
from .refine import Refine, chain_points


def _parts(chains, chain, t0, t1):
    """The parts of every request (chain ``chain[r]`` on [t0[r], t1[r]]): piece k of
    the chain restricted to its local [a, b] covers [t0, t1] (:class:`Parts`, in
    request order), as arrays for all requests at once; and each part's k."""
    kk, off = chains.k[chain], chains.off[chain]
    k0 = np.floor(t0).astype(int)
    k1 = np.minimum(kk, np.ceil(t1).astype(int))
    cnt = np.maximum(k1 - k0, 0)
    req = np.arange(chain.shape[0]).repeat(cnt)
    k = k0.repeat(cnt) + np.arange(np.add.reduce(cnt)) - (cnt.cumsum() - cnt).repeat(cnt)
    a = np.maximum(t0[req] - k, 0.0)
    b = np.minimum(t1[req] - k, 1.0)
    keep = b > a
    req, k, a, b = req[keep], k[keep], a[keep], b[keep]
    return Parts(req, chains.bank.order[off[req] + k], a, b, {}), k


def _sub_groups(bank, parts, sel):
    """The sub-pieces of the parts ``sel`` (piece restricted to [a, b]) by degree,
    [(positions in sel, stack)]: those the fitter cut (:func:`cut_pieces`), the others
    by one de Casteljau call per degree."""
    out = []
    for rows, h in bank.gather(parts.gid[sel]):
        at = sel[rows]
        cut = (parts.a[at] != 0.0) | (parts.b[at] != 1.0)
        if np.logical_or.reduce(cut):           # (h: gathered, a copy of its own)
            h[cut] = cut_pieces(parts, at[cut], h.compress(cut, axis=0))
        out.append((rows, h))
    return out


def _join_feet(parts, multi):
    """Where the joins of the ranges ``multi`` sit among the parts (the start points of
    every part but the first), padded to one count with each range's last join:
    (positions (r, n), count of joins (r,)); their feet on the fitted cubics are
    found in one call for all."""
    first = parts.req.searchsorted(multi)
    count = parts.req.searchsorted(multi, side="right") - first - 1
    col = np.minimum(np.arange(int(np.maximum.reduce(count)))[None], count[:, None] - 1)
    return first[:, None] + 1 + col, count


#: The fits of a round as arrays (:func:`_fit_batch`): chain (index into the batch's
#: chains), the range [t0, t1] of chain parameters, its end points, and ``need``: a
#: fit sampled below need tol is returned provisional, not certified.
Requests = namedtuple("Requests", "chain t0 t1 start end need")

#: What a fit of :class:`_Fits` is: provisional (sampled below its need, not
#: certified), the fitted cubic (certified where its bound <= tol), the same-parameter
#: fit, nothing fitted.
SHORT, FITTED, SAME, NONE = 0, 1, 2, 3


def _fit_batch(chains, req, tol):
    """Best certified cubics for many chain ranges at once (:class:`Requests`): a
    :class:`_Fits` (per request a cubic, its bound, whether it is certified, its
    panels on demand); where the fitted cubic's sampled distance is below ``need``
    tol it is returned as is, provisional: its sampled distance, not certified.

    All ranges are fitted in one call (:func:`moment_cubics`) and screened by their
    sampled distances (:func:`_screened`); every part of every cubic left is
    certified in one batch (:func:`_certified_parts`).  A single-piece range whose
    fitted cubic does not certify also gets the same-parameter fit of
    :func:`fit_cubic`; the smaller bound wins (:func:`_results`).
    """
    n = len(req.chain)
    bank = chains.bank
    parts, ks = _parts(chains, req.chain, req.t0, req.t1)
    cubics, sampled, fitted, rays = moment_cubics(bank, parts, req.start, req.end,
                                                  chains.tiny[req.chain], tol)
    nparts = np.bincount(parts.req, minlength=n)
    short, skip = _screened(sampled, fitted, req.need, tol)
    todo = fitted & ~skip
    s0, s1 = _part_cuts(bank, parts, cubics, rays, (todo & (nparts > 1)).nonzero()[0])
    cut_ok = np.empty(n, bool)
    cut_ok[:] = True
    np.logical_and.at(cut_ok, parts.req, s1 > s0)
    todo &= cut_ok
    bound, cert, where = _certified_parts(bank, parts, cubics, rays, todo, nparts, s0, s1, tol)
    bound = np.where(skip, sampled, bound)
    first = parts.req.searchsorted(np.arange(n))
    # a single piece whose fit fails tol: the same-parameter fit too (the smaller wins)
    retry = ((nparts == 1) & (~fitted | (bound > tol)) & ~short).nonzero()[0]
    alt = _same_param_fits(bank, parts, first, retry, req.start, req.end)
    return _results(cubics, bound, fitted, short, alt, (cert, where, parts, ks, s0, s1),
                    first, nparts)


def _screened(sampled, fitted, need, tol):
    """(short, skip) per range: which fits are not certified.  A cubic whose sampled
    distance exceeds SCREEN tol fails anyway (the sampled distance is nearly a lower
    bound of the certified one: it is reported, the search only needs to know it
    fails); one whose sampled distance is below the request's ``need`` share of tol
    is ``short``, a provisional result (the search will try a longer one)."""
    short = fitted & (sampled < need * tol)
    return short, (sampled > SCREEN * tol) | short


def _certified_parts(bank, parts, cubics, rays, todo, nparts, s0, s1, tol):
    """Certify every part of the ranges ``todo`` in one batch (:func:`certify_batch`):
    the cubic cut at [s0, s1] of the part (the feet of the join points: phi is
    continuous, mapping s_k to the join, and increasing) against the part's piece,
    phi fitted to the pairs of parameters the fitter's rays found
    (:class:`morph.export.fit.Rays`, mapped to the cut: the pieces are not sampled
    again).  Returns (bound per range: the worst of its parts, inf where not
    certified; the :class:`Certified` batch or None; each part's row in it, -1
    where not certified)."""
    n = todo.shape[0]
    sel = todo[parts.req].nonzero()[0]
    where = np.empty(parts.req.shape[0], int)
    where[:] = -1
    where[sel] = np.arange(sel.shape[0])
    bound = np.empty(n)
    bound[:] = np.inf
    if not sel.shape[0]:
        return bound, None, where
    one = nparts[parts.req[sel]] == 1
    pieces = cubics.take(parts.req[sel], axis=0)
    if not np.logical_and.reduce(one):
        cut = ~one
        pieces[cut] = bz.subsegment_many(pieces.compress(cut, axis=0), s0[sel[cut]], s1[sel[cut]])
    span = (s1 - s0)[sel, None]
    feet = ((rays.feet.take(sel, axis=0) - s0[sel, None]) / span).clip(0.0, 1.0)
    cert = certify_batch(_sub_groups(bank, parts, sel), pieces, tol,
                         pairs=(feet, _quadrature().gx, rays.speed.take(sel, axis=0),
                                rays.gap.take(sel, axis=0)))
    worst = np.empty(n)
    worst[:] = -np.inf
    np.maximum.at(worst, parts.req[sel], cert.bound)
    return np.where(todo, worst, bound), cert, where


def _results(cubics, bound, fitted, short, alt, maps, first, nparts):
    """The :class:`_Fits` of :func:`_fit_batch`: a short fit is provisional (its
    ``bound`` the sampled distance); else the better of the fitted cubic (NaN, inf
    where nothing was fitted) and the same-parameter fit ``alt`` ({request:
    (cubic, bound)}); ``maps``: the batch's certificate and part cuts (panels)."""
    kind = np.where(short, SHORT, np.where(fitted, FITTED, NONE))
    cubic = np.where((kind == NONE)[:, None, None], np.nan, cubics)
    bound = np.where(kind == NONE, np.inf, bound)
    for r, (c, b) in alt.items():
        if b < bound[r]:
            kind[r], cubic[r], bound[r] = SAME, c, b
    return _Fits(cubic, bound, kind, maps, first, nparts)


class _Fits:
    """The results of one round of fits (:func:`_fit_batch`), arrays in request
    order: ``cubic`` (n, 4, 2), ``bound`` (n,), ``kind`` (SHORT, FITTED, SAME or
    NONE), ``cert`` (a certified bound: FITTED or SAME); :meth:`reparam` makes a
    request's :class:`_Reparam` (only for the segments written)."""

    __slots__ = ("cubic", "bound", "kind", "cert", "provisional", "maps", "first", "nparts")

    def __init__(self, cubic, bound, kind, maps, first, nparts):
        self.cubic, self.bound, self.kind, self.maps = cubic, bound, kind, maps
        self.cert = (kind == FITTED) | (kind == SAME)
        self.provisional = kind == SHORT
        self.first, self.nparts = first, nparts

    def reparam(self, r):
        if not self.cert[r]:
            return None
        lo = int(self.first[r])
        return _Reparam(*self.maps, lo, lo + int(self.nparts[r]), True if self.kind[r] == SAME
                        else None)


def _part_cuts(bank, parts, cubics, rays, multi):
    """(s0, s1): where each part of a fitted cubic starts and ends on it: 0, the
    feet of the joins (the cubic's closest points to its pieces' join points), 1.
    ``multi``: the requests of more than one piece whose cubic is certified."""
    s0, s1 = np.zeros(parts.req.shape[0]), np.empty(parts.req.shape[0])
    s1[:] = 1.0
    if not multi.shape[0]:
        return s0, s1
    at, count = _join_feet(parts, multi)
    joins = bank.first[parts.gid[at]]
    homog = np.empty((multi.shape[0], 4, 3))
    homog[:, :, :2], homog[:, :, 2] = cubics[multi], 1.0
    # Newton from between the rays of the nodes next to the join (the fitter's:
    # close, so 3 steps where a start from 65 samples took 6)
    guess = 0.5 * (rays.feet[at - 1, -1] + rays.feet[at, 0])
    feet = np.empty(at.shape)
    known = np.logical_and.reduce(np.isfinite(guess), axis=1)
    if np.logical_or.reduce(known):
        feet[known] = nr.closest_params_many(homog[known], joins[known], guess[known],
                                             iters=3, jet=pc.jet2_power_many)
    if not np.logical_and.reduce(known):
        feet[~known] = nr.nearest_params_many(homog[~known], joins[~known], iters=6)
    ok = np.arange(at.shape[1])[None] < count[:, None]
    s0[at[ok]] = feet[ok]
    s1[at[ok] - 1] = feet[ok]
    return s0, s1


def _same_param_fits(bank, parts, first, retry, starts, ends):
    """{request: (cubic, bound)}: the same-parameter fit (:func:`fit_cubic`) of each
    single-piece request in ``retry``, its ends those asked for (then bounded by
    :func:`same_param_bound`)."""
    alt = {}
    if not len(retry):
        return alt
    for (rows, h) in _sub_groups(bank, parts, first[retry]):
        for j, sub in zip(rows.tolist(), h):
            r = int(retry[j])
            c, b = fit_cubic(sub)
            c[0], c[-1] = starts[r], ends[r]
            if not np.array_equal(c[[0, -1]], pc.cartesian(sub)[[0, -1]]):
                b = same_param_bound(sub, c)
            alt[r] = (c, b)
    return alt


class _Reparam:
    """The panels of one result of :func:`_fit_batch`, made on demand
    (:meth:`panels`): those of the certificates of its parts, each mapped to chain
    parameters T (``same``: the same-parameter fit, phi the identity on each
    part)."""

    __slots__ = ("cert", "where", "parts", "ks", "s0", "s1", "lo", "hi", "same")

    def __init__(self, cert, where, parts, ks, s0, s1, lo, hi, same):
        self.cert, self.where, self.parts, self.ks = cert, where, parts, ks
        self.s0, self.s1, self.lo, self.hi, self.same = s0, s1, lo, hi, same

    def panels(self):
        if self.same:
            i = self.lo
            f = np.array([[0.0, 1.0], [1.0, 1.0]])
            a, b = float(self.parts.a[i]), float(self.parts.b[i])
            return ((0.0, 1.0, affine_reparam(f, self.ks[i] + a, b - a)),)
        if self.cert is None or self.where[self.lo] < 0:
            return ()
        out = []
        for i in range(self.lo, self.hi):
            s0, s1 = float(self.s0[i]), float(self.s1[i])
            a, b = float(self.parts.a[i]), float(self.parts.b[i])
            for p, q, f in self.cert.panels(int(self.where[i])):
                out.append((s0 + p * (s1 - s0), s0 + q * (s1 - s0),
                            affine_reparam(f, self.ks[i] + a, b - a)))
        return tuple(out)


#: numpy's ufunc buffer size (elements) while the export runs (:func:`ufunc_buffer`;
#: numpy's default is 8192).  numpy 2.4 copies an operand broadcast against a plane
#: (a row or a column of numbers per coordinate plane) into its buffer at every
#: fill, about 7 times the work of the product itself; an iteration whose inner
#: dimension is at least the buffer's size runs on the operands as they are.  The
#: export's planes have inner dimensions of hundreds to thousands (parts, pairs,
#: columns of a round): Relief's whole export makes 7 % fewer instructions with
#: 1024 than with 8192.  The buffer does not change any number: elementwise
#: results do not depend on it, and numpy's sums along a contiguous axis run
#: unbuffered (the same pairwise blocks at any buffer size).
UFUNC_BUFFER = 1024


@contextlib.contextmanager
def ufunc_buffer():
    """Within the ``with`` block, numpy's ufuncs use buffers of UFUNC_BUFFER elements
    (the buffer size before it is restored on exit, with numpy's error state)."""
    with np.errstate():
        np.setbufsize(UFUNC_BUFFER)
        yield


#: ``callback(searches done, searches)`` after every round of :func:`_drive` while
#: set (:func:`observe_searches`): the font jobs' progress within a batch
_observer = None


@contextlib.contextmanager
def observe_searches(callback):
    """Within the ``with`` block, :func:`_drive` calls ``callback(done, total)``
    after each round: how many of its searches have ended (a batch's conversion
    done so far, for progress reports)."""
    global _observer
    before, _observer = _observer, callback
    try:
        yield
    finally:
        _observer = before


def _chain_points(chains, chain, t):
    """The points of chains ``chain`` at chain parameters t: a piece's first control
    point at an integer t, the chain's last at its end, else the piece evaluated
    (:func:`morph.export.refine.chain_points`, the points alone: no derivatives)."""
    return chain_points(chains, chain, t)


#: Chains at least this many pieces long are searched from both ends at once
#: (:func:`_drive`); their cubics span 2 to 3 pieces of a brushed or stroked
#: outline's long smooth runs.
BOTH_WAYS = 6.0


class _Rows:
    """The rows of :func:`_drive`'s greedy machine: the forward search of every chain,
    the backward search of the chains of BOTH_WAYS pieces or more (``two``), and a
    spare forward row of each of those (it searches the gap left where a join does not
    certify).  A backward row's parameter u is the chain's K - u.

    A search from both ends needs about half the rounds of one from the start, for
    the same count of segments: the greedy search's reach is monotone (a segment from
    a later start ends no earlier), so the fewest segments a + c with the forward
    search's a-th end past the backward search's c-th start is the fewest of any
    cover."""

    def __init__(self, chains):
        self.n = n = len(chains.k)
        self.top = top = chains.k.astype(float)
        self.two = two = np.nonzero(top >= BOTH_WAYS)[0]
        self.m = m = len(two)
        self.rchain = np.concatenate([np.arange(n), two, two])
        self.back = np.zeros(n + 2 * m, bool)
        self.back[n:n + m] = True
        self.bwd_of = np.full(n, -1)
        self.bwd_of[two] = n + np.arange(m)
        self.spare_of = np.full(n, -1)
        self.spare_of[two] = n + m + np.arange(m)
        self.start_t = np.where(self.back, top[self.rchain], 0.0)

    def greedy(self, chains, tol, min_width):
        """The :class:`Greedy` machine of the rows: the forward and backward rows
        searching from their start, the spare rows inactive, first tries of
        :func:`first_widths`."""
        n, m, rchain = self.n, self.m, self.rchain
        return Greedy(self.top[rchain], _chain_points(chains, rchain, self.start_t), tol,
                      min_width, partial(self.fail, chains, tol),
                      active=np.arange(n + 2 * m) < n + m,
                      width=first_widths(chains, tol)[rchain])

    def requests(self, chains, greedy, refine, join):
        """A round's requests: the greedy rows' (in the chains' parameters: a backward
        row's range [u0, u1] is the chain's [K - u1, K - u0]; the two searches of a
        chain trying the same range, the gap between them, get one fit), then the
        refinement's and the joins' (:meth:`Refine.requests`, :meth:`_Join.requests`),
        all their points found in one call.  Returns (rows, the points at the rows'
        ends, each row's request among the rows, the rows with a request of their
        own, the count of the refinement's requests, of the joins', Requests)."""
        rows, t0, t1, start, need = greedy.requests()
        crow, rev = self.rchain[rows], self.back[rows]
        nb = int(np.count_nonzero(rev))
        if nb:                              # backward rows: ranges reflected, shared
            top = self.top[crow]
            a, b = np.where(rev, top - t1, t0), np.where(rev, top - t0, t1)
            own = _same_ranges(crow, rev, a, b, need)
            mine = (own == np.arange(rows.shape[0])).nonzero()[0]
        else:                               # every row asks its own fit
            a, b, own = t0, t1, np.arange(rows.shape[0])
            mine = own
        more = refine.requests() if refine.active else (np.zeros(0, int),) + (np.zeros(0),) * 2
        joins = join.requests()
        chain, r0, r1 = [np.concatenate(x) for x in zip(more, joins)]
        nr, nm = rows.shape[0], chain.shape[0]
        # the points at the greedy rows' ends (tried), at the backward rows' starts,
        # then at both ends of the other requests
        pts = _chain_points(chains, np.concatenate([crow, crow[rev], chain, chain]),
                            np.concatenate([b, a[rev], r0, r1]))
        end = pts[:nr]
        tried = end
        if nb:
            start = start.copy()
            start[rev] = pts[nr:nr + nb]
            tried = np.where(rev[:, None], start, end)
        req = Requests(np.concatenate([crow[mine], chain]), np.concatenate([a[mine], r0]),
                       np.concatenate([b[mine], r1]),
                       np.concatenate([start[mine], pts[nr + nb:nr + nb + nm]]),
                       np.concatenate([end[mine], pts[nr + nb + nm:]]),
                       np.concatenate([need[mine], np.zeros(nm)]))
        return rows, tried, own, mine, len(more[0]), len(joins[0]), req

    def fail(self, chains, tol, row, t0, width, bound):
        """Raise ToleranceNotMetError for row ``row``'s interval [t0, t0 + width]."""
        c = int(self.rchain[row])
        if self.back[row]:
            t0 = self.top[c] - t0 - width
        bank = chains.bank
        piece = bank.pieces[bank.order[chains.off[c] + min(int(t0), int(chains.k[c]) - 1)]]
        raise ToleranceNotMetError(
            "cubic export did not reach tol %.3g on a parameter interval of width "
            "%.3g (bound %.3g)" % (tol, width, bound), piece=piece, achieved=bound)

    def meet(self, greedy):
        """Each search of a chain capped where the other has come; the chains whose
        two searches met (or one of which is done) marked done, returned."""
        two, bwd_of, top = self.two, self.bwd_of, self.top
        both = two[(greedy.mode[two] != DONE) & (greedy.mode[bwd_of[two]] != DONE)]
        greedy.cap(both, top[both] - greedy.t0[bwd_of[both]])
        greedy.cap(bwd_of[both], top[both] - greedy.t0[both])
        fwd = two[greedy.mode[two] != DONE]
        met = fwd[greedy.t0[fwd] >= top[fwd] - greedy.t0[bwd_of[fwd]]]
        one = two[(greedy.mode[two] == DONE) != (greedy.mode[bwd_of[two]] == DONE)]
        if len(one):                          # (met and one are sorted, and disjoint)
            met = np.sort(np.concatenate([met, one]))
        greedy.mode[met], greedy.mode[bwd_of[met]] = DONE, DONE
        return met

    def ended(self, found, greedy, rows, met):
        """The segments of the rows whose search ended in the round (of ``rows``, those
        done; both rows of the chains ``met``), in their chains' parameters, split by
        chain: ((segments, chains) of those searched alone: one-way, or a gap searched
        again; (segments, chains) of the two-way searches, to join); chains sorted.
        None when no row ended."""
        rchain, back, top, n, m = self.rchain, self.back, self.top, self.n, self.m
        ended = np.zeros(greedy.mode.shape[0], bool)
        ended[rows[greedy.mode[rows] == DONE]] = True
        ended[met], ended[self.bwd_of[met]] = True, True
        if not np.logical_or.reduce(ended):
            return None
        seg = found.take(ended)
        rc = rchain[seg[0]]
        flip = back[seg[0]]
        seg = (rc, np.where(flip, top[rc] - seg[2], seg[1]),
               np.where(flip, top[rc] - seg[1], seg[2])) + seg[3:]
        rows = ended.nonzero()[0]
        joined, alone = np.zeros((2, n), bool)
        joined[rchain[rows[(self.spare_of[rchain[rows]] >= 0) & (rows < n + m)]]] = True
        alone[rchain[rows]] = True
        sel = joined[seg[0]]
        rest = ~sel
        return ((tuple([x[rest] for x in seg]), (alone & ~joined).nonzero()[0]),
                (tuple([x[sel] for x in seg]), joined.nonzero()[0]))


#: A chain's guessed difficulty (:func:`first_widths`) per cubic of its first try:
#: on the bench sets the chains written as one cubic have a difficulty below 4 (three
#: in four of them), those of n cubics about 3 n.
DIFFICULTY = 4.0
#: The first try spans at most this many pieces: a chain of BOTH_WAYS pieces or more
#: is searched from both ends, and a failed try over many pieces costs rounds.
FIRST_MAX = 5.0


def first_widths(chains, tol):
    """The width of each chain's first try: the whole chain where its pieces' guessed
    difficulty (the sum of (L theta^5 / tol)^(1/6), :func:`morph.export.bank._bend`)
    is below 2 DIFFICULTY, else the chain cut into floor(difficulty / DIFFICULTY)
    equal widths; at most FIRST_MAX pieces.  Only a guess: the search moves on from
    it (most chains of a stroked outline are one cubic, which the whole chain's fit
    then finds at once instead of growing a segment piece by piece)."""
    bank = chains.bank
    if not len(chains.k):
        return np.zeros(0)
    d = (bank.bend[bank.order] / tol) ** (1.0 / 6.0)
    total = np.add.reduceat(d, chains.off) if len(d) else np.zeros(len(chains.k))
    total = np.where(chains.k > 0, total, 0.0)
    return np.minimum(chains.k / np.maximum(1.0, np.floor(total / DIFFICULTY)), FIRST_MAX)


def _drive(chains, tol, min_width, cubics_only=False):
    """The segment searches of all chains (:class:`morph.export.fit.ChainArrays`), run
    together; their CubicFit lists in order.

    Every chain is searched by the greedy search (:class:`morph.export.greedy.Greedy`)
    from its start, a chain of BOTH_WAYS pieces or more also from its end until the two
    meet (:class:`_Rows`, joined by :class:`_Join`); a chain searched one way whose
    whole fit fails is cut into equal lengths first (:func:`_split_wholes`); a
    chain left with two segments or more is refined (:class:`morph.export.refine.
    Refine`).  Each round fits and certifies the requests of all machines together
    (:func:`_fit_batch`).  The accepted segments stay arrays until the end; with
    ``cubics_only`` as lists of (4, 2) arrays (:func:`_cubic_arrays`)."""
    n = len(chains.k)
    lay = _Rows(chains)
    greedy = lay.greedy(chains, tol, min_width)
    whole_failed = np.zeros(n, bool)
    refine = Refine(chains, tol, whole_failed)
    join = _Join(tol, lay.top)
    found = _Segments()                   # the greedy segments of rows still searching
    final, rounds, done = [], [], 0

    def finished(seg, ended):
        """Chains ``ended`` (sorted), their segments ``seg``: to refine, or done."""
        nonlocal done
        if ended.shape[0]:
            many = np.bincount(seg[0], minlength=n)[ended] >= 2
            refined = np.zeros(n, bool)
            refined[ended[many]] = True
            sel = refined[seg[0]]
            refine.add(ended[many], *[x[sel] for x in seg])
            final.append(tuple([x[~sel] for x in seg]))
            done += ended.shape[0] - int(np.count_nonzero(many))

    while np.logical_or.reduce(greedy.active) or refine.active or join.active:
        rows, tried, own, mine, more, joins, req = lay.requests(chains, greedy, refine, join)
        if req.chain.shape[0]:
            fits = _fit_batch(chains, req, tol)
            rounds.append(fits)
            whole = (req.t0 == 0.0) & (req.t1 == chains.k[req.chain]) & ~(fits.bound <= tol)
            whole_failed[req.chain[whole & ~fits.provisional]] = True
            acc = _greedy_round(greedy, found, (rows, tried, own, mine), fits, len(rounds) - 1)
            moved = _refine_round(chains, lay, (greedy, refine, found), (req.chain, whole),
                                  fits, (len(mine), more, len(rounds) - 1), acc[0])
            if joins:
                _search_gaps(chains, lay, greedy, found,
                             join.update(fits, len(mine) + more, len(rounds) - 1))
            out = lay.ended(found, greedy, moved, lay.meet(greedy))
            if out is not None:
                finished(*out[0])
                join.add(*out[1], greedy.t0[out[1][1]])
            if join.touched:
                finished(*join.ready())
        if refine.active:
            out = refine.finished()
            final.append(out[1:])
            done += len(out[0])
        if _observer is not None:
            _observer(done, n)
    return (_cubic_arrays if cubics_only else _cubic_fits)(n, final, rounds)


def _greedy_round(greedy, found, asked, fits, at_round):
    """The greedy rows' fits of one round (``asked``: the rows, what they tried, the
    requests they own and the round's greedy requests) given to the search; the
    segments it accepts added to ``found``.  Returns what ``Greedy.update`` does."""
    rows, tried, own, mine = asked
    j = mine.searchsorted(own)
    at = np.empty((j.shape[0], 2), int)
    at[:, 0], at[:, 1] = at_round, j
    acc = greedy.update(rows, tried, (fits.cubic.take(j, axis=0), fits.bound[j], fits.cert[j]), at)
    found.add(acc[0], acc[1], acc[2], acc[4], acc[5])
    return acc


def _refine_round(chains, lay, machines, wholes, fits, counts, moved):
    """The refinement's fits of the round (``counts``: the greedy's requests, then
    the refinement's; the round ``counts[2]``) given to it, the chains whose equal
    cuts did not all certify searched again (:func:`_resume`), and the chains whose
    whole fit failed in the round cut (:func:`_split_wholes`; ``wholes``: each
    request's chain, and whether it is a failed fit of the whole chain).  Returns the
    greedy rows that moved on: ``moved``, and those resumed that did."""
    greedy, refine, found = machines
    n_greedy, more, at_round = counts
    if more:
        lost = refine.update(fits, n_greedy, at_round)
        if lost[0].shape[0]:
            moved = np.concatenate([moved, _resume(greedy, found, lost, fits, at_round)])
    _split_wholes(chains, lay, (greedy, refine), wholes, fits.bound, n_greedy)
    return moved


def _split_wholes(chains, lay, machines, wholes, bound, n_greedy):
    """The chains searched one way whose first try, the whole chain (one of the
    round's first ``n_greedy`` requests; ``wholes``: each request's chain, and
    whether it is a failed fit of the whole chain), failed: their greedy rows wait and
    the refinement tries each as n segments of equal length (:meth:`Refine.split`),
    n = (bound / tol)^(1 / ERROR_POWER) rounded up (the model bound ~ width^P: the
    count of segments that each reach tol), at least 2, and 2 where no cubic was
    fitted.  A chain that needs two or three segments is then done in two rounds,
    not one round for each try of its first segment."""
    greedy, refine = machines
    failed = wholes[1][:n_greedy]
    if not np.logical_or.reduce(failed, initial=False):
        return
    sel = failed.nonzero()[0]
    c = wholes[0][sel]
    one = (lay.spare_of[c] < 0) & (chains.extent[c] > 0)
    sel, c = sel[one], c[one]
    with np.errstate(invalid="ignore"):
        count = np.ceil((bound[sel] / refine.tol) ** (1.0 / ERROR_POWER))
    count = np.where(np.isfinite(count), np.maximum(count, 2.0), 2.0).astype(int)
    greedy.wait(c)
    refine.split(c, count)


def _resume(greedy, found, lost, fits, at_round):
    """The chains whose equal cuts did not all certify (``lost``: chains, the end of
    each first cut, its request in ``fits``) searched again by their greedy rows, the
    first cut's fit taken as their try.  Returns the rows that moved on (an accepted
    segment)."""
    chain, t1, j = lost
    greedy.resume(chain, t1)
    at = np.empty((j.shape[0], 2), int)
    at[:, 0], at[:, 1] = at_round, j
    acc = greedy.update(chain, fits.cubic[j, -1],
                        (fits.cubic.take(j, axis=0), fits.bound[j], fits.cert[j]), at)
    found.add(acc[0], acc[1], acc[2], acc[4], acc[5])
    return acc[0]


def _search_gaps(chains, lay, greedy, found, failed):
    """Joins that do not certify (``failed``: their chains, the segments kept and the
    gaps, from ``_Join.update``): each chain keeps its path's unbroken start and end,
    and its spare row searches the gap between them."""
    bad, kept, gap = failed
    spare = lay.spare_of[bad]
    found.add(lay.spare_of[kept[0]], *kept[1:])
    greedy.activate(spare, gap[:, 0], _chain_points(chains, bad, gap[:, 0]))
    greedy.cap(spare, gap[:, 1])


def _same_ranges(crow, rev, a, b, need):
    """For each greedy request, the request whose fit it takes: itself, or for a
    backward row the forward row of its chain asking the same range with the same
    ``need`` (the rows are sorted, forward rows first)."""
    own = np.arange(crow.shape[0])
    fwd = np.empty(int(np.maximum.reduce(crow, initial=-1)) + 1, int)
    fwd[:] = -1
    fwd[crow[~rev]] = (~rev).nonzero()[0]
    r = rev.nonzero()[0]
    f = fwd[crow[r]]
    same = (f >= 0)
    same[same] = (a[f[same]] == a[r[same]]) & (b[f[same]] == b[r[same]]) & (
        need[f[same]] == need[r[same]])
    own[r[same]] = f[same]
    return own


#: Parameter values of a chain (of parameter length K) that differ by at most this
#: many ulps of K are one point reflected twice (t -> K - t -> K - (K - t)).
REFLECT_ULPS = 4


class _Join:
    """The chains searched from both ends (:func:`_drive`), joined where the searches
    met.

    Each search ends where the other has come (:meth:`morph.export.greedy.Greedy.cap`),
    so that the forward search's last segment ends where the backward search's last
    one begins, and the chain's segments are those of the two.  Where both moved in
    the same round and overlap, the path keeps the segments in order of their starts
    and refits the first one that begins before the end e of the path so far from e
    ([a, b] with a < e becomes [e, b]: a part of an interval that fits; refitted and
    certified), trying one segment for it and the next ([e, next end]) or for it and
    the one before; segments that end before e are dropped.  Where the searches met
    end to end, one segment for the two meeting there is tried too (the two searches
    stop a little short of their reach, like the greedy search; the refinement
    tries one fewer over the whole chain).  Where a refit does not certify after all,
    the path keeps its segments that run unbroken from the chain's start and to its
    end, and the gap between them is searched again, from its start (:meth:`update`
    returns it).
    The paths are made once per chain (Python, over its segments); the refits of all
    chains of a round are one batch."""

    def __init__(self, tol, top):
        self.tol, self.top = tol, top      # each chain's parameter length K
        self.paths = {}                  # chain: segments (t0, t1, bound, at), None at a refit
        self.slots = []                  # refits: (chain, position in its path, kind, t0, t1)
        self.pending = set()             # chains with refits asked
        self.touched = set()             # chains whose paths changed since ready()

    @property
    def active(self):
        return bool(self.paths)

    def add(self, seg, chains, met):
        """The segments (chain, t0, t1, bound, at; chain parameters) of ``chains``
        whose searches ended, ``met``: where each one's forward search ended."""
        c, t0, t1, b, at = seg
        # each chain's segments (t0, t1, bound, at) in the order of those tuples
        order = np.lexsort((at[:, 1], at[:, 0], b, t1, t0, c))
        c = c[order]
        segs = list(zip(t0[order].tolist(), t1[order].tolist(), b[order].tolist(),
                        at[order].tolist()))
        chain = chains.tolist()
        for ch, f, lo, hi in zip(chain, met.tolist(), c.searchsorted(chains).tolist(),
                                 c.searchsorted(chains, side="right").tolist()):
            self._path(ch, segs[lo:hi], f)
        self.touched.update(chain)

    def _path(self, c, segs, f):
        """The path of chain c from its segments (sorted by t0, then t1), ``f`` where
        its forward search ended."""
        path, e = [], 0.0
        # a backward segment's start is K - u, u its row's cap K - t: t itself up to
        # the rounding of the two subtractions (2 ulps of K each); one that starts
        # that close after e is refitted from e, as one that starts before it
        slack = REFLECT_ULPS * math.ulp(float(self.top[c]))
        for i, (t0, t1, b, at) in enumerate(segs):
            if t1 <= e:
                continue
            if t0 < e or (t0 != e and t0 - e <= slack and path):
                self._ask(c, len(path), 0, e, t1)
                if i + 1 < len(segs) and segs[i + 1][0] == t1:
                    self._ask(c, len(path), 1, e, segs[i + 1][1])
                if path and path[-1] is not None:
                    self._ask(c, len(path), -1, path[-1][0], t1)
                path.append(None)
            else:
                path.append((t0, t1, b, at))
            e = t1
        for i in range(len(path) - 1):          # met end to end: one for the two
            if path[i] is not None and path[i + 1] is not None and path[i][1] == f:
                self._ask(c, i, 1, path[i][0], path[i + 1][1])
        self.paths[c] = path

    def _ask(self, c, pos, kind, t0, t1):
        """Ask the fit of [t0, t1] for path position ``pos`` of chain c: ``kind`` 0
        fills it, 1 replaces it and the next, -1 it and the one before."""
        self.pending.add(c)
        self.slots.append((c, pos, kind, t0, t1))

    def requests(self):
        """(chain, t0, t1) of the refits asked."""
        if not self.slots:
            return (np.zeros(0, int), np.zeros(0), np.zeros(0))
        c, _, _, t0, t1 = zip(*self.slots)
        return np.array(c, int), np.array(t0, float), np.array(t1, float)

    def update(self, fits, offset, round_no):
        """Take the refits (``fits`` a round's :class:`_Fits`, these requests from
        ``offset`` on, made in round ``round_no``); returns (the chains whose path has
        a refit that does not certify, dropped here; the segments (chain, t0, t1,
        bound, at) of their paths that run unbroken from the chain's start or to its
        end, kept; the gap (from, to) between those, to be searched again)."""
        chain, t0, t1 = self.requests()
        j = offset + np.arange(len(chain))
        good = fits.cert[j] & (fits.bound[j] <= self.tol)
        bad, gains = set(), {}
        for i, (c, pos, kind, _, _) in enumerate(self.slots):
            fit = (float(t0[i]), float(t1[i]), float(fits.bound[j[i]]), [round_no, int(j[i])])
            if kind:
                if good[i] and (c, pos) not in gains:
                    gains[c, pos] = (kind, fit)
            elif good[i]:
                self.paths[c][pos] = fit
            else:
                bad.add(c)
        # one segment for two, the later positions of a path first
        for (c, pos), (kind, fit) in sorted(gains.items(), key=lambda g: (g[0][0], -g[0][1])):
            path = self.paths[c]
            if kind > 0 and pos + 1 < len(path) and path[pos + 1] is not None:
                path[pos:pos + 2] = [fit]
            elif kind < 0 and pos > 0 and path[pos - 1] is not None:
                path[pos - 1:pos + 1] = [fit]
            else:
                continue
            if None not in path:
                bad.discard(c)
        self.touched |= self.pending
        self.slots, self.pending = [], set()
        bad = sorted(bad)
        chain, kept, gaps = [], [], []
        for c in bad:
            lead, trail, gap = _unbroken(self.paths.pop(c), float(self.top[c]))
            chain += [c] * (len(lead) + len(trail))
            kept += lead + trail
            gaps.append(gap)
        return np.array(bad, int), _seg_arrays(chain, kept), np.array(gaps, float).reshape(-1, 2)

    def ready(self):
        """(segments (chain, t0, t1, bound, at) sorted by chain and t0, chains) of the
        chains whose paths are complete, removed (only those whose paths changed
        since the last call can be)."""
        out, ended, count = [], [], []
        for c in sorted(self.touched):
            path = self.paths.get(c)
            if path is None or c in self.pending or None in path:
                continue
            ended.append(c)
            count.append(len(path))
            out += path
        self.touched = set()
        for c in ended:
            del self.paths[c]
        ended = np.array(ended, int)
        return _seg_arrays(ended.repeat(count), out), ended


def _seg_arrays(chain, segs):
    """The arrays (chain, t0, t1, bound, at) of the segments ``segs`` (tuples (t0, t1,
    bound, at)) of the chains ``chain``."""
    if not segs:
        return (np.zeros(0, int),) + (np.zeros(0),) * 3 + (np.zeros((0, 2), int),)
    t0, t1, b, at = zip(*segs)
    return (np.array(chain, int), np.array(t0, float), np.array(t1, float), np.array(b, float),
            np.array(at, int).reshape(-1, 2))


def _unbroken(path, top):
    """The segments of a path (:class:`_Join`) of a chain of parameter length ``top``
    that follow each other from its start (t = 0) up to the path's first gap or refit,
    those that follow each other back from its end, and the gap (from, to) they leave
    (the path has a refit)."""
    lead, e = [], 0.0
    for p in path:
        if p is None or p[0] != e:
            break
        lead.append(p)
        e = p[1]
    trail, f = [], top
    for p in path[len(lead):][::-1]:
        if p is None or p[1] != f:
            break
        trail.append(p)
        f = p[0]
    return lead, trail[::-1], (e, f)


class _Segments:
    """Segments accepted by the greedy search, kept as flat arrays until their chain's
    search ends: chain, t0, t1, bound, at (round, request)."""

    def __init__(self):
        self.parts = []

    def add(self, chain, t0, t1, bound, at):
        self.parts.append((chain, t0, t1, bound, at))

    def take(self, rows):
        """The segments of the rows ``rows`` (a mask; all their searches ended),
        removed: flat arrays sorted by row, then t0."""
        every = [np.concatenate(x) for x in zip(*self.parts)]
        mine = rows[every[0]]
        rest = ~mine
        self.parts = [tuple([x[rest] for x in every])]
        order = mine.nonzero()[0][np.lexsort((every[1][mine], every[0][mine]))]  # a chain's
        return tuple([x[order] for x in every])                       # segments in t0 order


def _cubic_fits(n, final, rounds):
    """Each chain's list of CubicFit from the segments' arrays ``final`` ([(chain, t0,
    t1, bound, at)], each chain's segments in one entry, in order): the cubic of the
    fit that made each (round, request) and its panels on demand."""
    chain, t0, t1, bound, at = (np.concatenate(x) for x in zip(*final)) if final else \
        ((),) * 5
    order = np.argsort(chain, kind="stable")
    out = [[] for _ in range(n)]
    for c, a, b, e, (r, j) in zip(np.asarray(chain)[order].tolist(), np.asarray(t0)[order].tolist(),
                                  np.asarray(t1)[order].tolist(), np.asarray(bound)[order].tolist(),
                                  np.asarray(at).reshape(-1, 2)[order].tolist()):
        fits = rounds[r]
        out[c].append(CubicFit(a, b, fits.cubic[j], e, _Panels(fits, j)))
    return out


def _cubic_arrays(n, final, rounds):
    """Each chain's cubics as a list of (4, 2) arrays, in order, from the segments'
    arrays ``final`` (as :func:`_cubic_fits`): one gather per round, no CubicFit."""
    if not final:
        return [[] for _ in range(n)]
    chain, _, _, _, at = (np.concatenate(x) for x in zip(*final))
    at = at.reshape(-1, 2)
    cubic = np.empty((len(chain), 4, 2))
    for r in unique(at[:, 0]).tolist():
        sel = np.nonzero(at[:, 0] == r)[0]
        cubic[sel] = rounds[r].cubic.take(at[sel, 1], axis=0)
    order = np.argsort(chain, kind="stable")
    ends = np.cumsum(np.bincount(chain, minlength=n)).tolist()
    every = list(cubic.take(order, axis=0))  # one (4, 2) view per cubic (np.split: 30x slower)
    return [every[a:b] for a, b in zip([0] + ends[:-1], ends)]


class _Panels:
    """The panels of request j of a round's :class:`_Fits`, made when asked for
    (:meth:`panels`; writers of outlines need the cubics only)."""

    __slots__ = ("fits", "j")

    def __init__(self, fits, j):
        self.fits, self.j = fits, j

    def panels(self):
        return self.fits.reparam(self.j).panels()



def _exact_cubic(piece):
    """(4, 2) control points of a polynomial piece of degree <= 3, else None."""
    if len(piece) > 4 or not pc.is_polynomial(piece):
        return None
    return bz.to_degree(pc.cartesian(piece), 3)


def cubic_segments(piece, tol, max_depth=16):
    """Certified cubics covering a piece: a list of :class:`CubicFit`.

    Fit k has parameter interval [t0, t1] (consecutive, from 0 to 1), a (4, 2)
    cubic C, its ``bound`` <= tol and ``reparam`` (panels of a continuous increasing
    piecewise-polynomial phi from t0 to t1, see :class:`CubicFit`) with

        max_{s in [0,1]} |R(phi(s)) - C(s)| <= bound <= tol

    (certified, :func:`cubic_bound` with ``reparam``): the Fréchet and hence the
    Hausdorff distance between C and R on [t0, t1] are <= tol.  Exact pieces
    (polynomial, degree <= 3) give one fit with bound 0.  Raises as
    :func:`piece_to_cubics`.
    """
    if not (tol > 0 and math.isfinite(tol)):
        raise ValueError("tol must be positive and finite, got %r" % (tol,))
    piece = check_piece(piece)
    exact = _exact_cubic(piece)
    if exact is not None:
        return [CubicFit(0.0, 1.0, exact, 0.0, ((0.0, 1.0, np.array([[0.0, 1.0], [1.0, 1.0]])),))]
    return chain_segments([piece], tol, max_depth)


def chain_segments(pieces, tol, max_depth=16):
    """Certified cubics covering consecutive pieces as one curve: a list of CubicFit.

    The pieces (end of one = start of the next) form one curve of parameter T in
    [0, K], piece k on [k, k + 1]; cubics may span joins.  Fit intervals [t0, t1]
    and the values of its ``reparam`` panels are such T, and

        max_{s in [0,1]} |R(phi(s)) - C(s)| <= bound <= tol

    with R the chain and phi continuous and increasing: the Fréchet (hence
    Hausdorff) distance between each cubic and the chain on [t0, t1] is <= tol.
    Spanning a join pays where the join is G1 (tangent continuous: one smooth curve
    split into pieces, as sums produce); at corners the fits fail and the search
    ends segments near them, so callers split chains at corners
    (:func:`loop_to_beziers` does).  Raises as :func:`piece_to_cubics`.
    """
    return chains_segments([pieces], tol, max_depth)[0]


def chains_segments(chains, tol, max_depth=16):
    """:func:`chain_segments` of several chains, searched in lockstep (:func:`_drive`)."""
    sizes = [len(c) for c in chains]
    bank = Bank([p for c in chains for p in c])
    offs = np.concatenate([[0], np.cumsum(sizes)]).astype(int)
    runs = [np.arange(a, b) for a, b in zip(offs[:-1], offs[1:])]
    return [[seg._replace(reparam=seg.reparam.panels()) for seg in segs]
            for segs in runs_segments(bank, runs, tol, max_depth)]


def runs_segments(bank, runs, tol, max_depth=16, cubics_only=False):
    """:func:`chains_segments` of runs of the pieces of a :class:`Bank` (arrays of
    global piece ids), searched in lockstep (:func:`_drive`).  The CubicFits'
    ``reparam`` has a method ``panels()`` that makes the panels (on demand: writers
    need the cubics, not the maps); with ``cubics_only`` each run's cubics come back
    as a list of (4, 2) arrays instead."""
    if not (tol > 0 and math.isfinite(tol)):
        raise ValueError("tol must be positive and finite, got %r" % (tol,))
    with ufunc_buffer():
        chains = make_chains(bank, runs)
        return _drive(chains, tol, 2.0 ** -max_depth, cubics_only) if len(chains.k) else []


def piece_to_cubics(piece, tol, max_depth=16):
    """Polynomial cubics within ``tol`` of a (rational) piece, list of (4, 2) arrays.

    Each returned cubic C_k covers the piece's parameter interval [t_k, t_k+1] with
    ``max_s |R(phi_k(s)) - C_k(s)| <= tol`` for an increasing polynomial
    reparametrisation phi_k of [0, 1] onto [t_k, t_k+1] (a-priori bound of
    :func:`cubic_bound`, not sampled; see :func:`cubic_segments`): the Fréchet
    distance, and so the Hausdorff distance, between the cubics and the piece is
    <= tol.  The cubics keep the piece's end points exactly and their joins are exact
    (G1 where the piece is regular: end tangent directions are matched).
    Polynomial pieces of degree <= 3 are returned exactly (degree-elevated).  tol is
    absolute, in the piece's units.

    Raises:
        ValueError: tol not positive and finite, or weights not positive.
        ToleranceNotMetError: no cubic certifies on a parameter interval narrower
            than ``2**-max_depth`` (e.g. tol below floating-point resolution of the
            coordinates); ``.achieved`` holds its bound.
    """
    return [seg.cubic for seg in cubic_segments(piece, tol, max_depth)]
