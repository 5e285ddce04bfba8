"""The greedy search for certified cubics along a chain of pieces.

**Search.**  Per piece (or per run of pieces with smooth joins, see below),
segments are chosen greedily from the start: the longest parameter interval whose
certified bound is <= tol is looked for with a few fits (error predicted from the
previous fits as ~ h^p, a segment accepted once its bound reaches 0.7 tol), then one
segment fewer is tried while the segments' bounds say it may fit (cuts at equal
shares of the modelled difficulty, :func:`_balanced_cuts`), or of equal arc length
after a short last segment.  The searches of all runs go in lockstep
(:func:`_drive`), over all loops of a region or of many glyphs
(:func:`morph.export.loops.loops_to_beziers`: the pieces of the whole batch live in
one :class:`morph.export.bank.Bank`, one stack per degree): each round fits the
pending ranges of every run with a few array calls
(:func:`morph.export.fit.moment_cubics`: all ranges' parts sampled in one
evaluation per degree, all candidates measured at once) and certifies all their
cubics in one batch (:func:`morph.export.certify.certify_batch`, started from the
feet the fitter's rays found: the pieces are not sampled again; a cubic whose
sampled distance exceeds SCREEN tol is not certified, nor is a try whose sampled
distance is below PROVISIONAL tol: the search extends it anyway, and certifies it
only if it ends there).  bench/export.py compares the cubic counts with kurbo's and
with the classic circle cubic.  Where the fit finds no cubic, or its cubic does not
certify, the same-parameter fit of :func:`morph.export.certify.fit_cubic` (Hermite /
least squares) is tried, and the interval shrinks until one certifies.

**The protocol of a search.**  A search is a generator (:func:`_search` and its
steps :func:`_next_segment`, :func:`_split_at`, composed with ``yield from``): it
yields a list of fit requests ``(chain, t0, t1, (start, end)[, need])`` and is sent
back the list of their results ``(cubic, bound, panels)`` (:func:`_fit_ranges`), in
order, or it yields :data:`NEED_ARC` when it needs its chain's arc-length table
(made for all searches that ask in one batch); its return value
(``StopIteration.value``) is the chain's list of
:class:`~morph.export.certify.CubicFit`.  :func:`_drive` advances every search to
its next yield, fits all pending requests of all searches in one batch, sends each
search its share, and repeats until every search has returned.  A generator keeps
the search's state (bracket, last fit) in its local variables between rounds: the
numerical work is O(rounds) array calls; what remains per search and round is the
scalar bookkeeping of its bracket (a few microseconds).
"""

import contextlib
import math

import numpy as np

from .. import bernstein as bz
from .. import piece as pc
from .. import nearest as nr
from ..errors import ToleranceNotMetError
from .bank import Bank
from .certify import (SCREEN, CubicFit, affine_reparam, certify_batch, check_piece, fit_cubic,
                      same_param_bound, start_at_nodes)
from .fit import Parts, _quadrature, arc_tables, make_chains, moment_cubics


def _parts(requests):
    """The parts of every request ``(chain, t0, t1, ends[, need])``: piece k of the
    chain restricted to its local [a, b] covers [t0, t1] (:class:`Parts`, in request
    order), as arrays for all requests at once."""
    chains = [r[0] for r in requests]
    t0 = np.array([r[1] for r in requests], float)
    t1 = np.array([r[2] for r in requests], float)
    kk = np.array([c.k for c in chains])
    off = np.array([c.off for c in chains])
    k0 = np.floor(t0).astype(int)
    k1 = np.minimum(kk, np.ceil(t1).astype(int))
    cnt = np.maximum(k1 - k0, 0)
    req = np.repeat(np.arange(len(requests)), cnt)
    k = np.repeat(k0, cnt) + np.arange(cnt.sum()) - np.repeat(np.cumsum(cnt) - cnt, cnt)
    a = np.maximum(t0[req] - k, 0.0)
    b = np.minimum(t1[req] - k, 1.0)
    keep = b > a
    req, k, a, b = req[keep], k[keep], a[keep], b[keep]
    bank = chains[0].bank
    return Parts(req, bank.order[off[req] + k], a, b), k


def _sub_groups(bank, parts, sel):
    """The sub-pieces of the parts ``sel`` (piece restricted to [a, b]) by degree,
    [(positions in sel, stack)]: one de Casteljau call per degree."""
    out = []
    for rows, h in bank.gather(parts.gid[sel]):
        a, b = parts.a[sel[rows]], parts.b[sel[rows]]
        cut = (a != 0.0) | (b != 1.0)
        if cut.any():
            h = h.copy()
            h[cut] = bz.subsegment_many(h[cut], a[cut], b[cut])
        out.append((rows, h))
    return out


def _join_feet(parts, multi):
    """Where the joins of the ranges ``multi`` sit among the parts (the start points of
    every part but the first), padded to one count with each range's last join:
    (positions (r, n), count of joins (r,)); their feet on the fitted cubics are
    found in one call for all."""
    first = np.searchsorted(parts.req, multi)
    count = np.searchsorted(parts.req, multi, side="right") - first - 1
    col = np.minimum(np.arange(int(count.max()))[None], count[:, None] - 1)
    return first[:, None] + 1 + col, count


def _fit_ranges(requests, tol):
    """Best certified cubics for many chain ranges at once: for each request
    ``(chain, t0, t1, (start, end)[, need])`` a result (cubic, bound, panels); where
    the fitted cubic's sampled distance is below ``need`` tol it is returned as is,
    not certified: (cubic, sampled distance, None).  ``panels`` is a
    :class:`_Reparam` (made into panels on demand).

    All ranges are fitted in one call (:func:`moment_cubics`) and screened by their
    sampled distances (:func:`_screened`); every part of every cubic left is
    certified in one batch (:func:`_certified_parts`).  A single-piece range whose
    fitted cubic does not certify also gets the same-parameter fit of
    :func:`fit_cubic`; the smaller bound wins (:func:`_results`).
    """
    n = len(requests)
    bank = requests[0][0].bank
    parts, ks = _parts(requests)
    starts = np.array([r[3][0] for r in requests], float)
    ends = np.array([r[3][1] for r in requests], float)
    need = np.array([r[4] if len(r) > 4 else 0.0 for r in requests], float)
    tiny = np.array([r[0].tiny for r in requests], float)
    cubics, sampled, fitted, rays = moment_cubics(bank, parts, starts, ends, tiny, tol)
    nparts = np.bincount(parts.req, minlength=n)
    short, skip = _screened(sampled, fitted, need, tol)
    todo = fitted & ~skip
    s0, s1 = _part_cuts(bank, parts, cubics, rays, np.nonzero(todo & (nparts > 1))[0])
    cut_ok = np.ones(n, bool)
    np.logical_and.at(cut_ok, parts.req, s1 > s0)
    todo &= cut_ok
    bound, cert, where = _certified_parts(bank, parts, cubics, rays, todo, nparts, s0, s1, tol)
    bound = np.where(skip, sampled, bound)
    first = np.searchsorted(parts.req, np.arange(n))
    # a single piece whose fit fails tol: the same-parameter fit too (the smaller wins)
    retry = np.nonzero((nparts == 1) & (~fitted | (bound > tol)) & ~short)[0]
    alt = _same_param_fits(bank, parts, first, retry, starts, ends)
    return _results(cubics, bound, fitted, short, sampled, alt,
                    (cert, where, parts, ks, s0, s1), first, nparts)


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
    started from the feet the fitter's rays found (the pieces are not sampled
    again).  Returns (bound per range: the worst of its parts, inf where not
    certified; the :class:`Certified` batch or None; each part's row in it, -1
    where not certified)."""
    n = len(todo)
    sel = np.nonzero(todo[parts.req])[0]
    where = np.full(len(parts.req), -1)
    where[sel] = np.arange(len(sel))
    bound = np.full(n, np.inf)
    if not len(sel):
        return bound, None, where
    one = nparts[parts.req[sel]] == 1
    pieces = cubics[parts.req[sel]]
    if not one.all():
        pieces[~one] = bz.subsegment_many(pieces[~one], s0[sel[~one]], s1[sel[~one]])
    span = (s1 - s0)[sel, None]
    start = start_at_nodes((rays[sel] - s0[sel, None]) / span, _quadrature().gx)
    cert = certify_batch(_sub_groups(bank, parts, sel), pieces, tol, start=start)
    worst = np.full(n, -np.inf)
    np.maximum.at(worst, parts.req[sel], cert.bound)
    return np.where(todo, worst, bound), cert, where


def _results(cubics, bound, fitted, short, sampled, alt, maps, first, nparts):
    """The results of :func:`_fit_ranges` in request order: (cubic, sampled, None)
    for a short fit, else the better of the fitted cubic (None, inf where nothing
    was fitted) and the same-parameter fit ``alt`` ({request: (cubic, bound)}), with
    its :class:`_Reparam` (``maps``: the batch's certificate and part cuts)."""
    out = []
    bound_l, fitted_l, short_l = bound.tolist(), fitted.tolist(), short.tolist()
    sampled_l, first_l, nparts_l = sampled.tolist(), first.tolist(), nparts.tolist()
    for r in range(len(cubics)):
        if short_l[r]:
            out.append((cubics[r], sampled_l[r], None))
            continue
        lo, hi = first_l[r], first_l[r] + nparts_l[r]
        if r in alt and alt[r][1] < (bound_l[r] if fitted_l[r] else np.inf):
            out.append((alt[r][0], alt[r][1], _Reparam(*maps, lo, hi, True)))
        elif fitted_l[r]:
            out.append((cubics[r], bound_l[r], _Reparam(*maps, lo, hi, None)))
        else:
            out.append((None, np.inf, None))
    return out


def _part_cuts(bank, parts, cubics, rays, multi):
    """(s0, s1): where each part of a fitted cubic starts and ends on it: 0, the
    feet of the joins (the cubic's closest points to its pieces' join points), 1.
    ``multi``: the requests of more than one piece whose cubic is certified."""
    s0, s1 = np.zeros(len(parts.req)), np.ones(len(parts.req))
    if not len(multi):
        return s0, s1
    at, count = _join_feet(parts, multi)
    joins = bank.first[parts.gid[at]]
    homog = np.concatenate([cubics[multi], np.ones(cubics[multi].shape[:2] + (1,))], axis=2)
    # Newton from between the rays of the nodes next to the join (the fitter's:
    # close, so 3 steps where a start from 65 samples took 6)
    guess = 0.5 * (rays[at - 1, -1] + rays[at, 0])
    feet = np.empty(at.shape)
    known = np.all(np.isfinite(guess), axis=1)
    if known.any():
        feet[known] = nr.closest_params_many(homog[known], joins[known], guess[known],
                                             iters=3, jet=pc.jet2_power_many)
    if not known.all():
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
    """The panels of one result of :func:`_fit_ranges`, made on demand
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


def _drive(searches, tol, chains):
    """Run search generators in lockstep and return their results in order.

    A search (:func:`_search`) yields a list of fit requests and is sent back their
    results; the pending requests of all searches are fitted and certified together
    (:func:`_fit_ranges`), so the numerical work is one batch per round, not one
    call per fit.  A search that needs its chain's arc-length table yields
    :data:`NEED_ARC` instead: the tables of all that asked are made in one batch
    (:func:`arc_tables`, ``chains[i]`` is search i's chain) and the searches resumed."""
    observer = _observer
    results = [None] * len(searches)
    pending = {}
    for i, g in enumerate(searches):
        try:
            pending[i] = next(g)
        except StopIteration as stop:
            results[i] = stop.value
    while pending:
        arcs = [i for i, v in pending.items() if v is NEED_ARC]
        if arcs:
            arc_tables([chains[i] for i in arcs])
            for i in arcs:
                try:
                    pending[i] = searches[i].send(None)
                except StopIteration as stop:
                    results[i] = stop.value
                    del pending[i]
            continue
        order = [(i, len(reqs)) for i, reqs in pending.items()]
        fits = _fit_ranges([r for reqs in pending.values() for r in reqs], tol)
        pending, k = {}, 0
        for i, n in order:
            try:
                pending[i] = searches[i].send(fits[k:k + n])
            except StopIteration as stop:
                results[i] = stop.value
            k += n
        if observer is not None:
            observer(len(searches) - len(pending), len(searches))
    return results


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


def runs_segments(bank, runs, tol, max_depth=16):
    """:func:`chains_segments` of runs of the pieces of a :class:`Bank` (arrays of
    global piece ids), searched in lockstep (:func:`_drive`).  The CubicFits'
    ``reparam`` is a :class:`_Reparam`: its ``panels()`` are the panels (made on
    demand: writers need the cubics, not the maps)."""
    if not (tol > 0 and math.isfinite(tol)):
        raise ValueError("tol must be positive and finite, got %r" % (tol,))
    chains = make_chains(bank, runs)
    return _drive([_search(c, tol, 2.0 ** -max_depth) for c in chains], tol, chains)


def _search(chain, tol, min_width):
    """The segment search of one chain, a generator for :func:`_drive`: yields lists
    of fit requests ``(chain, t0, t1, (start, end))``, is sent their results, and
    returns the chain's list of CubicFit.

    Segments are found greedily from the start (:func:`_next_segment`); then one
    segment fewer is tried while the segments' bounds say it may fit
    (:func:`_balanced_cuts`), and after a short last segment one fewer of equal
    arc length."""
    out = []
    t0, start, width = 0.0, chain.point(0.0), min(float(chain.k), 2.0)
    while t0 < chain.k:
        t1, cubic, bound, reparam, end = yield from _next_segment(
            chain, t0, start, width, tol, min_width)
        out.append(CubicFit(t0, t1, cubic, bound, reparam))
        width = t1 - t0
        t0, start = t1, end
    # the greedy search stops each segment a little short of its longest reach: try
    # one segment fewer, cut where the greedy segments' bounds say it may fit
    while len(out) >= 2:
        cuts = yield from _balanced_cuts(chain, out, tol)
        fewer = None if cuts is None else (yield from _split_at(chain, cuts, tol))
        if fewer is None:
            break
        out = fewer
    widths = [seg.t1 - seg.t0 for seg in out]
    if len(out) == 2 and widths[-1] < 0.5 * widths[0]:
        # a short last one is left: try one cubic for the whole chain (for more
        # segments, n - 1 of equal arc length rarely fit where the model said no)
        t, cum = yield from _arclength_table(chain)
        if cum[-1] > 0:
            fewer = yield from _split_at(
                chain, np.interp(np.linspace(0.0, cum[-1], len(out)), cum, t), tol)
            out = out if fewer is None else fewer
    return out


#: Error model of :func:`_balanced_cuts`: a cubic's bound grows like the P-th power
#: of the arc length it spans.
ERROR_POWER = 5.0
#: One segment fewer is tried when the greedy segments' shares add up to at most this
#: many segments fewer than there are (the greedy segments stop short of their reach).
FEWER_SLACK = 1.0


#: What a search yields when it needs its chain's arc-length table: :func:`_drive`
#: makes the tables of all searches that asked in one batch (:func:`arc_tables`).
NEED_ARC = "arc table"


def _arclength_table(chain):
    """(T, cumulative arc length) at the knots of the chain's arc-length table; a
    generator step (yields :data:`NEED_ARC` when the table is not made yet)."""
    if chain._arc is None:
        yield NEED_ARC
    tl, tr, sl, sr, _, _ = chain.arc_table()
    return np.append(tl, tr[-1]), np.append(sl, sr[-1])


def _balanced_cuts(chain, segs, tol):
    """Cuts of len(segs) - 1 segments, or None (not plausible).

    Segment i of ``segs`` (bound b_i over arc length L_i) counts as d_i = (b_i /
    tol)^(1/P) of a segment that just reaches tol (model bound ~ L^P, P =
    :data:`ERROR_POWER`), spread evenly over its arc length.  When the d_i add up to
    at most len(segs) - 1, the cuts are placed at equal shares of that sum (equal arc
    lengths where the curve is equally hard); the caller fits and certifies them
    (:func:`_split_at`) and keeps ``segs`` if any fails."""
    n = len(segs) - 1
    d = np.array([(max(seg.bound, 1e-3 * tol) / tol) ** (1.0 / ERROR_POWER)
                  for seg in segs])
    if not (n >= 1 and d.sum() <= len(segs) - FEWER_SLACK):
        return None
    t, cum = yield from _arclength_table(chain)
    if not cum[-1] > 0:
        return None
    edges = np.interp([segs[0].t0] + [seg.t1 for seg in segs], t, cum)
    hard = np.concatenate([[0.0], np.cumsum(d)])
    return np.interp(np.interp(np.linspace(0.0, hard[-1], n + 1), hard, edges), cum, t)


def _split_at(chain, cuts, tol):
    """Certified segments between the chain parameters ``cuts`` (all fitted in one
    request list), or None if one fails; a generator step of :func:`_search`."""
    cuts = np.array(cuts, float)
    cuts[0], cuts[-1] = 0.0, float(chain.k)
    if np.any(np.diff(cuts) <= 0):
        return None
    points = [chain.point(0.0)] + [chain.point(float(t)) for t in cuts[1:]]
    fits = yield [(chain, float(t0), float(t1), (p0, p1))
                  for t0, t1, p0, p1 in zip(cuts[:-1], cuts[1:], points[:-1], points[1:])]
    if not all(bound <= tol for _, bound, _ in fits):
        return None
    return [CubicFit(float(t0), float(t1), cubic, bound, reparam)
            for t0, t1, (cubic, bound, reparam) in zip(cuts[:-1], cuts[1:], fits)]


#: The search stops at a certified segment whose bound is at least this share of tol
#: (higher: longer segments, more fits).  Equal to PROVISIONAL, so that a try that is
#: certified at all ends the first pass (tries sampled below PROVISIONAL tol are not
#: certified); bench/export_profile.py counts the fits and certificates it saves.
ACCEPT = 0.7


#: The search for a segment's end stops once the bracket (longest certified, shortest
#: failed end) is this narrow relative to the certified width.
BRACKET_REL = 0.02


#: The model of :func:`_next_try`: bound ~ width^p, p from the last two fits kept in
#: [P_MIN, P_MAX] (ERROR_POWER without them; widths closer than SAME_WIDTH relative
#: give no slope), the next width aimed at AIM tol.
P_MIN, P_MAX = 2.0, 8.0
SAME_WIDTH = 0.01
AIM = 0.9
#: The next width is kept within these factors of the last one; after a fit with no
#: finite bound it is SHRINK times the last.
STEP_MIN, STEP_MAX = 0.125, 4.0
SHRINK = 0.5


def _next_try(t0, w, bound, last, good, bad, top, tol):
    """The next end to try after a fit of width w with ``bound`` (``last``: the
    previous (width, bound); ``good``: the longest certified fit; ``bad``: the
    shortest failed end), or None when the bracket is tight enough.  The model is
    bound ~ width^p with p from the last two fits (P_MIN <= p <= P_MAX,
    ERROR_POWER without them), aimed at AIM tol, the step kept within STEP_MIN to
    STEP_MAX times the width and inside the bracket (bisecting it otherwise)."""
    p = ERROR_POWER
    if (last is not None and abs(last[0] - w) > SAME_WIDTH * w and last[1] > 0 and bound > 0
            and math.isfinite(bound) and math.isfinite(last[1])):
        p = min(P_MAX, max(P_MIN, math.log(bound / last[1]) / math.log(w / last[0])))
    if not math.isfinite(bound):
        ratio = SHRINK
    else:
        ratio = (AIM * tol / bound) ** (1.0 / p) if bound > 0 else STEP_MAX
    target = min(top, t0 + w * min(STEP_MAX, max(STEP_MIN, ratio)))
    lo = good[0] if good is not None else t0
    hi = bad if bad is not None else top
    if bad is not None and not lo < target < hi:
        target = 0.5 * (lo + hi)
    if good is not None and (target <= lo
                             or (bad is not None and hi - lo <= BRACKET_REL * (lo - t0))):
        return None
    return target


#: A try whose sampled distance is below this share of tol is not certified (the
#: search extends it anyway); the longest such try is certified once the search
#: would end on it.
PROVISIONAL = 0.7
#: The first try of a segment runs to the chain's end when less than this share of
#: its width would be left; a pass makes at most MAX_TRIES fits.
REACH_END = 0.3
MAX_TRIES = 8


def _next_segment(chain, t0, start, width, tol, min_width):
    """The longest certified segment from t0 found with a few fits: (t1, cubic, bound,
    reparam, end point); a generator step of :func:`_search`.  The first try spans
    ``width``; later ones follow the model bound ~ width^p, p from the last two fits
    (2 <= p <= 8, 5 at first), bracketed by the longest certified (or provisional:
    sampled below PROVISIONAL tol, certified only if the search ends on it) and the
    shortest failed interval."""
    top = float(chain.k)

    def attempt(t1, need):
        end = chain.point(t1)
        (cubic, bound, reparam), = yield [(chain, t0, t1, (start, end), need)]
        return (t1, cubic, bound, reparam, end)

    t1 = min(top, t0 + width)
    if top - t1 < REACH_END * (t1 - t0):
        t1 = top
    good, bad, last, fit = None, None, None, None
    for provisional in (PROVISIONAL, 0.0):
        for _ in range(MAX_TRIES):
            fit = yield from attempt(t1, 0.0 if t1 == top else provisional)
            w, bound = t1 - t0, fit[2]
            if bound <= tol:
                good = fit if good is None or t1 > good[0] else good
                if fit[3] is not None and (t1 == top or bound >= ACCEPT * tol):
                    break
            else:
                bad = t1 if bad is None else min(bad, t1)
            target = _next_try(t0, w, bound, last, good, bad, top, tol)
            last = (w, bound)
            if target is None or target - t0 < min_width:
                break
            t1 = target
        if good is None or good[3] is not None:
            break
        # the search ends on a provisional try: certify it; where that fails (the
        # certificate is loose here), search again certifying every try
        fit = yield from attempt(good[0], 0.0)
        if fit[2] <= tol:
            return fit
        bad, last = good[0], (good[0] - t0, fit[2])
        t1 = _next_try(t0, good[0] - t0, fit[2], None, None, bad, top, tol) or 0.5 * (t0 + bad)
        good = None
    while good is None:
        # no certified fit yet: halve the shortest failed interval down to min_width
        t1 = t0 + 0.5 * (bad - t0)
        if t1 - t0 < min_width:
            raise ToleranceNotMetError(
                "cubic export did not reach tol %.3g on a parameter interval of width "
                "%.3g (bound %.3g)" % (tol, bad - t0, fit[2]),
                piece=chain.piece(min(int(t0), chain.k - 1)), achieved=fit[2])
        fit = yield from attempt(t1, 0.0)
        if fit[2] <= tol:
            good = fit
        else:
            bad = t1
    return good


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
